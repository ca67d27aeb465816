#include "puppet/compare/verdict.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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

}  // namespace
}  // namespace puppet::compare
