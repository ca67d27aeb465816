// The validate command: a model checked, and the MJCF elements skipped with a note or refused
// strictly
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

TEST(TestbedCli, Validate) {
  const Outcome ok = testbed("validate pinocchio");
  EXPECT_EQ(ok.status, 0);
  EXPECT_NE(ok.output.find("14 segments, 13 joints, total mass 69.600 kg"), std::string::npos);
  EXPECT_EQ(testbed("validate chain:3").status, 0);
  expect_bad("validate " + std::string(PUPPET_SOURCE_DIR) + "/tests/data/bad/negative_mass.json",
             "negative_mass.json: segment \"lower\": field \"mass\" must be positive");
  expect_bad("validate /no/such/file.json", "/no/such/file.json: cannot open");
  expect_bad("gate /no/such/bench.json --thresholds " + std::string(PUPPET_SOURCE_DIR) +
                 "/results/gate.json",
             "/no/such/bench.json: cannot open");
  expect_bad("gate /no/such/bench.json --thresholds /no/such/gate.json",
             "/no/such/gate.json: cannot open");
}

// A model with joint springs, dampers and armature: validate shows each joint's, a box's per
// angle where they differ, and which engines approximate armature; a run says so once, in one
// line naming those engines, and runs them
TEST(TestbedCli, SpringsAndArmatureAreShownAndTheirApproximationNoted) {
  const std::string model = std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/springs.xml";
  const Outcome validated = testbed("validate " + model);
  EXPECT_EQ(validated.status, 0) << validated.output;
  EXPECT_NE(validated.output.find("range [0, 150]; stiffness 8, damping 1.5, springref 20, "
                                  "armature 0.02"),
            std::string::npos)
      << validated.output;
  EXPECT_NE(validated.output.find("angle 1: stiffness 5, damping 0.4, springref 10"),
            std::string::npos);
  EXPECT_NE(validated.output.find("ode approximates: joint armature"), std::string::npos);
  EXPECT_EQ(validated.output.find("mujoco approximates"), std::string::npos);
  const fs::path out = fresh_folder("sprung");
  const Outcome run = testbed("run --model " + model +
                              " --scenario spin --solver mujoco,ode,procedural --rule xpbd "
                              "--duration 0.05 --no-timing --out " +
                              out.string());
  EXPECT_EQ(run.status, 0) << run.output;
  const std::string note = "note: ode, procedural: joint armature is added to each child's";
  const auto at = run.output.find(note);
  EXPECT_NE(at, std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("joint armature", at + note.size()), std::string::npos) << "once";
}

// A published-style MJCF file: what it has that the testbed does not model is one line on stderr,
// once, and the command goes on; with --strict it is refused (exit 2, one line) before anything
// runs; an include outside the model's folder needs --include-outside
TEST(TestbedCli, SkippedElementsAreOneNoteOrRefusedStrictly) {
  const std::string model = std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/published_style.xml";
  const std::string note =
      "skipped what the testbed does not model: 1 <camera>, 1 <jointpos>, 1 <light>, 2 <motor>, "
      "1 <numeric>";
  const Outcome validated = testbed("validate " + model);
  EXPECT_EQ(validated.status, 0) << validated.output;
  const auto at = validated.output.find(note);
  EXPECT_NE(at, std::string::npos) << validated.output;
  EXPECT_EQ(validated.output.find(note, at + 1), std::string::npos) << "once";
  const fs::path out = fresh_folder("skipped");
  const Outcome run = testbed("run --model " + model +
                              " --scenario hang --solver procedural --rule xpbd --duration 0.05 "
                              "--no-timing --out " +
                              out.string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find(note), std::string::npos) << run.output;
  expect_bad("validate --strict " + model,
             "published_style.xml:28: <motor name=\"right_hip\">: is not modelled by the testbed");
  const fs::path strict = fresh_folder("strict");
  expect_bad("run --strict --model " + model + " --scenario hang --out " + strict.string(),
             "is not modelled by the testbed (skipped unless --strict)");
  EXPECT_FALSE(fs::exists(strict));
  const std::string outside =
      std::string(PUPPET_SOURCE_DIR) + "/tests/data/bad/mjcf_include_outside.xml";
  expect_bad("validate " + outside, "is outside the model's folder (--include-outside allows it)");
  EXPECT_EQ(testbed("validate --include-outside " + outside).status, 0);
  fs::remove_all(out);
}

}  // namespace
}  // namespace puppet::cli_test
