// An engine's own error inside a step (MuJoCo's mju_error, whose default handler waits for Enter
// and exits; ODE's internal assertions, which abort) is that run's divergence, said in one line:
// the command goes on, its other runs and its results are whole.
#include <sstream>

#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

const std::string kData = std::string(PUPPET_SOURCE_DIR) + "/tests/data/engine_errors/";

struct Provoked {
  const char* engine;
  const char* model;  // in tests/data/engine_errors/
  const char* flags;
  const char* scenario;
  const char* line;  // the one line it says
};

// Models found by the fourth hostile corpus and its search: segments of 1e6 and 1e-6 kg in turn.
// MuJoCo's sparse Newton solver (nv ≥ 60) finds its Hessian rank-deficient; ODE's dWorldStep trips
// an assertion in its LDLT update under a hard pin.
constexpr Provoked kProvoked[] = {
    {"mujoco", "mujoco_rank_deficient.json", "", "drop",
     "mujoco: MuJoCo stopped a step with its error \"Rank-defficient Hessian in HessianDirect\"; "
     "the run reads as diverged"},
    {"ode", "ode_ldlt_assert.json", "--ode-stepper step", "marionette",
     "ode: ODE stopped a step with its error \"assertion \"d[i] != dReal(0.0)\" failed in "
     "dxLDLTRemove()"},
};

TEST(TestbedCli, AnEnginesOwnErrorIsThatRunsDivergence) {
  for (const Provoked& p : kProvoked) {
    const fs::path out = fresh_folder(std::string("engine_error_") + p.engine);
    const std::string common = "--model " + kData + p.model + " --solver " + p.engine + " " +
                               p.flags + " --dt 1/240 --duration 1 --no-accuracy --no-timing" +
                               " --out " + out.string();
    // the old results: a scenario that holds
    const Outcome old = testbed("run " + common + " --scenario hang");
    ASSERT_EQ(old.status, 0) << old.output;
    const Outcome o = testbed("run " + common + " --scenario hang," + p.scenario);
    EXPECT_EQ(o.status, 0) << p.engine << "\n" << o.output;
    EXPECT_NE(o.output.find(p.line), std::string::npos) << p.engine << "\n" << o.output;
    // one line for the one run that met the error
    std::istringstream lines(o.output);
    int said = 0;
    for (std::string line; std::getline(lines, line);) {
      said += line.rfind(p.engine + std::string(": "), 0) == 0;
    }
    EXPECT_EQ(said, 1) << o.output;
    // the new results, whole: the provoked run diverged, and the other run is there too
    const std::string summary = slurp(out / "summary.csv");
    EXPECT_NE(summary.find(std::string(p.scenario) + "," + p.engine + ",,0.00416666667,1," +
                           "diverged_at_s,value,"),
              std::string::npos)
        << summary;
    EXPECT_NE(summary.find("hang," + std::string(p.engine)), std::string::npos) << summary;
    fs::remove_all(out);
  }
}

// the divergence's reason is the engine's error, not a non-finite state: robustness.csv says so
TEST(TestbedCli, AnEnginesErrorIsItsOwnDivergenceReason) {
  const fs::path out = fresh_folder("engine_error_reason");
  const Outcome o = testbed("robustness --model " + kData +
                            "mujoco_rank_deficient.json --solver mujoco --scenario collapse "
                            "--dt 1/240 --duration 1 --starts 4 --out " +
                            out.string());
  EXPECT_EQ(o.status, 0) << o.output;
  const std::string rows = slurp(out / "robustness.csv");
  EXPECT_NE(rows.find("engine error"), std::string::npos) << rows;
  fs::remove_all(out);
}

}  // namespace
}  // namespace puppet::cli_test
