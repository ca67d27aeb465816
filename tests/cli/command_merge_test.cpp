// The robustness command's shards and the merge command: the merge gives the unsharded bytes and
// trusts no shard
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

TEST(TestbedCli, RobustnessShardsMergeIntoTheUnshardedBytes) {
  const fs::path root = fresh_folder("shards");
  ASSERT_EQ(testbed(kSweep + " --out " + (root / "all").string()).status, 0);
  // shards run out of order, merged in another
  ASSERT_NO_FATAL_FAILURE(run_shards(root, {"2", "0", "1"}));
  const std::string shards =
      " " + (root / "s1").string() + " " + (root / "s2").string() + " " + (root / "s0").string();
  const Outcome merged = testbed("merge" + shards + " --out " + (root / "merged").string());
  ASSERT_EQ(merged.status, 0) << merged.output;
  for (const char* file : {"robustness.csv", "robustness_summary.csv", "worst.csv"}) {
    const std::string expected = slurp(root / "all" / file);
    EXPECT_FALSE(expected.empty()) << file;
    EXPECT_EQ(slurp(root / "merged" / file), expected) << file;
  }
  EXPECT_FALSE(fs::exists(root / "merged" / "shard.txt"));
  // the rows count every run once, and each worst start replays as a command
  const std::string rows = slurp(root / "all" / "robustness.csv");
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 33);
  EXPECT_NE(slurp(root / "all" / "worst.csv").find("testbed run --model chain:4 --scenario"),
            std::string::npos);
}

TEST(TestbedCli, MergeNamesAMissingForeignOrDamagedShard) {
  const fs::path root = fresh_folder("merge_bad");
  ASSERT_NO_FATAL_FAILURE(run_shards(root));
  const std::string s0 = (root / "s0").string(), s1 = (root / "s1").string(),
                    s2 = (root / "s2").string(), out = " --out " + (root / "m").string();
  expect_bad("merge " + s0 + " " + s2 + out, "1 of 3 shards missing: 1");
  expect_bad("merge " + s0 + " " + s0 + " " + s1 + " " + s2 + out, "are both shard 0/3");
  // a shard of another sweep (another seed)
  ASSERT_EQ(testbed(kSweep + " --seed 2 --shard 1/3 --out " + (root / "other").string()).status, 0);
  expect_bad("merge " + s0 + " " + (root / "other").string() + " " + s2 + out, "another sweep");
  // a shard whose rows were cut short
  {
    std::string rows = slurp(root / "s2" / "robustness.csv");
    rows.resize(rows.rfind('\n', rows.size() - 2) + 1);
    std::ofstream(root / "s2" / "robustness.csv", std::ios::binary) << rows;
  }
  expect_bad("merge " + s0 + " " + s1 + " " + s2 + out, "the file was changed or cut");
  expect_bad("merge " + (root / "none").string() + out, "shard.txt");
  EXPECT_FALSE(fs::exists(root / "m"));
}

