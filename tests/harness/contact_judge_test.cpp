// The contact scenes' judge (contact_judge.h): the two-sample statistic against its textbook
// values and its level, the violations read from a run's trace, and the verdict's rows for a
// contact scene.
#include "puppet/compare/contact_judge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "puppet/compare/metrics.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/verdict.h"

namespace puppet::compare {
namespace {

TEST(ContactJudge, TheKsStatisticIsTheLargestGapOfTheEmpiricalDistributions) {
  const std::vector<double> a{1, 2, 3, 4}, b{3, 4, 5, 6};
  // at 2: F_a = 1/2, F_b = 0
  EXPECT_DOUBLE_EQ(ks_statistic(a, b), 0.5);
  EXPECT_DOUBLE_EQ(ks_statistic(a, a), 0.0);
  EXPECT_DOUBLE_EQ(ks_statistic(std::vector<double>{0, 1}, std::vector<double>{2, 3}), 1.0);
  // ties: at 1, F_a = 2/3 and F_b = 1/3; at 2 both are 1
  EXPECT_NEAR(ks_statistic(std::vector<double>{1, 1, 2}, std::vector<double>{1, 2, 2}), 1.0 / 3,
              1e-15);
  // unequal sizes, order of the samples does not matter
  EXPECT_DOUBLE_EQ(ks_statistic(std::vector<double>{3, 1, 2}, std::vector<double>{2.5}), 2.0 / 3);
  EXPECT_TRUE(std::isnan(ks_statistic(std::vector<double>{}, a)));
}

TEST(ContactJudge, TheCriticalValueIsTheTablesAtFivePercent) {
  // Smirnov's asymptotic c(0.05) = 1.358 (every table of the two-sample test)
  EXPECT_NEAR(ks_critical(32, 32, 0.05), 1.358 * std::sqrt(2.0 / 32), 1e-3);
  EXPECT_NEAR(ks_critical(100, 50, 0.01), 1.628 * std::sqrt(150.0 / 5000), 1e-3);
}

// uniform numbers from a fixed SplitMix64 stream: the test's level and power, measured
double uniform(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

TEST(ContactJudge, TheTestRejectsOneDistributionAtMostItsLevelAndAShiftedOneAlmostAlways) {
  uint64_t state = 7;
  const int trials = 2000, n = 32;
  const double critical = ks_critical(n, n, 0.05);
  int same = 0, shifted = 0;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> a(n), b(n), c(n);
    for (int i = 0; i < n; ++i) {
      a[i] = uniform(state);
      b[i] = uniform(state);
      c[i] = uniform(state) + 0.5;  // shifted by half the range
    }
    same += ks_statistic(a, b) > critical;
    shifted += ks_statistic(a, c) > critical;
  }
  // the asymptotic value is conservative at n = 32: the rate is at most the level, not far under
  EXPECT_LE(same, 0.05 * trials);
  EXPECT_GE(same, 0.01 * trials);
  EXPECT_GE(shifted, 0.99 * trials);
}

TEST(ContactJudge, OutcomesAreHeldToTheLargerOfTheCriticalValueAndTheTruthsOwnStatistic) {
  std::vector<ContactOutcome> truth(32), near(32), far(32);
  for (int i = 0; i < 32; ++i) {
    truth[i] = {0.1 + 0.01 * i, 0.5 + 0.01 * i, 1.0 + 0.03 * i};
    near[i] = truth[i];
    near[i].rest_time_s += 0.03;  // one rank: a statistic of 1/32
    far[i] = truth[i];
    far[i].com_travel_m += 0.2;  // 20 ranks: 20/32
  }
  const std::array<double, kOutcomeCount> none{NAN, NAN, NAN};
  EXPECT_TRUE(compare_outcomes(near, truth, none).alike());
  const OutcomeComparison c = compare_outcomes(far, truth, none);
  EXPECT_FALSE(c.alike());
  EXPECT_EQ(c.worst, 1);
  EXPECT_NEAR(c.statistic[1], 20.0 / 32, 1e-12);
  EXPECT_NEAR(c.worst_ratio, (20.0 / 32) / ks_critical(32, 32, kOutcomeAlpha), 1e-12);
  // when the truths themselves are that far apart, the bar is theirs
  EXPECT_TRUE(compare_outcomes(far, truth, {NAN, 0.7, NAN}).alike());
  // no runs: never alike
  EXPECT_FALSE(compare_outcomes({}, truth, none).alike());
}

// a trace by hand: the energy's rises count over its least value while nothing is in the ground
TEST(ContactJudge, EnergyGainedIsCountedOverTheLeastEnergyOutOfContact) {
  const Model model = load_named_model("chain:3");
  const Scenario scenario = make_scenario("drop", model);
  RunResult run;
  auto step = [&](double t, double drift, double penetration) {
    StepMetrics m;
    m.t = t;
    m.energy_drift = drift;
    m.penetration = penetration;
    run.trace.push_back(m);
  };
  step(0.0, 0.0, 0.0);
  step(0.1, -0.2, 0.002);   // in the ground: a soft contact holds energy the sum misses
  step(0.2, -0.05, 0.001);  // and gives it back: not a gain (still under 0)
  step(0.3, -0.3, 0.0);     // out of the ground, the least so far
  step(0.4, -0.1, 0.0);     // a gain of 0.2 E_ref
  const ContactViolations v = contact_violations(model, scenario, run);
  const double e_ref = energy_reference(model, scenario.environment, scenario.initial);
  EXPECT_NEAR(v.energy_gain_m, 0.2 * e_ref / (model.total_mass * kStandardGravity), 1e-12);
  EXPECT_DOUBLE_EQ(v.penetration_m, 0.002);
  EXPECT_STREQ(v.worst_name(), v.energy_gain_m > 0.002 ? "energy gained" : "penetration");
  EXPECT_DOUBLE_EQ(first_contact_time(run), 0.1);
}

TEST(ContactJudge, TheGroundScenesAreJudgedByContactAndStartTouchingOrAMetreUp) {
  const Model model = load_named_model("pinocchio");
  for (const std::string& name : scenario_names()) {
    EXPECT_EQ(judged_by_contact(name), name == "drop" || name == "collapse") << name;
  }
  for (const auto& [name, height] : {std::pair{"drop", 1.0}, std::pair{"collapse", 0.0}}) {
    const Scenario s = make_scenario(name, model);
    double lowest = INFINITY;
    for (int i = 0; i < model.segment_count(); ++i) {
      double low = 0.0, high = 0.0;
      vertical_extent(model.segments[i], s.initial[i].q, s.initial[i].x, &low, &high);
      lowest = std::min(lowest, low);
    }
    EXPECT_NEAR(lowest, height, 1e-12) << name;
    EXPECT_TRUE(s.environment.ground) << name;
  }
}

// the verdict on a contact scene: rows with numbers and reasons, none refused for the fall's
// chaos, and the truths' window, floor and outcomes in contact.csv
TEST(ContactJudge, TheVerdictJudgesADropWithoutRefusingIt) {
  const Model model = load_named_model("chain:3");
  VerdictSpec spec;
  spec.model = &model;
  spec.scenarios = {"drop"};
  spec.solvers = {{"procedural", {}}};
  spec.solvers[0].options.procedural.rule = procedural::Rule::kTree;
  spec.dts = {1.0 / 60, 1.0 / 240};
  spec.budgets_m = {0.01, 0.05};
  spec.starts = 8;
  spec.jobs = 2;
  const VerdictResult result = run_verdict(spec);
  ASSERT_EQ(result.contact.size(), 1u);
  const ContactScene& scene = result.contact[0];
  EXPECT_GT(scene.first_contact_s, 0.3);  // about √(2 · 1 m / g) = 0.45 s, less the tilt
  EXPECT_LT(scene.first_contact_s, 0.5);
  EXPECT_GE(scene.window_end_s, scene.first_contact_s + kContactWindowAfter - 1e-12);
  EXPECT_EQ(scene.truth_outcomes.size(), 8u);
  ASSERT_EQ(result.floors.size(), 1u);
  EXPECT_LT(result.floors[0].floor, 0.01);  // the truths agree on the first impact
  for (const Candidate& c : result.candidates) {
    if (c.diverged) continue;
    EXPECT_FALSE(c.measure.empty());
    EXPECT_GE(c.error_m, c.window_error_m);
    EXPECT_GE(c.error_m, c.violations.worst());
  }
  for (const VerdictRow& row : result.rows) {
    EXPECT_NE(row.verdict, kRefused) << row.why;
  }
  const std::string csv = verdict_contact_csv(result, {"chain-3", "abc", "a machine"});
  EXPECT_NE(csv.find("drop,truth,mujoco,window_error,floor,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("ks_critical"), std::string::npos);
}

}  // namespace
}  // namespace puppet::compare
