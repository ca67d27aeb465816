/// \file
/// A box of intrinsic Euler angles: a ball joint's rotation written as three turns about distinct
/// axes of its frame, q = R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂), each angle within a range of its own.
/// It is the seed's eq. 4 reading of a joint limit (each constrained rotation direction with its
/// own [θmin, θmax]) and the one limit every engine can build alike: MuJoCo as three hinges in one
/// body (they compose in this order), btGeneric6DofSpring2Constraint as RO_ZYX with the angles
/// negated for the x→y→z order.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "puppet/model/model.h"
#include "puppet/model/rotation.h"

namespace puppet {

/// "xyz", "zyx", ...: three different letters of x, y, z; false for anything else
bool parse_euler_order(std::string_view text, EulerOrder* order);
std::string euler_order_name(const EulerOrder& order);

/// R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂)
Quaterniond euler_rotation(const EulerOrder& order, const Vector3d& angles);
/// the angles of q: θ₁ in [−π/2, π/2], θ₀ and θ₂ in [−π, π] (Eigen's EulerAngles); at θ₁ = ±π/2
/// (gimbal lock) θ₀ takes the whole turn about the shared axis
Vector3d euler_angles(const EulerOrder& order, const Quaterniond& q);

/// the angles' gradients with respect to a turn δ of q's own frame, q exp(δ): row k is ∂θₖ/∂δ.
/// The inverse of E, where ω = E θ̇ in q's frame: E's columns are a₀ seen through the later two
/// turns, a₁ through the last, and a₂. Finite while the middle angle is off ±π/2.
Matrix3d euler_gradients(const EulerOrder& order, const Vector3d& angles);

/// q with each angle clamped into [lower, upper] and recomposed; q itself (the same bits) when
/// every angle is inside. The nearest rotation in the angles, not along the sphere: what the
/// procedural solver's clamp does and what a limit of three hinges enforces, axis by axis.
Quaterniond clamp_to_box(const EulerOrder& order, const Vector3d& lower, const Vector3d& upper,
                         const Quaterniond& q);

/// the most any angle of q lies outside [lower, upper] (rad; 0 inside)
double box_excess(const EulerOrder& order, const Vector3d& lower, const Vector3d& upper,
                  const Quaterniond& q);

/// whether the joint is a box of hinges at different points (Joint::box_offsets)
inline bool has_box_offsets(const Joint& joint) {
  return !joint.box_offsets[0].isZero(0.0) || !joint.box_offsets[1].isZero(0.0);
}

/// The joint's point on the parent's side, in the parent's frame, at the relative rotation q_rel
/// (joint_relative_rotation): anchor_in_parent, carried along a box's hinge offsets by its
/// angles, F_p R(a₀, θ₀) (d₀ + R(a₁, θ₁) d₁) with dₖ the offsets in the joint frame, where each
/// later hinge's point turns with the earlier hinges as MuJoCo composes them; anchor_in_parent
/// itself for every other joint. The child's point, anchor_in_child, meets it when the joint holds.
Vector3d parent_anchor(const Joint& joint, const Quaterniond& q_rel);
/// the same at the parent's and the child's orientations (anchor_in_parent, untouched, for a
/// joint without offsets: the hot paths pay a test)
inline Vector3d parent_anchor(const Joint& joint, const Quaterniond& q_parent,
                              const Quaterniond& q_child) {
  if (!has_box_offsets(joint)) return joint.anchor_in_parent;
  return parent_anchor(joint, joint_relative_rotation(joint, q_parent, q_child));
}

/// "" when no joint is a box of hinges at different points; else the first such joint, named
/// with how far apart its hinges are, and the engines that build it (for an engine that does not)
std::string box_offsets_problem(const Model& model);

/// the middle angle's range is within ±kMaxBoxMiddle (85°): Euler angles lose an axis at ±90°
inline constexpr double kMaxBoxMiddle = 85.0 * 3.14159265358979323846 / 180.0;

}  // namespace puppet
