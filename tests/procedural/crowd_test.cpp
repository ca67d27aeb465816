#include "puppet/procedural/crowd.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>

#include <memory>
#include <utility>
#include <vector>

#include "model_tables.h"
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

// A thread done with its own range takes puppets from the back of another's: every puppet is
// still stepped exactly once per step, and the same as alone. The first thread's puppets are made
// slow (its control sleeps), so the other thread runs out of work and must take some of them.
TEST(Crowd, AThreadDoneEarlyTakesTheOthersPuppetsEachSteppedOnce) {
  const Model model = compare::load_named_model("pinocchio");
  constexpr int kPuppets = 96, kSteps = 5;  // 48 per thread: 3 of the chunks a thread takes
  constexpr double kDt = 1.0 / 240.0;
  Settings settings;
  settings.rule = Rule::kWeighted;
  const Environment environment;
  Crowd crowd(model, settings, environment, kPuppets, 2);
  std::array<std::atomic<int>, kPuppets> calls{};
  std::atomic<int> taken{0};  // slow puppets stepped by another thread than the caller's
  const std::thread::id caller = std::this_thread::get_id();
  const Crowd::Control control = [&](int k, Solver&) {
    calls[k].fetch_add(1);
    if (k < kPuppets / 2) {
      if (std::this_thread::get_id() != caller) taken.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
  for (int step = 0; step < kSteps; ++step) crowd.step(kDt, control);

  Solver lone(model, settings, environment);
  for (int step = 0; step < kSteps; ++step) lone.step(kDt);
  for (int k = 0; k < kPuppets; ++k) {
    EXPECT_EQ(calls[k].load(), kSteps) << "puppet " << k;
    const auto& bodies = crowd.puppet(k).state().bodies;
    for (size_t s = 0; s < bodies.size(); ++s) {
      EXPECT_EQ(bodies[s].x, lone.state().bodies[s].x) << "puppet " << k;
      EXPECT_EQ(bodies[s].q.coeffs(), lone.state().bodies[s].q.coeffs()) << "puppet " << k;
    }
  }
  EXPECT_GT(taken.load(), 0);
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
