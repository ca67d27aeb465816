// The run command: a short run's files, and a model an engine refuses judged before anything runs
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

TEST(TestbedCli, ShortRunWritesSummaryAndTraces) {
  const fs::path out = fresh_folder("run");
  const Outcome o =
      testbed("run --scenario hang,spin --rule weighted --duration 0.2 --sample-hz 30 --out " +
              out.string());
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
  EXPECT_TRUE(
      fs::exists(out / "traces" / "pinocchio__hang__procedural__weighted__0.00416666667.csv"));
  EXPECT_TRUE(fs::exists(out / "traces" /
                         "pinocchio__spin__procedural__weighted__0.00416666667__poses.csv"));
  // --solver all: the references run the same scenarios, without a rule
  for (const std::string solver : {"bullet-multibody", "bullet-rigid"}) {
    EXPECT_TRUE(fs::exists(out / "traces" /
                           ("pinocchio__spin__" + solver + "__-__0.00416666667__poses.csv")));
  }
  std::ifstream summary(out / "summary.csv");
  const std::string text((std::istreambuf_iterator<char>(summary)), {});
  EXPECT_NE(text.find("\nhang,bullet-multibody,,0.00416666667,1,joint_gap_m,max,"),
            std::string::npos);
  EXPECT_NE(text.find("\nspin,bullet-rigid,,0.00416666667,1,momentum_drift,angular_max,"),
            std::string::npos);
  EXPECT_NE(o.output.find("joint gap m"), std::string::npos);  // the table
  fs::remove_all(out);
}

// One verdict per model, before any run: a model MuJoCo's compiler refuses (a hinge whose range
// is [0, 0], which the model allows) is named by validate, refused when --solver names mujoco, and
// leaves mujoco out with one note when --solver is all, the other runs going ahead
TEST(TestbedCli, AModelAnEngineRefusesIsJudgedBeforeAnyRun) {
  const fs::path folder = fresh_folder("verdict");
  fs::create_directories(folder);
  std::string json = slurp(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json");
  json.replace(json.find("\"range_deg\": [-5, 145]"), 23, "\"range_deg\": [0, 0]");
  const fs::path model = folder / "stiff_elbow.json";
  write_text(model, json);
  const Outcome validate = testbed("validate " + model.string());
  EXPECT_EQ(validate.status, 0) << validate.output;
  // jolt where this build has it (Node.js and its package): the last of list's solvers
  const std::string jolt =
      testbed("list").output.find(" jolt\n") != std::string::npos ? ", jolt" : "";
  EXPECT_NE(validate.output.find("engines: procedural, bullet-multibody, bullet-rigid, ode" + jolt +
                                 "\n"),
            std::string::npos)
      << validate.output;
  EXPECT_NE(validate.output.find("not mujoco: the compiler rejected the model"), std::string::npos);
  const std::string out = " --out " + (folder / "out").string();
  const std::string run = "run --model " + model.string() +
                          " --scenario hang --dt 1/60 --duration 0.1 --no-timing --no-accuracy";
  expect_bad(run + " --solver mujoco" + out, "--solver: mujoco cannot run");
  expect_bad(run + " --solver procedural,mujoco" + out, "--solver: mujoco cannot run");
  EXPECT_FALSE(fs::exists(folder / "out"));
  const Outcome all = testbed(run + " --rule xpbd" + out);
  EXPECT_EQ(all.status, 0) << all.output;
  EXPECT_EQ(all.output.rfind("testbed: note: mujoco left out, it cannot run", 0), 0u) << all.output;
  const std::string summary = slurp(folder / "out" / "summary.csv");
  EXPECT_NE(summary.find(",bullet-rigid,"), std::string::npos);
  EXPECT_EQ(summary.find(",mujoco,"), std::string::npos);

  // a box limit: every engine builds it, so a run has every solver and a truth
  const std::string box = std::string(PUPPET_SOURCE_DIR) + "/tests/data/two_rods_box.json";
  const Outcome shown_box = testbed("validate " + box);
  EXPECT_NE(shown_box.output.find("box zxy [-50, 70] [-30, 40] [-20, 25]"), std::string::npos)
      << shown_box.output;
  EXPECT_NE(shown_box.output.find(
                "engines: procedural, bullet-multibody, bullet-rigid, mujoco, ode" + jolt + "\n"),
            std::string::npos)
      << shown_box.output;
  const Outcome box_all = testbed("run --model " + box +
                                  " --scenario hang --dt 1/240 --duration 0.2 --no-timing"
                                  " --rule tree" +
                                  out);
  EXPECT_EQ(box_all.status, 0) << box_all.output;
  EXPECT_EQ(box_all.output.find("note:"), std::string::npos) << box_all.output;
  const std::string box_summary = slurp(folder / "out" / "summary.csv");
  for (const char* solver :
       {"procedural,tree", "bullet-multibody", "bullet-rigid", "mujoco", "ode"}) {
    EXPECT_NE(box_summary.find(std::string("hang,") + solver + ","), std::string::npos) << solver;
  }
  fs::remove_all(folder);
}

// Each engine refuses a model it cannot step one simulated second of within the budget, in one
// line naming it and its estimate; validate lists it among the refusals; --engine-budget lifts it
TEST(TestbedCli, AnEngineRefusesAModelPastItsBudget) {
  const fs::path folder = fresh_folder("budget");
  const fs::path model = limited_chain(folder, 3000, 30.0);
  const Outcome validate = testbed("validate " + model.string());
  EXPECT_EQ(validate.status, 0) << validate.output;
  EXPECT_NE(validate.output.find("not bullet-multibody: one simulated second"), std::string::npos)
      << validate.output;
  EXPECT_NE(validate.output.find("(--engine-budget)"), std::string::npos);
  EXPECT_NE(validate.output.find("engines: procedural, bullet-rigid"), std::string::npos);
  expect_bad("run --model " + model.string() +
                 " --scenario hang --solver bullet-multibody --duration 0.1 --out " +
                 (folder / "out").string(),
             "--solver: bullet-multibody cannot run");
  EXPECT_FALSE(fs::exists(folder / "out"));
  const Outcome lifted = testbed("validate --engine-budget 1e9 " + model.string());
  EXPECT_EQ(lifted.output.find("not bullet-multibody"), std::string::npos) << lifted.output;
  expect_bad("validate --engine-budget 0 " + model.string(), "--engine-budget");
  // Pinocchio and chain:3000 (no limits) are well within it everywhere
  for (const char* name : {"pinocchio", "chain:3000"}) {
    const Outcome o = testbed(std::string("validate ") + name);
    EXPECT_EQ(o.output.find("past the budget"), std::string::npos) << o.output;
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace puppet::cli_test
