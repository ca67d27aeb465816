#include "tree_rows.h"

#include <algorithm>
#include <cmath>

#include "puppet/model/euler_box.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"

namespace puppet::procedural {

// the Jacobian of a world point r (segment frame) of a segment turned by R in its (Δx, Δθ)
// block: [E, −R[r]×]
Matrix36d point_jacobian(const Matrix3d& rotation, const Vector3d& r) {
  Matrix36d jacobian;
  jacobian.leftCols<3>().setIdentity();
  jacobian.rightCols<3>().noalias() = -rotation * cross_matrix(r);
  return jacobian;
}

void set_segment_node(const Segment& segment, TreeNode& node) {
  node.rows = 6;
  node.d.setZero();
  node.d.diagonal() << segment.mass, segment.mass, segment.mass, segment.inertia;
  node.b.setZero();
}

// a constraint node of `rows` rows: its diagonal −α̃, its right side C + α̃ λ (the accumulated
// multiplier's compliance term); a node of four or five rows is padded to six with −1 on the
// diagonal, no coupling and no right side, so the padding's multiplier is zero
void set_constraint_node(int rows, const Vector6d& c, TreeNode& node) {
  node.rows = rows;
  node.d.setZero();
  node.b.setZero();
  for (int r = 0; r < 6; ++r) {
    node.d(r, r) = r < rows ? -node.alpha(r) : -1.0;
    if (r < rows) node.b(r) = c(r) + node.alpha(r) * node.lambda(r);
  }
}

// the pin's rows: C = x + R r − target, and J = [E, −R[r]×] in its segment's coordinates
void set_pin_rows(const Pin& pin, const Vector3d& target, const BodyState& body,
                  const Matrix3d& rotation, double alpha, TreeNode& node, Matrix36d& jacobian) {
  node.alpha.head<3>().setConstant(alpha);
  Vector6d c;
  c.head<3>() = world_point(body, pin.local_point) - target;
  set_constraint_node(3, c, node);
  jacobian = point_jacobian(rotation, pin.local_point);
}

// The world's hold on the root (RootJoint), rigid, in the root's (Δx, Δθ): the anchor's rows
// along the held directions (all three; a slide's two across it, and one along it past an end of
// its range; a planar root's one along its normal), C its stray from where the hold lets it be;
// then the orientation's: a weld's and a slide's three, C the rotation from rest (world); a
// hinge's two across its axis, C the rotation that tilts the axis from its rest direction, and one
// along it past an end of its range. At most six rows, padded to six when more than three.
void set_hold_rows(const Model& model, const BodyState& body, const Matrix3d& rotation,
                   TreeNode& node, Matrix6d& jacobian) {
  const RootJoint& root = model.root;
  const bool planar = root.hold == RootHold::kPlanar;
  jacobian.setZero();
  Vector6d c = Vector6d::Zero();
  int rows = 0;
  const Matrix36d point = point_jacobian(rotation, root.anchor_in_root);
  const Vector3d stray = world_point(body, root.anchor_in_root) - root.anchor_world;
  const auto add_row = [&](const Eigen::Matrix<double, 1, 6>& row, double value) {
    jacobian.row(rows) = row;
    c(rows) = value;
    ++rows;
  };
  if (root.hold == RootHold::kSlide) {
    const Vector3d& a = root.axes[0];
    const Vector3d u = any_orthogonal(a), v = a.cross(u);
    add_row(u.transpose() * point, u.dot(stray));
    add_row(v.transpose() * point, v.dot(stray));
    const double s = a.dot(stray);
    if (root.limited && (s > root.upper || s < root.lower)) {
      add_row(a.transpose() * point, s - std::clamp(s, root.lower, root.upper));
    }
  } else if (planar) {
    const Vector3d& n = root.axes[2];
    add_row(n.transpose() * point, n.dot(stray));
  } else {
    for (int k = 0; k < 3; ++k) add_row(point.row(k), stray(k));
  }
  // a turn δ of the root in world is R Δθ; C the held turn (none along a hinge's own axis)
  const auto add_turn_row = [&](const Vector3d& direction, double value) {
    Eigen::Matrix<double, 1, 6> row = Eigen::Matrix<double, 1, 6>::Zero();
    row.tail<3>() = direction.transpose() * rotation;
    add_row(row, value);
  };
  const Vector3d turned = root_held_turn(model, body.q);
  if (root.hold == RootHold::kWeld || root.hold == RootHold::kSlide) {
    for (int k = 0; k < 3; ++k) add_turn_row(Vector3d::Unit(k), turned(k));
  } else if (const int hinge = root_hinge_index(root.hold); hinge >= 0) {
    const Vector3d& a = root.axes[static_cast<size_t>(hinge)];
    const Vector3d u = any_orthogonal(a), v = a.cross(u);
    add_turn_row(u, u.dot(turned));
    add_turn_row(v, v.dot(turned));
    if (root.limited && !planar) {
      const double angle = root_coordinates(model, body).value[0];
      if (angle > root.upper || angle < root.lower) {
        add_turn_row(a, angle - std::clamp(angle, root.lower, root.upper));
      }
    }
  }
  node.alpha.setZero();
  set_constraint_node(rows, c, node);
}

// A ball joint's limit rows (at most three): one per limit function that is positive, along its
// gradient with respect to a turn of the child (its frame), both from ball_excess (analytic).
// Swing and twist are not independent coordinates: past 90° of swing a turn across the swing
// changes the twist at first order (by about tan(φ/2)), so rows along the two parts of the clamp's
// rotation do not reduce both and Newton stalls at the corner of the two limits (measured at a
// shoulder at 110° swing and 80° twist); the functions' own gradients do.
int ball_limit_rows(const Joint& joint, const Quaterniond& q_rel, Matrix3d& directions,
                    Vector3d& targets) {
  const BallExcess limit = ball_excess(joint, q_rel);
  int count = 0;
  for (int k = 0; k < 3; ++k) {
    if (limit.excess(k) <= 0.0) continue;
    // q_rel exp(δ) for a turn δ_c of the child (its frame) is δ = Fc⁻¹ δ_c: the row is Fc g
    directions.row(count) =
        (joint.frame_in_child * Vector3d(limit.gradients.row(k).transpose())).transpose();
    // a row asks u·δ_c = target: the excess removed at first order
    targets(count) = -limit.excess(k);
    ++count;
  }
  return count;
}

// a joint's rows (its point, then its active limit rows) and its two Jacobian blocks, parent's
// and child's, in those segments' (Δx, Δθ) coordinates; true when a limit function is past its
// bound (a ball's limit rows, a hinge's row along its axis: the velocity pass's mark)
bool set_joint_rows(const Joint& joint, const JointTerms& terms, const BodyState& parent,
                    const BodyState& child, const Matrix3d& r_parent, const Matrix3d& r_child,
                    double point_alpha, double limit_alpha, TreeNode& node, Matrix6d& j_parent,
                    Matrix6d& j_child, LimitRows& past_rows) {
  j_parent.setZero();
  j_child.setZero();
  Vector6d c;
  // the point: C = p_parent − p_child (world). A box of hinges at different points carries the
  // parent's point along its angles; its Jacobian leaves out how the point moves with them (the
  // Newton iteration converges on it the less fast, the next substep's rows starting from there)
  Vector3d anchor_parent = parent_anchor(joint, parent.q, child.q);
  // a slide's: the parent's point moved along the slide by its coordinate s, clamped to its range
  // (both sides' points then one point), held across the slide (two rows), and along it too past
  // an end. Its rows leave out how the slide's direction turns with the parent, at second order
  // while the point holds
  Vector3d slide_direction{0, 0, 0};  // world; zero when held along it too
  if (joint.type == JointType::kSlide) {
    const Vector3d in_parent = joint.frame_in_parent * joint.hinge_axis;
    const Vector3d a = r_parent * in_parent;
    const double s =
        a.dot(world_point(child, joint.anchor_in_child) - world_point(parent, anchor_parent));
    const double kept = std::clamp(s, joint.lower, joint.upper);
    anchor_parent += kept * in_parent;
    if (kept == s) slide_direction = a;
  }
  c.head<3>() = world_point(parent, anchor_parent) - world_point(child, joint.anchor_in_child);
  j_parent.topRows<3>() = point_jacobian(r_parent, anchor_parent);
  j_child.topRows<3>() = -point_jacobian(r_child, joint.anchor_in_child);
  int rows = 3;
  if (!slide_direction.isZero()) {
    Matrix3d across;  // rows: two directions across the slide, then zero
    across.row(0) = any_orthogonal(slide_direction).transpose();
    across.row(1) = slide_direction.cross(across.row(0).transpose()).transpose();
    across.row(2).setZero();
    c.head<3>() = across * c.head<3>();
    j_parent.topRows<3>() = across * j_parent.topRows<3>();
    j_child.topRows<3>() = across * j_child.topRows<3>();
    rows = 2;
  }
  const int point_rows = rows;
  // the limit: the child needs the rotation e (its frame) with the parent fixed; a change of
  // δc (child's frame) and δp (parent's) turns it by δc − R δp, R the parent's frame seen from
  // the child's, so a row u asks uᵀ(δc − R δp) = uᵀ e, i.e. C = −uᵀ e
  const Quaterniond child_to_parent = child.q.conjugate() * parent.q;
  bool past = false;
  if (may_reach_limit(terms, child_to_parent)) {
    Matrix3d directions;  // rows: the constrained directions in the child's frame
    Vector3d targets;     // and how far the child must turn along each
    int count = 0;
    Vector3d error;
    if (has_limit_functions(joint)) {
      // rows built from the limit functions themselves (ball_limit_rows)
      count = ball_limit_rows(joint, joint_relative_rotation(joint, parent.q, child.q), directions,
                              targets);
      past = count > 0;
      past_rows.count = count;
      past_rows.directions = directions;
      past_rows.excess = -targets;
    } else if (limit_error(joint, terms, child_to_parent, &error)) {
      switch (joint.type) {
        case JointType::kBall: {
          // a zero half-angle (swing forbidden about one axis) keeps the clamp's rotation as
          // one row
          const double angle = error.norm();
          if (angle > 0.0) {
            directions.row(0) = error.transpose() / angle;
            targets(0) = angle;
            count = 1;
          }
          break;
        }
        case JointType::kHinge: {
          // across the axis always; along it only when the angle is out of its range
          const Vector3d axis = joint.frame_in_child * joint.hinge_axis;
          const Vector3d across = any_orthogonal(axis);
          directions.row(0) = across.transpose();
          directions.row(1) = axis.cross(across).transpose();
          targets.head<2>() = directions.topRows<2>() * error;
          count = 2;
          const Quaterniond q_rel = joint_relative_rotation(joint, parent.q, child.q);
          const double angle = decompose_swing_twist(q_rel, joint.hinge_axis).twist_angle;
          if (angle < joint.lower || angle > joint.upper) {
            directions.row(2) = axis.transpose();
            targets(2) = axis.dot(error);
            count = 3;
            past = true;
            past_rows.count = 1;
            past_rows.directions.row(0) =
                (angle > joint.upper ? axis : Vector3d(-axis)).transpose();
            past_rows.excess(0) = std::max(angle - joint.upper, joint.lower - angle);
          }
          break;
        }
        case JointType::kFixed:
        case JointType::kSlide:  // it turns not at all
          directions.setIdentity();
          targets = error;
          count = 3;
          break;
      }
    }
    const Matrix3d rotation = count > 0 ? child_to_parent.toRotationMatrix() : Matrix3d();
    for (int k = 0; k < count; ++k) {
      const Vector3d u = directions.row(k).transpose();
      c(rows) = -targets(k);
      j_child.block<1, 3>(rows, 3) = u.transpose();
      j_parent.block<1, 3>(rows, 3) = -u.transpose() * rotation;
      ++rows;
    }
  }
  node.alpha.setConstant(limit_alpha);
  node.alpha.head(point_rows).setConstant(point_alpha);
  set_constraint_node(rows, c, node);
  return past;
}

}  // namespace puppet::procedural
