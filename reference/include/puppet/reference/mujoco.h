// The same humanoid in MuJoCo 2.2 (reduced coordinates, soft constraints solved as a convex
// problem), built from the same Model through the MJCF document write_mjcf gives it, driven by
// the same environment forces and pins (docs/design.md, "The references"):
//   - bodies are the segments in their principal frames at their COMs, the inertia the model's;
//   - gravity, drag and buoyancy are applied as external wrenches (xfrc_applied) from the shared
//     formulas, evaluated at the start of each step, and MuJoCo's own gravity is off; joints
//     have no armature, damping or friction;
//   - one hard pin whose target stays put is exact: the tree hangs from its point by a ball
//     joint to the world. Other hard pins are connect equalities to mocap bodies at their
//     targets, soft as MuJoCo's constraints are (time constant τ = 2·dt, critically damped,
//     impedance 0.9999). A mocap body has no velocity, so MuJoCo's constraint damping would
//     brake the point's own velocity (a lag of 2τ·v behind a moving target); the mocap body is
//     placed 2τ·v_target ahead instead, which makes it damp the velocity relative to the target
//     (exact for a flat impedance: a_ref = −b·(v − v_t) − k·(p − p_t) with b/k = 2τ). A
//     compliant pin is a spring force, as in the Bullet references;
//   - ground contact has the model's μ in an elliptic (exact Coulomb) cone, as stiff as pins;
//   - a swing–twist ball limit is MuJoCo's cone on the whole rotation angle (mjcf_ball_range); a
//     box limit is exactly the model's, three hinges in one body; hinge limits the model's.
// Compiled only when Debian's libmujoco-dev is installed (PUPPET_HAVE_MUJOCO).
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <memory>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/reference/solver.h"

namespace puppet::reference {

enum class MujocoIntegrator { kEuler, kImplicit, kRk4 };

struct MujocoSettings {
  // MuJoCo's semi-implicit Euler (its default), implicit in velocity, or RK4
  MujocoIntegrator integrator = MujocoIntegrator::kEuler;
  // the constraints' time constant τ (s); 0: 2·dt, the stiffest MuJoCo allows at each dt. A
  // fixed τ keeps the constraint model the same at every dt (the second truth and its check);
  // below 2·dt MuJoCo raises it to 2·dt
  double constraint_time_constant = 0.0;
};

// whether this build has MuJoCo
bool have_mujoco();

// MuJoCo sizes its solver's stack as 5 (njmax + neq + nv)² numbers: the model's arena, held by
// every mujoco solver, may take at most this many bytes
inline constexpr double kMujocoMaxArenaBytes = double(1u << 30);

// Why MuJoCo cannot run the model (empty when it can), decided before anything runs: the tree
// within MJCF's depth (mjcf_write_problem), the arena within kMujocoMaxArenaBytes, and then the
// verdict of MuJoCo's own compiler on the document a mujoco solver builds (a zero-width hinge
// range, a principal moment under its 1e-15 floor, ...), which names the body or joint. A build
// without MuJoCo says so.
std::string mujoco_model_problem(const Model& model);

// builds the model at rest in the environment; throws ModelError when MuJoCo's compiler rejects
// the document (or the build has no MuJoCo)
std::unique_ptr<Solver> make_mujoco(const Model& model, const Environment& environment,
                                    const MujocoSettings& settings = {});

}  // namespace puppet::reference
