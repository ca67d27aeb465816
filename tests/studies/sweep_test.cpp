// sweep.cpp: the sweep's summary in the tidy schema with its accuracy rows, the same whatever the
// number of threads; accuracy.cpp's rows of the truth against itself.
#include "puppet/compare/sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "puppet/compare/output.h"
#include "support/csv.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

// a small sweep: a four-link chain hanging, three solvers, two dts, 1.2 s (enough for every
// accuracy stat and for 8 re-seeded runs of 0.5 s)
SweepSpec small_sweep(const Model& model, int jobs, bool timing) {
  SweepSpec spec;
  spec.model = &model;
  spec.scenarios = {make_scenario("hang", model)};
  spec.configs = {{"procedural", {}}, {"bullet-multibody", {}}, {"bullet-rigid", {}}};
  spec.dts = {1.0 / 60, 1.0 / 120};
  spec.run.duration = 1.2;
  spec.run.timing = timing;
  spec.jobs = jobs;
  return spec;
}

TEST(Sweep, SummaryHasEveryRunItsAccuracyAndStableUnits) {
  const Model model = make_chain(4);
  const std::vector<RunResult> results = run_sweep(small_sweep(model, 2, true));
  // a chain of unlimited balls is exact in MuJoCo: it is the first truth, bullet-multibody the
  // second (when the build has MuJoCo); the runs, then per truth its h/2 and 2h runs against its
  // h, then each truth against the other
  const std::vector<Truth> truths = truths_for(model, kDefaultEngineBudget);
  const bool second = truths.size() == 2;
  ASSERT_EQ(truths[0].solver, second ? "mujoco" : "bullet-multibody");
  ASSERT_EQ(results.size(), 3u * 2u + (second ? 6u : 2u));
  const std::string csv = summary_csv(results, {"chain:4", "abc", "machine"});
  std::stringstream in(csv);
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line, kSummaryHeader);
  const std::map<std::string, std::string> units = {
      {"joint_gap_m", "m"},           {"pin_gap_m", "m"},         {"limit_violation_deg", "deg"},
      {"energy_drift", "1"},          {"peak_speed_mps", "m/s"},  {"step_us", "us"},
      {"realtime_factor", "1"},       {"update_us", "us"},        {"adjust_us", "us"},
      {"contacts_us", "us"},          {"velocities_us", "us"},    {"pose_err_m", "m"},
      {"joint_angle_err_deg", "deg"}, {"reseeded_diverged", "1"}, {"truth_dt", "s"}};
  // (solver, dt, reference) → the accuracy stats seen
  std::map<std::tuple<std::string, std::string, std::string>, std::set<std::string>> accuracy;
  std::set<std::pair<std::string, std::string>> timed;
  std::map<std::string, std::pair<std::string, double>> truth_dt;  // reference → (solver, h)
  while (std::getline(in, line)) {
    const auto cells = test::split_csv_line(line);
    ASSERT_EQ(cells.size(), 14u) << line;
    ASSERT_TRUE(units.count(cells[5])) << cells[5];
    EXPECT_EQ(cells[8], units.at(cells[5])) << line;
    EXPECT_TRUE(std::isfinite(std::stod(cells[7]))) << line;
    EXPECT_TRUE(cells[10].empty() || cells[10] == kTruthReference || cells[10] == "pairwise" ||
                (second && cells[10] == kSecondTruthReference))
        << line;
    EXPECT_EQ(cells[11], "ok") << line;
    if (cells[5] == "pose_err_m") accuracy[{cells[1], cells[3], cells[10]}].insert(cells[6]);
    if (cells[5] == "step_us") timed.insert({cells[1], cells[3]});
    if (cells[5] == "truth_dt") truth_dt[cells[10]] = {cells[1], std::stod(cells[7])};
  }
  const std::set<std::string> all = {"at_0.267s", "at_0.5s",       "at_1s",
                                     "mean_1s",   "reseeded_mean", "reseeded_max"};
  for (const std::string dt : {"0.0166666667", "0.00833333333"}) {
    for (const std::string solver : {"procedural", "bullet-multibody", "bullet-rigid"}) {
      EXPECT_EQ((accuracy[{solver, dt, kTruthReference}]), all) << solver << " " << dt;
      if (second) {
        EXPECT_EQ((accuracy[{solver, dt, kSecondTruthReference}]), all) << solver;
      }
      EXPECT_TRUE(timed.count({solver, dt})) << solver << " " << dt;
      // pairwise against bullet-multibody at the same dt, for the others only
      const bool paired = solver != "bullet-multibody";
      EXPECT_EQ(accuracy.count({solver, dt, "pairwise"}), paired ? 1u : 0u) << solver;
    }
  }
  // each truth's h/2 and 2h runs against its h, never timed, and the rows that name it
  for (const Truth& truth : truths) {
    SCOPED_TRACE(truth.reference);
    EXPECT_EQ(truth_dt[truth.reference].first, truth.solver);
    EXPECT_NEAR(truth_dt[truth.reference].second, truth.dt, 5e-9 * truth.dt);  // 9 digits
    for (const double dt : {truth.dt / 2, 2 * truth.dt}) {
      const std::string text = format_dt(dt);
      EXPECT_EQ((accuracy[{truth.solver, text, truth.reference}]), all) << text;
      EXPECT_FALSE(timed.count({truth.solver, text}));
    }
  }
  if (second) {
    // each truth at its h against the other
    EXPECT_EQ((accuracy[{"mujoco", "0.000130208333", kSecondTruthReference}]), all);
    EXPECT_EQ((accuracy[{"bullet-multibody", "0.000260416667", kTruthReference}]), all);
  }

  // bullet-multibody is first order: halving dt roughly halves its error against the truth, and
  // the truth's own difference to h/2 is far below both
  auto reseeded = [&](const RunResult& r) {
    for (const SummaryRow& row : r.summary) {
      if (row.metric == "pose_err_m" && row.stat == "reseeded_mean" &&
          row.reference != "pairwise") {
        return row.value;
      }
    }
    return std::numeric_limits<double>::quiet_NaN();
  };
  const double coarse = reseeded(results[2]), fine = reseeded(results[3]),
               check = reseeded(results[6]), truth_coarse = reseeded(results[7]);
  EXPECT_EQ(results[2].solver, "bullet-multibody");
  EXPECT_EQ(results[6].solver, truths[0].solver);
  EXPECT_EQ(results[6].dt, truths[0].dt / 2);
  EXPECT_EQ(results[7].dt, truths[0].dt * 2);
  std::printf(
      "[ sweep ] chain:4 hang bullet-multibody re-seeded: %.2e m (1/60) %.2e m (1/120); the "
      "truth (%s) at h/2 %.2e m, at 2h %.2e m\n",
      coarse, fine, truths[0].solver.c_str(), check, truth_coarse);
  EXPECT_GT(coarse / fine, 1.4);
  EXPECT_LT(coarse / fine, 2.8);
  EXPECT_LT(10 * check, fine);
  // the truth converges: its 2h run is further from h than its h/2 run, by 2^p with p ≥ 1 (a
  // first-order pin or better)
  EXPECT_GT(truth_coarse / check, 1.8);

  // a chain of free ball joints is the same physics in both engines: the truths agree within a
  // few times bullet-multibody's own (first-order) difference to h/2, and neither leaves the
  // absent limits
  if (second) {
    const double bullet_check = reseeded(results[8]);
    const RunResult& agreement = results[10];
    ASSERT_EQ(agreement.solver, "mujoco");
    double reseeded_agreement = NAN, violation = NAN, pin_gap = NAN;
    for (const SummaryRow& row : agreement.summary) {
      if (row.metric == "pose_err_m" && row.stat == "reseeded_mean") reseeded_agreement = row.value;
      if (row.metric == "limit_violation_deg") violation = row.value;
      if (row.metric == "pin_gap_m" && row.stat == "max") pin_gap = row.value;
    }
    // hung from an exact ball joint to the world, MuJoCo's pin does not move
    EXPECT_LT(pin_gap, 1e-9);
    std::printf("[ sweep ] chain:4 hang: the truths agree to %.2e m re-seeded\n",
                reseeded_agreement);
    EXPECT_LT(reseeded_agreement, 5 * bullet_check);
    EXPECT_EQ(violation, 0.0);
  }
}

