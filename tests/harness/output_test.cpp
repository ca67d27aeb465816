// run.cpp and output.cpp: a short run, its summary in the tidy schema, its file names.
#include "puppet/compare/output.h"

#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "puppet/compare/run.h"
#include "support/csv.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

RunResult short_hang() {
  const Model model = load_model(kPinocchio);
  const Scenario scenario = make_scenario("hang", model);
  SolverOptions relaxed;  // whose joints close to rounding
  relaxed.procedural.rule = procedural::Rule::kRelaxed;
  auto simulator = make_simulator("procedural", relaxed);
  RunOptions options;
  options.duration = 0.25;
  options.sample_hz = 30;
  return run_scenario(*simulator, model, scenario, options);
}

TEST(Output, SummaryIsTidyWithStableUnits) {
  const RunResult result = short_hang();
  const std::string csv = summary_csv({result}, {"pinocchio", "abc123", "test machine x2"});
  std::stringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, kSummaryHeader);
  const std::map<std::string, std::string> units = {
      {"joint_gap_m", "m"},     {"pin_gap_m", "m"},        {"limit_violation_deg", "deg"},
      {"energy_drift", "1"},    {"peak_speed_mps", "m/s"}, {"step_us", "us"},
      {"realtime_factor", "1"}, {"update_us", "us"},       {"adjust_us", "us"},
      {"contacts_us", "us"},    {"velocities_us", "us"}};
  std::map<std::string, int> seen;
  while (std::getline(in, line)) {
    const auto cells = test::split_csv_line(line);
    ASSERT_EQ(cells.size(), 14u) << line;
    EXPECT_EQ(cells[0], "hang");
    EXPECT_EQ(cells[1], "procedural");
    EXPECT_EQ(cells[2], "relaxed");
    EXPECT_EQ(cells[3], "0.00416666667");  // 9 significant digits
    EXPECT_EQ(cells[4], "1");
    ASSERT_TRUE(units.count(cells[5])) << cells[5];
    EXPECT_EQ(cells[8], units.at(cells[5])) << cells[5];
    EXPECT_NO_THROW(std::stod(cells[7]));
    EXPECT_EQ(cells[9], "pinocchio");
    EXPECT_EQ(cells[11], "ok");
    ++seen[cells[5]];
  }
  EXPECT_EQ(seen.size(), units.size());
}

TEST(Output, RunKeepsTracesAndSampledPoses) {
  const RunResult result = short_hang();
  EXPECT_EQ(result.trace.size(), 61u);       // t = 0 and 60 steps
  EXPECT_EQ(result.poses.size(), 14u * 8u);  // t = 0 and every 8th step
  EXPECT_LT(result.value("joint_gap_m", "max"), 1e-9);
  EXPECT_GT(result.value("step_us", "median"), 0.0);
  EXPECT_EQ(trace_stem("chain:4", result), "chain-4__hang__procedural__relaxed__0.00416666667");
  const std::string poses = poses_csv(load_model(kPinocchio), result);
  EXPECT_EQ(poses.substr(0, poses.find('\n')), "t,segment,x,y,z,qw,qx,qy,qz");
}

// a stand-in solver whose state turns non-finite at its 10th step
class FailingSimulator : public Simulator {
 public:
  std::string name() const override { return "failing"; }
  void reset(const Model& model, const Scenario& scenario) override {
    bodies_ = scenario.initial;
    steps_ = 0;
    (void)model;
  }
  void set_pins(std::span<const Pin>) override {}
  void set_pin_targets(std::span<const Vector3d>) override {}
  void step(double) override {
    if (++steps_ == 10) bodies_[3].x.z() = NAN;
  }
  void set_time(double) override {}
  std::span<const Wrench> user_wrenches() const override { return {}; }
  void read_state(std::span<BodyState> out) const override {
    std::copy(bodies_.begin(), bodies_.end(), out.begin());
  }
  void set_state(std::span<const BodyState> bodies) override {
    bodies_.assign(bodies.begin(), bodies.end());
  }
  std::unique_ptr<Snapshot> snapshot() const override { return nullptr; }
  void restore(const Snapshot&) override {}
  bool diverged() const override { return false; }

 private:
  std::vector<BodyState> bodies_;
  int steps_ = 0;
};

TEST(Output, DivergenceIsReportedWithItsTime) {
  const Model model = load_model(kPinocchio);
  const Scenario scenario = make_scenario("hang", model);
  FailingSimulator simulator;
  RunOptions run;
  run.timing = false;
  const RunResult result = run_scenario(simulator, model, scenario, run);
  ASSERT_TRUE(result.diverged);
  EXPECT_NEAR(result.value("diverged_at_s", "value"), 10 * run.dt, 1e-12);
  EXPECT_EQ(result.trace.size(), 10u);  // t = 0 and nine finite steps
  const std::string csv = summary_csv({result}, {"pinocchio", "x", "y"});
  EXPECT_NE(csv.find(",diverged,"), std::string::npos);
}

}  // namespace
}  // namespace puppet::compare
