// A solver's scratch: sized once, so that a step allocates nothing.
#include "workspace.h"

#include <numeric>

namespace puppet::procedural {

Workspace::Workspace(const Model& model, const ModelTables& tables) {
  const int n = model.segment_count();
  subtree_mass.resize(n);
  subtree_moment.resize(n);
  subtree_second.resize(n);
  motion_q.resize(n);
  motion_t.resize(n);
  tremble_delta.assign(n, Vector3d::Zero());
  user_wrenches.assign(n, Wrench{});
  applied_wrenches.assign(n, Wrench{});
  joint_lambda.assign(model.joint_count(), Vector3d::Zero());
  limit_lambda.assign(model.joint_count(), Vector3d::Zero());
  start_inverse_inertia.assign(n, Matrix3d::Identity());
  limit_violated.assign(model.joint_count(), 0);
  limit_rows.assign(model.joint_count(), LimitRows{});
  w_before.assign(n, Vector3d::Zero());
  tree_nodes.resize(n + model.joint_count() + 1);
  tree_solution.resize(tree_nodes.size());
  tree_column.resize(tree_nodes.size());
  tree_all.resize(tree_nodes.size());
  std::iota(tree_all.begin(), tree_all.end(), 0);
  tree_path.resize(tree_nodes.size());
  tree_marked.resize(tree_nodes.size());
  tree_rotations.resize(n);
  tree_loop_factor = Eigen::PartialPivLU<LoopMatrix>(kMaxLoopRows);
  if (tables.orders.empty()) {
    // a large model: the workspace's orders hold any anchor's without allocating in a step
    order_scratch.reserve(n);
    for (int slot = 0; slot < 2; ++slot) {
      fill_anchor_order(model, tables.incidence, 0, orders[slot], order_scratch);
      order_anchor[slot] = 0;
    }
  }
}

const AnchorOrder& anchor_order(const Model& model, const ModelTables& tables, Workspace& ws,
                                int anchor) {
  if (!tables.orders.empty()) return tables.orders[anchor];
  for (int slot = 0; slot < 2; ++slot) {
    if (ws.order_anchor[slot] == anchor) return ws.orders[slot];
  }
  const int slot = ws.order_next;
  ws.order_next = 1 - slot;
  fill_anchor_order(model, tables.incidence, anchor, ws.orders[slot], ws.order_scratch);
  ws.order_anchor[slot] = anchor;
  return ws.orders[slot];
}

}  // namespace puppet::procedural
