// testbed merge: the shards of one robustness sweep into what one unsharded run writes. Nothing
// is written before every shard and every row is checked; a signal meanwhile ends the command at
// once (cancel.h).
#include <algorithm>
#include <cstdio>
#include <memory>

#include "cli.h"
#include "commands.h"
#include "flags.h"
#include "puppet/compare/output_folder.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/shard.h"
#include "puppet/model/text.h"
#include "robustness_files.h"
#include "tables.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

// the replay flags of a shard's manifest as robustness writes them, from what its own flag
// parsers make of them (ShardError when they do not parse): shard.h's canonical_replay
std::string canonical_replay(const std::string& replay) {
  std::vector<std::string> words;
  if (!split_shell_words(replay, &words)) {
    throw ShardError("not words a shell reads as they are written");
  }
  CLI::App app;
  Flags f;
  add_robustness_flags(&app, f);
  std::reverse(words.begin(), words.end());  // CLI11 reads its argument vector from the back
  try {
    app.parse(words);
    if (!f.duration.empty()) parse_in("--duration", f.duration, 0.0, 3600.0, " s");
    parse_scenario_options(f);
  } catch (const CLI::ParseError& e) {
    throw ShardError(e.what());
  } catch (const UsageError& e) {
    throw ShardError(e.what());
  }
  return replay_flags(f);
}

int merge(const std::vector<std::string>& folders, const std::string& out) {
  std::vector<ShardManifest> shards;
  for (const std::string& folder : folders) {
    shards.push_back(read_shard_manifest(folder, [](const std::string& replay) {
      try {
        return canonical_replay(replay);
      } catch (const ShardError& e) {
        throw ShardError("replay: " + shown(replay) + ": " + e.what());
      }
    }));
  }
  check_shard_set(shards);
  std::sort(shards.begin(), shards.end(),
            [](const ShardManifest& a, const ShardManifest& b) { return a.index < b.index; });
  std::vector<RobustnessRow> rows;
  rows.reserve(static_cast<size_t>(std::min<int64_t>(shards.front().jobs, kMaxShardRuns)));
  for (const ShardManifest& shard : shards) {
    const std::vector<RobustnessRow> part = read_shard_rows(shard);
    rows.insert(rows.end(), part.begin(), part.end());
  }
  // each row was its shard's job, each shard there once: every job is here once
  std::sort(rows.begin(), rows.end(),
            [](const RobustnessRow& a, const RobustnessRow& b) { return a.job < b.job; });
  RobustnessSpec spec;
  spec.model_name = shards.front().model;
  spec.replay_flags = shards.front().replay;
  OutputFolder folder("--out", out, {"robustness.csv", "robustness_summary.csv", "worst.csv"});
  write_robustness(folder, rows, spec);
  folder.commit();
  print_rates(rows);
  std::printf("\nmerged %zu shards, %zu runs into %s\n", shards.size(), rows.size(),
              folder.path().c_str());
  return 0;
}

}  // namespace

Command add_merge_command(CLI::App& app) {
  struct Args {
    std::vector<std::string> folders;
    std::string out = robustness_defaults().out;
  };
  auto args = std::make_shared<Args>();
  CLI::App* command = app.add_subcommand(
      "merge",
      "merge the shards of one testbed robustness sweep into what one unsharded run writes");
  command->add_option("DIR", args->folders, "the shards' output folders")->required();
  command->add_option("--out", args->out, "output folder")->capture_default_str();
  return {command, [args] { return merge(args->folders, args->out); }};
}

}  // namespace puppet::testbed
