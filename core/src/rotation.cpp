#include "puppet/model/rotation.h"

#include "puppet/model/euler_box.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace puppet {

double angle_between(const Quaterniond& a, const Quaterniond& b) {
  return quat_log(a.conjugate() * b).norm();
}

Vector3d any_orthogonal(const Vector3d& v) {
  const Vector3d other = std::abs(v.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  return v.cross(other).normalized();
}

namespace {

// q = swing ⊗ twist about a unit axis, the twist on its shortest arc (w ≥ 0), with the twist's
// half-angle sine: its half-angle lies in [−π/2, π/2], where the sine grows with the angle, so a
// limit is a comparison with the sine of the half-limit and needs no atan2
struct ShortTwist {
  Quaterniond swing, twist;
  double half_sin = 0.0;  // sin(angle / 2)
};

// the twist alone, as (w, p): cos and sin of its half-angle, w ≥ 0; false for a half turn of
// swing, which has no twist
bool twist_of(const Quaterniond& q, const Vector3d& axis, double* w, double* p) {
  const double projection = q.vec().dot(axis);
  const double norm2 = q.w() * q.w() + projection * projection;
  if (norm2 < 1e-24) return false;
  // one square root and one division; the sign of q.w() folded in (shortest arc)
  const double scale = (q.w() < 0.0 ? -1.0 : 1.0) / std::sqrt(norm2);
  *w = scale * q.w();
  *p = scale * projection;
  return true;
}

ShortTwist split_twist(const Quaterniond& q, const Vector3d& axis) {
  double w, p;
  if (!twist_of(q, axis, &w, &p)) return {q, Quaterniond::Identity(), 0.0};
  const Quaterniond twist(w, p * axis.x(), p * axis.y(), p * axis.z());
  return {q * twist.conjugate(), twist, p};
}

}  // namespace

SwingTwist decompose_swing_twist(const Quaterniond& q, const Vector3d& axis) {
  const ShortTwist st = split_twist(q, axis);
  // the angle of the twist as q carries it (its w of q's sign), wrapped into (−π, π]
  const double sign = q.w() < 0.0 ? -1.0 : 1.0;
  double angle = 2.0 * std::atan2(sign * st.half_sin, sign * st.twist.w());
  if (angle > M_PI) angle -= 2.0 * M_PI;
  if (angle <= -M_PI) angle += 2.0 * M_PI;
  return {st.swing, angle, st.twist};
}

namespace {

// the rotation by a limit angle about an axis, from the half-angle's sine and cosine
Quaterniond about_axis(const Vector3d& axis, double half_sin, double half_cos) {
  return Quaterniond(half_cos, half_sin * axis.x(), half_sin * axis.y(), half_sin * axis.z());
}

// q = swing ⊗ twist about z, both read from q's components without a product. With
// n² = w² + z² and s = (x w − y z, y w + x z):
//   twist (shortest arc)  = (|w|, 0, 0, sign(w) z) / n
//   swing (w ≥ 0)         = (n, s_x, s_y, 0) / n
// (n = 0 is half a turn of swing: no twist, and the swing is q on its w ≥ 0 arc.)
// Twist: |angle| ≤ twist limit, clamped onto ±limit. Swing: its vector (angle φ · unit direction
// u = s/|s|) lies in the frame's xy plane; the ellipse has half-angles a = swing_x and b = swing_y
// about those axes, so along u the largest swing is φ_max = 1/√E with E = u_x²/a² + u_y²/b².
// Inside ⟺ φ/2 ≤ α = φ_max/2; with tan(φ/2) = |s|/n² that is |s| cos α ≤ n² sin α, and outside
// the clamped swing is (cos α, sin α · u): one sincos, no atan2. The swing's test reads s alone,
// so it never waits for the square root and division that normalise the twist.
Quaterniond clamp_ball(const Joint& joint, const Quaterniond& q_rel) {
  const double w = q_rel.w(), x = q_rel.x(), y = q_rel.y(), z = q_rel.z();
  const bool elliptic = joint.swing_x > 0.0 && joint.swing_y > 0.0;
  const double n2 = w * w + z * z;
  double sx, sy, swing_w;  // the swing's vector and w, both scaled by n
  Quaterniond swing, twist = Quaterniond::Identity();
  if (n2 >= 1e-24) {
    sx = x * w - y * z;
    sy = y * w + x * z;
    swing_w = n2;
    // surely inside, decided without trigonometry: the twist angle 2·atan(|z|/|w|) and the swing
    // angle 2·atan(|s|/n²) are at most 2|z|/|w| and 2|s|/n² (atan y ≤ y); when those bounds are
    // inside, so are the angles: (2|s|/n²)² E ≤ 1 ⟺ 4 (s_x²/a² + s_y²/b²) ≤ n⁴
    if (elliptic && 2.0 * std::abs(z) <= joint.twist * std::abs(w)) {
      const double ex = sx / joint.swing_x, ey = sy / joint.swing_y;
      if (4.0 * (ex * ex + ey * ey) <= n2 * n2) return q_rel;
    }
    const double inv_n = 1.0 / std::sqrt(n2);
    twist = Quaterniond(std::abs(w) * inv_n, 0.0, 0.0, (w < 0.0 ? -z : z) * inv_n);
    swing = Quaterniond(n2 * inv_n, sx * inv_n, sy * inv_n, 0.0);
  } else {
    const double sign = w < 0.0 ? -1.0 : 1.0;
    sx = sign * x;
    sy = sign * y;
    swing_w = sign * w;
    swing = Quaterniond(swing_w, sx, sy, 0.0);
  }
  bool changed = false;

  if (std::abs(twist.z()) > joint.twist_half_sin) {
    twist = about_axis(Vector3d::UnitZ(), std::copysign(joint.twist_half_sin, twist.z()),
                       joint.twist_half_cos);
    changed = true;
  }

  const double s2 = sx * sx + sy * sy;
  if (s2 > 0.0 && elliptic) {
    const double ex = sx / joint.swing_x, ey = sy / joint.swing_y;
    const double alpha = 0.5 * std::sqrt(s2 / (ex * ex + ey * ey));
    if (alpha < 0.5 * M_PI) {
      const double sin_alpha = std::sin(alpha), cos_alpha = std::cos(alpha);
      const double s_norm = std::sqrt(s2);
      if (s_norm * cos_alpha > swing_w * sin_alpha) {
        const double k = sin_alpha / s_norm;
        swing = Quaterniond(cos_alpha, k * sx, k * sy, 0.0);
        changed = true;
      }
    }
  } else if (s2 > 0.0) {
    // a zero half-angle removes that direction entirely
    const Vector3d swing_vector = quat_log(swing);
    const Vector3d clamped(
        joint.swing_x > 0.0 ? std::clamp(swing_vector.x(), -joint.swing_x, joint.swing_x) : 0.0,
        joint.swing_y > 0.0 ? std::clamp(swing_vector.y(), -joint.swing_y, joint.swing_y) : 0.0,
        0.0);
    if (clamped.x() != swing_vector.x() || clamped.y() != swing_vector.y()) {
      swing = quat_exp(clamped);
      changed = true;
    }
  }
  if (!changed) return q_rel;
  return swing * twist;
}

Quaterniond clamp_hinge(const Joint& joint, const Quaterniond& q_rel) {
  // other directions are not allowed at all: keep only the rotation about the axis (the twist
  // itself when its angle is in range), else the nearer end of the range
  double half_cos = 1.0, half_sin = 0.0;  // a half turn of swing: no twist
  twist_of(q_rel, joint.hinge_axis, &half_cos, &half_sin);
  if (half_sin < joint.lower_half_sin) {
    return about_axis(joint.hinge_axis, joint.lower_half_sin, joint.lower_half_cos);
  }
  if (half_sin > joint.upper_half_sin) {
    return about_axis(joint.hinge_axis, joint.upper_half_sin, joint.upper_half_cos);
  }
  return about_axis(joint.hinge_axis, half_sin, half_cos);
}

}  // namespace

Quaterniond clamp_to_limits(const Joint& joint, const Quaterniond& q_rel) {
  // derive_limit_terms() was called after the limits were last set
  assert(joint.type == JointType::kSlide ||
         (std::abs(joint.twist_half_sin - std::sin(0.5 * joint.twist)) < 1e-12 &&
          std::abs(joint.lower_half_sin - std::sin(0.5 * joint.lower)) < 1e-12 &&
          std::abs(joint.upper_half_sin - std::sin(0.5 * joint.upper)) < 1e-12));
  switch (joint.type) {
    case JointType::kBall:
      return joint.ball_limit == BallLimit::kEulerBox
                 ? clamp_to_box(joint.box_order, joint.box_lower, joint.box_upper, q_rel)
                 : clamp_ball(joint, q_rel);
    case JointType::kHinge:
      return clamp_hinge(joint, q_rel);
    case JointType::kFixed:
    case JointType::kSlide:  // it turns not at all; its range is a distance (joint_limits.h)
      return Quaterniond::Identity();
  }
  return q_rel;
}

void derive_limit_terms(Joint& joint) {
  if (joint.type == JointType::kSlide) return;  // its range is a distance, not an angle
  joint.twist_half_sin = std::sin(0.5 * joint.twist);
  joint.twist_half_cos = std::cos(0.5 * joint.twist);
  joint.lower_half_sin = std::sin(0.5 * joint.lower);
  joint.lower_half_cos = std::cos(0.5 * joint.lower);
  joint.upper_half_sin = std::sin(0.5 * joint.upper);
  joint.upper_half_cos = std::cos(0.5 * joint.upper);
}

double limit_violation(const Joint& joint, const Quaterniond& q_rel) {
  // a box in its own terms: the most an angle lies past its range
  if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox) {
    return box_excess(joint.box_order, joint.box_lower, joint.box_upper, q_rel);
  }
  return angle_between(q_rel, clamp_to_limits(joint, q_rel));
}

}  // namespace puppet
