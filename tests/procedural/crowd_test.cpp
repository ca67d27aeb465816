#include "puppet/procedural/crowd.h"

#include <gtest/gtest.h>

#include <memory>
#include <utility>
#include <vector>

#include "puppet/compare/scenario.h"

namespace puppet::procedural {
namespace {

// every puppet of a crowd, on 1 and on 3 threads, reaches bit for bit the state of a lone solver
// given the same start and targets; the puppets differ (tilt) so that a mix-up would show
TEST(Crowd, EveryPuppetMatchesALoneSolverBitForBit) {
  const Model model = compare::load_named_model("pinocchio");
  constexpr int kPuppets = 5;
  constexpr double kDt = 1.0 / 240.0;
  std::vector<compare::Scenario> scenarios;
  for (int k = 0; k < kPuppets; ++k) {
    compare::ScenarioOptions options;
    options.tilt_deg = 10.0 + 8.0 * k;
    scenarios.push_back(compare::make_scenario("drag", model, options));
  }
  Settings settings;
  settings.rule = Rule::kWeighted;
  const Environment& environment = scenarios[0].environment;

  std::vector<std::vector<BodyState>> lone(kPuppets);
  for (int k = 0; k < kPuppets; ++k) {
    Solver solver(model, settings, environment);
    solver.reset(scenarios[k].initial);
    solver.set_pins(scenarios[k].initial_pins());
    std::vector<Vector3d> targets;
    for (int step = 0; step < 120; ++step) {
      scenarios[k].targets_at((step + 1) * kDt, targets);
      solver.set_pin_targets(targets);
      solver.step(kDt);
    }
    lone[k] = solver.state().bodies;
  }

  // targets set by the caller between steps, or by the crowd's control on the stepping threads
  for (auto [threads, with_control] : {std::pair{1, false}, {3, false}, {1, true}, {3, true}}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads, control " << with_control);
    Crowd crowd(model, settings, environment, kPuppets, threads);
    ASSERT_EQ(crowd.threads(), threads);
    for (int k = 0; k < kPuppets; ++k) {
      crowd.puppet(k).reset(scenarios[k].initial);
      crowd.puppet(k).set_pins(scenarios[k].initial_pins());
    }
    std::vector<std::vector<Vector3d>> targets(kPuppets);  // one buffer per puppet: no race
    double t = 0.0;
    const Crowd::Control control = [&](int k, Solver& puppet) {
      scenarios[k].targets_at(t, targets[k]);
      puppet.set_pin_targets(targets[k]);
    };
    for (int step = 0; step < 120; ++step) {
      t = (step + 1) * kDt;
      if (with_control) {
        crowd.step(kDt, control);
        continue;
      }
      for (int k = 0; k < kPuppets; ++k) control(k, crowd.puppet(k));
      crowd.step(kDt);
    }
    for (int k = 0; k < kPuppets; ++k) {
      const auto& bodies = crowd.puppet(k).state().bodies;
      for (size_t s = 0; s < bodies.size(); ++s) {
        EXPECT_EQ(bodies[s].x, lone[k][s].x) << "puppet " << k;
        EXPECT_EQ(bodies[s].q.coeffs(), lone[k][s].q.coeffs());
        EXPECT_EQ(bodies[s].v, lone[k][s].v);
        EXPECT_EQ(bodies[s].w, lone[k][s].w);
      }
    }
  }
  // and the puppets really differ
  EXPECT_NE(lone[0][5].x, lone[1][5].x);
}

// a crowd's puppets share one set of model tables; tables built for another model are refused
TEST(Crowd, ModelTablesAreSharedOnlyWithinAModel) {
  const Model model = compare::load_named_model("pinocchio");
  const std::shared_ptr<const ModelTables> tables = make_model_tables(model);
  ASSERT_EQ(static_cast<int>(tables->orders.size()), model.segment_count());
  ASSERT_EQ(static_cast<int>(tables->joints.size()), model.joint_count());
  for (int anchor = 0; anchor < model.segment_count(); ++anchor) {
    EXPECT_EQ(tables->orders[anchor].anchor, anchor);
    EXPECT_EQ(static_cast<int>(tables->orders[anchor].links.size()), model.joint_count());
  }
  EXPECT_NO_THROW(Solver(model, Settings{}, Environment{}, tables));
  const Model chain = make_chain(3);
  EXPECT_THROW(Solver(chain, Settings{}, Environment{}, tables), std::invalid_argument);
}

TEST(Crowd, RejectsEmptyCounts) {
  const Model model = compare::load_named_model("pinocchio");
  EXPECT_THROW(Crowd(model, Settings{}, Environment{}, 0, 1), std::invalid_argument);
  EXPECT_THROW(Crowd(model, Settings{}, Environment{}, 1, 0), std::invalid_argument);
}

}  // namespace
}  // namespace puppet::procedural