// MuJoCo judges first where it models every joint exactly; a swing–twist ball limit (its cone
// in MuJoCo) leaves bullet-multibody first
TEST(Sweep, TheFirstTruthIsTheEngineThatModelsTheLimitsExactly) {
  if (!reference::have_mujoco()) GTEST_SKIP() << "no MuJoCo in this build";
  const auto pinocchio = truths_for(
      load_model(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json"), kDefaultEngineBudget);
  ASSERT_EQ(pinocchio.size(), 2u);
  EXPECT_EQ(pinocchio[0].solver, "mujoco");
  EXPECT_EQ(pinocchio[0].reference, kTruthReference);
  EXPECT_EQ(pinocchio[1].solver, "bullet-multibody");
  EXPECT_EQ(pinocchio[1].reference, kSecondTruthReference);
  const auto swing_twist =
      truths_for(load_model(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio-swing-twist.json"),
                 kDefaultEngineBudget);
  ASSERT_EQ(swing_twist.size(), 2u);
  EXPECT_EQ(swing_twist[0].solver, "bullet-multibody");
  EXPECT_EQ(swing_twist[1].solver, "mujoco");
}

TEST(Sweep, ParallelJobsGiveTheSameSummary) {
  const Model model = make_chain(4);
  const OutputContext context{"chain:4", "abc", "machine"};
  const std::string one = summary_csv(run_sweep(small_sweep(model, 1, false)), context);
  const std::string two = summary_csv(run_sweep(small_sweep(model, 2, false)), context);
  EXPECT_EQ(one, two);
}

TEST(Sweep, TheTruthAgainstItselfHasZeroError) {
  const Model model = make_chain(4);
  const Scenario hang = make_scenario("hang", model);
  auto simulator = make_simulator(kBulletTruthSolver, {});
  const Trajectory truth = record_trajectory(*simulator, model, hang, kBulletTruthDt, 1.2);
  const auto rows = accuracy_rows(*simulator, model, hang, kBulletTruthDt, truth, truth, "truth");
  ASSERT_EQ(rows.size(), 2u * 6u + 1u);
  for (const SummaryRow& row : rows) {
    if (row.stat.rfind("reseeded", 0) == 0) {
      // re-seeding goes through set_state, which rounds the joint coordinates
      EXPECT_LT(row.value, 1e-9) << row.metric << " " << row.stat;
    } else {
      EXPECT_EQ(row.value, 0.0) << row.metric << " " << row.stat;
    }
  }
}

}  // namespace
}  // namespace puppet::compare
