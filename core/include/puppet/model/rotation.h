/// \file
/// Rotation helpers shared by every solver and metric: the exact exponential map and logarithm,
/// swing–twist decomposition, and a joint's relative rotation and limit violation.
#pragma once

#include <cmath>

#include "puppet/model/model.h"

namespace puppet {

/// Below this rotation angle (rad) exp and log use their Taylor series: the first omitted term is
/// < 1e-19 relative, below the rounding of libm's sin, cos and atan2. A step's rotations are
/// that small, so the solvers' inner loops (inlined from here) call no trigonometry for them.
inline constexpr double kSeriesAngle = 0.1;

/// cos(angle/2) and sin(angle/2)/angle of a rotation vector of squared angle `angle2`: the
/// exponential map's scalar part and the factor of its vector part
inline void exp_coefficients(double angle2, double* c, double* k) {
  if (angle2 < kSeriesAngle * kSeriesAngle) {
    /// series in x = (angle/2)²: no sqrt, sin or cos
    const double x = 0.25 * angle2;
    /// Horner in x with the coefficients folded at compile time (a division by a constant stays
    /// a division)
    *c = 1.0 + x * (-1.0 / 2 +
                    x * (1.0 / 24 + x * (-1.0 / 720 + x * (1.0 / 40320 + x * (-1.0 / 3628800)))));
    *k = 0.5 + x * (-1.0 / 12 + x * (1.0 / 240 + x * (-1.0 / 10080 + x * (1.0 / 725760))));
  } else {
    const double angle = std::sqrt(angle2);
    *c = std::cos(0.5 * angle);
    *k = std::sin(0.5 * angle) / angle;
  }
}

/// exp of a rotation vector (axis · angle) as a unit quaternion
inline Quaterniond quat_exp(const Vector3d& rotation_vector) {
  double c, k;
  exp_coefficients(rotation_vector.squaredNorm(), &c, &k);
  return Quaterniond(c, k * rotation_vector.x(), k * rotation_vector.y(), k * rotation_vector.z());
}

/// q ⊗ exp(r), written out without forming exp(r): (w c − k v·r, c v + k (w r + v × r))
inline Quaterniond times_exp(const Quaterniond& q, const Vector3d& r) {
  double c, k;
  exp_coefficients(r.squaredNorm(), &c, &k);
  const Vector3d v = q.vec();
  const Vector3d vector = c * v + k * (q.w() * r + v.cross(r));
  return Quaterniond(q.w() * c - k * v.dot(r), vector.x(), vector.y(), vector.z());
}

/// A product of unit quaternions is unit but for rounding (|q|² − 1 of order 1e-16). One Newton
/// step of 1/√n, q·(3 − n)/2 with n = |q|², makes it unit to rounding again without a square root
/// or a division. Only for such products: far from unit length it does not converge in one step.
inline Quaterniond renormalized(const Quaterniond& q) {
  return Quaterniond((1.5 - 0.5 * q.squaredNorm()) * q.coeffs());
}

/// exact logarithm, shortest arc: 2·atan2(|v|, w)·v̂ with the sign of w folded in
inline Vector3d quat_log(const Quaterniond& q) {
  const double sign = q.w() < 0.0 ? -1.0 : 1.0;
  const Vector3d v = sign * q.vec();
  const double w = sign * q.w();
  const double s2 = v.squaredNorm();
  /// small half-angles (s/w < tan(kSeriesAngle/2)): the series of atan(y)/y in y² = (s/w)²
  const double limit = 0.5 * kSeriesAngle;
  if (s2 < limit * limit * w * w) {
    const double inv_w = 1.0 / w;  ///< one division
    const double y2 = s2 * inv_w * inv_w;
    const double atan_ratio =
        1.0 -
        y2 * (1.0 / 3.0 -
              y2 * (1.0 / 5.0 -
                    y2 * (1.0 / 7.0 - y2 * (1.0 / 9.0 - y2 * (1.0 / 11.0 - y2 * (1.0 / 13.0))))));
    return (2.0 * atan_ratio * inv_w) * v;
  }
  const double s = std::sqrt(s2);
  if (s == 0.0) return Vector3d::Zero();  ///< only a zero quaternion gets here
  return (2.0 * std::atan2(s, w) / s) * v;
}
/// geodesic angle between two orientations (rad, in [0, π])
double angle_between(const Quaterniond& a, const Quaterniond& b);
/// a unit vector orthogonal to v
Vector3d any_orthogonal(const Vector3d& v);

/// q = swing ⊗ twist: twist about `axis` (unit), swing about an axis orthogonal to it
struct SwingTwist {
  Quaterniond swing;
  double twist_angle;                           ///< in (−π, π]
  Quaterniond twist = Quaterniond::Identity();  ///< exp(twist_angle·axis), w ≥ 0
};
SwingTwist decompose_swing_twist(const Quaterniond& q, const Vector3d& axis);

/// q ⊗ frame for a joint frame, without the product when the frame is exactly the identity (as
/// most are in a model whose segments rest along their joints' axes): the same value either way
inline Quaterniond times_frame(const Quaterniond& q, const Quaterniond& frame) {
  if (frame.w() == 1.0 && frame.x() == 0.0 && frame.y() == 0.0 && frame.z() == 0.0) return q;
  return q * frame;
}

/// q_rel = (joint frame seen from the parent)⁻¹ ⊗ (joint frame seen from the child)
inline Quaterniond joint_relative_rotation(const Joint& joint,
                                           const Quaterniond& parent_orientation,
                                           const Quaterniond& child_orientation) {
  return times_frame(parent_orientation, joint.frame_in_parent).conjugate() *
         times_frame(child_orientation, joint.frame_in_child);
}

/// the nearest relative rotation inside the joint's limits (hinge: angle about its axis, other
/// directions removed; ball: twist clamped, swing scaled radially onto the ellipse; fixed:
/// identity). Returns q_rel itself when it is inside.
Quaterniond clamp_to_limits(const Joint& joint, const Quaterniond& q_rel);

/// how far q_rel is outside the joint's limits (rad, 0 inside): the geodesic angle to the
/// clamped rotation
double limit_violation(const Joint& joint, const Quaterniond& q_rel);

}  // namespace puppet
