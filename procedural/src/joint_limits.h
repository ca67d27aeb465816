// Joint limits (seed eq. 4): the swing–twist clamp of a joint's relative rotation, as the
// orientation of the moved side, as a rotation, or as a shared correction's error. Private to
// procedural/; joint_limits.cpp.
#pragma once

#include <cmath>

#include "joint_terms.h"
#include "puppet/model/model.h"

namespace puppet::procedural {

// The orientation of b that brings the joint back inside its limits with a fixed (eq. 4),
// evaluated on q_rel = (parent frame)⁻¹(child frame) whichever side b is: false when the joint
// is inside, and *q_b_limited is left alone; else a product of unit quaternions (unit but for
// rounding: renormalized() is enough; q_b_limited may point at q_b). Reads the joint's
// limit_free_w and frame_shift from `terms`.
bool limited_orientation(const Joint& joint, const JointTerms& terms, bool b_is_child,
                         const Quaterniond& q_a, const Quaterniond& q_b, Quaterniond* q_b_limited);
// the same as the rotation that takes b there (world; identity when inside), for the callers that
// move more than b about the joint point
Quaterniond limit_correction(const Joint& joint, const JointTerms& terms, bool b_is_child,
                             const Quaterniond& q_a, const Quaterniond& q_b);
// false when the relative rotation, read from child_to_parent = q_c⁻¹ q_p, is below the joint's
// free angle (limit_free_w): inside every limit, with no decomposition needed
inline bool may_reach_limit(const JointTerms& terms, const Quaterniond& child_to_parent) {
  // |w(q_rel)| = |w(frame_shift ⊗ (q_c⁻¹ q_p)⁻¹)| = |frame_shift · (q_c⁻¹ q_p)|
  return std::abs(terms.frame_shift.coeffs().dot(child_to_parent.coeffs())) <= terms.limit_free_w;
}
// whether a ball joint's limits are read as limit functions (ball_excess: a box, or a swing–twist
// whose half-angles are both positive); a swing forbidden about an axis is a clamp only
inline bool has_limit_functions(const Joint& joint) {
  return joint.type == JointType::kBall &&
         (joint.ball_limit == BallLimit::kEulerBox || (joint.swing_x > 0.0 && joint.swing_y > 0.0));
}
struct LimitRows {
  int count = 0;
  Matrix3d directions;
  Vector3d excess;
};
LimitRows limit_rows(const Joint& joint, const Quaterniond& q_rel, double above);

// the same for rule relaxed's shared correction, seen from the child: the rotation vector (child's
// frame) that turns the child inside the limits with the parent fixed, from
// child_to_parent = q_c⁻¹ q_p (the parent's frame seen from the child's); false when inside
// `rows` (optional): a ball's violated limit functions, when it has them (has_limit_functions);
// `functions` false: the clamp's rotation always (relaxed's sweeps)
bool limit_error(const Joint& joint, const JointTerms& terms, const Quaterniond& child_to_parent,
                 Vector3d* error, LimitRows* rows = nullptr, bool functions = true);
// A ball joint's limit functions at q_rel (rad, > 0 outside) and their gradients with respect to
// a turn δ of q_rel's frame, q_rel exp(δ) (row k: ∂excessₖ/∂δ), for rule tree's limit rows.
// A box's: each Euler angle's excess over its range. Swing–twist's: the twist's excess over its
// limit, the swing's over the ellipse's half-angle in the swing's direction, and a third that is
// never positive. Both analytic (the swing–twist ones from q_rel's components, as
// decompose_swing_twist reads them).
struct BallExcess {
  Vector3d excess;
  Matrix3d gradients;
};
BallExcess ball_excess(const Joint& joint, const Quaterniond& q_rel);

// A joint's limit rows at q_rel whose excess is above `above` (rad; 0 for the violated ones):
// each one limit function's gradient with respect to a turn of the child (rows, in the child's
// frame: Fc g) and its excess. A ball's come from ball_excess (a box, or a swing–twist whose
// half-angles are both positive; none for a swing forbidden about an axis), a hinge's is its axis
// signed toward the end it is past or near; a fixed joint has none.

// An Euler box's ranges as BoxTest reads them (disabled for any other limit, or a box the test
// cannot read: a range without 0, a middle range beyond ±85°)
BoxTest make_box_test(const Joint& joint);
// true when q_rel's Euler angles are each inside their range by more than kBoxMargin, read from
// q_rel's rotation matrix without an angle: the middle angle's sine is ±R[i][k], and the first
// and last angles' directions are (R[k][k], ∓R[j][k]) and (R[i][i], ∓R[i][j]) scaled by the
// middle angle's cosine (> 0 in the box). False says nothing: the clamp then decides.
bool surely_inside_box(const BoxTest& box, const Quaterniond& q_rel);
// what surely_inside_box leaves to the clamp (rad, or sine of the middle angle): many orders of
// magnitude above the rounding of the matrix, and a negligible band to decompose in full
inline constexpr double kBoxMargin = 1e-9;

// cos(ρ/2) for the largest angle ρ that no limit of the joint can reach in any direction (> 1
// when there is none): a relative rotation by less than ρ needs no swing–twist decomposition
double limit_free_w(const Joint& joint);

}  // namespace puppet::procedural
