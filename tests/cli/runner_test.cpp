// The command line as a function (puppet/testbed/testbed.h), called over and over in one process
// as the Python package calls it: what one call's flags set is never seen by the next, refused
// calls included.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/cli_support.h"
#include "puppet/testbed/testbed.h"

namespace puppet::cli_test {
namespace {

testbed::Outcome call(std::vector<std::string> args) {
  args.insert(args.begin(), "testbed");
  return testbed::run_testbed(args, false);
}

const std::string kOutside =
    std::string(PUPPET_SOURCE_DIR) + "/tests/data/bad/mjcf_include_outside.xml";
const std::string kPublished =
    std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/published_style.xml";

TEST(TestbedRunner, ModelReadingOptionsLastOneCall) {
  for (int round = 0; round < 2; ++round) {
    EXPECT_EQ(call({"validate", kOutside}).status, 2);
    EXPECT_EQ(call({"validate", "--include-outside", kOutside}).status, 0);
    EXPECT_EQ(call({"validate", kOutside}).status, 2) << "--include-outside outlived its call";
    EXPECT_EQ(call({"export-mjcf", kOutside, "-o", "-"}).status, 2);
    EXPECT_EQ(call({"validate", "--strict", kPublished}).status, 2);
    EXPECT_EQ(call({"validate", kPublished}).status, 0) << "--strict outlived its call";
    // a call refused for another flag leaves nothing behind either
    const testbed::Outcome refused =
        call({"validate", "--strict", "--include-outside", "--engine-budget", "nan", kOutside});
    EXPECT_EQ(refused.status, 2);
    EXPECT_NE(refused.error.find("--engine-budget"), std::string::npos) << refused.error;
    EXPECT_EQ(call({"validate", kPublished}).status, 0);
    EXPECT_EQ(call({"validate", kOutside}).status, 2);
  }
}

TEST(TestbedRunner, AnEngineBudgetLastsOneCall) {
  const fs::path out = fresh_folder("runner_budget");
  const std::vector<std::string> run = {
      "run",  "--solver", "bullet-multibody", "--scenario",    "hang",  "--duration", "0.02",
      "--dt", "1/240",    "--no-timing",      "--no-accuracy", "--out", out.string()};
  std::vector<std::string> tight = run;
  tight.insert(tight.end(), {"--engine-budget", "1e-3"});
  for (int round = 0; round < 2; ++round) {
    const testbed::Outcome refused = call(tight);
    EXPECT_EQ(refused.status, 2);
    EXPECT_NE(refused.error.find("past the budget of 0.001 s (--engine-budget)"), std::string::npos)
        << refused.error;
    EXPECT_EQ(call(run).status, 0) << "the budget outlived its call";
  }
  fs::remove_all(out);
}

// the budget is a finite positive number of seconds: NaN (which every comparison lets through)
// and infinity are refused before anything runs, and the old results stay
TEST(TestbedRunner, AnEngineBudgetIsFinite) {
  for (const char* budget : {"nan", "NaN", "inf", "-inf", "0", "-1", "1e10"}) {
    const testbed::Outcome o = call({"validate", "--engine-budget", budget, "pinocchio"});
    EXPECT_EQ(o.status, 2) << budget;
    EXPECT_NE(o.error.find("--engine-budget"), std::string::npos) << budget << ": " << o.error;
  }
  const fs::path out = fresh_folder("runner_nan_budget");
  const std::vector<std::string> run = {
      "run",        "--solver", "procedural",  "--rule",        "xpbd",  "--scenario", "hang",
      "--duration", "0.02",     "--no-timing", "--no-accuracy", "--out", out.string()};
  ASSERT_EQ(call(run).status, 0);
  const std::string before = slurp(out / "summary.csv");
  std::vector<std::string> nan = run;
  nan.insert(nan.end(), {"--engine-budget", "nan"});
  EXPECT_EQ(call(nan).status, 2);
  EXPECT_EQ(slurp(out / "summary.csv"), before);
  fs::remove_all(out);
}

// an argument with a NUL byte would be read only up to it (a path cut short names another file)
TEST(TestbedRunner, ANulByteInAnArgumentIsRefused) {
  const testbed::Outcome o = call({"validate", std::string("pinocchio\0.json", 15)});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.error.find("holds a NUL byte"), std::string::npos) << o.error;
  EXPECT_EQ(o.error.find('\0'), std::string::npos);
  const fs::path out = fresh_folder("runner_nul");
  const testbed::Outcome run =
      call({"run", "--scenario", "hang", "--out", out.string() + std::string("\0x", 2)});
  EXPECT_EQ(run.status, 2);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace puppet::cli_test
