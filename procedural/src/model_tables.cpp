// The model's tables: the segments' incidence, the tree's order from every anchor (depth-first
// preorder with contiguous subtrees, and the same links breadth-first), and each joint's
// constant terms.
#include <algorithm>
#include <memory>

#include "geometry.h"
#include "joint_limits.h"
#include "model_tables.h"

namespace puppet::procedural {

Incidence make_incidence(const Model& model) {
  const int n = model.segment_count();
  Incidence incidence;
  incidence.offsets.assign(n + 1, 0);
  for (const Joint& joint : model.joints) {
    ++incidence.offsets[joint.parent + 1];
    ++incidence.offsets[joint.child + 1];
  }
  for (int s = 0; s < n; ++s) incidence.offsets[s + 1] += incidence.offsets[s];
  incidence.joints.resize(incidence.offsets[n]);
  std::vector<int> filled(incidence.offsets.begin(), incidence.offsets.end() - 1);
  for (int j = 0; j < model.joint_count(); ++j) {
    incidence.joints[filled[model.joints[j].parent]++] = j;
    incidence.joints[filled[model.joints[j].child]++] = j;
  }
  return incidence;
}

void AnchorOrderScratch::reserve(int segments) {
  position.resize(segments);
  depth.resize(segments);
  depth_start.resize(segments + 1);
  stack.reserve(segments);
}

void fill_anchor_order(const Model& model, const Incidence& incidence, int anchor,
                       AnchorOrder& order, AnchorOrderScratch& scratch) {
  const int n = model.segment_count();
  order.anchor = anchor;
  order.links.clear();
  order.preorder.clear();
  order.parent_position.assign(n, -1);
  std::vector<int>& position = scratch.position;
  std::fill(position.begin(), position.end(), -1);
  // depth-first preorder: parents before children, and every subtree a contiguous range
  auto& stack = scratch.stack;
  stack.clear();
  stack.push_back({anchor, -1, -1});
  while (!stack.empty()) {
    const AnchorOrderScratch::Frame frame = stack.back();
    stack.pop_back();
    const int k = static_cast<int>(order.preorder.size());
    position[frame.segment] = k;
    order.preorder.push_back(frame.segment);
    order.parent_position[k] = frame.from_position;
    if (frame.via_joint >= 0) {
      const Joint& joint = model.joints[frame.via_joint];
      const bool b_is_child = joint.child == frame.segment;
      order.links.push_back(
          {frame.via_joint, b_is_child ? joint.parent : joint.child, frame.segment, b_is_child});
    }
    // the segment's joints in reverse, so that the first one is walked first
    for (int e = incidence.offsets[frame.segment + 1] - 1; e >= incidence.offsets[frame.segment];
         --e) {
      const Joint& joint = model.joints[incidence.joints[e]];
      const int other = joint.parent == frame.segment ? joint.child : joint.parent;
      if (position[other] < 0) stack.push_back({other, incidence.joints[e], k});
    }
  }
  // breadth-first: depth by depth, in preorder within a depth (a counting sort, O(n))
  std::vector<int>& depth = scratch.depth;
  std::vector<int>& start = scratch.depth_start;
  std::fill(start.begin(), start.end(), 0);
  if (n > 0) depth[0] = 0;
  for (int k = 1; k < n; ++k) {
    depth[k] = depth[order.parent_position[k]] + 1;
    ++start[depth[k]];
  }
  for (int d = 1; d <= n; ++d) start[d] += start[d - 1];  // start[d]: links of depth ≤ d
  order.level_links.resize(order.links.size());
  for (int k = n - 1; k > 0; --k) order.level_links[--start[depth[k]]] = order.links[k - 1];
  // subtree ends, from the back: a subtree ends where its last descendant's does
  order.subtree_end.resize(n);
  for (int k = 0; k < n; ++k) order.subtree_end[k] = k + 1;
  for (int k = n - 1; k > 0; --k) {
    const int p = order.parent_position[k];
    order.subtree_end[p] = std::max(order.subtree_end[p], order.subtree_end[k]);
  }
}

AnchorOrder make_anchor_order(const Model& model, int anchor) {
  AnchorOrder order;
  AnchorOrderScratch scratch;
  scratch.reserve(model.segment_count());
  fill_anchor_order(model, make_incidence(model), anchor, order, scratch);
  return order;
}

namespace {

JointTerms make_joint_terms(const Model& model, const Joint& joint,
                            std::span<const PrepareJointFn> prepare) {
  JointTerms terms;
  terms.limit_free_w = limit_free_w(joint);
  terms.box = make_box_test(joint);
  terms.frame_shift = joint.frame_in_child * joint.frame_in_parent.conjugate();
  const std::array<const Segment*, 2> segments = {&model.segments[joint.parent],
                                                  &model.segments[joint.child]};
  const std::array<const Vector3d*, 2> anchors = {&joint.anchor_in_parent, &joint.anchor_in_child};
  for (int side = 0; side < 2; ++side) {
    const Segment& segment = *segments[side];
    const Vector3d& r = *anchors[side];
    terms.point_mass[side] = diagonal_point_mass_matrix(segment.inv_mass, segment.inv_inertia, r);
    terms.inv_inertia[side] = segment.inv_inertia;
    // what each rule keeps of the joint (its row's prepare_joint)
    for (const PrepareJointFn prepare_joint : prepare) prepare_joint(segment, r, side, terms);
  }
  return terms;
}

}  // namespace

std::shared_ptr<const ModelTables> make_model_tables(const Model& model,
                                                     std::span<const PrepareJointFn> prepare) {
  auto tables = std::make_shared<ModelTables>();
  tables->incidence = make_incidence(model);
  if (model.segment_count() <= kKeptOrderSegments) {
    AnchorOrderScratch scratch;
    scratch.reserve(model.segment_count());
    tables->orders.resize(model.segment_count());
    for (int anchor = 0; anchor < model.segment_count(); ++anchor) {
      fill_anchor_order(model, tables->incidence, anchor, tables->orders[anchor], scratch);
    }
  }
  tables->joints.reserve(model.joint_count());
  for (const Joint& joint : model.joints) {
    tables->joints.push_back(make_joint_terms(model, joint, prepare));
  }
  return tables;
}

}  // namespace puppet::procedural
