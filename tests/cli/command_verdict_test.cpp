// The verdict command end to end
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

// a small verdict end to end: both files, a row per scenario × solver × view × budget, a budget
// below the truth's floor refused with its reason, the chosen rows naming a candidate that was
// put through every start
TEST(TestbedCli, AVerdictWritesEveryRowAndRefusesABudgetBelowTheFloor) {
  const fs::path out = fresh_folder("verdict_command");
  const Outcome o = testbed(
      "verdict --model chain:3 --scenario hang --solver procedural,bullet-rigid --rule "
      "xpbd,literal "
      "--dt 1/30,1/60,1/120 --budget 1um,5cm --starts 3 --out " +
      out.string());
  ASSERT_EQ(o.status, 0) << o.output;
  std::ifstream in(out / "verdict.csv");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 1u + 3 * 2 * 2) << "header, then 3 solvers x 2 views x 2 budgets";
  int refused = 0, met = 0;
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].find(",1e-06,refused,") != std::string::npos) {
      ++refused;
      EXPECT_NE(lines[i].find("below the truth's floor"), std::string::npos) << lines[i];
    }
    if (lines[i].find(",met,") != std::string::npos) {
      ++met;
      EXPECT_NE(lines[i].find(",3,"), std::string::npos) << "survived 3 starts: " << lines[i];
    }
  }
  EXPECT_EQ(refused, 6);
  EXPECT_GE(met, 2) << "bullet-rigid and xpbd hold a 3-link chain within 5 cm";
  std::ifstream candidates(out / "candidates.csv");
  size_t rows = 0;
  for (std::string line; std::getline(candidates, line);) ++rows;
  // xpbd: 5 substep counts, literal: 1, bullet-rigid: 2 sweep counts; 3 dts each
  EXPECT_EQ(rows, 1u + (5 + 1 + 2) * 3);
  fs::remove_all(out);
}

}  // namespace
}  // namespace puppet::cli_test
