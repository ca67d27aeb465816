// The testbed command as a user meets it: exit codes, one-line errors, nothing half-written.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status;
  std::string output;  // stdout and stderr
};

Outcome testbed(const std::string& arguments) {
  const std::string command = std::string(TESTBED_BINARY) + " " + arguments + " 2>&1";
  Outcome outcome{-1, ""};
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return outcome;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) outcome.output += buffer.data();
  const int raw = pclose(pipe);
  outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return outcome;
}

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / ("testbed_cli_" + name);
  fs::remove_all(folder);
  return folder;
}

// exit 2 with one line that names the flag or file
void expect_bad(const std::string& arguments, const std::string& names) {
  const Outcome o = testbed(arguments);
  EXPECT_EQ(o.status, 2) << arguments << "\n" << o.output;
  EXPECT_NE(o.output.find(names), std::string::npos) << arguments << "\n" << o.output;
  EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << arguments << "\n" << o.output;
}

TEST(TestbedCli, HelpAndList) {
  EXPECT_EQ(testbed("--help").status, 0);
  EXPECT_EQ(testbed("run --help").status, 0);
  const Outcome list = testbed("list");
  EXPECT_EQ(list.status, 0);
  EXPECT_NE(list.output.find("yank"), std::string::npos);
  EXPECT_NE(list.output.find("subtree"), std::string::npos);
}

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

// export-mjcf: the document to stdout, or whole to a file; a bad model or an unwritable path
// exits 2 with one line and leaves no file
TEST(TestbedCli, ExportMjcf) {
  const Outcome out = testbed("export-mjcf pinocchio");
  EXPECT_EQ(out.status, 0);
  EXPECT_EQ(out.output.rfind("<!-- pinocchio", 0), 0u);
  EXPECT_NE(out.output.find("<mujoco model=\"pinocchio\">"), std::string::npos);
  EXPECT_NE(out.output.find("</mujoco>\n"), std::string::npos);
  const fs::path folder = fresh_folder("export");
  fs::create_directories(folder);
  const fs::path file = folder / "pinocchio.xml";
  EXPECT_EQ(testbed("export-mjcf pinocchio -o " + file.string()).status, 0);
  EXPECT_TRUE(fs::exists(file));
  EXPECT_EQ(fs::file_size(file), out.output.size());
  expect_bad("export-mjcf /no/such/model.json -o " + (folder / "x.xml").string(),
             "/no/such/model.json: cannot open");
  EXPECT_FALSE(fs::exists(folder / "x.xml"));
  expect_bad("export-mjcf pinocchio -o /no/such/folder/x.xml", "/no/such/folder/x.xml");
  expect_bad("run --solver mujoco --mujoco-integrator rk5", "--mujoco-integrator");
}

TEST(TestbedCli, BadFlagsExitTwoBeforeWritingAnything) {
  const fs::path out = fresh_folder("bad");
  const std::string o = " --out " + out.string();
  expect_bad("run --scenario swim" + o, "--scenario");
  expect_bad("run --solver ode" + o, "--solver");
  expect_bad("run --rule magic" + o, "--rule");
  expect_bad("run --dt 0" + o, "--dt");
  expect_bad("run --dt -0.01" + o, "--dt");
  expect_bad("run --dt abc" + o, "--dt");
  expect_bad("run --dt nan" + o, "--dt");
  expect_bad("run --duration -1" + o, "--duration");
  expect_bad("run --pin head:1,2" + o, "--pin");
  expect_bad("run --pin tail --scenario hang" + o, "--pin");
  expect_bad("run --grab r_forearm:a,b,c" + o, "--grab");
  expect_bad("run --gravity 0,0" + o, "--gravity");
  expect_bad("run --ground maybe" + o, "--ground");
  expect_bad("run --model /no/such/model.json" + o, "--model");
  expect_bad("run --frobnicate" + o, "--frobnicate");
  expect_bad("run --bullet-iterations 0" + o, "--bullet-iterations");
  expect_bad("run --bullet-iterations 2.5" + o, "--bullet-iterations");
  expect_bad("run --dt 1/60,abc" + o, "--dt");
  expect_bad("run --jobs 0" + o, "--jobs");
  expect_bad("frontier --jobs x" + o, "--jobs");
  expect_bad("frontier --solver ode" + o, "--solver");
  expect_bad("frontier --grab tail" + o, "--grab");
  EXPECT_FALSE(fs::exists(out / "frontier.csv"));
  EXPECT_FALSE(fs::exists(out / "summary.csv"));
  expect_bad("run --scenario hang --duration 0.1 --out /proc/forbidden", "--out");
}

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

}  // namespace
