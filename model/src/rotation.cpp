#include "puppet/model/rotation.h"

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

// the rotation by a limit angle about an axis, from the half-angle's sine and cosine
Quaterniond about_axis(const Vector3d& axis, double half_sin, double half_cos) {
  return Quaterniond(half_cos, half_sin * axis.x(), half_sin * axis.y(), half_sin * axis.z());
}

Quaterniond clamp_ball(const Joint& joint, const Quaterniond& q_rel) {
  if (surely_inside_ball(joint, q_rel)) return q_rel;
  const ShortTwist st = split_twist(q_rel, Vector3d::UnitZ());
  bool changed = false;

  // twist: |angle| ≤ twist limit, clamped onto ±limit
  Quaterniond twist = st.twist;
  if (std::abs(st.half_sin) > joint.twist_half_sin) {
    twist = about_axis(Vector3d::UnitZ(), std::copysign(joint.twist_half_sin, st.half_sin),
                       joint.twist_half_cos);
    changed = true;
  }

  // swing: its vector (angle φ · unit direction n) lies in the frame's xy plane; the ellipse has
  // half-angles a = swing_x and b = swing_y about those axes, so along n the largest swing is
  // φ_max = 1/√E with E = n_x²/a² + n_y²/b². Inside ⟺ φ/2 ≤ α = φ_max/2; with the swing on its
  // shortest arc (w ≥ 0), tan(φ/2) = |v|/w, so inside ⟺ |v| cos α ≤ w sin α, and outside the
  // clamped swing is (cos α, sin α · n): one sincos, no atan2
  Quaterniond swing = st.swing;
  if (swing.w() < 0.0) swing.coeffs() *= -1.0;
  const double v = std::sqrt(swing.x() * swing.x() + swing.y() * swing.y());
  if (v > 0.0 && joint.swing_x > 0.0 && joint.swing_y > 0.0) {
    const double nx = swing.x() / v, ny = swing.y() / v;
    const double ex = nx / joint.swing_x, ey = ny / joint.swing_y;
    const double alpha = 0.5 / std::sqrt(ex * ex + ey * ey);
    if (alpha < 0.5 * M_PI) {
      const double sin_alpha = std::sin(alpha), cos_alpha = std::cos(alpha);
      if (v * cos_alpha > swing.w() * sin_alpha) {
        swing = Quaterniond(cos_alpha, sin_alpha * nx, sin_alpha * ny, 0.0);
        changed = true;
      }
    }
  } else if (v > 0.0) {
    // a zero half-angle removes that direction entirely
    const Vector3d swing_vector = quat_log(swing);
    const double sx = swing_vector.x(), sy = swing_vector.y();
    const Vector3d clamped(
        joint.swing_x > 0.0 ? std::clamp(sx, -joint.swing_x, joint.swing_x) : 0.0,
        joint.swing_y > 0.0 ? std::clamp(sy, -joint.swing_y, joint.swing_y) : 0.0, 0.0);
    if (clamped.x() != sx || clamped.y() != sy) {
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
  assert(std::abs(joint.twist_half_sin - std::sin(0.5 * joint.twist)) < 1e-12 &&
         std::abs(joint.lower_half_sin - std::sin(0.5 * joint.lower)) < 1e-12 &&
         std::abs(joint.upper_half_sin - std::sin(0.5 * joint.upper)) < 1e-12);
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

void derive_limit_terms(Joint& joint) {
  joint.twist_half_sin = std::sin(0.5 * joint.twist);
  joint.twist_half_cos = std::cos(0.5 * joint.twist);
  joint.lower_half_sin = std::sin(0.5 * joint.lower);
  joint.lower_half_cos = std::cos(0.5 * joint.lower);
  joint.upper_half_sin = std::sin(0.5 * joint.upper);
  joint.upper_half_cos = std::cos(0.5 * joint.upper);
}

double limit_violation(const Joint& joint, const Quaterniond& q_rel) {
  return angle_between(q_rel, clamp_to_limits(joint, q_rel));
}

}  // namespace puppet
