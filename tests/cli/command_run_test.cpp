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

  // hinges at different points: rules xpbd and tree and mujoco run it, each other rule and engine
  // is left out in one line (a rule named is refused), and the one truth that runs it stands
  const std::string apart = std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/offset_hinges.xml";
  const Outcome shown_apart = testbed("validate " + apart);
  EXPECT_NE(shown_apart.output.find("hinges 4 and 0 cm apart"), std::string::npos)
      << shown_apart.output;
  EXPECT_NE(shown_apart.output.find("engines: procedural (rules xpbd, tree), mujoco\n"),
            std::string::npos)
      << shown_apart.output;
  const Outcome apart_all = testbed("run --model " + apart +
                                    " --scenario hang --dt 1/240 --duration 0.2 --no-timing" + out);
  EXPECT_EQ(apart_all.status, 0) << apart_all.output;
  EXPECT_NE(apart_all.output.find("note: procedural rule relaxed left out, it cannot run"),
            std::string::npos)
      << apart_all.output;
  EXPECT_NE(apart_all.output.find("one truth for this model (mujoco)"), std::string::npos);
  const std::string apart_summary = slurp(folder / "out" / "summary.csv");
  for (const char* solver : {"procedural,xpbd", "procedural,tree", "mujoco"}) {
    EXPECT_NE(apart_summary.find(std::string("hang,") + solver + ","), std::string::npos) << solver;
  }
  EXPECT_EQ(apart_summary.find(",relaxed,"), std::string::npos);
  expect_bad("run --model " + apart + " --scenario hang --rule relaxed --duration 0.1" + out,
             "--rule: relaxed cannot run");

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

// Contact counts: four rods of 32 boxes each, 128 shapes on three joints, lie on the ground at
// 512 points. ODE's exact stepper took 4.6 s a step on them folded (bench_budget): it refuses
// them, naming the contact points, where the estimate without contact was 0.004 s of CPU per
// simulated second; the quick stepper, linear in its rows, takes them
TEST(TestbedCli, AnEstimateCountsTheContactPoints) {
  const fs::path folder = fresh_folder("budget_contact");
  fs::create_directories(folder);
  nlohmann::json segments = nlohmann::json::array(), joints = nlohmann::json::array();
  for (int i = 0; i < 4; ++i) {
    nlohmann::json shapes = nlohmann::json::array();
    for (int b = 0; b < 32; ++b) {
      shapes.push_back({{"type", "box"},
                        {"half_extents", {0.02, 0.02, 0.0056}},
                        {"position", {0.0, 0.0, -0.4 * i - 0.4 * (b + 0.5) / 32}}});
    }
    segments.push_back({{"name", "rod" + std::to_string(i)}, {"mass", 2.0}, {"shapes", shapes}});
    if (i > 0) {
      joints.push_back({{"name", "ball" + std::to_string(i)},
                        {"parent", "rod" + std::to_string(i - 1)},
                        {"child", "rod" + std::to_string(i)},
                        {"anchor", {0.0, 0.0, -0.4 * i}},
                        {"type", "ball"},
                        {"swing_deg", {180.0, 180.0}},
                        {"twist_deg", 180.0}});
    }
  }
  const fs::path model = folder / "rods.json";
  write_text(model,
             nlohmann::json{{"name", "rods"}, {"segments", segments}, {"joints", joints}}.dump());
  expect_bad("run --model " + model.string() +
                 " --scenario collapse --solver ode --ode-stepper step --out " +
                 (folder / "out").string(),
             "512 contact points on the ground");
  EXPECT_FALSE(fs::exists(folder / "out"));
  const Outcome quick = testbed("run --model " + model.string() +
                                " --scenario hang --solver ode --duration 0.02 --no-accuracy "
                                "--no-timing --out " +
                                (folder / "out").string());
  EXPECT_EQ(quick.status, 0) << quick.output;
  fs::remove_all(folder);
}

}  // namespace
}  // namespace puppet::cli_test
