// A robustness sweep's shards (studies/src/shard.cpp) one function at a time: the manifest
// written and read back, each shard's place in its set, the model names and replay words a
// manifest may carry. (The merge end to end, with damaged and hostile shards, is in
// tests/cli/command_merge_test.cpp.)
#include "puppet/compare/shard.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "puppet/compare/output.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/sweep.h"
#include "puppet/model/model.h"

namespace puppet::compare {
namespace {

namespace fs = std::filesystem;

// the FNV-1a 64-bit test vectors of its authors' reference (Fowler, Noll, Vo): the checksum a
// manifest carries is that hash, not one of its own
TEST(ContentChecksum, IsFnv1a64) {
  EXPECT_EQ(content_checksum(""), "cbf29ce484222325");
  EXPECT_EQ(content_checksum("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(content_checksum("foobar"), "85944171f73967e8");
}

// the manifest's bound on a model's name, as its message states it (1 to 1024 characters)
constexpr size_t kMaxModelName = 1024;

TEST(Shard, AModelNameIsPrintableAsciiOfBoundedLength) {
  EXPECT_EQ(shard_model_problem("pinocchio"), "");
  EXPECT_EQ(shard_model_problem("chain:8"), "");
  EXPECT_EQ(shard_model_problem(std::string(kMaxModelName, 'm')), "");
  const std::vector<std::string> bad_names = {std::string(), std::string(kMaxModelName + 1, 'm'),
                                              "a\nb", "a\x7f", "\xc3\xa9"};
  for (const std::string& bad : bad_names) {
    EXPECT_NE(shard_model_problem(bad), "") << bad;
  }
}

TEST(Shard, ShellWordsAreReadAsAPosixShellReadsThem) {
  std::vector<std::string> words;
  ASSERT_TRUE(split_shell_words("--duration 3 'a b' 'it'\\''s'", &words));
  EXPECT_EQ(words, (std::vector<std::string>{"--duration", "3", "a b", "it's"}));
  // what a shell would expand or a writer of shell_word never writes
  for (const char* bad : {"\"double\"", "$(touch x)", "`x`", "'open", "a;b", "a|b", "~", "*"}) {
    std::vector<std::string> out;
    EXPECT_FALSE(split_shell_words(bad, &out)) << bad;
  }
}

// one shard of a small sweep written as the robustness command writes it
RobustnessSpec small_spec(const Model& model, int shard, int shards) {
  RobustnessSpec spec;
  spec.model = &model;
  spec.model_name = "chain:3";
  spec.scenarios = {"hang"};
  const procedural::Rule rules[] = {procedural::Rule::kXpbd};
  spec.configs = solver_configs({"procedural"}, rules);
  spec.dts = {1.0 / 60};
  spec.starts = 4;
  spec.seed = 7;
  spec.shard = shard;
  spec.shards = shards;
  spec.replay_flags = " --duration 0.5";
  spec.code = "abc123";
  return spec;
}

fs::path write_shard(const std::string& name, const RobustnessSpec& spec, const std::string& csv,
                     int64_t rows) {
  const fs::path folder = fs::temp_directory_path() / ("shard_test_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::ofstream(folder / "shard.txt") << shard_manifest(spec, rows, csv);
  std::ofstream(folder / "robustness.csv") << csv;
  return folder;
}

std::string as_written(const std::string& replay) { return replay; }

// the runs of shard I of N: the jobs j with j mod N = I (in_shard), counted here
int64_t rows_of(const RobustnessSpec& spec) {
  int64_t rows = 0;
  for (int64_t job = 0; job < robustness_job_count(spec); ++job) rows += in_shard(spec, job);
  return rows;
}

TEST(Shard, AManifestReadsBackAsWritten) {
  const Model model = make_chain(3);
  const RobustnessSpec spec = small_spec(model, 1, 2);
  const std::string csv = "job,scenario\n";
  const fs::path folder = write_shard("manifest", spec, csv, rows_of(spec));
  const ShardManifest m = read_shard_manifest(folder.string(), as_written);
  EXPECT_EQ(m.model, "chain:3");
  EXPECT_EQ(m.scenarios, (std::vector<std::string>{"hang"}));
  EXPECT_EQ(m.configs, (std::vector<std::string>{"procedural:xpbd"}));
  EXPECT_EQ(m.dts.size(), 1u);
  EXPECT_EQ(m.starts, 4);
  EXPECT_EQ(m.seed, 7u);
  EXPECT_EQ(m.replay, " --duration 0.5");
  EXPECT_EQ(m.code, "abc123");
  EXPECT_EQ(m.index, 1);
  EXPECT_EQ(m.count, 2);
  EXPECT_EQ(m.jobs, robustness_job_count(spec));
  EXPECT_EQ(m.rows, 2);  // 4 starts of one scenario, configuration and dt: jobs 1 and 3
  EXPECT_EQ(m.csv_bytes, static_cast<int64_t>(csv.size()));
  EXPECT_EQ(m.csv_checksum, content_checksum(csv));
  fs::remove_all(folder);
}

TEST(Shard, ASetIsOneSweepWithEachPlaceOnce) {
  const Model model = make_chain(3);
  std::vector<ShardManifest> shards;
  for (int k = 0; k < 3; ++k) {
    const RobustnessSpec spec = small_spec(model, k, 3);
    const fs::path folder =
        write_shard("set" + std::to_string(k), spec, "job,scenario\n", rows_of(spec));
    shards.push_back(read_shard_manifest(folder.string(), as_written));
    fs::remove_all(folder);
  }
  EXPECT_NO_THROW(check_shard_set(shards));
  // a place missing, a place twice, a shard of another sweep (its seed)
  std::vector<ShardManifest> missing(shards.begin(), shards.begin() + 2);
  EXPECT_THROW(check_shard_set(missing), ShardError);
  std::vector<ShardManifest> twice = {shards[0], shards[1], shards[1]};
  EXPECT_THROW(check_shard_set(twice), ShardError);
  std::vector<ShardManifest> foreign = shards;
  foreign[2].seed = 8;
  EXPECT_THROW(check_shard_set(foreign), ShardError);
}

}  // namespace
}  // namespace puppet::compare
