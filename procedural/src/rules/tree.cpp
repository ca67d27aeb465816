// Rule `tree`: the mass-weighted position projection of xpbd solved exactly, in O(n), on the
// tree (Baraff 1996, "Linear-time dynamics using Lagrange multipliers"; Deul, Kugelstadt, Weiler,
// Bender 2018, "Direct position-based solver for stiff rods"). Per substep of h = dt/substeps:
//
//   update            every segment alone under its forces (the same stage as every rule)
//   adjust            `iterations` Newton iterations (default 1): the ground pushed out
//                     segment by segment, as xpbd does; then every pin, joint point and
//                     active limit linearised at the current poses, and the whole system
//                        [ M   −Jᵀ ] [ Δx ]   [    0    ]
//                        [ −J  −α̃  ] [ Δλ ] = [ C + α̃ λ ]
//                     solved at once by a block LDLᵀ factorisation in tree order
//   velocities        v = Δx/h, ω = log(q q_prev⁻¹)/h, then xpbd's ground velocity pass
//
// The matrix's graph is a tree: segments and constraints are its nodes, each constraint linked
// to the two segments it joins. Eliminated from the leaves, no block fills in (Baraff §5), so
// one factorisation costs O(n) 6×6 blocks. Unknowns per segment node are (Δx world, Δθ in the
// segment's frame), where its mass matrix diag(m, m, m, I) is constant. A constraint node holds
// three to six rows (a joint: its point's three, then its active limit rows), so a joint inside
// its limits costs 3×3 and 3×6 blocks.
//
// Limits are active constraints re-read at every Newton iteration: a ball joint outside its limits
// gets a row along the gradient of each limit function that is positive (ball_excess: each Euler
// angle's excess for a box; the twist's and the swing's for swing–twist); a hinge two rows
// across its axis always and a third along it when its angle is out of range, a fixed joint all
// three. The first pin is the tree's root. A second pin closes a loop through the world (the
// marionette's head and its dragged hand): its rows join the system through their Schur
// complement on the factored tree, solved on the loops' ancestors alone, so it is exact too for
// a few path passes. The ground is not in the system: it is pushed out before each Newton
// iteration, as xpbd does.
//
// seed: the same update and velocities as every rule; the adjust that the seed does by local
// moves is here the exact minimum-energy projection of one linearisation (the "g = 0" of XPBD:
// the correction from the predicted pose is not carried into the next iteration's right side).
#include <algorithm>
#include <cmath>

#include "puppet/model/euler_box.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"
#include "rules.h"

