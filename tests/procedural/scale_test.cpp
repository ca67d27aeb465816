// Setup is linear in segments: a model above kKeptOrderSegments keeps no anchor orders (every
// anchor's would be O(n²)), its solvers fill the ones they need in O(n), and the results are the
// same bits as with every order kept.
#include <gtest/gtest.h>
#include <malloc.h>

#include "model_tables.h"
#include "puppet/model/environment.h"
#include "puppet/procedural/solver.h"
#include "support/state_hash.h"

namespace puppet::procedural {
namespace {

double heap_bytes() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd);
}

// a chain lying on the ground, held by a segment in its middle: the pin anchors the adjust pass
// and each contact re-anchors it at the segment that hit deepest, so orders change every step
uint64_t run_chain(const Model& model, Rule rule, std::shared_ptr<const ModelTables> tables) {
  Settings settings;
  settings.rule = rule;
  Environment environment;
  environment.ground = true;
  Solver solver(model, settings, environment, std::move(tables));
  std::vector<BodyState> bodies = rest_pose(model);
  const Quaterniond lie(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()));
  for (BodyState& b : bodies) {
    b.x = lie * b.x + Vector3d(0, 0, 0.02);
    b.q = lie * b.q;
  }
  solver.reset(bodies);
  const int middle = model.segment_count() / 2;
  Pin pin;
  pin.segment = middle;
  pin.target = bodies[middle].x + Vector3d(0, 0, 0.3);
  solver.set_pins(std::span<const Pin>(&pin, 1));
  for (int k = 0; k < 60; ++k) solver.step(1.0 / 240.0);
  EXPECT_FALSE(solver.state().diverged);
  return test::state_hash(solver.state().bodies);
}

TEST(Scale, LargeModelsFillTheirOrdersAndAgreeBitForBit) {
  const Model model = make_chain(kKeptOrderSegments + 72);
  const auto lazy = make_model_tables(model);
  EXPECT_TRUE(lazy->orders.empty());
  // the same tables with every order kept, as a small model's are
  auto kept = std::make_shared<ModelTables>(*lazy);
  for (int anchor = 0; anchor < model.segment_count(); ++anchor) {
    kept->orders.push_back(make_anchor_order(model, anchor));
  }
  for (const Rule rule : {Rule::kLiteral, Rule::kSubtree, Rule::kRelaxed, Rule::kXpbd}) {
    EXPECT_EQ(run_chain(model, rule, lazy), run_chain(model, rule, kept)) << rule_name(rule);
  }
}

// memory per segment does not grow with the model: 4 000 and 16 000 segments
TEST(Scale, SolverMemoryIsLinearInSegments) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's allocator does not fill mallinfo2";
#endif
  double per_segment[2] = {0, 0};
  const int sizes[2] = {4000, 16000};
  for (int i = 0; i < 2; ++i) {
    const Model model = make_chain(sizes[i]);
    const double before = heap_bytes();
    {
      Settings settings;
      settings.rule = Rule::kTree;
      Solver solver(model, settings, Environment{});
      solver.step(1.0 / 240.0);
      per_segment[i] = (heap_bytes() - before) / sizes[i];
      EXPECT_FALSE(solver.state().diverged);
    }
  }
  std::printf("[ memory   ] solver and tables %.0f and %.0f bytes per segment\n", per_segment[0],
              per_segment[1]);
  EXPECT_NEAR(per_segment[1] / per_segment[0], 1.0, 0.05);
  EXPECT_LT(per_segment[1], 8192.0);
}

}  // namespace
}  // namespace puppet::procedural
