// Rotation helpers shared by every solver and metric: the exact exponential map and logarithm,
// swing–twist decomposition, and a joint's relative rotation and limit violation.
#pragma once

#include "puppet/model/model.h"

namespace puppet {

// exp of a rotation vector (axis · angle) as a unit quaternion
Quaterniond quat_exp(const Vector3d& rotation_vector);
// exact logarithm, shortest arc: 2·atan2(|v|, w)·v̂ with the sign of w folded in
Vector3d quat_log(const Quaterniond& q);
// geodesic angle between two orientations (rad, in [0, π])
double angle_between(const Quaterniond& a, const Quaterniond& b);
// a unit vector orthogonal to v
Vector3d any_orthogonal(const Vector3d& v);

// q = swing ⊗ twist: twist about `axis` (unit), swing about an axis orthogonal to it
struct SwingTwist {
  Quaterniond swing;
  double twist_angle;  // in (−π, π]
};
SwingTwist decompose_swing_twist(const Quaterniond& q, const Vector3d& axis);

// q_rel = (joint frame seen from the parent)⁻¹ ⊗ (joint frame seen from the child)
Quaterniond joint_relative_rotation(const Joint& joint, const Quaterniond& parent_orientation,
                                    const Quaterniond& child_orientation);

// the nearest relative rotation inside the joint's limits (hinge: angle about its axis, other
// directions removed; ball: twist clamped, swing scaled radially onto the ellipse; fixed:
// identity). Returns q_rel itself when it is inside.
Quaterniond clamp_to_limits(const Joint& joint, const Quaterniond& q_rel);

// how far q_rel is outside the joint's limits (rad, 0 inside): the geodesic angle to the
// clamped rotation
double limit_violation(const Joint& joint, const Quaterniond& q_rel);

}  // namespace puppet
