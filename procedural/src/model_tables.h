// What the solver reads that depends on the model alone, built once per model and shared by
// every solver of it: the tree's order from each anchor, the joints' constant terms and the
// segments' incidence. Private to procedural/ (tests include it to check the tables).
#pragma once

#include <array>
#include <memory>
#include <span>
#include <vector>

#include "joint_terms.h"
#include "puppet/model/model.h"

namespace puppet::procedural {

// An order of the tree from one anchor, computed once per anchor: segments in depth-first
// preorder, each with the joint that places it and the segment it hangs from in this order.
struct AnchorOrder {
  struct Link {
    int joint = -1;
    int a = -1;              // placed already
    int b = -1;              // moved now
    bool b_is_child = true;  // false when the edge is walked against the model's direction
  };
  int anchor = -1;
  std::vector<Link> links;           // links[k] places preorder[k + 1]
  std::vector<int> preorder;         // segments, anchor first
  std::vector<int> subtree_end;      // preorder position one past the subtree of preorder[k]
  std::vector<int> parent_position;  // preorder position of the segment preorder[k] hangs from
  // links in breadth-first order: parents still come before children, and consecutive links
  // (siblings, cousins) are independent, so the processor overlaps their latency. A one-sided
  // pass of single segments gives bit for bit the same result in any parent-first order.
  std::vector<AnchorOrder::Link> level_links;
};
// the joints at each segment, both ways (compressed rows: joints[offsets[s] .. offsets[s + 1]))
struct Incidence {
  std::vector<int> offsets;
  std::vector<int> joints;
};
Incidence make_incidence(const Model& model);
// scratch of fill_anchor_order, sized by the model: filling allocates nothing once reserved
struct AnchorOrderScratch {
  std::vector<int> position, depth, depth_start;
  struct Frame {
    int segment, via_joint, from_position;
  };
  std::vector<Frame> stack;
  void reserve(int segments);
};
// the order from `anchor` into `order` in O(n), reusing its storage (no allocation when `order`
// has held an order of this model and `scratch` is reserved for it)
void fill_anchor_order(const Model& model, const Incidence& incidence, int anchor,
                       AnchorOrder& order, AnchorOrderScratch& scratch);
AnchorOrder make_anchor_order(const Model& model, int anchor);

inline constexpr int kKeptOrderSegments = 128;
struct ModelTables {
  std::vector<AnchorOrder> orders;  // by anchor segment: every one, or none for a large model
  std::vector<JointTerms> joints;   // by joint
  Incidence incidence;
};

// the tables of `model`, each joint's terms filled in by every rule's `prepare` (the rule
// catalogue's; procedural::make_model_tables(model) passes them)
std::shared_ptr<const ModelTables> make_model_tables(const Model& model,
                                                     std::span<const PrepareJointFn> prepare);

}  // namespace puppet::procedural
