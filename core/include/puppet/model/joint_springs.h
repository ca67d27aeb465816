/// \file
/// Joint springs and dampers (MuJoCo's passive joint forces), the same formulas in every engine
/// that does not build them natively. Each engine evaluates them on the state at the start of each
/// of its steps and applies them as external torques, equal and opposite on the child and its
/// parent, as it applies the environment's forces.
#pragma once

#include <optional>
#include <span>

#include "puppet/model/environment.h"

namespace puppet {

/// Adds every joint's spring and damper torques (world) to `out` (one wrench per segment) for a
/// step of length h from `bodies`. About each degree of freedom the generalized force is
///   f = −stiffness (angle − spring_ref) − damping′ · rate,
/// with the angle and rate MuJoCo's: a hinge's angle about its axis; a slide's coordinate along
/// its direction (a force then, at each side's point on the slide's line); an Euler box's three
/// angles (their rates through euler_gradients); a swing–twist ball's rotation from rest as a
/// rotation vector in the child's joint frame, its rate the child's angular velocity relative to
/// the parent. The damper is integrated implicitly per joint, as MuJoCo's Euler integrates damping:
/// with K = I_p⁻¹ + I_c⁻¹ the two segments' world inverse inertias, the rate it acts on is the rate
/// after the step, (1 + h · damping · K)⁻¹ · rate (a hinge's or a box angle's K along its own
/// direction; a ball's the 3×3), so that a stiff damper on a light segment slows it without
/// overshooting for any h (h = 0: the explicit damper). The joint's constraints only add
/// inertia, so this is what the pair alone would do. No allocation.
void add_joint_spring_wrenches(const Model& model, std::span<const BodyState> bodies, double h,
                               std::span<Wrench> out);
/// the part of it that the world's joint on the root gives (RootJoint): along each slide a force
/// at the anchor, about the hinge a torque, each damper implicit in the mass or the inertia about
/// the hinge's line; nothing for a free, welded or ball root
void add_root_spring_wrench(const Model& model, const BodyState& root, double h, Wrench& out);

/// one joint's coordinates as MuJoCo reads them, those its springs and dampers act on (one per
/// degree of freedom: 1 for a hinge or a slide, 3 for a ball), and their rates
struct JointCoordinates {
  Vector3d angle{0, 0, 0};  ///< hinge: [0]; slide: [0] its distance (m); box: the Euler angles;
                            ///< ball: the rotation vector
  Vector3d rate{0, 0, 0};   ///< the same coordinates' rates
};
JointCoordinates joint_coordinates(const Joint& joint, const BodyState& parent,
                                   const BodyState& child);

/// the energy the joints' springs hold: Σ ½ stiffness (angle − spring_ref)² over every degree of
/// freedom (a ball's: ½ stiffness |r|²)
double joint_spring_energy(const Model& model, std::span<const BodyState> bodies);

/// Armature as an engine in maximal coordinates builds it: each joint's rotor inertia added to its
/// child's inertia about the joint's axes at rest (a hinge's axis, a box's three axes, a ball's
/// every axis), the part off the segment frame's diagonal left out (none when the axes are the
/// segment's own, as a ball's always are). MuJoCo adds it to the degree of freedom itself; the
/// two agree while the parent turns slowly about the axis, and the tests measure how far they part
/// (docs/model-format.md). Returns `model` itself when it has no armature, else `holder` filled.
const Model& armature_in_inertia(const Model& model, std::optional<Model>& holder);

}  // namespace puppet
