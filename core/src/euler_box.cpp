#include "puppet/model/euler_box.h"

#include <algorithm>
#include <cstdio>
#include <unsupported/Eigen/EulerAngles>

namespace puppet {
namespace {

// Eigen's EulerSystem is a compile-time order: one instance per Tait-Bryan order, chosen at run
// time. F is called with the EulerAngles type of the order.
template <typename F>
auto with_system(const EulerOrder& order, F&& f) {
  using Eigen::EulerSystem;
  constexpr int X = Eigen::EULER_X, Y = Eigen::EULER_Y, Z = Eigen::EULER_Z;
  const auto& a = order.axes;
  if (a == std::array<int, 3>{0, 1, 2})
    return f(Eigen::EulerAngles<double, EulerSystem<X, Y, Z>>());
  if (a == std::array<int, 3>{0, 2, 1})
    return f(Eigen::EulerAngles<double, EulerSystem<X, Z, Y>>());
  if (a == std::array<int, 3>{1, 0, 2})
    return f(Eigen::EulerAngles<double, EulerSystem<Y, X, Z>>());
  if (a == std::array<int, 3>{1, 2, 0})
    return f(Eigen::EulerAngles<double, EulerSystem<Y, Z, X>>());
  if (a == std::array<int, 3>{2, 0, 1})
    return f(Eigen::EulerAngles<double, EulerSystem<Z, X, Y>>());
  return f(Eigen::EulerAngles<double, EulerSystem<Z, Y, X>>());
}

}  // namespace

bool parse_euler_order(std::string_view text, EulerOrder* order) {
  if (text.size() != 3) return false;
  EulerOrder out;
  for (int k = 0; k < 3; ++k) {
    if (text[k] < 'x' || text[k] > 'z') return false;
    out.axes[k] = text[k] - 'x';
  }
  if (out.axes[0] == out.axes[1] || out.axes[1] == out.axes[2] || out.axes[0] == out.axes[2]) {
    return false;
  }
  *order = out;
  return true;
}

std::string euler_order_name(const EulerOrder& order) {
  std::string out;
  for (int axis : order.axes) out += static_cast<char>('x' + axis);
  return out;
}

Quaterniond euler_rotation(const EulerOrder& order, const Vector3d& angles) {
  return with_system(order, [&](auto euler) {
    using Angles = decltype(euler);
    return Quaterniond(Angles(angles[0], angles[1], angles[2]));
  });
}

Vector3d euler_angles(const EulerOrder& order, const Quaterniond& q) {
  return with_system(order, [&](auto euler) {
    using Angles = decltype(euler);
    return Vector3d(Angles(q.toRotationMatrix()).angles());
  });
}

Vector3d parent_anchor(const Joint& joint, const Quaterniond& q_rel) {
  if (!has_box_offsets(joint)) return joint.anchor_in_parent;
  const auto& a = joint.box_order.axes;
  const Vector3d angles = euler_angles(joint.box_order, q_rel);
  const Eigen::AngleAxisd first(angles[0], Vector3d::Unit(a[0]));
  const Eigen::AngleAxisd second(angles[1], Vector3d::Unit(a[1]));
  const Quaterniond to_frame = joint.frame_world.conjugate();
  const Vector3d along =
      first * (to_frame * joint.box_offsets[0] + second * (to_frame * joint.box_offsets[1]));
  return joint.anchor_in_parent + joint.frame_in_parent * along;
}

std::string box_offsets_problem(const Model& model) {
  for (const Joint& joint : model.joints) {
    if (!has_box_offsets(joint)) continue;
    const double apart = (joint.box_offsets[0] + joint.box_offsets[1]).norm();
    char line[256];
    std::snprintf(line, sizeof line,
                  "its joint \"%s\" is hinges at different points (%.3g cm apart), which this "
                  "engine does not build (mujoco and the procedural rules xpbd and tree do)",
                  joint.name.c_str(), 100.0 * apart);
    return line;
  }
  return {};
}

Matrix3d euler_gradients(const EulerOrder& order, const Vector3d& angles) {
  const auto& a = order.axes;
  const Eigen::AngleAxisd last(angles[2], Vector3d::Unit(a[2]));
  const Eigen::AngleAxisd middle(angles[1], Vector3d::Unit(a[1]));
  Matrix3d rates;
  rates.col(2) = Vector3d::Unit(a[2]);
  rates.col(1) = last.inverse() * Vector3d::Unit(a[1]);
  rates.col(0) = last.inverse() * (middle.inverse() * Vector3d::Unit(a[0]));
  return rates.inverse();
}

Quaterniond clamp_to_box(const EulerOrder& order, const Vector3d& lower, const Vector3d& upper,
                         const Quaterniond& q) {
  const Vector3d angles = euler_angles(order, q);
  const Vector3d clamped = angles.cwiseMax(lower).cwiseMin(upper);
  if (clamped == angles) return q;
  return euler_rotation(order, clamped);
}

double box_excess(const EulerOrder& order, const Vector3d& lower, const Vector3d& upper,
                  const Quaterniond& q) {
  const Vector3d angles = euler_angles(order, q);
  return std::max({0.0, (angles - upper).maxCoeff(), (lower - angles).maxCoeff()});
}

}  // namespace puppet
