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
#include "tree_rows.h"

namespace puppet::procedural {
namespace {

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
