// The rows of rule `tree`'s system (tree.cpp): each node's block, and the constraint rows and
// Jacobians in the segments' (Δx, Δθ) coordinates of a pin, the world's hold on the root and a
// joint (its point, a slide's across it, and its active limit rows)
#pragma once

#include "rules.h"

namespace puppet::procedural {

// the Jacobian of a world point r (segment frame) of a segment turned by R in its (Δx, Δθ)
// block: [E, −R[r]×]
Matrix36d point_jacobian(const Matrix3d& rotation, const Vector3d& r);

void set_segment_node(const Segment& segment, TreeNode& node);

// a constraint node of `rows` rows: its diagonal −α̃, its right side C + α̃ λ (the accumulated
// multiplier's compliance term); a node of four or five rows is padded to six with −1 on the
// diagonal, no coupling and no right side, so the padding's multiplier is zero
void set_constraint_node(int rows, const Vector6d& c, TreeNode& node);

// the pin's rows: C = x + R r − target, and J = [E, −R[r]×] in its segment's coordinates
void set_pin_rows(const Pin& pin, const Vector3d& target, const BodyState& body,
                  const Matrix3d& rotation, double alpha, TreeNode& node, Matrix36d& jacobian);

// The world's hold on the root (RootJoint), rigid, in the root's (Δx, Δθ): the anchor's rows
// along the held directions (all three; a slide's two across it, and one along it past an end of
// its range; a planar root's one along its normal), C its stray from where the hold lets it be;
// then the orientation's: a weld's and a slide's three, C the rotation from rest (world); a
// hinge's two across its axis, C the rotation that tilts the axis from its rest direction, and one
// along it past an end of its range. At most six rows, padded to six when more than three.
void set_hold_rows(const Model& model, const BodyState& body, const Matrix3d& rotation,
                   TreeNode& node, Matrix6d& jacobian);

// A ball joint's limit rows (at most three): one per limit function that is positive, along its
// gradient with respect to a turn of the child (its frame), both from ball_excess (analytic).
// Swing and twist are not independent coordinates: past 90° of swing a turn across the swing
// changes the twist at first order (by about tan(φ/2)), so rows along the two parts of the clamp's
// rotation do not reduce both and Newton stalls at the corner of the two limits (measured at a
// shoulder at 110° swing and 80° twist); the functions' own gradients do.
int ball_limit_rows(const Joint& joint, const Quaterniond& q_rel, Matrix3d& directions,
                    Vector3d& targets);

// a joint's rows (its point, then its active limit rows) and its two Jacobian blocks, parent's
// and child's, in those segments' (Δx, Δθ) coordinates; true when a limit function is past its
// bound (a ball's limit rows, a hinge's row along its axis: the velocity pass's mark)
bool set_joint_rows(const Joint& joint, const JointTerms& terms, const BodyState& parent,
                    const BodyState& child, const Matrix3d& r_parent, const Matrix3d& r_child,
                    double point_alpha, double limit_alpha, TreeNode& node, Matrix6d& j_parent,
                    Matrix6d& j_child, LimitRows& past_rows);

}  // namespace puppet::procedural
