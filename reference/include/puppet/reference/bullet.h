// The same humanoid in Bullet 3 (double precision), built from the same Model and driven by the
// same environment forces and pins as the procedural solver, so that every difference the
// testbed reports is a difference between solvers (docs/design.md, "The references").
//
//   multibody: btMultiBody (Featherstone, reduced coordinates): a floating base at the root and
//              one spherical / revolute / fixed link per joint. Joints cannot open; limits and
//              pins are soft (Baumgarte) constraints in its sequential-impulse solver.
//   rigid:     one btRigidBody per segment tied by btConeTwist / btHinge / btFixed constraints
//              (maximal coordinates): the ragdoll most games ship. Its joints drift under load.
//
// Bullet's types stay inside reference/src: this header speaks the model's language only.
#pragma once

#include <memory>
#include <string>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/reference/solver.h"

namespace puppet::reference {

// which of Bullet's two worlds
enum class Kind { kMultibody, kRigid };

struct Settings {
  // sequential-impulse sweeps per step; 10 is Bullet's default for both worlds
  int iterations = 10;
  // error reduction of the constraint solver (btContactSolverInfo::m_erp, Bullet's default);
  // the multibody pins and limits read m_erp, the rigid joints their own bias factors
  double erp = 0.2;
  // multibody ball limits: Bullet's btMultiBodySphericalJointLimit (a box of Euler angles)
  // instead of the model's swing–twist limit; kept to reproduce why it is not the default
  bool euler_ball_limits = false;
};

// empty when valid, else what is wrong
std::string validate(const Settings& settings);

// why Bullet cannot build the model (empty when it can), decided before anything runs: both
// solvers build every joint and limit kind the model has (a box limit as the multibody's own
// rows, limit_rows.cpp, and as the ragdoll's btGeneric6DofSpring2Constraint). A root the world
// holds the ragdoll builds (a btGeneric6DofSpring2Constraint to the world) but for a slide's
// armature; the multibody does not build it yet
std::string bullet_model_problem(Kind kind, const Model& model);
std::string bullet_multibody_model_problem(const Model& model);
std::string bullet_rigid_model_problem(const Model& model);

// How many constraints hold to Bullet's process-wide static body (btTypedConstraint::
// getFixedBody()). No solver of this project uses it (a pin holds to a static body of its own
// solver's: adding constraints to the shared one from two threads corrupts the heap), so this is
// 0 whatever has run; for the tests.
int bullet_shared_fixed_body_constraints();

// builds the model at rest in the environment (its ground, gravity and forces); the model must
// outlive the solver. Throws ModelError when the model cannot be expressed in Bullet
// (bullet_model_problem for its kind).
std::unique_ptr<Solver> make_solver(Kind kind, const Model& model, const Environment& environment,
                                    const Settings& settings = {});

}  // namespace puppet::reference
