#include "jolt_box.h"

#include <algorithm>
#include <cmath>

#include "puppet/model/euler_box.h"

namespace puppet::compare {
namespace {

constexpr double kDeg = 180.0 / M_PI;
constexpr int kGrid = 13;  // points along each side of a face of either region

// the constraint frame's axes (columns) in the joint frame
Matrix3d frame_of(const JoltPyramid& p) {
  Matrix3d b;
  b.col(0) = Vector3d::Unit(p.x);
  b.col(1) = p.y_sign * Vector3d::Unit(p.y);
  b.col(2) = Vector3d::Unit(p.z);
  return b;
}

// the joint's relative rotation at pyramid angles (τ, y, z)
Quaterniond rotation_at(const JoltPyramid& p, const Vector3d& angles) {
  const double sy = std::sin(0.5 * angles[1]), cy = std::cos(0.5 * angles[1]);
  const double sz = std::sin(0.5 * angles[2]), cz = std::cos(0.5 * angles[2]);
  const Quaterniond swing = Quaterniond(cy * cz, 0.0, sy * cz, cy * sz).normalized();
  const Quaterniond in_frame = swing * Quaterniond(Eigen::AngleAxisd(angles[0], Vector3d::UnitX()));
  const Quaterniond b(frame_of(p));
  const Quaterniond q = b * in_frame * b.conjugate();
  return p.twist_first ? q.conjugate() : q;
}

// the pyramid angles (τ, y, z) of a joint's relative rotation, as Jolt decomposes it
Vector3d angles_of(const JoltPyramid& p, const Quaterniond& q_rel) {
  const Quaterniond b(frame_of(p));
  Quaterniond q = b.conjugate() * (p.twist_first ? q_rel.conjugate() : q_rel) * b;
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double norm = std::hypot(q.x(), q.w());
  const Quaterniond twist =
      norm > 0.0 ? Quaterniond(q.w() / norm, q.x() / norm, 0.0, 0.0) : Quaterniond::Identity();
  Quaterniond swing = q * twist.conjugate();
  if (swing.w() < 0.0) swing.coeffs() = -swing.coeffs();
  return {2.0 * std::atan2(twist.x(), twist.w()), 2.0 * std::atan2(swing.y(), swing.w()),
          2.0 * std::atan2(swing.z(), swing.w())};
}

// the points of a grid on each face of the box [lower, upper]
template <typename Visit>
void boundary(const double* lower, const double* upper, Visit&& visit) {
  for (int face = 0; face < 6; ++face) {
    const int k = face / 2;
    for (int i = 0; i < kGrid; ++i) {
      for (int j = 0; j < kGrid; ++j) {
        Vector3d a;
        a[k] = face % 2 ? upper[k] : lower[k];
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        a[u] = lower[u] + (upper[u] - lower[u]) * i / (kGrid - 1);
        a[v] = lower[v] + (upper[v] - lower[v]) * j / (kGrid - 1);
        visit(a);
      }
    }
  }
}

}  // namespace

JoltPyramid jolt_pyramid(const Joint& joint, bool twist_first) {
  JoltPyramid p;
  p.twist_first = twist_first;
  const auto& a = joint.box_order.axes;
  const Vector3d& lo = joint.box_lower;
  const Vector3d& hi = joint.box_upper;
  // twist last: R_Z(θ₀) R_Y(±θ₁) R_X(θ₂); first: the inverse, R_Z(−θ₂) R_Y(∓θ₁) R_X(−θ₀)
  p.x = twist_first ? a[0] : a[2];
  p.y = a[1];
  p.z = twist_first ? a[2] : a[0];
  p.y_sign = Vector3d::Unit(p.x).cross(Vector3d::Unit(p.y)).dot(Vector3d::Unit(p.z)) > 0 ? 1 : -1;
  const int angle_of[3] = {twist_first ? 0 : 2, 1, twist_first ? 2 : 0};  // τ, y, z
  for (int k = 0; k < 3; ++k) {
    const double sign = (twist_first ? -1.0 : 1.0) * (k == 1 ? p.y_sign : 1.0);
    const int i = angle_of[k];
    p.lower[k] = sign > 0 ? lo[i] : -hi[i];
    p.upper[k] = sign > 0 ? hi[i] : -lo[i];
  }
  boundary(p.lower, p.upper, [&](const Vector3d& angles) {
    const double excess = box_excess(joint.box_order, lo, hi, rotation_at(p, angles));
    p.beyond_deg = std::max(p.beyond_deg, kDeg * excess);
  });
  const double box_lower[3] = {lo[0], lo[1], lo[2]}, box_upper[3] = {hi[0], hi[1], hi[2]};
  boundary(box_lower, box_upper, [&](const Vector3d& angles) {
    const Vector3d t = angles_of(p, euler_rotation(joint.box_order, angles));
    for (int k = 0; k < 3; ++k) {
      p.cut_deg = std::max({p.cut_deg, kDeg * (p.lower[k] - t[k]), kDeg * (t[k] - p.upper[k])});
    }
  });
  return p;
}

JoltPyramid nearest_jolt_pyramid(const Joint& joint) {
  const JoltPyramid last = jolt_pyramid(joint, false);
  const JoltPyramid first = jolt_pyramid(joint, true);
  const auto gap = [](const JoltPyramid& p) { return std::max(p.beyond_deg, p.cut_deg); };
  return gap(first) < gap(last) ? first : last;
}

}  // namespace puppet::compare
