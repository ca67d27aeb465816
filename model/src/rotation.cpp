#include "puppet/model/rotation.h"

#include <algorithm>
#include <cmath>

namespace puppet {

double angle_between(const Quaterniond& a, const Quaterniond& b) {
  return quat_log(a.conjugate() * b).norm();
}

Vector3d any_orthogonal(const Vector3d& v) {
  const Vector3d other = std::abs(v.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  return v.cross(other).normalized();
}

SwingTwist decompose_swing_twist(const Quaterniond& q, const Vector3d& axis) {
  const double projection = q.vec().dot(axis);
  Quaterniond twist(q.w(), projection * axis.x(), projection * axis.y(), projection * axis.z());
  const double norm = twist.norm();
  if (norm < 1e-12) {
    // a half turn of swing: the twist is undefined, take none
    return {q, 0.0};
  }
  twist.coeffs() /= norm;
  double angle = 2.0 * std::atan2(projection / norm, twist.w());
  if (angle > M_PI) angle -= 2.0 * M_PI;
  if (angle <= -M_PI) angle += 2.0 * M_PI;
  const Quaterniond swing = q * twist.conjugate();
  if (twist.w() < 0.0) twist.coeffs() *= -1.0;  // the same rotation, on the shortest arc
  return {swing, angle, twist};
}

Quaterniond joint_relative_rotation(const Joint& joint, const Quaterniond& parent_orientation,
                                    const Quaterniond& child_orientation) {
  return (parent_orientation * joint.frame_in_parent).conjugate() *
         (child_orientation * joint.frame_in_child);
}

namespace {

// Surely inside the limits, decided without trigonometry: the twist angle 2·atan(|p|/|w|) and
// the swing angle 2·atan(|v_s|/w_s) are at most 2|p|/|w| and 2|v_s|/w_s (atan y ≤ y), so when
// those bounds are inside, so are the angles. It never says inside when the exact test would not.
bool surely_inside_ball(const Joint& joint, const Quaterniond& q_rel) {
  const double w = std::abs(q_rel.w()), p = std::abs(q_rel.z());
  if (!(2.0 * p <= joint.twist * w)) return false;
  if (!(joint.swing_x > 0.0 && joint.swing_y > 0.0)) return false;
  // swing = q ⊗ twist⁻¹ with twist = (w, 0, 0, z)/n: w_s = n, v_s = (x w − y z, y w + x z, 0)/n
  const double x = q_rel.x(), y = q_rel.y(), z = q_rel.z();
  const double n2 = q_rel.w() * q_rel.w() + z * z;
  const double sx = x * q_rel.w() - y * z, sy = y * q_rel.w() + x * z;  // n·v_s
  // (2|v_s|/w_s)² (n_x²/a² + n_y²/b²) ≤ 1  ⟺  4 (sx²/a² + sy²/b²) ≤ n⁴
  const double ex = sx / joint.swing_x, ey = sy / joint.swing_y;
  return 4.0 * (ex * ex + ey * ey) <= n2 * n2;
}

Quaterniond clamp_ball(const Joint& joint, const Quaterniond& q_rel) {
  if (surely_inside_ball(joint, q_rel)) return q_rel;
  const SwingTwist st = decompose_swing_twist(q_rel, Vector3d::UnitZ());
  bool changed = false;

  // twist: |angle| ≤ twist limit
  double twist = st.twist_angle;
  if (std::abs(twist) > joint.twist) {
    twist = std::copysign(joint.twist, twist);
    changed = true;
  }

  // swing vector (angle · axis) lies in the frame's xy plane; the ellipse has half-angles
  // swing_x and swing_y about those axes; scale radially onto it when outside
  Vector3d swing_vector = quat_log(st.swing);
  const double sx = swing_vector.x(), sy = swing_vector.y();
  const double ex = joint.swing_x > 0.0 ? sx / joint.swing_x : (sx == 0.0 ? 0.0 : INFINITY);
  const double ey = joint.swing_y > 0.0 ? sy / joint.swing_y : (sy == 0.0 ? 0.0 : INFINITY);
  const double ellipse = std::hypot(ex, ey);
  if (ellipse > 1.0) {
    if (std::isinf(ellipse)) {
      // a zero half-angle removes that direction entirely
      swing_vector =
          Vector3d(joint.swing_x > 0.0 ? std::clamp(sx, -joint.swing_x, joint.swing_x) : 0.0,
                   joint.swing_y > 0.0 ? std::clamp(sy, -joint.swing_y, joint.swing_y) : 0.0, 0.0);
    } else {
      swing_vector = Vector3d(sx, sy, 0.0) / ellipse;
    }
    changed = true;
  }
  if (!changed) return q_rel;
  const Vector3d swing_xy(swing_vector.x(), swing_vector.y(), 0.0);
  return quat_exp(swing_xy) * quat_exp(Vector3d(0, 0, twist));
}

Quaterniond clamp_hinge(const Joint& joint, const Quaterniond& q_rel) {
  const SwingTwist st = decompose_swing_twist(q_rel, joint.hinge_axis);
  // other directions are not allowed at all: keep only the rotation about the axis (the twist
  // itself when its angle is in range; no need to rebuild it from the angle)
  if (st.twist_angle >= joint.lower && st.twist_angle <= joint.upper) return st.twist;
  const double angle = std::clamp(st.twist_angle, joint.lower, joint.upper);
  return quat_exp(angle * joint.hinge_axis);
}

}  // namespace

Quaterniond clamp_to_limits(const Joint& joint, const Quaterniond& q_rel) {
  switch (joint.type) {
    case JointType::kBall:
      return clamp_ball(joint, q_rel);
    case JointType::kHinge:
      return clamp_hinge(joint, q_rel);
    case JointType::kFixed:
      return Quaterniond::Identity();
  }
  return q_rel;
}

double limit_violation(const Joint& joint, const Quaterniond& q_rel) {
  return angle_between(q_rel, clamp_to_limits(joint, q_rel));
}

}  // namespace puppet
