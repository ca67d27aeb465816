/// \file
/// A model as MJCF, MuJoCo's XML format: the articulated body written for MuJoCo's own compiler
/// (testbed export-mjcf, and the mujoco reference, which loads what this writes from memory).
///
/// What MJCF cannot say is kept in user data, so that reading the file back gives the same model
/// bit for bit: each body's rest pose in world (7 numbers) and each joint's rest anchor, frame and
/// limits (10 numbers, see kJointUserSize). MuJoCo ignores user data; a file without it is read
/// in MuJoCo's own terms.
#pragma once

#include <string>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet {

/// user data per body: rest COM (x, y, z) and rest orientation (w, x, y, z), both in world
inline constexpr int kBodyUserSize = 7;
/// user data per joint: rest anchor in world (3), rest joint frame in world (w, x, y, z), then
/// swing_x, swing_y, twist (rad) for a ball or the hinge axis in the joint frame for a hinge
inline constexpr int kJointUserSize = 10;

/// MuJoCo 2.2's integrators: semi-implicit Euler (its default), implicit in velocity (Coriolis
/// and gyroscopic forces included in the implicit step), and fourth-order Runge–Kutta
enum class MjcfIntegrator { kEuler, kImplicit, kRk4 };

struct MjcfOptions {
  Environment environment;  ///< gravity, and the ground plane z = 0 with its μ when it has one
  double timestep = 1.0 / 240.0;
  MjcfIntegrator integrator = MjcfIntegrator::kEuler;

  /// The root of MuJoCo's body tree. By default the model's root on a free joint. With a segment
  /// here the tree hangs from it instead: a ball joint at `pinned_point` (segment frame) holds
  /// that point at `pinned_target` (world), exactly, as reduced coordinates do; the joints on the
  /// path from it to the model's root are written reversed. The rest of the figure starts at its
  /// rest pose, translated so that the point is on its target.
  int pinned_segment = -1;
  Vector3d pinned_point{0, 0, 0};
  Vector3d pinned_target{0, 0, 0};

  /// points held by a moving target: each a mocap body (named "pin<k>") where the point is in the
  /// written configuration, tied to its segment by a connect equality
  std::vector<Pin> driven_pins;

  /// the mujoco reference's settings: every constraint (joint limits, pins, contacts) as stiff as
  /// MuJoCo allows with a flat impedance (solref 2·timestep after MuJoCo's refsafe, critically
  /// damped; solimp 0.9999 whatever the violation) and the exact (elliptic) friction cone; off,
  /// MuJoCo's defaults
  bool stiff_constraints = false;
  /// with stiff_constraints, the constraints' time constant τ (s) instead of the stiffest: a
  /// constraint model that stays the same when the timestep changes (it must be at least
  /// 2·timestep, or MuJoCo raises it); 0 for the stiffest
  double constraint_time_constant = 0.0;
  /// record the exact rest values as user data (see above)
  bool user_data = true;
  /// bodies, joints and geoms named by the segments and joints; off, `s<i>`, `j<i>` and `g<i>` by
  /// index (a solver's own document: no name can clash with `pin<k>` or need escaping)
  bool model_names = true;
};

/// the damping ratio of the joint limits write_mjcf writes with stiff constraints (solreflimit):
/// near-inelastic impacts, as every other engine's limits (a hinge driven into its end at 3 rad/s
/// gives back 1.0% of the speed, 4.2% at MuJoCo's default 1; LimitImpact). Not more: at 4 (0.3%)
/// the softer spring kept limits engaged longer and a step after landing in `drop` took 2.3 times
/// as long
inline constexpr double kLimitDampingRatio = 2.0;

/// MJCF readers built on tinyxml2 (MuJoCo 2.2.2's and this project's) nest at most 100 elements:
/// `mujoco`, `worldbody`, a `body` per level of the tree and the deepest body's `geom` leave room
/// for a tree 96 segments deep (measured: MuJoCo builds chain:96, not chain:97)
inline constexpr int kMjcfMaxDepth = 96;
/// why the model cannot be written as MJCF that reads back (empty when it can): its depth, or a
/// joint name that a box limit's hinges (`<joint>:x`, `:y`, `:z`) would repeat
std::string mjcf_write_problem(const Model& model);

/// the first joint whose limit MJCF holds only approximately (a swing–twist ball limit, written as
/// MuJoCo's cone), empty when every joint is exact (hinges, box limits, unlimited balls)
std::string mjcf_inexact_joint(const Model& model);

/// the model as an MJCF document. A box limit becomes three hinges in the child's body, which
/// MuJoCo composes in the box's order: the same joint, each range enforced on its own angle. A
/// swing–twist limit becomes MuJoCo's cone on the whole rotation angle, of the model's largest
/// half-angle (swing or twist) so that it forbids nothing the model allows.
std::string write_mjcf(const Model& model, const MjcfOptions& options = {});

/// Reads an MJCF articulated body (docs/mjcf.md: what is read, what is refused). `source` names
/// the file in error messages, which give the element's line. User data as write_mjcf writes it
/// gives back the exact rest values; without it the rest pose comes from the bodies' frames, a
/// ball limit is MuJoCo's cone (swing and twist both bounded by its angle) and a ball's joint
/// frame is its child's segment frame. An <include> is read from the folder of `source` (a path).
/// `note`, when given, gets what was skipped (see ReadOptions) as one line, or nothing. Throws
/// ModelError.
Model parse_mjcf(const std::string& xml_text, const std::string& source,
                 const ReadOptions& options = {}, std::string* note = nullptr);

/// the body of segment s in a document written without model names: "s<s>"
std::string mjcf_segment_body(int segment);

/// the ball limit write_mjcf gives MuJoCo (rad), or a negative value for none
double mjcf_ball_range(const Joint& joint);

}  // namespace puppet
