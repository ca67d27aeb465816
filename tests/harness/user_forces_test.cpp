// The user's forces in every engine (user_forces.h): each engine applies the same grab and the
// same tremble, computed by the same function from its own state; the grab's force stays under
// its cap however hard the path pulls; and the tremble moves every engine, truths included.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/user_forces.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

constexpr double kDt = 1.0 / 240.0;

Model pinocchio() { return load_model(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json"); }

SolverOptions one_substep() {
  SolverOptions options;
  options.procedural.substeps =
      1;  // the procedural user forces are the last substep's: the step's here
  return options;
}

// steps a solver through a scenario, calling `check` after each step with the state the step
// started from, the targets it was given and the time it started at
template <typename Check>
void run(Simulator& simulator, const Model& model, const Scenario& scenario, int steps,
         Check check) {
  simulator.reset(model, scenario);
  std::vector<BodyState> start(model.segment_count());
  std::vector<Vector3d> targets;
  for (int k = 0; k < steps; ++k) {
    simulator.read_state(start);
    scenario.targets_at((k + 1) * kDt, targets);
    simulator.set_pin_targets(targets);
    simulator.step(kDt);
    ASSERT_FALSE(simulator.diverged()) << k;
    check(start, targets, k * kDt);
  }
}

TEST(UserForcesInEngines, EveryEngineAppliesTheSameGrabAndTrembleToItsState) {
  const Model model = pinocchio();
  const Scenario scenario = make_scenario("tremble", model);
  ASSERT_TRUE(scenario.environment.tremble);
  ASSERT_TRUE(scenario.pins.back().pin.is_grab());
  std::vector<Pin> pins = scenario.initial_pins();
  std::vector<Wrench> expected(model.segment_count());
  for (const std::string& solver : solver_names()) {
    SCOPED_TRACE(solver);
    auto simulator = make_simulator(solver, one_substep());
    double largest = 0.0, worst = 0.0, tremble = 0.0;
    run(*simulator, model, scenario, 240,
        [&](const std::vector<BodyState>& start, const std::vector<Vector3d>& targets, double t) {
          for (size_t i = 0; i < pins.size(); ++i) pins[i].target = targets[i];
          user_wrenches(model, scenario.environment, pins, start, t, expected);
          const auto applied = simulator->user_wrenches();
          ASSERT_EQ(applied.size(), expected.size());
          for (size_t s = 0; s < expected.size(); ++s) {
            worst = std::max({worst, (applied[s].force - expected[s].force).norm(),
                              (applied[s].torque - expected[s].torque).norm()});
            largest = std::max(largest, expected[s].force.norm());
            if (static_cast<int>(s) != pins.back().segment) {
              tremble = std::max(tremble, expected[s].force.norm());
            }
          }
        });
    // to rounding, relative to the largest force: a target or a position off in its last bit
    // (~2e-16 m near 1 m) times the grab's stiffness (~1e4 N/m) is ~1e-12 N; measured up to
    // 3.1e-14 of the largest force (bullet-multibody), 1.6e-14 (procedural), where a wrong term
    // is off by newtons
    EXPECT_LE(worst, 1e-13 * largest);
    EXPECT_GT(largest, 1.0);   // N: the grab pulls
    EXPECT_GT(tremble, 1e-3);  // N: and the other segments tremble
  }
}

// a path far out of reach (the hand led 3 m away, by a spring ten times as stiff) asks for far
// more than the cap: the force reaches the cap and stays under it in every engine
TEST(UserForcesInEngines, TheGrabsForceNeverPassesItsCap) {
  const Model model = pinocchio();
  ScenarioOptions options;
  options.grab_spring = {.hz = 20.0, .damping_ratio = 1.0, .cap_weights = 0.05};
  Scenario scenario = make_scenario("drag", model, options);
  scenario.pins.back().radius = 3.0;
  const Pin grab = scenario.pins.back().pin;
  const double cap = grab.grab.max_force;
  EXPECT_DOUBLE_EQ(cap, 0.05 * model.total_mass * kStandardGravity);
  for (const std::string& solver : solver_names()) {
    SCOPED_TRACE(solver);
    auto simulator = make_simulator(solver, one_substep());
    double largest = 0.0;
    run(*simulator, model, scenario, 480,
        [&](const std::vector<BodyState>&, const std::vector<Vector3d>&, double) {
          largest = std::max(largest, simulator->user_wrenches()[grab.segment].force.norm());
        });
    EXPECT_LE(largest, cap * (1.0 + 1e-12));
    EXPECT_GE(largest, cap * (1.0 - 1e-9));  // the cap was reached
  }
}

// the tremble is a force every engine feels: a second of drag and of tremble end apart
TEST(UserForcesInEngines, TheTrembleMovesEveryEngine) {
  const Model model = pinocchio();
  const Scenario drag = make_scenario("drag", model);
  Scenario tremble = drag;
  tremble.environment.tremble = true;
  for (const std::string& solver : solver_names()) {
    SCOPED_TRACE(solver);
    std::vector<BodyState> ends[2];
    for (int k = 0; k < 2; ++k) {
      auto simulator = make_simulator(solver, SolverOptions{});
      run(*simulator, model, k == 0 ? drag : tremble, 240,
          [](const std::vector<BodyState>&, const std::vector<Vector3d>&, double) {});
      ends[k].resize(model.segment_count());
      simulator->read_state(ends[k]);
    }
    double apart = 0.0;
    for (int s = 0; s < model.segment_count(); ++s) {
      apart = std::max(apart, (ends[0][s].x - ends[1][s].x).norm());
    }
    EXPECT_GT(apart, 1e-5);  // m
  }
}

}  // namespace
}  // namespace puppet::compare
