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
#include <span>
#include <string>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::reference {

enum class Kind { kMultibody, kRigid, kMujoco };

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

// One Bullet world holding one model. Not copyable; one step(dt) is one Bullet internal step.
class Solver {
 public:
  virtual ~Solver() = default;

  virtual Kind kind() const = 0;
  // holds each pin's point at its target, replacing any pins set before
  virtual void set_pins(std::span<const Pin> pins) = 0;
  // the targets of the pins, in order, for the end of the next step
  virtual void set_pin_targets(std::span<const Vector3d> targets) = 0;
  virtual void step(double dt) = 0;
  // per segment, in the model's segment frames: COM, orientation, v, ω (world)
  virtual void read_state(std::span<BodyState> out) const = 0;
  // places every segment; the multibody reads the base's pose and velocity and each joint's
  // relative rotation and angular velocity, so the state must be joint-consistent
  virtual void set_state(std::span<const BodyState> bodies) = 0;
  // the complete state as numbers (exact: restoring it and stepping repeats the same result)
  virtual std::vector<double> save() const = 0;
  virtual void load(std::span<const double> saved) = 0;
  // a non-finite value appeared in the state
  virtual bool diverged() const = 0;

  // what Bullet was given, read back from Bullet's own objects (correspondence tests):
  // a segment's mass, its inertia (diagonal, segment frame), and a joint's anchor as each of
  // its two segments carries it, in world
  virtual double segment_mass(int segment) const = 0;
  virtual Vector3d segment_inertia(int segment) const = 0;
  virtual void joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const = 0;
};

// why Bullet cannot build the model (empty when it can), decided before anything runs: both
// solvers build every joint and limit kind the model has (a box limit as the multibody's own
// rows, limit_rows.cpp, and as the ragdoll's btGeneric6DofSpring2Constraint), so this is the
// place a limitation would be stated
std::string bullet_model_problem(const Model& model);

// builds the model at rest in the environment (its ground, gravity and forces); the model must
// outlive the solver. Throws ModelError when the model cannot be expressed in Bullet
// (bullet_model_problem).
std::unique_ptr<Solver> make_solver(Kind kind, const Model& model, const Environment& environment,
                                    const Settings& settings = {});

}  // namespace puppet::reference
