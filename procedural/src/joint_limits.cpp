// Joint limits (seed eq. 4). A joint's relative rotation q_rel = (parent frame)⁻¹(child frame)
// is clamped to its limits (clamp_to_limits, model/rotation.cpp: a ball's swing cone and twist, a
// hinge's angle); the moved side is then turned so that its relative rotation is the clamped one.
// A cheap test first: a rotation by less than the smallest limit angle is surely inside, and
// |w(q_rel)| tells it from the two orientations without forming q_rel (JointTerms::frame_shift).
#include <algorithm>
#include <cmath>

#include "geometry.h"
#include "joint_limits.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/rotation.h"

namespace puppet::procedural {

double limit_free_w(const Joint& joint) {
  if (joint.type != JointType::kBall) return 2.0;  // a hinge removes every other direction
  // a box's Euler angles are not bounded by the rotation's angle near gimbal lock: always test
  if (joint.ball_limit == BallLimit::kEulerBox) return 2.0;
  // a rotation by ρ has twist ≤ ρ and swing ≤ ρ: inside when ρ is below every half-angle
  const double free_angle = std::min({joint.twist, joint.swing_x, joint.swing_y});
  return free_angle > 0.0 ? std::cos(0.5 * free_angle) : 2.0;
}

BoxTest make_box_test(const Joint& joint) {
  BoxTest box;
  if (joint.type != JointType::kBall || joint.ball_limit != BallLimit::kEulerBox) return box;
  for (int k = 0; k < 3; ++k) {
    const double lower = joint.box_lower[k], upper = joint.box_upper[k];
    if (!(lower <= 0.0 && upper >= 0.0)) return box;
    box.lower_cos[k] = std::cos(lower);
    box.lower_sin[k] = std::sin(lower);
    box.upper_cos[k] = std::cos(upper);
    box.upper_sin[k] = std::sin(upper);
    box.wide[k] = upper - lower > M_PI;
  }
  if (joint.box_lower[1] < -kMaxBoxMiddle || joint.box_upper[1] > kMaxBoxMiddle) return box;
  const auto& axes = joint.box_order.axes;
  box.axes = axes;
  // (i, j, k) = (0, 1, 2) and its rotations are cyclic
  box.sign = (axes[1] - axes[0] + 3) % 3 == 1 ? 1.0 : -1.0;
  box.enabled = true;
  return box;
}

namespace {

// the direction (c, s) = |d| (cos θ, sin θ) inside [lower + margin, upper − margin] of range k
bool direction_inside(const BoxTest& box, int k, double c, double s) {
  const double margin = kBoxMargin * (std::abs(c) + std::abs(s));         // ≥ |d| sin(kBoxMargin)
  const double from_lower = box.lower_cos[k] * s - box.lower_sin[k] * c;  // |d| sin(θ − lower)
  const double to_upper = box.upper_sin[k] * c - box.upper_cos[k] * s;    // |d| sin(upper − θ)
  // a range of at most a half turn: both ends on the right side; a wider one: either
  if (box.wide[k]) return from_lower >= margin || to_upper >= margin;
  return from_lower >= margin && to_upper >= margin;
}

}  // namespace

bool surely_inside_box(const BoxTest& box, const Quaterniond& q_rel) {
  const Matrix3d r = q_rel.toRotationMatrix();
  const int i = box.axes[0], j = box.axes[1], k = box.axes[2];
  const double middle_sin = box.sign * r(i, k);
  if (!(middle_sin <= box.upper_sin[1] - kBoxMargin &&
        middle_sin >= box.lower_sin[1] + kBoxMargin)) {
    return false;
  }
  return direction_inside(box, 0, r(k, k), -box.sign * r(j, k)) &&
         direction_inside(box, 2, r(i, i), -box.sign * r(i, j));
}

bool limited_orientation(const Joint& joint, const JointTerms& terms, bool b_is_child,
                         const Quaterniond& q_a, const Quaterniond& q_b, Quaterniond* q_b_limited) {
  const Quaterniond& q_parent = b_is_child ? q_a : q_b;
  const Quaterniond& q_child = b_is_child ? q_b : q_a;
  // |w(q_rel)| = |q_p · (q_c ⊗ frame_shift)|: surely inside without forming q_rel
  if (terms.limit_free_w < 1.0 &&
      std::abs(q_parent.coeffs().dot(times_frame(q_child, terms.frame_shift).coeffs())) >
          terms.limit_free_w) {
    return false;
  }
  const Quaterniond q_rel = joint_relative_rotation(joint, q_parent, q_child);
  if (terms.box.enabled && surely_inside_box(terms.box, q_rel)) return false;
  const Quaterniond clamped = clamp_to_limits(joint, q_rel);
  if (clamped.coeffs() == q_rel.coeffs()) return false;
  // rebuild b from a and the clamped q_rel (inverted when b is the parent), never from a
  // re-decomposed inverse
  *q_b_limited = b_is_child
                     ? times_frame(times_frame(q_a, joint.frame_in_parent) * clamped,
                                   joint.frame_in_child.conjugate())
                     : times_frame(times_frame(q_a, joint.frame_in_child) * clamped.conjugate(),
                                   joint.frame_in_parent.conjugate());
  return true;
}

namespace {

// how far past its bounds a joint may be for the limit functions' linear correction (rad, 11°)
constexpr double kRowsReach = 0.2;

// The limit functions' correction: the smallest relative turn d (child's frame) in the metric of
// the two sides' inverse inertias W = I_c⁻¹ + R I_p⁻¹ Rᵀ that takes every violated function
// back to its bound at first order, U d = −excess, i.e. d = W Uᵀ (U W Uᵀ)⁻¹ (−excess): the violated
// faces solved together, each along its own gradient. A shared correction then turns the two
// sides by W⁻¹ d through their inverse inertias, which is Uᵀ λ: XPBD's angular rows. A box's
// per-angle clamp instead moves the rotation to the clamped angles, which near gimbal lock (the
// middle angle near ±90°, where the first and last angles turn about nearly one axis) is a far
// turn along a direction the next correction undoes: measured, a shoulder at (108°, 77°, 109°)
// against a ±80° last angle left 29° past after four sweeps.
bool limit_functions_error(const JointTerms& terms, const Quaterniond& child_to_parent,
                           const Quaterniond& q_rel, const Joint& joint, Vector3d* error,
                           double* reach, LimitRows& rows) {
  rows = limit_rows(joint, q_rel, 0.0);
  if (rows.count == 0) return false;
  *reach = rows.excess.head(rows.count).maxCoeff();
  const Matrix3d rotation = child_to_parent.toRotationMatrix();
  Matrix3d w = rotation * terms.inv_inertia[0].asDiagonal() * rotation.transpose();
  w.diagonal() += terms.inv_inertia[1];
  Matrix3d a = Matrix3d::Identity();  // U W Uᵀ over the rows, padded
  Vector3d b = Vector3d::Zero();
  for (int k = 0; k < rows.count; ++k) {
    const Vector3d wu = w * rows.directions.row(k).transpose();
    for (int l = 0; l < rows.count; ++l) a(l, k) = rows.directions.row(l).dot(wu);
    b(k) = -rows.excess(k);
  }
  // two faces whose gradients are nearly parallel (the first and last angles at gimbal lock) make
  // U W Uᵀ nearly singular: a relative 1e-9 on its diagonal keeps the solve finite
  a.diagonal().array() += 1e-9 * a.trace();
  const Vector3d lambda = solve3(a, b);
  Vector3d turn = Vector3d::Zero();
  for (int k = 0; k < rows.count; ++k) turn += lambda(k) * rows.directions.row(k).transpose();
  *error = w * turn;
  return true;
}

}  // namespace

bool limit_error(const Joint& joint, const JointTerms& terms, const Quaterniond& child_to_parent,
                 Vector3d* error, LimitRows* rows, bool functions) {
  if (!may_reach_limit(terms, child_to_parent)) return false;
  // q_rel = Fp⁻¹ q_p⁻¹ q_c Fc = (q_c⁻¹ q_p Fp)⁻¹ Fc
  const Quaterniond parent_frame = times_frame(child_to_parent, joint.frame_in_parent);
  const Quaterniond q_rel = times_frame(parent_frame.conjugate(), joint.frame_in_child);
  if (terms.box.enabled && surely_inside_box(terms.box, q_rel)) return false;
  if (functions && has_limit_functions(joint)) {
    // the functions' first-order turn within kRowsReach of the bounds; beyond it (a cone left
    // tens of degrees behind, a random pose) the linearisation can turn the wrong way, and the
    // clamp's turn, bounded by the violation, is taken
    double reach = 0.0;  // the largest excess
    LimitRows past;
    if (!limit_functions_error(terms, child_to_parent, q_rel, joint, error, &reach, past)) {
      return false;
    }
    if (rows) *rows = past;
    if (reach <= kRowsReach) return true;
  }
  const Quaterniond clamped = clamp_to_limits(joint, q_rel);
  if (clamped.coeffs() == q_rel.coeffs()) return false;
  // the limited child is q_p Fp clamped Fc⁻¹, and q_c⁻¹ times it is q_c⁻¹ q_p Fp clamped Fc⁻¹
  *error = quat_log(times_frame(parent_frame * clamped, joint.frame_in_child.conjugate()));
  return true;
}

Quaterniond limit_correction(const Joint& joint, const JointTerms& terms, bool b_is_child,
                             const Quaterniond& q_a, const Quaterniond& q_b) {
  Quaterniond q_b_limited;
  if (!limited_orientation(joint, terms, b_is_child, q_a, q_b, &q_b_limited)) {
    return Quaterniond::Identity();
  }
  return (q_b_limited * q_b.conjugate()).normalized();
}

namespace {

// ∂(w, x, y, z)/∂δ of q exp(δ) at δ = 0: the components of ½ q ⊗ (0, δ)
Eigen::Matrix<double, 4, 3> quaternion_rates(const Quaterniond& q) {
  const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
  Eigen::Matrix<double, 4, 3> rates;
  rates << -x, -y, -z,  //
      w, -z, y,         //
      z, w, -x,         //
      -y, x, w;
  return 0.5 * rates;
}

// With n² = w² + z², ρ² = x² + y² and s = (x w − y z, y w + x z) (decompose_swing_twist's
// reading): the twist is 2 atan2(z, w), the swing's angle 2 atan2(ρ, n), its direction ψ the
// angle of s; the ellipse's half-angle in direction ψ is r = (cos²ψ/a² + sin²ψ/b²)^(−1/2), and
// dr/dψ = r³ cos ψ sin ψ (1/a² − 1/b²)
BallExcess swing_twist_excess(const Joint& joint, const Quaterniond& q_rel) {
  const SwingTwist parts = decompose_swing_twist(q_rel, Vector3d::UnitZ());
  const Vector3d swing = quat_log(parts.swing);
  const double angle = swing.norm();
  const double a = joint.swing_x, b = joint.swing_y;
  BallExcess out;
  out.gradients.setZero();
  out.excess << std::abs(parts.twist_angle) - joint.twist, -std::min(a, b), -1.0;
  const Eigen::Matrix<double, 4, 3> dq = quaternion_rates(q_rel);
  const double w = q_rel.w(), x = q_rel.x(), y = q_rel.y(), z = q_rel.z();
  const double n2 = w * w + z * z, rho2 = x * x + y * y;
  if (n2 > 0.0) {
    const double sign = parts.twist_angle < 0.0 ? -1.0 : 1.0;
    out.gradients.row(0) = sign * 2.0 * (w * dq.row(3) - z * dq.row(0)) / n2;
  }
  if (angle > 0.0) {
    const double ex = swing.x() / angle, ey = swing.y() / angle;
    const double ux = ex / a, uy = ey / b;
    const double r = 1.0 / std::sqrt(ux * ux + uy * uy);
    out.excess(1) = angle - r;
    const double n = std::sqrt(n2), rho = std::sqrt(rho2);
    if (n > 0.0 && rho > 0.0) {
      const Eigen::RowVector3d d_rho = (x * dq.row(1) + y * dq.row(2)) / rho;
      const Eigen::RowVector3d d_n = (w * dq.row(0) + z * dq.row(3)) / n;
      const Eigen::RowVector3d d_angle = 2.0 * (n * d_rho - rho * d_n) / (n2 + rho2);
      const double sx = x * w - y * z, sy = y * w + x * z;
      const Eigen::RowVector3d d_sx = w * dq.row(1) + x * dq.row(0) - z * dq.row(2) - y * dq.row(3);
      const Eigen::RowVector3d d_sy = w * dq.row(2) + y * dq.row(0) + z * dq.row(1) + x * dq.row(3);
      const Eigen::RowVector3d d_psi = (sx * d_sy - sy * d_sx) / (sx * sx + sy * sy);
      const double dr_dpsi = r * r * r * ex * ey * (1.0 / (a * a) - 1.0 / (b * b));
      out.gradients.row(1) = d_angle - dr_dpsi * d_psi;
    }
  }
  return out;
}

}  // namespace

BallExcess ball_excess(const Joint& joint, const Quaterniond& q_rel) {
  if (joint.ball_limit != BallLimit::kEulerBox) return swing_twist_excess(joint, q_rel);
  // each angle's excess, its gradient ± as the angle is above or below its range
  const Vector3d angles = euler_angles(joint.box_order, q_rel);
  const Vector3d above = angles - joint.box_upper, below = joint.box_lower - angles;
  BallExcess out{above.cwiseMax(below), euler_gradients(joint.box_order, angles)};
  for (int k = 0; k < 3; ++k) {
    if (below(k) > above(k)) out.gradients.row(k) = -out.gradients.row(k);
  }
  return out;
}

LimitRows limit_rows(const Joint& joint, const Quaterniond& q_rel, double above) {
  LimitRows rows;
  const auto add = [&](const Vector3d& direction, double excess) {
    rows.directions.row(rows.count) = (joint.frame_in_child * direction).transpose();
    rows.excess(rows.count) = excess;
    ++rows.count;
  };
  switch (joint.type) {
    case JointType::kBall: {
      if (!has_limit_functions(joint)) break;
      const BallExcess limit = ball_excess(joint, q_rel);
      for (int k = 0; k < 3; ++k) {
        if (limit.excess(k) > above) add(limit.gradients.row(k).transpose(), limit.excess(k));
      }
      break;
    }
    case JointType::kHinge: {
      const double angle = decompose_swing_twist(q_rel, joint.hinge_axis).twist_angle;
      if (angle - joint.upper > above) add(joint.hinge_axis, angle - joint.upper);
      if (joint.lower - angle > above) add(-joint.hinge_axis, joint.lower - angle);
      break;
    }
    case JointType::kFixed:
    case JointType::kSlide:  // no limit on a turn (none is free); a slide's range is held with
      break;                 // its point (two_sided.cpp, tree.cpp)
  }
  return rows;
}

}  // namespace puppet::procedural
