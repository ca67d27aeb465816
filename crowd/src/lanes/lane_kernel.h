// The interface between the crowd's lane stepper (lane_stepper.cpp, built for any x86-64) and
// xpbd's substep kernel, compiled once per instruction set (xpbd_lanes_sse2.cpp: 2 lanes,
// xpbd_lanes_avx2.cpp: 4, xpbd_lanes_avx512.cpp: 8). Plain data only: a kernel's file includes
// nothing that another file also instantiates, so no inline function compiled for AVX2 can be
// linked into a caller that runs on a machine without it.
//
// A batch's state is an array of slots of `lanes` doubles each, one lane per puppet:
//   body b, field f         slot b·kBodyFields + f            (x, q (w x y z), v, ω, x_prev,
//   q_prev,
//                                                              the user's force and torque)
//   pin p, field f          slot pin_offset + p·kPinFields + f
//   multipliers             slot lambda_offset + …            (the kernel's own scratch)
#pragma once

namespace puppet::procedural::lanes {

enum BodyField {
  kX = 0,
  kQ = 3,  // w, x, y, z
  kV = 7,
  kW = 10,
  kXPrev = 13,
  kQPrev = 16,  // w, x, y, z
  kForce = 20,
  kTorque = 23,
  kBodyFields = 26,
};
enum PinField {
  kPinPoint = 0,       // the pinned point in its segment's frame
  kPinCompliance = 3,  // m/N
  kPinFrom = 4,        // the target at the start of the step
  kPinTo = 7,          // and at its end
  kPinForce = 10,      // out: the pull of the last substep, as Solver's pin_force
  kPinFields = 11,
};

struct SegmentTerms {
  double mass, inv_mass;
  double inertia[3], inv_inertia[3];  // diagonal, in the segment's frame
};
// how the kernel reads a joint's limit: lane by lane through Plan::limit_error, a box's or an
// elliptic cone's surely-inside test in lanes first (joint_limits.h, surely_inside_box;
// rotation.cpp, clamp_ball), or a hinge in lanes
enum LimitKind { kAskEachLane, kBox, kCone, kHinge };
struct JointPlan {
  int parent, child;
  LimitKind limit;
  double frame_parent[4], frame_child[4];  // w, x, y, z
  // kBox: BoxTest's terms
  int box_axes[3];
  double box_sign;
  double box_lower_cos[3], box_lower_sin[3], box_upper_cos[3], box_upper_sin[3];
  bool box_wide[3];
  double box_margin;  // kBoxMargin
  // kCone: the swing ellipse's half-angles (rad) and tan of half the twist limit
  double swing_x, swing_y, twist_half_tan;
  // kHinge: the axis in the joint frame, and the sines and cosines of its half-limits
  double hinge_axis[3];
  double lower_half_sin, lower_half_cos, upper_half_sin, upper_half_cos;
  double anchor_parent[3], anchor_child[3];  // the joint point in each segment's frame
  double mass_parent[9], mass_child[9];      // JointTerms::point_mass, row-major
  double frame_shift[4];                     // w, x, y, z: JointTerms::frame_shift
  double limit_free_w;                       // JointTerms::limit_free_w
  double hinge_row[3];                       // kHinge: its axis in the child's frame (Fc a)
};

// A joint's limit rows as the lanes keep them: their count, then up to three directions in the
// child's frame, row by row (joint_limits.h's LimitRows without the excess)
inline constexpr int kRowFields = 10;
// A joint's limit error for one lane, computed by the scalar solver's own limit_error(): false
// when the joint is inside its limits, else the child's rotation vector in `error` and the limit
// functions past their bounds in `rows` (count 0 for a limit that has none).
// child_to_parent is q_c⁻¹ q_p (w, x, y, z).
using LimitError = bool (*)(const void* context, int joint, const double child_to_parent[4],
                            double error[3], double rows[kRowFields]);

// The limits' velocity pass, lane by lane with the scalar solver's own function
// (limit_velocities.cpp): one joint's part of the pass, for its rows, on its two segments, each
// given as its orientation (w, x, y, z) then v and ω (world); v and ω are changed in place
using HoldLimitRates = void (*)(const void* context, int joint, const double rows[kRowFields],
                                double parent[10], double child[10]);

// everything one step of a batch reads besides its state
struct Plan {
  int segments = 0, joints = 0;
  const SegmentTerms* segment = nullptr;
  const JointPlan* joint = nullptr;
  // the joints in the adjust pass's order from the batch's anchor (AnchorOrder::links)
  const int* order = nullptr;
  int links = 0;
  int pins = 0;
  const int* pin_segment = nullptr;  // shared by every lane of the batch
  int pin_offset = 0, lambda_offset = 0;
  int mark_offset = 0;  // kRowFields slots per joint: the rows its limit correction last found past
                        // their bounds in this substep (count 0: none), for the velocity pass
  double gravity[3] = {0, 0, 0};
  double air_rate = 0.0;  // step_drag_rate(air drag, h)
  int substeps = 1, iterations = 1;
  double h = 0.0;
  double joint_compliance = 0.0, limit_compliance = 0.0;
  bool derive_velocities = true;
  bool start_lever_arms = true;  // Settings::start_lever_arms
  bool limit_pass = true;        // the limits' velocity pass (restitution 0: the lanes' only one)
  LimitError limit_error = nullptr;
  HoldLimitRates hold_limit_rates = nullptr;
  const void* limit_context = nullptr;
};

// slots of a batch of this plan's model
inline int slot_count(int segments, int joints, int pins) {
  return segments * kBodyFields + pins * kPinFields + 6 * joints + 3 * pins + kRowFields * joints;
}

// one step of h·substeps on every lane of `slots` (32-byte aligned); returns a bit per lane that
// met a non-finite value at the end of some substep (its state is then not to be used)
unsigned step_xpbd_sse2(const Plan& plan, double* slots);
unsigned step_xpbd_avx2(const Plan& plan, double* slots);
unsigned step_xpbd_avx512(const Plan& plan, double* slots);
inline constexpr int kMostLanes = 8;

}  // namespace puppet::procedural::lanes
