// What the solver reads that depends on the model alone, built once per model and shared by
// every solver of it: the tree's order from each anchor, the joints' constant terms and the
// segments' incidence. Private to procedural/ (tests include it to check the tables).
#pragma once

#include <array>
#include <memory>
#include <vector>

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

// A ball's Euler box as a test that needs no trigonometry (joint_limits.cpp, surely_inside_box):
// each angle's range as the cosines and sines of its ends
struct BoxTest {
  bool enabled = false;  // an Euler box whose ranges contain 0, the middle one within ±85°
  std::array<int, 3> axes{0, 1, 2};
  double sign = 1.0;  // +1 for a cyclic order (xyz, yzx, zxy), −1 for the others
  std::array<double, 3> lower_cos{}, lower_sin{}, upper_cos{}, upper_sin{};
  std::array<bool, 3> wide{};  // the range is wider than a half turn
};

// What the corrections read of one joint. A segment's inertia is diagonal and constant in its own
// frame, and so is its joint point, so everything here is too: [0] is the parent's side, [1] the
// child's (index by b_is_child).
struct JointTerms {
  // cos(ρ/2) for the largest angle ρ that no limit of the joint can reach (limit_free_w())
  double limit_free_w = 2.0;
  // an Euler box's ranges, to tell a rotation surely inside without its angles (make_box_test())
  BoxTest box;
  // Fc ⊗ Fp⁻¹, the joint's frame in the child carried into the parent's: w is unchanged by
  // conjugation, so w(q_rel) = w(Fp⁻¹ q_p⁻¹ q_c Fc) = q_p · (q_c ⊗ frame_shift), a 4-D dot product
  // that tells a joint surely inside its limits without forming q_rel
  Quaterniond frame_shift = Quaterniond::Identity();
  // K = E/m − [r]× D⁻¹ [r]× of the joint point, r its offset from the segment's centre:
  // relaxed's shared corrections add the two sides' K in one frame
  std::array<Matrix3d, 2> point_mass;
  // each side's inverse inertia (diagonal, its frame): the metric a limit's shared correction is
  // the smallest in (limit_error)
  std::array<Vector3d, 2> inv_inertia;
  // the weighted rule's rotation vector of that side per unit gap, both in its frame:
  // D⁻¹ [r]× K⁻¹ (the minimum-energy correction of the gap, made a constant matrix)
  std::array<Matrix3d, 2> rotation_gain;
  // the literal rule: |r × s|² below which moving that side closes the joint by translation alone
  // (literal_still_cross(), squared; at least the parallel threshold)
  std::array<double, 2> literal_still_cross2{0.0, 0.0};
};

// Everything the solver reads that depends on the model alone, built once. Solvers of one model
// (a crowd's puppets) share one table instead of each holding a copy.
// Every anchor's order is kept for models of up to kKeptOrderSegments segments (O(n²) memory:
// 0.9 MB for 128); a larger model keeps none, and each solver fills the orders it needs into its
// workspace when its anchor changes (O(n) each, see anchor_order()).
inline constexpr int kKeptOrderSegments = 128;
struct ModelTables {
  std::vector<AnchorOrder> orders;  // by anchor segment: every one, or none for a large model
  std::vector<JointTerms> joints;   // by joint
  Incidence incidence;
};

}  // namespace puppet::procedural