// merge trusts no shard: every number bounded, every row the job it claims, every file as its
// manifest says; and what reaches a replay command line is inert in a shell
TEST(TestbedCli, MergeVerifiesEveryShardBeforeWriting) {
  const fs::path root = fresh_folder("merge_hostile");
  ASSERT_NO_FATAL_FAILURE(run_shards(root / "good"));
  const fs::path out = root / "merged";
  int trial = 0;
  // a fresh copy of the good shards, `edit` applied to shard 1, merged: refused, naming `names`
  auto refused = [&](const std::function<void(const fs::path&)>& edit, const std::string& names) {
    // appended, not "t" + ...: GCC 12 warns of an overlap in that temporary once inlined here
    // (-Wrestrict, a false positive of its own)
    std::string name = "t";
    name += std::to_string(trial++);
    const fs::path copy = root / name;
    fs::copy(root / "good", copy, fs::copy_options::recursive);
    edit(copy / "s1");
    const auto begin = std::chrono::steady_clock::now();
    expect_bad("merge " + (copy / "s0").string() + " " + (copy / "s1").string() + " " +
                   (copy / "s2").string() + " --out " + out.string(),
               names);
    EXPECT_LT(std::chrono::steady_clock::now() - begin, std::chrono::seconds(5)) << names;
    EXPECT_FALSE(fs::exists(out)) << names;
  };
  using Edit = std::function<void(const fs::path&)>;
  const std::vector<std::pair<Edit, std::string>> cases = {
      // the manifest: bounds, names, the sweep's arithmetic, the flags
      {[](const fs::path& s) { edit_manifest(s, "shard", "1/999999999999999999"); }, "shard: "},
      {[](const fs::path& s) { edit_manifest(s, "shard", "1/100001"); }, "shard: "},
      {[](const fs::path& s) { edit_manifest(s, "jobs", "33"); }, "jobs: 33"},
      {[](const fs::path& s) { edit_manifest(s, "jobs", "99999999999999999999"); }, "jobs: "},
      {[](const fs::path& s) { edit_manifest(s, "rows", "12"); }, "rows: 12"},
      {[](const fs::path& s) { edit_manifest(s, "starts", "0"); }, "starts: "},
      {[](const fs::path& s) { edit_manifest(s, "scenarios", "hang,swim"); }, "\"swim\" is not"},
      {[](const fs::path& s) { edit_manifest(s, "configs", "procedural:xpbd,physx"); },
       "\"physx\""},
      {[](const fs::path& s) { edit_manifest(s, "dts", "1/60,1/120"); }, "dts: "},
      {[](const fs::path& s) { edit_manifest(s, "seed", "2"); }, "another sweep"},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --duration 0.5; touch x"); },
       "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --duration '$(id)'"); }, "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --starts 5"); }, "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --duration 1e9"); }, "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "code", "$(id)"); }, "code: "},
      {[](const fs::path& s) { write_text(s / "shard.txt", slurp(s / "shard.txt") + "x: 1\n"); },
       "unknown line"},
      {[](const fs::path& s) {
         write_text(s / "shard.txt", slurp(s / "shard.txt") + "rows: 11\n");
       },
       "a second rows line"},
      // the rows, under a manifest rewritten to match them
      {[](const fs::path& s) { edit_row(s, 0, 20, "inf"); }, "finite metrics"},
      {[](const fs::path& s) { edit_row(s, 0, 20, "nan"); }, "not a number"},
      {[](const fs::path& s) { edit_row(s, 0, 20, "0x1p-3"); }, "not a number"},
      {[](const fs::path& s) { edit_row(s, 0, 16, "diverged"); }, "without a reason"},
      {[](const fs::path& s) { edit_row(s, 2, 5, "2"); }, "not the run"},
      {[](const fs::path& s) { edit_row(s, 2, 1, "swim"); }, "not the run"},
      {[](const fs::path& s) { edit_row(s, 2, 3, "relaxed"); }, "not the run"},
      {[](const fs::path& s) { edit_row(s, 2, 6, "0"); }, "not the run"},  // job 7: start 3
      {[](const fs::path& s) { edit_row(s, 2, 0, "4"); }, "job 4 where"},
      {[](const fs::path& s) { edit_row(s, 2, 22, "99999999999999"); }, "steps"},
      // a file changed without its manifest: two bytes cut, one digit changed
      {[](const fs::path& s) {
         std::string rows = slurp(s / "robustness.csv");
         write_text(s / "robustness.csv", rows.substr(0, rows.size() - 2));
       },
       "changed or cut"},
      {[](const fs::path& s) {
         std::string rows = slurp(s / "robustness.csv");
         rows[rows.size() - 2] = rows[rows.size() - 2] == '1' ? '2' : '1';
         write_text(s / "robustness.csv", rows);
       },
       "changed or cut"},
  };
  for (const auto& [edit, names] : cases) refused(edit, names);

  // a hostile model name agreed by every shard merges, and stays one inert word in a shell
  const fs::path proof = root / "pwned";
  const fs::path copy = root / "hostile";
  fs::copy(root / "good", copy, fs::copy_options::recursive);
  const std::string model = "chain:4; touch " + proof.string() + " $(touch " + proof.string() +
                            ") `touch " + proof.string() + "` it's";
  for (const char* shard : {"s0", "s1", "s2"}) edit_manifest(copy / shard, "model", model);
  const Outcome merged = testbed("merge " + (copy / "s0").string() + " " + (copy / "s1").string() +
                                 " " + (copy / "s2").string() + " --out " + out.string());
  ASSERT_EQ(merged.status, 0) << merged.output;
  const std::string worst = slurp(out / "worst.csv");
  const size_t at = worst.find("build/release/testbed run --model ");
  ASSERT_NE(at, std::string::npos);
  // the replay command (a plain CSV field: no comma or double quote in it), its program replaced
  // by one that prints its words, run by a POSIX shell
  std::string line = worst.substr(at, worst.find(",build/release/viewer", at) - at);
  line.replace(0, std::string("build/release/testbed").size(), "printf '%s\\n'");
  write_text(root / "replay.sh", line + "\n");
  const Outcome words = shell("sh " + (root / "replay.sh").string());
  EXPECT_EQ(words.status, 0) << line;
  EXPECT_NE(words.output.find("--model\n" + model + "\n--scenario"), std::string::npos)
      << line << "\n"
      << words.output;
  EXPECT_FALSE(fs::exists(proof)) << line;
  fs::remove_all(root);
}

}  // namespace
}  // namespace puppet::cli_test
