// What depends on the model alone (model_tables.cpp): the tree orders from every anchor, filled
// in place for a large model, and each joint's constants: the weighted rule's gain against a
// generic least-energy solve, and the point mass matrices as the point's response to an impulse.
#include "model_tables.h"

#include <gtest/gtest.h>

#include <cmath>

#include "puppet/model/model.h"
#include "puppet/procedural/solver.h"
#include "support/source_dir.h"

namespace puppet::procedural {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

TEST(AnchorOrder, PreorderWithContiguousSubtrees) {
  const Model model = load_model(kPinocchio);
  const AnchorOrder order = make_anchor_order(model, model.find_segment("r_forearm"));
  ASSERT_EQ(order.preorder.size(), 14u);
  EXPECT_EQ(order.preorder[0], model.find_segment("r_forearm"));
  EXPECT_EQ(order.subtree_end[0], 14);
  // the first link is walked against the model: the upper arm is the forearm's parent
  EXPECT_FALSE(order.links[0].b_is_child);
  EXPECT_EQ(order.links[0].b, model.find_segment("r_upper_arm"));
  for (size_t k = 1; k < order.preorder.size(); ++k) {
    const int p = order.parent_position[k];
    EXPECT_LT(p, static_cast<int>(k));
    EXPECT_LE(order.subtree_end[k], order.subtree_end[p]);
  }
}

// The weighted rule's constant gain against a generic minimum-norm solve: a segment moved by
// Δx and turned by ω (its frame) so that its joint point r moves by the gap s, to first order
// Δx + ω × r = s, with the least kinetic energy ½ m |Δx|² + ½ ωᵀ D ω. In y = (√m Δx, √D ω) that
// is the least-norm y of A y = s, A = [E/√m, −[r]× D^(−1/2)], solved here by pseudo-inverse.
TEST(JointTerms, WeightedGainIsTheLeastEnergyCorrection) {
  const Model model = load_model(kPinocchio);
  const std::shared_ptr<const ModelTables> tables = make_model_tables(model);
  const Vector3d gap(0.003, -0.001, 0.002);
  for (int j = 0; j < model.joint_count(); ++j) {
    const Joint& joint = model.joints[j];
    for (int side = 0; side < 2; ++side) {
      const Segment& segment = model.segments[side == 0 ? joint.parent : joint.child];
      const Vector3d& r = side == 0 ? joint.anchor_in_parent : joint.anchor_in_child;
      Eigen::Matrix<double, 3, 6> a;
      a.leftCols<3>() = Matrix3d::Identity() / std::sqrt(segment.mass);
      Matrix3d r_cross;
      r_cross << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
      const Vector3d inv_sqrt_inertia = segment.inertia.cwiseSqrt().cwiseInverse();
      a.rightCols<3>() = -r_cross * inv_sqrt_inertia.asDiagonal();
      const Eigen::Matrix<double, 6, 1> y =
          a.completeOrthogonalDecomposition().pseudoInverse() * gap;
      const Vector3d omega = inv_sqrt_inertia.cwiseProduct(y.tail<3>());
      const JointTerms& terms = tables->joints[j];
      EXPECT_LT((terms.rotation_gain[side] * gap - omega).norm(), 1e-9 * omega.norm() + 1e-15)
          << model.joints[j].name << " side " << side;
      // and K is A Aᵀ, the point's response to an impulse
      EXPECT_LT((terms.point_mass[side] - a * a.transpose()).norm(),
                1e-12 * terms.point_mass[side].norm())
          << model.joints[j].name << " side " << side;
    }
  }
}

TEST(AnchorOrder, EveryAnchorReachesEverySegmentOnceThroughItsJoints) {
  const Model model = load_model(kPinocchio);
  for (int anchor = 0; anchor < model.segment_count(); ++anchor) {
    const AnchorOrder order = make_anchor_order(model, anchor);
    std::vector<int> seen(model.segment_count(), 0);
    for (int s : order.preorder) ++seen[s];
    for (int s = 0; s < model.segment_count(); ++s) EXPECT_EQ(seen[s], 1) << anchor << " " << s;
    // every link joins a placed segment a to the next one b by its joint, parent-first
    ASSERT_EQ(order.links.size(), static_cast<size_t>(model.joint_count()));
    std::vector<bool> placed(model.segment_count(), false);
    placed[anchor] = true;
    for (const AnchorOrder::Link& link : order.links) {
      const Joint& joint = model.joints[link.joint];
      EXPECT_TRUE(placed[link.a]) << anchor;
      EXPECT_FALSE(placed[link.b]) << anchor;
      EXPECT_EQ(link.b_is_child ? joint.child : joint.parent, link.b);
      EXPECT_EQ(link.b_is_child ? joint.parent : joint.child, link.a);
      placed[link.b] = true;
    }
  }
}

TEST(AnchorOrder, AFilledOrderIsTheOrderMade) {
  // a large model keeps no orders: each solver fills the one it needs in place (O(n), no
  // allocation once reserved); it must be the order make_anchor_order gives
  const Model model = load_model(kPinocchio);
  const Incidence incidence = make_incidence(model);
  AnchorOrder filled;
  AnchorOrderScratch scratch;
  scratch.reserve(model.segment_count());
  for (int anchor = 0; anchor < model.segment_count(); ++anchor) {
    fill_anchor_order(model, incidence, anchor, filled, scratch);
    const AnchorOrder made = make_anchor_order(model, anchor);
    EXPECT_EQ(filled.preorder, made.preorder) << anchor;
    EXPECT_EQ(filled.subtree_end, made.subtree_end) << anchor;
    EXPECT_EQ(filled.parent_position, made.parent_position) << anchor;
    ASSERT_EQ(filled.links.size(), made.links.size());
    ASSERT_EQ(filled.level_links.size(), made.level_links.size());
    for (size_t k = 0; k < made.links.size(); ++k) {
      EXPECT_EQ(filled.links[k].b, made.links[k].b) << anchor;
      EXPECT_EQ(filled.links[k].joint, made.links[k].joint) << anchor;
      EXPECT_EQ(filled.level_links[k].b, made.level_links[k].b) << anchor;
    }
  }
}

}  // namespace
}  // namespace puppet::procedural
