#include "puppet/compare/verdict.h"

#include "puppet/compare/output.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "../support/csv.h"
#include "../support/source_dir.h"

namespace puppet::compare {
namespace {

// a synthetic table: error falls and cost rises as dt shrinks, one rule's substeps in between
std::vector<Candidate> table() {
  std::vector<Candidate> out;
  const double dts[] = {1.0 / 30, 1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480};
  for (int i = 0; i < 5; ++i) {
    for (int substeps : {1, 4}) {
      Candidate c;
      c.solver = "procedural";
      c.rule = "xpbd";
      c.dt = dts[i];
      c.setting = "--substeps " + std::to_string(substeps);
      c.cost_us_per_s = 100.0 * substeps / dts[i];  // µs per simulated second
      c.error_m = 0.1 * dts[i] * 30.0 / substeps;   // first order in dt / substeps
      c.starts = 100;
      out.push_back(c);
    }
  }
  return out;
}

// within 1 cm the table has two at 6.25 mm for 48,000 µs per simulated second, 1/120 s with 4
// substeps and 1/480 s with 1 (the larger dt is taken); one planted at 1/90 s with 9 mm for
// 20,000 µs is cheaper
TEST(Verdict, FindsThePlantedOptimum) {
  std::vector<Candidate> c = table();
  const Choice before = cheapest(c, 0.01, 0.05);
  ASSERT_EQ(before.verdict, Verdict::kMet);
  EXPECT_DOUBLE_EQ(c[before.index].dt, 1.0 / 120);
  EXPECT_EQ(c[before.index].setting, "--substeps 4");
  Candidate planted = c[0];
  planted.dt = 1.0 / 90;
  planted.cost_us_per_s = 20000.0;
  planted.error_m = 0.009;
  c.push_back(planted);
  const Choice choice = cheapest(c, 0.01, 0.05);
  ASSERT_EQ(choice.verdict, Verdict::kMet);
  EXPECT_EQ(choice.index, static_cast<int>(c.size()) - 1);
  EXPECT_LT(choice.divergence_upper, 0.05);
}

TEST(Verdict, EqualCostsGoToTheLargerDt) {
  std::vector<Candidate> c(2);
  for (Candidate& x : c) {
    x.cost_us_per_s = 10.0;
    x.error_m = 0.001;
    x.starts = 100;
  }
  c[0].dt = 1.0 / 120;
  c[1].dt = 1.0 / 60;
  const Choice choice = cheapest(c, 0.01, 0.05);
  ASSERT_EQ(choice.verdict, Verdict::kMet);
  EXPECT_EQ(choice.index, 1);
}

TEST(Verdict, SaysWhyNothingMeetsIt) {
  std::vector<Candidate> c = table();
  EXPECT_EQ(cheapest(c, 1e-6, 0.05).verdict, Verdict::kErrorFloor);
  EXPECT_NEAR(cheapest(c, 1e-6, 0.05).best_error_m, 0.1 * 30.0 / 480 / 4, 1e-15);
  for (Candidate& x : c) x.diverged_starts = 3;  // 3 of 100: upper bound 0.085
  EXPECT_EQ(cheapest(c, 1.0, 0.05).verdict, Verdict::kNotRobust);
  EXPECT_EQ(cheapest(c, 1.0, 0.10).verdict, Verdict::kMet);
  for (Candidate& x : c) x.diverged = true;
  EXPECT_EQ(cheapest(c, 1.0, 0.10).verdict, Verdict::kDiverges);
  EXPECT_EQ(cheapest({}, 1.0, 0.10).verdict, Verdict::kNotMeasured);
}

// a contact scene's candidate that survives its starts but ends unlike the truth is not met
TEST(Verdict, OutcomesUnlikeTheTruthsAreNotMet) {
  std::vector<Candidate> c = table();
  const Choice met = cheapest(c, 1.0, 0.05);
  ASSERT_EQ(met.verdict, Verdict::kMet);
  c[met.index].outcome_ratio = 1.5;
  const Choice next = cheapest(c, 1.0, 0.05);
  EXPECT_EQ(next.verdict, Verdict::kMet);
  EXPECT_NE(next.index, met.index);
  for (Candidate& x : c) x.outcome_ratio = 1.01;
  EXPECT_EQ(cheapest(c, 1.0, 0.05).verdict, Verdict::kUnlikeTruth);
  for (Candidate& x : c) x.outcome_ratio = 1.0;  // at the bar: alike
  EXPECT_EQ(cheapest(c, 1.0, 0.05).verdict, Verdict::kMet);
  for (Candidate& x : c) x.diverged_starts = 3;
  EXPECT_EQ(cheapest(c, 1.0, 0.05).verdict, Verdict::kNotRobust);
}

TEST(Verdict, ABudgetBelowTheTruthsFloorIsRefused) {
  EXPECT_EQ(budget_problem(0.01, 0.0048), "");
  EXPECT_NE(budget_problem(0.001, 0.0048).find("below the truth's floor"), std::string::npos);
  EXPECT_NE(budget_problem(0.0, 0.0048), "");
  EXPECT_NE(budget_problem(NAN, 0.0048), "");
}

TEST(Verdict, TheSixtyHertzViewIsThePerSecondViewAtASixtiethOfASecond) {
  // at dt = 1/60 s one step is one frame: µs per frame is µs per step
  const double us_per_step = 42.0;
  const FrameCost frame = at_frame_rate(us_per_step * 60.0);
  EXPECT_DOUBLE_EQ(frame.us_per_frame, us_per_step);
  EXPECT_DOUBLE_EQ(frame.puppets_per_core, 1e6 / (us_per_step * 60.0));
}

// the frame view is the per-second view restricted to whole steps per frame: where the cheapest
// per second runs at 1/60 s both views choose it, and a step of 1/30 s, which a 60 Hz frame
// cannot take whole, is left out of the frame view only
TEST(Verdict, TheFrameViewIsThePerSecondViewInWholeStepsPerFrame) {
  std::vector<Candidate> c = table();
  EXPECT_EQ(steps_per_frame(1.0 / 60, 60.0), 1);
  EXPECT_EQ(steps_per_frame(1.0 / 240, 60.0), 4);
  EXPECT_EQ(steps_per_frame(1.0 / 30, 60.0), 0);
  EXPECT_EQ(steps_per_frame(1.0 / 90, 60.0), 0);
  // within 5 cm: 1/60 s with 1 substep (5 cm, 6,000 µs per simulated second) is the cheapest
  const Choice second = cheapest(c, 0.05, 0.05);
  const Choice frame = cheapest_per_frame(c, 0.05, 0.05, 60.0);
  ASSERT_EQ(second.verdict, Verdict::kMet);
  ASSERT_EQ(frame.verdict, Verdict::kMet);
  EXPECT_EQ(second.index, frame.index);
  EXPECT_DOUBLE_EQ(c[frame.index].dt, 1.0 / 60);
  EXPECT_DOUBLE_EQ(at_frame_rate(c[frame.index].cost_us_per_s, 60.0).us_per_frame, 100.0);
  // within 10 cm the per-second view takes 1/30 s (3,000 µs); a frame takes 1/60 s
  const Choice coarse = cheapest(c, 0.1, 0.05);
  ASSERT_EQ(coarse.verdict, Verdict::kMet);
  EXPECT_DOUBLE_EQ(c[coarse.index].dt, 1.0 / 30);
  const Choice framed = cheapest_per_frame(c, 0.1, 0.05, 60.0);
  ASSERT_EQ(framed.verdict, Verdict::kMet);
  EXPECT_DOUBLE_EQ(c[framed.index].dt, 1.0 / 60);
}

// "no divergence in N starts": 0 of N meets the bar, 1 of N does not
TEST(Verdict, TheRobustnessBarIsNoDivergenceInNStarts) {
  std::vector<Candidate> c(1);
  c[0].cost_us_per_s = 1.0;
  c[0].error_m = 0.001;
  c[0].dt = 1.0 / 60;
  for (int64_t n : {1, 8, 32, 100}) {
    c[0].starts = n;
    c[0].diverged_starts = 0;
    EXPECT_EQ(cheapest(c, 0.01, no_divergence_ceiling(n)).verdict, Verdict::kMet) << n;
    c[0].diverged_starts = 1;
    EXPECT_EQ(cheapest(c, 0.01, no_divergence_ceiling(n)).verdict, Verdict::kNotRobust) << n;
  }
  // the stated bound: 3.84 / (32 + 3.84) for 0 of 32
  EXPECT_NEAR(wilson_interval(0, 32).high, 0.1072, 5e-4);
}

// Richardson with the order the differences give: d1 = 1, d2 = 4 is p = 2 and a bar of
// 1.5 × 4/3 × 1 = 2; an order under 1/2 is taken as 1/2 (a bar of 1.5 × 3.41 × d1); the other
// truth's disagreement raises the floor, never lowers it
TEST(Verdict, TheTruthsFloorIsItsErrorBarOrTheTruthsDisagreement) {
  EXPECT_DOUBLE_EQ(truth_floor(1.0, 4.0, NAN), 2.0);
  EXPECT_DOUBLE_EQ(truth_floor(1.0, 4.0, 3.0), 3.0);
  EXPECT_DOUBLE_EQ(truth_floor(1.0, 4.0, 0.5), 2.0);
  EXPECT_NEAR(truth_floor(1.0, 1.0, NAN), 1.5 * std::sqrt(2.0) / (std::sqrt(2.0) - 1.0), 1e-12);
}

// every setting searched can be named back from the flags candidates.csv writes
TEST(Verdict, EverySettingSearchedIsFoundByItsFlags) {
  for (const char* rule : {"literal", "relaxed", "xpbd", "tree"}) {
    SolverConfig base{"procedural", {}};
    base.options.procedural.rule = *procedural::parse_rule(rule);
    for (const Setting& s : settings_searched(base.solver, base.options)) {
      const SolverOptions o = candidate_options("procedural", rule, s.flags);
      EXPECT_EQ(o.procedural.substeps, s.options.procedural.substeps) << rule << " " << s.flags;
      EXPECT_EQ(o.procedural.iterations, s.options.procedural.iterations) << rule << " " << s.flags;
      EXPECT_EQ(o.procedural.rule, base.options.procedural.rule);
    }
  }
  for (const char* solver : {"bullet-multibody", "mujoco"}) {
    for (const Setting& s : settings_searched(solver, {})) {
      const SolverOptions o = candidate_options(solver, "", s.flags);
      EXPECT_EQ(o.bullet.iterations, s.options.bullet.iterations) << s.flags;
      EXPECT_EQ(o.mujoco.integrator, s.options.mujoco.integrator) << s.flags;
    }
  }
  EXPECT_THROW(candidate_options("procedural", "xpbd", "--substeps 3"), ScenarioError);
  EXPECT_THROW(candidate_options("procedural", "magic", ""), ScenarioError);
  EXPECT_EQ(budget_text(0.01), "1cm");
  EXPECT_EQ(budget_text(0.05), "5cm");
  EXPECT_EQ(budget_text(0.001), "1mm");
  EXPECT_EQ(budget_text(5e-5), "50um");
}

// the committed verdict searched what the catalogue rows search: every configuration of every
// built engine (procedural once per rule), setting for setting; a grid changed in a row without
// the verdict re-run fails here
TEST(Verdict, TheCommittedCandidatesAreTheCataloguesSearch) {
  std::ifstream in(std::string(PUPPET_SOURCE_DIR) + "/results/verdict/candidates.csv");
  ASSERT_TRUE(in) << "results/verdict/candidates.csv";
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = test::split_csv_line(line);
  auto column = [&](const std::string& name) {
    const auto at = std::find(header.begin(), header.end(), name);
    EXPECT_NE(at, header.end()) << name;
    return static_cast<size_t>(at - header.begin());
  };
  const size_t solver = column("solver"), rule = column("rule"), setting = column("setting");
  using Key = std::tuple<std::string, std::string, std::string>;
  std::set<Key> committed;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = test::split_csv_line(line);
    ASSERT_GT(f.size(), std::max({solver, rule, setting})) << line;
    // an engine this build lacks (MuJoCo, ODE or Jolt left out) is not searched here
    const auto& built = solver_names();
    if (std::find(built.begin(), built.end(), f[solver]) == built.end()) continue;
    committed.insert({f[solver], f[rule], f[setting]});
  }
  std::set<Key> searched;
  for (const SolverConfig& config : solver_configs(solver_names(), procedural::kAllRules)) {
    for (const Setting& s : settings_searched(config.solver, config.options)) {
      searched.insert({config.solver, rule_of(config), s.flags});
      EXPECT_EQ(s.flags.empty(), s.label.empty()) << config.solver << " " << s.flags;
    }
  }
  EXPECT_EQ(committed, searched);
}

// the floors a sweep's summary.csv implies: the truth's h/2 and 2h rows and the second truth's,
// as testbed run writes them; another model, commit or a missing row is refused by name
TEST(Verdict, TheFloorsAreReadFromASweepsSummary) {
  const Model model = load_named_model("pinocchio");
  const std::vector<Truth> truths = truths_for(model, kDefaultEngineBudget);
  ASSERT_FALSE(truths.empty());
  auto row = [&](const std::string& scenario, const Truth& t, double dt, const std::string& metric,
                 double value, const std::string& sha) {
    return scenario + "," + t.solver + ",," + format_dt(dt) + ",1," + metric + "," +
           (metric == "truth_dt" ? "h" : "reseeded_mean") + "," + csv_number(value) + ",m," +
           model.name + ",truth,ok," + sha + ",a machine\n";
  };
  const Truth& first = truths[0];
  std::string text = std::string(kSummaryHeader) + "\n";
  text += row("hang", first, first.dt / 2, "truth_dt", first.dt, "abc");
  text += row("hang", first, first.dt / 2, "pose_err_m", 1e-4, "abc");
  text += row("hang", first, first.dt * 2, "pose_err_m", 4e-4, "abc");
  if (truths.size() > 1) text += row("hang", truths[1], truths[1].dt, "pose_err_m", 5e-4, "abc");
  const auto floors =
      floors_from_summary(text, "summary.csv", model, {"hang"}, "abc", kDefaultEngineBudget);
  ASSERT_EQ(floors.size(), 1u);
  // p = 2: a bar of 1.5 × 4/3 × 1e-4 = 2e-4, under the truths' disagreement of 5e-4
  EXPECT_NEAR(floors[0].floor, truths.size() > 1 ? 5e-4 : 2e-4, 1e-15);
  auto refused = [&](const std::string& summary, const std::vector<std::string>& scenarios,
                     const std::string& sha, const std::string& says) {
    try {
      floors_from_summary(summary, "summary.csv", model, scenarios, sha, kDefaultEngineBudget);
      ADD_FAILURE() << "accepted; expected: " << says;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused(text, {"hang"}, "def", "written at commit abc");
  refused(text, {"hang", "drag"}, "abc", "in drag");
  refused("scenario,solver\n", {"hang"}, "abc", "not a summary.csv");
  std::string other = text;
  other.replace(other.find(",pinocchio,"), 11, ",chain-3,");
  refused(other, {"hang"}, "abc", "a run of model chain-3");
}

}  // namespace
}  // namespace puppet::compare
