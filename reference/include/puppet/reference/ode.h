// The same humanoid in the Open Dynamics Engine 0.16 (Debian's libode-dev, double precision): the
// classic ragdoll of a generation of games and robotics simulators, built from the same Model and
// driven by the same environment forces and pins as every engine (docs/references.md, "ode"):
//   - one dBody per segment (maximal coordinates), its frame the segment frame, its mass and
//     inertia the model's; gravity, drag and buoyancy are applied as forces from the shared
//     formulas and ODE's own gravity is off;
//   - a ball joint is a dBallJoint; a box limit is an AMotor in Euler mode whose three stops are
//     the box's ranges (exact: ODE's Euler angles are the box's, each negated); a swing–twist
//     limit is an AMotor in user mode whose two axes, the swing's and the twist's, and angles
//     are set before every step (the rows Bullet's cone–twist uses); a hinge is a dHingeJoint
//     with its stops; a fixed joint a dFixedJoint;
//   - a hard pin is a ball joint to the world whose world anchor is moved to the target;
//     compliant pins and grabs are forces, as in the Bullet references;
//   - ground contact is a plane with the model's μ in ODE's friction pyramid (dContactApprox1:
//     the friction bound proportional to the normal force), no bounce.
// Limits, pins and contacts are ODE's: rows with error reduction ERP and softness CFM, solved
// exactly (dWorldStep, a pivoting LCP solver) or by projected Gauss–Seidel (dWorldQuickStep).
// Compiled only when libode-dev is installed (PUPPET_HAVE_ODE).
#pragma once

#include <memory>
#include <string>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/reference/solver.h"

namespace puppet::reference {

enum class OdeStepper {
  kQuick,  // dWorldQuickStep: projected Gauss–Seidel with over-relaxation, O(rows) a sweep
  kStep    // dWorldStep: the exact (Dantzig) LCP over all rows, O(rows³)
};

struct OdeSettings {
  OdeStepper stepper = OdeStepper::kQuick;
  // dWorldQuickStep's sweeps (ODE's default 20)
  int iterations = 20;
  // the rows' error reduction (ODE's default 0.2, as Bullet's) and softness (ODE's default in
  // double precision, 1e-10)
  double erp = 0.2;
  double cfm = 1e-10;
};

// empty when valid, else what is wrong
std::string validate(const OdeSettings& settings);

// whether this build has ODE
bool have_ode();

// Why ODE cannot run the model (empty when it can), decided before anything runs: ODE has no
// ellipsoid geom. (Its Euler-mode motor is singular at a box's middle angle of ±90°, which the
// model keeps within ±85°.) A build without ODE says so.
std::string ode_model_problem(const Model& model);

// builds the model at rest in the environment; the model must outlive the solver. Throws
// ModelError when ODE cannot run the model (ode_model_problem) and std::invalid_argument for
// invalid settings.
std::unique_ptr<Solver> make_ode(const Model& model, const Environment& environment,
                                 const OdeSettings& settings = {});

}  // namespace puppet::reference
