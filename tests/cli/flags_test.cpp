// The flags every command shares: bad input exits 2 with one line before anything is written
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

TEST(TestbedCli, BadFlagsExitTwoBeforeWritingAnything) {
  const fs::path out = fresh_folder("bad");
  const std::string o = " --out " + out.string();
  expect_bad("run --scenario swim" + o, "--scenario");
  expect_bad("run --solver physx" + o, "--solver");
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
  expect_bad("run --limit-restitution 1.5" + o, "--limit-restitution");
  expect_bad("run --limit-restitution -0.1" + o, "--limit-restitution");
  expect_bad("run --limit-restitution nan" + o, "--limit-restitution");
  expect_bad("run --limit-restitution soft" + o, "--limit-restitution");
  expect_bad("run --dt 1/60,abc" + o, "--dt");
  expect_bad("run --jobs 0" + o, "--jobs");
  expect_bad("run --truth-cache /etc/passwd" + o, "--truth-cache");
  expect_bad("run --truth-cache /etc/passwd/truths" + o, "--truth-cache");
  expect_bad("run --truth-cache /proc/version/x --scenario swim" + o, "--scenario");
  expect_bad("frontier --jobs x" + o, "--jobs");
  // counts are plain decimal digits: CLI11 alone would read 0x10 as 16 and 010 as 8
  expect_bad("run --jobs 0x10" + o, "--jobs");
  expect_bad("run --jobs 010" + o, "--jobs");
  expect_bad("run --substeps -1" + o, "--substeps");
  expect_bad("frontier --solver physx" + o, "--solver");
  expect_bad("frontier --grab tail" + o, "--grab");
  expect_bad("robustness --shard 3/3" + o, "--shard");
  expect_bad("robustness --shard 1" + o, "--shard");
  expect_bad("robustness --shard a/b" + o, "--shard");
  expect_bad("robustness --shard 0/0" + o, "--shard");
  expect_bad("robustness --starts 0" + o, "--starts");
  expect_bad("robustness --starts 1.5" + o, "--starts");
  expect_bad("robustness --starts 1e3" + o, "--starts");
  expect_bad("robustness --starts 1000000 --solver all --rule all" + o, "use more shards");
  expect_bad("robustness --seed -1" + o, "--seed");
  expect_bad("robustness --seed 0x10" + o, "--seed");
  // a run's steps: the same check and words as run's
  expect_bad("robustness --starts 1 --duration 3600 --dt 1e-5" + o, "--duration: 3600 s at dt");
  expect_bad("robustness --starts 1 --duration 0.001 --dt 1/30" + o, "takes no step");
  expect_bad("robustness --scenario swim" + o, "--scenario");
  expect_bad("robustness --shard 0/2 --model \"$(printf '/tmp/caf\\303\\251.json')\"" + o,
             "printable ASCII");
  expect_bad("verdict --budget 1furlong" + o, "--budget");
  expect_bad("verdict --budget 0mm" + o, "--budget");
  expect_bad("verdict --budget 1cm,10mm" + o, "listed already");
  expect_bad("verdict --budget 1cm," + o, "--budget");
  expect_bad("verdict --budget nan" + o, "--budget");
  expect_bad("verdict --budget ' 1mm'" + o, "--budget");
  expect_bad("verdict --budget 1e3m" + o, "--budget");
  expect_bad("verdict --dt 1/100" + o, "1/30 s");
  expect_bad("verdict --starts 0" + o, "--starts");
  expect_bad("verdict --starts 2.5" + o, "--starts");
  expect_bad("verdict --frame-hz 0" + o, "--frame-hz");
  expect_bad("verdict --scenario swim" + o, "--scenario");
  expect_bad("verdict --substeps 4" + o, "--substeps");
  expect_bad("verdict --floors-from /no/such/summary.csv" + o, "--floors-from");
  expect_bad("verdict --floors-from /dev/zero" + o, "--floors-from");
  expect_bad("verdict --floors-from /tmp" + o, "--floors-from");
  expect_bad("verdict --floors-from " + std::string(PUPPET_SOURCE_DIR) + "/README.md" + o,
             "not a summary.csv");
  expect_bad("run --start 1" + o, "--start");
  expect_bad("run --start x:2" + o, "--start");
  expect_bad("run --start 1:-2" + o, "--start");
  EXPECT_FALSE(fs::exists(out));
  expect_bad("run --scenario hang --duration 0.1 --out /proc/forbidden", "--out");
  // what a flag implies, and its ranges: each of these ran (or crashed) before it was checked
  for (const auto& [arguments, names] : std::vector<std::pair<std::string, std::string>>{
           {"run --dt 1e-300", "--dt"},
           {"run --dt 4.9e-324", "--dt"},
           {"run --dt 1e300", "--dt"},
           {"run --dt 1/3/4", "--dt"},
           {"run --dt 0x10", "--dt"},
           {"run --dt ' 1/60'", "--dt"},
           {"run --dt 1/240,0.00416666667", "--dt"},
           {"run --dt 1/60,", "--dt"},
           {"run --dt 1e-9", "--dt"},
           {"run --duration 1e7", "--duration"},
           {"run --duration 0", "--duration"},
           {"run --duration 600 --dt 1e-5 --no-accuracy", "--duration"},
           {"run --duration 1000 --dt 1/60", "--duration"},
           {"run --scenario hang,hang --jobs 2", "--scenario"},
           {"run --solver mujoco,mujoco", "--solver"},
           {"run --scenario hang,", "--scenario"},
           {"run --air-drag 1e10", "--air-drag"},
           {"run --tilt 1e300", "--tilt"},
           {"run --hz 0", "--hz"},
           {"run --jobs 100000", "--jobs"},
           {"run --iterations 1000000", "--iterations"},
           {"run --grab r_forearm:1e9,0,0", "--grab"},
           {"run --gravity 0,0,-1e9", "--gravity"},
           {"run --grab-compliance 1e300", "--grab-compliance"},
           {"run --grab-hz -1", "--grab-hz"},
           {"run --grab-hz 0", "--grab-hz"},
           {"run --grab-ratio nan", "--grab-ratio"},
           {"run --grab-ratio -0.1", "--grab-ratio"},
           {"run --grab-cap 0", "--grab-cap"},
           {"verdict --grab-cap inf", "--grab-cap"},
           {"robustness --grab-hz 1/0", "--grab-hz"},
           {"run --model chain:20000 --sample-hz 0 --no-accuracy --scenario hang", "MiB"},
           {"run --model chain:150 --solver mujoco --scenario hang", "--solver: mujoco"},
           {"run --scenario \"$(printf 'a\\nb')\"", "--scenario"},
       }) {
    expect_bad(arguments + o, names);
  }
  expect_bad("explode", "\"explode\"");
  // a message that quotes a long path stays within its 400 characters, prefix included
  expect_bad("run --model /" + std::string(300, 'm') + "/" + std::string(200, 'x') + ".json" + o,
             "--model: /mmm");
  expect_bad("export-mjcf pinocchio -o /" + std::string(300, 'n') + "/" + std::string(200, 'y'),
             "-o: ");
  expect_bad("run --out ''", "--out");
  expect_bad("run --out /", "--out");
  // a folder that holds anything but the command's own files is not replaced
  const fs::path mine = fresh_folder("foreign");
  fs::create_directories(mine);
  std::ofstream(mine / "thesis.tex") << "years of work";
  expect_bad("run --scenario hang --duration 0.1 --out " + mine.string(), "thesis.tex");
  EXPECT_TRUE(fs::exists(mine / "thesis.tex"));
  fs::remove_all(mine);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace puppet::cli_test
