// The procedural solver against independent answers: the analytic physical pendulum, a
// Lagrangian double pendulum integrated here, conservation of momentum, and its own invariants
// (joints closed, limits held, finite, deterministic).
#include "puppet/procedural/solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "puppet/compare/metrics.h"
#include "puppet/compare/scenario.h"
#include "puppet/model/rotation.h"
#include "support/pendulum.h"
#include "support/rule_runs.h"
#include "support/source_dir.h"
#include "support/spinning_box.h"
#include "support/state_hash.h"

namespace puppet::procedural {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";
constexpr double kDt = 1.0 / 240.0;
// pinned: any change to the solver's arithmetic shows here first (update it deliberately)
constexpr uint64_t kExpectedDragHash = 0x21228d73504755e3ULL;

using test::analytic_period;
using test::rods;
using test::rods_at;
using test::top_pin;

// the rules whose pass closes every joint exactly (the seed's); xpbd closes to a residual
// (xpbd_test.cpp)
constexpr std::array kClosingRules = {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted,
                                      Rule::kSubtree, Rule::kRelaxed};

double max_joint_gap(const Model& model, const State& state) {
  std::vector<double> gaps(model.joint_count());
  compare::joint_gaps(model, state.bodies, gaps);
  double worst = 0;
  for (double g : gaps) worst = std::max(worst, g);
  return worst;
}

double max_limit_violation_rad(const Model& model, const State& state) {
  double worst = 0;
  for (const Joint& j : model.joints) {
    const Quaterniond q_rel =
        joint_relative_rotation(j, state.bodies[j.parent].q, state.bodies[j.child].q);
    worst = std::max(worst, limit_violation(j, q_rel));
  }
  return worst;
}

// period from upward zero crossings of ω_x, over `seconds`
double measured_period(Rule rule, double seconds) {
  const Model model = rods(1);
  Settings settings;
  settings.rule = rule;
  Solver solver(model, settings, Environment{});
  solver.reset(rods_at({10.0 * M_PI / 180.0}));
  const Pin pins[] = {top_pin()};
  solver.set_pins(pins);
  test::PeriodMeter meter;
  for (int k = 0; k < std::lround(seconds / kDt); ++k) {
    solver.step(kDt);
    meter.add((k + 1) * kDt, kDt, solver.state().bodies[0].w.x());
  }
  return meter.period();
}

TEST(Pendulum, PeriodMatchesThePhysicalPendulum) {
  const double expected = analytic_period(10.0 * M_PI / 180.0);
  for (Rule rule : {Rule::kWeighted, Rule::kSubtree, Rule::kRelaxed}) {
    const double period = measured_period(rule, 12.0);
    std::printf("[ period   ] %-8s %.6f s vs analytic %.6f s: %+.3f %%\n",
                std::string(rule_name(rule)).c_str(), period, expected,
                100 * (period / expected - 1));
    EXPECT_NEAR(period / expected, 1.0, 0.01) << rule_name(rule);
  }
  // reported, not required: the literal rule never swings, smoothed runs fast
  for (Rule rule : {Rule::kLiteral, Rule::kSmoothed}) {
    std::printf("[ period   ] %-8s %.6f s (not required)\n", std::string(rule_name(rule)).c_str(),
                measured_period(rule, 12.0));
  }
}

TEST(Pendulum, DoublePendulumAgainstLagrange) {
  for (Rule rule : kAllRules) {
    Settings settings;
    settings.rule = rule;
    const double error = test::double_pendulum_error(settings, kDt);
    std::printf("[ 2 rods   ] %-8s mean pose error over 5 s: %.4f m\n",
                std::string(rule_name(rule)).c_str(), error);
    if (rule == Rule::kRelaxed) {
      EXPECT_LT(error, 0.03);
    }
  }
}

TEST(FreeBody, MomentumOfASpinningBox) {
  const test::SpinResult spin = test::spin_box(Settings{}, kDt);
  std::printf("[ momentum ] |L| drift over 10 s: %+.2e, direction drift %.2e rad\n",
              spin.momentum_ratio - 1, spin.direction_drift);
  EXPECT_EQ(spin.end_velocity, Vector3d::Zero());
  EXPECT_NEAR(spin.momentum_ratio, 1.0, 1e-3);
}

std::unique_ptr<Solver> scenario_solver(const Model& model, const compare::Scenario& scenario,
                                        Rule rule) {
  Settings settings;
  settings.rule = rule;
  auto solver = std::make_unique<Solver>(model, settings, scenario.environment);
  solver->reset(scenario.initial);
  solver->set_pins(scenario.initial_pins());
  return solver;
}

// single-pin scenarios: every joint closed and inside its limits after every step
TEST(Scenarios, JointsClosedAndLimitsHeldEveryStep) {
  const Model model = load_model(kPinocchio);
  compare::ScenarioOptions options;
  options.hz = 2.0;  // yank at 2 Hz: the stability claim
  for (const char* name : {"hang", "yank"}) {
    const compare::Scenario scenario = compare::make_scenario(name, model, options);
    for (Rule rule : kClosingRules) {
      auto solver = scenario_solver(model, scenario, rule);
      std::vector<Vector3d> targets;
      double worst_gap = 0, worst_limit = 0, peak_speed = 0;
      bool finite = true;
      for (int k = 0; k < std::lround(scenario.duration / kDt); ++k) {
        scenario.targets_at((k + 1) * kDt, targets);
        solver->set_pin_targets(targets);
        solver->step(kDt);
        finite = finite && !solver->state().diverged;
        worst_gap = std::max(worst_gap, max_joint_gap(model, solver->state()));
        worst_limit = std::max(worst_limit, max_limit_violation_rad(model, solver->state()));
        peak_speed = std::max(peak_speed, compare::peak_speed(solver->state().bodies));
      }
      std::printf(
          "[ %-8s ] %-8s max gap %.1e m, max limit violation %.1e rad, peak speed %.1f m/s\n", name,
          std::string(rule_name(rule)).c_str(), worst_gap, worst_limit, peak_speed);
      EXPECT_TRUE(finite) << name << " " << rule_name(rule);
      EXPECT_LE(worst_gap, 1e-9) << name << " " << rule_name(rule);
      EXPECT_LE(worst_limit, 1e-6) << name << " " << rule_name(rule);
    }
  }
}

// a two-pin scenario run to its end (or its divergence): the worst gaps seen after any step
struct TwoPinRun {
  double anchor_pin = 0, joint = 0;        // m
  double second_pin = 0, mean_second = 0;  // m
  bool diverged = false;
};
TwoPinRun run_two_pins(const Model& model, const compare::Scenario& scenario, Rule rule) {
  auto solver = scenario_solver(model, scenario, rule);
  std::vector<Vector3d> targets;
  std::vector<double> pin_gap(2);
  TwoPinRun run;
  double sum_pin = 0;
  const int steps = static_cast<int>(std::lround(scenario.duration / kDt));
  for (int k = 0; k < steps && !solver->state().diverged; ++k) {
    scenario.targets_at((k + 1) * kDt, targets);
    solver->set_pin_targets(targets);
    solver->step(kDt);
    run.joint = std::max(run.joint, max_joint_gap(model, solver->state()));
    compare::pin_gaps(scenario.initial_pins(), targets, solver->state().bodies, pin_gap);
    run.anchor_pin = std::max(run.anchor_pin, pin_gap[0]);
    run.second_pin = std::max(run.second_pin, pin_gap[1]);
    sum_pin += pin_gap[1];
  }
  run.mean_second = sum_pin / steps;
  run.diverged = solver->state().diverged;
  return run;
}

// two pins: the pass starts from the first, so joints stay closed; the second pin's gap is what
// the rule leaves, reported
TEST(Scenarios, TwoPinScenariosKeepJointsClosedAndReportThePinGap) {
  const Model model = load_model(kPinocchio);
  for (const char* name : {"marionette", "shake"}) {
    const compare::Scenario scenario = test::with_hard_hand(compare::make_scenario(name, model));
    for (Rule rule : kClosingRules) {
      const TwoPinRun run = run_two_pins(model, scenario, rule);
      std::printf("[ %-8s ] %-8s second pin gap: max %.3f m, mean %.3f m\n", name,
                  std::string(rule_name(rule)).c_str(), run.second_pin, run.mean_second);
      EXPECT_LT(run.anchor_pin, 1e-9) << "the anchor's pin is closed exactly";
      EXPECT_FALSE(run.diverged) << name << " " << rule_name(rule);
      EXPECT_LE(run.joint, 1e-9) << name << " " << rule_name(rule);
    }
  }
}

// relaxed shares the second pin through its sweeps. In `drag` the hand's circle drives the right
// shoulder onto its limit (from 0.95 s): a sweep that corrected each limit right after its own
// joint left the shoulder up to 31° past it, the final pass clamped it and let the hand go by up
// to 0.50 m. Correcting every limit after every joint holds the hand within 4.2 mm; 1 cm is the
// bound.
TEST(Scenarios, RelaxedHoldsTheDraggedHandWhileTheShoulderIsOnItsLimit) {
  // the swing–twist shoulder this was measured on; with the box limits relaxed lets the hand go
  // by 0.26 m in drag (the shoulder at two faces of its box, REPORT.md's findings)
  const Model model = load_model(test::kPinocchioSwingTwistPath);
  const TwoPinRun run =
      run_two_pins(model, compare::make_scenario("marionette", model), Rule::kRelaxed);
  EXPECT_FALSE(run.diverged);
  EXPECT_LT(run.second_pin, 0.01);
}

// a user drags a hand far past what the elbow and shoulder allow: limits still hold, whether the
// hand is the anchor (edges walked against the model) or a second pin
TEST(Scenarios, LimitsHoldWhenALimbIsDraggedAgainstThem) {
  const Model model = load_model(kPinocchio);
  const int hand = model.find_segment("r_forearm");
  const int pelvis = model.find_segment("pelvis");
  Pin grab;
  grab.segment = hand;
  grab.local_point = Vector3d(0, 0, -0.14);
  Pin hip;
  hip.segment = pelvis;
  hip.target = model.segments[pelvis].rest_position;
  for (bool hand_first : {true, false}) {
    for (Rule rule : kClosingRules) {
      Settings settings;
      settings.rule = rule;
      Solver solver(model, settings, Environment{});
      grab.target = model.segments[hand].rest_position + Vector3d(-0.3, -0.2, -0.1);
      const std::vector<Pin> pins =
          hand_first ? std::vector<Pin>{grab, hip} : std::vector<Pin>{hip, grab};
      solver.set_pins(pins);
      double worst = 0;
      for (int k = 0; k < 480; ++k) {
        // the hand is pulled behind the back and up over the head
        const double t = (k + 1) * kDt;
        const Vector3d target =
            model.segments[hand].rest_position + Vector3d(-0.5 * t, -0.2, 0.6 * t);
        const std::vector<Vector3d> targets = hand_first
                                                  ? std::vector<Vector3d>{target, hip.target}
                                                  : std::vector<Vector3d>{hip.target, target};
        solver.set_pin_targets(targets);
        solver.step(kDt);
        worst = std::max(worst, max_limit_violation_rad(model, solver.state()));
      }
      EXPECT_LE(worst, 1e-6) << rule_name(rule) << (hand_first ? " hand first" : " hip first");
    }
  }
}

TEST(Determinism, DragAfterThousandSteps) {
  const Model model = load_model(test::kPinocchioSwingTwistPath);  // where the hash was pinned
  // marionette: the hand on a hard pin, as drag's was when the hash was pinned
  const compare::Scenario scenario = compare::make_scenario("marionette", model);
  uint64_t hashes[2];
  for (uint64_t& hash : hashes) {
    auto solver = scenario_solver(model, scenario, Rule::kRelaxed);
    std::vector<Vector3d> targets;
    for (int k = 0; k < 1000; ++k) {
      scenario.targets_at((k + 1) * kDt, targets);
      solver->set_pin_targets(targets);
      solver->step(kDt);
    }
    hash = test::state_hash(solver->state().bodies);
  }
  std::printf("[ hash     ] %016llx\n", static_cast<unsigned long long>(hashes[0]));
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], kExpectedDragHash);
}

// flagged at the end of the (sub)step where it appeared: relaxed's one step, xpbd's first substep
TEST(Divergence, NonFiniteStateIsFlaggedNotThrown) {
  const Model model = rods(2);
  for (const Rule rule : {Rule::kRelaxed, Rule::kXpbd}) {
    SCOPED_TRACE(rule_name(rule));
    Solver solver(model, Settings{.rule = rule}, Environment{});
    std::vector<BodyState> bodies = solver.state().bodies;
    bodies[1].v.x() = NAN;
    solver.place(bodies);
    EXPECT_NO_THROW(solver.step(kDt));
    EXPECT_TRUE(solver.state().diverged);
    EXPECT_NEAR(solver.state().diverged_time, kDt / rule_info(rule).substeps, 1e-15);
  }
}

}  // namespace
}  // namespace puppet::procedural