namespace puppet::procedural {
namespace {

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
  const Vector3d anchor_parent = parent_anchor(joint, parent.q, child.q);
  c.head<3>() = world_point(parent, anchor_parent) - world_point(child, joint.anchor_in_child);
  j_parent.topRows<3>() = point_jacobian(r_parent, anchor_parent);
  j_child.topRows<3>() = -point_jacobian(r_child, joint.anchor_in_child);
  int rows = 3;
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
  node.alpha.head<3>().setConstant(point_alpha);
  node.alpha.tail<3>().setConstant(limit_alpha);
  set_constraint_node(rows, c, node);
  return past;
}

// the loops' nodes and all their ancestors, ascending, into ws.tree_path
std::span<const int> loop_ancestors(int loops, int count, Workspace& ws) {
  if (loops <= 0) return {};
  std::vector<char>& marked = ws.tree_marked;
  std::fill(marked.begin(), marked.begin() + count, 0);
  for (int l = 0; l < loops; ++l) {
    for (int i = ws.tree_loops[l].node; i >= 0 && !marked[i]; i = ws.tree_nodes[i].parent) {
      marked[i] = 1;
    }
  }
  int size = 0;
  for (int i = 0; i < count; ++i) {
    if (marked[i]) ws.tree_path[size++] = i;
  }
  return {ws.tree_path.data(), static_cast<size_t>(size)};
}

// one anchor's tree for a substep: its nodes (`count`) and the loops' nodes with their ancestors
struct Topology {
  int count = 0;
  std::span<const int> loop_path;
  int first_loop = 1;  // the first pin that is a loop (0 when the world holds the root)
};

// the nodes of one anchor's tree, root first: [the first pin], the anchor's segment, then per
// link its joint and the segment it places; each later pin is a loop, and ws.tree_loops keeps
// the node of its segment
Topology build_topology(const AnchorOrder& order, const State& state, Workspace& ws) {
  std::vector<TreeNode>& nodes = ws.tree_nodes;
  int count = 0;
  const auto place = [&](TreeNode::Kind kind, int index, int parent) {
    TreeNode& node = nodes[count++];
    node.kind = kind;
    node.index = index;
    node.parent = parent;
  };
  // the world's hold on the root, else the first pin, hangs the tree; every other pin is a loop
  const bool held = state.root_held;
  const bool pinned = held || state.pin_count > 0;
  if (held) {
    place(TreeNode::kHold, -1, -1);
  } else if (pinned) {
    place(TreeNode::kPin, 0, -1);
  }
  const int first_loop = held ? 0 : 1;
  const int n = static_cast<int>(order.preorder.size());
  // segment node of preorder position k: 0 or 1 for the anchor, then 2k or 2k + 1
  const int first = count;
  const auto segment_node = [first](int k) { return k == 0 ? first : first + 2 * k; };
  place(TreeNode::kSegment, order.preorder[0], pinned ? 0 : -1);
  for (int k = 1; k < n; ++k) {
    const AnchorOrder::Link& link = order.links[k - 1];
    const int joint_node = count;
    place(TreeNode::kJoint, link.joint, segment_node(order.parent_position[k]));
    place(TreeNode::kSegment, order.preorder[k], joint_node);
  }
  for (int i = first_loop; i < state.pin_count; ++i) {
    int k = 0;
    while (order.preorder[k] != state.pins[i].segment) ++k;
    ws.tree_loops[i - first_loop].node = segment_node(k);
  }
  return {count, loop_ancestors(state.pin_count - first_loop, count, ws), first_loop};
}

// every node's diagonal and right side, and each node's coupling to its parent, `up`, from the
// current poses; then the loops' rows
void linearise(const Model& model, std::span<const JointTerms> joints, const Settings& settings,
               const Topology& topology, const PinTargets& targets, const State& state,
               Workspace& ws, double inv_h2) {
  const int count = topology.count;
  std::vector<TreeNode>& nodes = ws.tree_nodes;
  const double point_alpha = settings.joint_compliance * inv_h2;
  const double limit_alpha = settings.limit_compliance * inv_h2;
  std::vector<Matrix3d>& rotations = ws.tree_rotations;
  for (int s = 0; s < model.segment_count(); ++s) {
    rotations[s] = state.bodies[s].q.toRotationMatrix();
  }
  for (int i = 0; i < count; ++i) {
    TreeNode& node = nodes[i];
    switch (node.kind) {
      case TreeNode::kSegment:
        // (only d and b: the coupling a joint or the root pin wrote into `up` stands)
        set_segment_node(model.segments[node.index], node);
        break;
      case TreeNode::kHold: {
        // the world's hold on the root: node 1 is the root's segment
        Matrix6d jacobian;
        set_hold_rows(model, state.bodies[0], rotations[0], node, jacobian);
        nodes[1].up = -jacobian.transpose();
        break;
      }
      case TreeNode::kPin: {
        // the root pin is its segment's parent: node 1, whose `up` is then −Jᵀ
        const Pin& pin = state.pins[node.index];
        Matrix36d jacobian;
        set_pin_rows(pin, targets[node.index], state.bodies[pin.segment], rotations[pin.segment],
                     pin.compliance * inv_h2, node, jacobian);
        nodes[1].up.setZero();
        nodes[1].up.topLeftCorner<6, 3>() = -jacobian.transpose();
        break;
      }
      case TreeNode::kJoint: {
        const Joint& joint = model.joints[node.index];
        Matrix6d j_parent, j_child;
        LimitRows rows;
        if (set_joint_rows(joint, joints[node.index], state.bodies[joint.parent],
                           state.bodies[joint.child], rotations[joint.parent],
                           rotations[joint.child], point_alpha, limit_alpha, node, j_parent,
                           j_child, rows)) {
          // the velocity pass reads the rows at the solved pose: one Newton step moves a joint
          // near gimbal lock far enough that the linearisation's rows point elsewhere (measured:
          // a box held to 0.03° with the solved pose's rows, 2.6° with these)
          rows.count = kRowsAtPose;
          mark_limit(ws, node.index, rows);
        }
        // the tree's parent of a joint node is the segment nearer the anchor, which is the
        // model's parent unless the anchor order walks the edge backwards
        const bool parent_is_nearer = nodes[node.parent].index == joint.parent;
        node.up = -(parent_is_nearer ? j_parent : j_child);
        nodes[i + 1].up = -(parent_is_nearer ? j_child : j_parent).transpose();
        break;
      }
    }
  }
  for (int l = 0; l + topology.first_loop < state.pin_count; ++l) {
    TreeLoop& loop = ws.tree_loops[l];
    const int k = l + topology.first_loop;
    const Pin& pin = state.pins[k];
    const BodyState& body = state.bodies[pin.segment];
    loop.alpha = pin.compliance * inv_h2;
    loop.jacobian = point_jacobian(rotations[pin.segment], pin.local_point);
    loop.c = world_point(body, pin.local_point) - targets[k] + loop.alpha * loop.lambda;
  }
}

// A node's block width: six unknowns for a segment, and for a constraint three (a joint inside
// its limits, a pin) or six (padded). Every block below is fixed-size: a joint inside its limits
// costs 3×3 and 3×6 products, not 6×6.
int width(const TreeNode& node) { return node.rows == 3 ? 3 : 6; }

// A segment's D is positive definite (its mass plus what its subtree's constraints add), a
// constraint's negative definite (−α̃ minus its child's inverse effective mass): either way each
// 3×3 block on its diagonal and their Schur complements are definite, so D is inverted
// explicitly by 3×3 blocks, each 3×3 inverse by cofactors (Eigen's closed form):
//   D = [A B; Bᵀ C],  S = C − Bᵀ A⁻¹ B,  D⁻¹ = [A⁻¹ + A⁻¹B S⁻¹ BᵀA⁻¹, −A⁻¹B S⁻¹; ·ᵀ, S⁻¹].
// Every later use of D⁻¹ (X = D⁻¹U, a right side in substitute) is then one fixed-size product.
// Eigen's LLT of a fixed 6×6, solved column by column, costs several times this (measured).
template <int R>
void invert_block(TreeNode& node) {
  if constexpr (R == 3) {
    node.inverse.topLeftCorner<3, 3>() = Matrix3d(node.d.topLeftCorner<3, 3>()).inverse();
  } else {
    const Matrix3d a_inverse = Matrix3d(node.d.topLeftCorner<3, 3>()).inverse();
    const Matrix3d a_inverse_b = a_inverse * node.d.topRightCorner<3, 3>();
    Matrix3d schur = node.d.bottomRightCorner<3, 3>();
    schur.noalias() -= node.d.topRightCorner<3, 3>().transpose() * a_inverse_b;
    const Matrix3d s_inverse = schur.inverse();
    const Matrix3d corner = -a_inverse_b * s_inverse;
    node.inverse.topLeftCorner<3, 3>() = a_inverse;
    node.inverse.topLeftCorner<3, 3>().noalias() -= corner * a_inverse_b.transpose();
    node.inverse.topRightCorner<3, 3>() = corner;
    node.inverse.bottomLeftCorner<3, 3>() = corner.transpose();
    node.inverse.bottomRightCorner<3, 3>() = s_inverse;
  }
}

// node (R unknowns) eliminated into its parent (P): X = D⁻¹ U, D_p −= Uᵀ X
template <int R, int P>
void eliminate(TreeNode& node, TreeNode& parent) {
  invert_block<R>(node);
  const auto up = node.up.topLeftCorner<R, P>();
  node.x.topLeftCorner<R, P>().noalias() = node.inverse.topLeftCorner<R, R>() * up;
  parent.d.topLeftCorner<P, P>().noalias() -= up.transpose() * node.x.topLeftCorner<R, P>();
}

// f.template operator()<R, P>() for a non-root node of R unknowns under a parent of P: (3, 6),
// (6, 3) or (6, 6), since segments and constraints alternate
template <typename F>
void with_widths(const TreeNode& node, const TreeNode& parent, F&& f) {
  if (width(node) == 3) {
    f.template operator()<3, 6>();
  } else if (width(parent) == 3) {
    f.template operator()<6, 3>();
  } else {
    f.template operator()<6, 6>();
  }
}

// H = L D Lᵀ from the leaves: D_i = H_ii − Σ_children Uᵀ D⁻¹ U, each D factored, X = D⁻¹ U kept
void factor(int count, std::vector<TreeNode>& nodes) {
  for (int i = count - 1; i > 0; --i) {
    TreeNode& node = nodes[i];
    TreeNode& parent = nodes[node.parent];
    with_widths(node, parent, [&]<int R, int P>() { eliminate<R, P>(node, parent); });
  }
  if (width(nodes[0]) == 3) {
    invert_block<3>(nodes[0]);
  } else {
    invert_block<6>(nodes[0]);
  }
}

// H y = r in place (r per node in, y out) as two passes over the nodes `on`: ascending, and
// holding each one's parent (so the root, 0, first). On all nodes they give the whole solution.
// forward: from the leaves, each node's z = D⁻¹ r̃ and its parent's r̃ −= Uᵀ z, then the root's
// solve; linear in r, and a right side nonzero only on `on` moves nothing else
void forward(std::span<const int> on, const std::vector<TreeNode>& nodes, std::span<Vector6d> r) {
  for (size_t k = on.size() - 1; k > 0; --k) {
    const int i = on[k];
    const TreeNode& node = nodes[i];
    with_widths(node, nodes[node.parent], [&]<int R, int P>() {
      const Eigen::Matrix<double, R, 1> z =
          node.inverse.template topLeftCorner<R, R>() * r[i].template head<R>();
      r[i].template head<R>() = z;
      r[node.parent].template head<P>().noalias() -=
          node.up.template topLeftCorner<R, P>().transpose() * z;
    });
  }
  if (width(nodes[0]) == 3) {
    r[0].head<3>() = (nodes[0].inverse.topLeftCorner<3, 3>() * r[0].head<3>()).eval();
  } else {
    r[0] = (nodes[0].inverse * r[0]).eval();
  }
}
// backward: from the root, y = z − X y_parent; a node's y reads only its ancestors', so on the
// ancestors of a few nodes it gives y exactly there, for a path's cost
void backward(std::span<const int> on, const std::vector<TreeNode>& nodes, std::span<Vector6d> r) {
  for (size_t k = 1; k < on.size(); ++k) {
    const int i = on[k];
    const TreeNode& node = nodes[i];
    with_widths(node, nodes[node.parent], [&]<int R, int P>() {
      r[i].template head<R>().noalias() -=
          node.x.template topLeftCorner<R, P>() * r[node.parent].template head<P>();
    });
  }
}

// one Newton iteration: linearise, factor, solve, close the loops, apply
void solve_once(const Model& model, std::span<const JointTerms> joints, const Settings& settings,
                const Topology& topology, const PinTargets& targets, State& state, Workspace& ws,
                double h) {
  const int count = topology.count;
  std::vector<TreeNode>& nodes = ws.tree_nodes;
  linearise(model, joints, settings, topology, targets, state, ws, 1.0 / (h * h));
  factor(count, nodes);
  const std::span<Vector6d> y(ws.tree_solution.data(), count);
  for (int i = 0; i < count; ++i) y[i] = nodes[i].b;
  const std::span<const int> all(ws.tree_all.data(), count);
  forward(all, nodes, y);
  // Loops (pins after the first) by their Schur complement on the factored tree: with G = −J a
  // loop's rows in its segment's columns, the system [H Gᵀ; G −A] [y; μ] = [r; c] gives
  //   (G H⁻¹ Gᵀ + A) μ = G H⁻¹ r − c,   y = H⁻¹ (r − Gᵀ μ).
  // Everything but the last is read at the loops' nodes only: G H⁻¹ Gᵀ's columns and G H⁻¹ r
  // are solved on those nodes' ancestors alone (a path each); Gᵀ μ, nonzero on the path, is taken
  // off r's forward pass there, and one backward pass over all nodes gives y
  const int loops = state.pin_count - topology.first_loop;
  if (loops > 0) {
    const std::span<const int> path = topology.loop_path;
    const int size = 3 * loops;
    LoopMatrix schur(size, size);
    LoopVector rhs(size);
    const std::span<Vector6d> w(ws.tree_column.data(), count);
    for (int col = 0; col < size; ++col) {
      const TreeLoop& source = ws.tree_loops[col / 3];
      for (const int i : path) w[i].setZero();
      w[source.node] = -source.jacobian.row(col % 3).transpose();
      forward(path, nodes, w);
      backward(path, nodes, w);
      for (int row = 0; row < size; ++row) {
        const TreeLoop& loop = ws.tree_loops[row / 3];
        schur(row, col) = -loop.jacobian.row(row % 3).dot(w[loop.node]);
      }
    }
    for (const int i : path) w[i] = y[i];
    backward(path, nodes, w);
    for (int row = 0; row < size; ++row) {
      const TreeLoop& loop = ws.tree_loops[row / 3];
      schur(row, row) += loop.alpha;
      rhs(row) = -loop.jacobian.row(row % 3).dot(w[loop.node]) - loop.c(row % 3);
    }
    ws.tree_loop_factor.compute(schur);
    const LoopVector mu = ws.tree_loop_factor.solve(rhs);
    for (const int i : path) w[i].setZero();
    for (int l = 0; l < loops; ++l) {
      TreeLoop& loop = ws.tree_loops[l];
      const Vector3d mu_l = mu.segment<3>(3 * l);
      w[loop.node] -= loop.jacobian.transpose() * mu_l;
      loop.lambda += mu_l;
    }
    forward(path, nodes, w);
    for (const int i : path) y[i] -= w[i];
  }
  backward(all, nodes, y);
  // apply: segments move, constraints accumulate their multipliers
  for (int i = 0; i < count; ++i) {
    TreeNode& node = nodes[i];
    if (node.kind == TreeNode::kSegment) {
      BodyState& body = state.bodies[node.index];
      body.x += y[i].head<3>();
      body.q = renormalized(times_exp(body.q, y[i].tail<3>()));
    } else {
      for (int r = 0; r < node.rows; ++r) node.lambda(r) += y[i](r);
    }
  }
}

}  // namespace

void tree_adjust(const Model& model, std::span<const JointTerms> joints, const Settings& settings,
                 const Environment& environment, const AnchorOrder& order,
                 const PinTargets& targets, State& state, Workspace& ws, double h) {
  const Topology topology = build_topology(order, state, ws);
  for (int i = 0; i < topology.count; ++i) ws.tree_nodes[i].lambda.setZero();
  for (TreeLoop& loop : ws.tree_loops) loop.lambda.setZero();
  for (int iteration = 0; iteration < settings.iterations; ++iteration) {
    // the ground is not in the system: pushed out before each solve, which then closes what
    // the push opened (what it pushes back in is reported as penetration)
    if (environment.ground) {
      for (int s = 0; s < model.segment_count(); ++s) {
        push_out_of_ground(model, environment, s, state);
      }
    }
    solve_once(model, joints, settings, topology, targets, state, ws, h);
  }
}

}  // namespace puppet::procedural
