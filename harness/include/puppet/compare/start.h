// Random starts: the inputs of one scenario run drawn from a seed and an index, reproducibly on
// any machine and compiler, so that `testbed robustness` can run thousands of starts nobody chose
// and any one of them can be replayed (`testbed run --start SEED:INDEX`, the viewer's --start).
//
// What is drawn, in this order, from a SplitMix64 stream of (seed, index) (docs/robustness.md):
//   tilt       uniform in [−45°, 45°]: the hanging scenarios' tilt about world x
//   hz         uniform in [0.25, 1] Hz: the frequency of the grab's circle (or shake)
//   phase      uniform in [0, 2π): where on its circle (or shake) the grab starts
//   grab       a direction uniform on the sphere; the grab is the grab segment's surface point
//              farthest along it (segment frame)
//   per joint, in model order:
//     ball     swing: direction uniform, magnitude √u·0.8 of the ellipse's radius that way;
//              twist uniform in the central 80 % of its range
//     hinge    the angle uniform in the central 80 % of its range
//     then the relative angular velocity: ball uniform in a ball of 2 rad/s, hinge uniform in
//     ±2 rad/s about its axis (fixed joints draw nothing)
// The same index gives the same pose in every scenario of a model.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::compare {

struct StartInputs {
  uint64_t seed = 0;
  int64_t index = 0;
  double tilt_deg = 0.0;
  double hz = 0.5;
  double phase = 0.0;                       // rad
  Vector3d grab_direction{0, 0, -1};        // segment frame, unit
  std::vector<Quaterniond> joint_rotation;  // q_rel per joint, inside its limits
  std::vector<Vector3d> joint_velocity;     // ω_rel per joint, in the joint's frame (rad/s);
                                            // a slide's rate along its direction (m/s)
  std::vector<double> joint_offset;         // a slide's coordinate (m), 0 for the other joints

  // summaries for a CSV row: the RMS of the joints' relative angles (deg) and speeds (rad/s)
  double joint_angle_rms_deg() const;
  double joint_speed_rms() const;
};

// the ranges drawn from
inline constexpr double kStartTiltDeg = 45.0;
inline constexpr double kStartHzLow = 0.25, kStartHzHigh = 1.0;
inline constexpr double kStartLimitFraction = 0.8;
inline constexpr double kStartJointSpeed = 2.0;  // rad/s
inline constexpr double kStartSlideSpeed = 0.2;  // m/s; an unlimited slide starts at its rest

StartInputs random_start(const Model& model, uint64_t seed, int64_t index);

// the model posed by the start's joint rotations and moving by its joint velocities, from
// `anchor` (which keeps its rest pose, at rest): every joint closed, inside its limits, and
// every velocity consistent with the joints
std::vector<BodyState> posed_start(const Model& model, const StartInputs& start, int anchor);

// "SEED:INDEX" (plain decimal digits); throws std::invalid_argument with what is wrong
void parse_start(const std::string& text, uint64_t* seed, int64_t* index);

}  // namespace puppet::compare
