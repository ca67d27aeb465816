// A shard of a robustness sweep and its merge (docs/robustness.md). Each shard writes, beside its
// robustness.csv, a manifest (shard.txt) with everything needed to check it: the sweep it belongs
// to (model, scenarios, configurations, dts, starts, seed, the replayed flags, the code), its
// place (I/N), the number of runs of the whole sweep, its own row count, and robustness.csv's
// size and checksum. A merge trusts none of it: every number is bounded, every name known, the
// sweep's size recomputed, and every row checked against the job it claims to be.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "puppet/compare/robustness.h"

namespace puppet::compare {

// a shard or a set of shards that cannot be merged: one line naming the file and the problem
class ShardError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr int64_t kMaxShards = 100000;
inline constexpr int64_t kMaxSweepRuns = 1000000000;
inline constexpr int64_t kMaxShardRuns = 2000000;  // a row is about 300 bytes held

// what is wrong with a model's name as a manifest carries it (empty when nothing): 1 to 1024
// characters of printable ASCII. robustness --shard refuses such a name up front, merge on read.
std::string shard_model_problem(const std::string& model);

// shard.txt for a shard of `spec` whose robustness.csv is `csv` (holding `rows` rows)
std::string shard_manifest(const RobustnessSpec& spec, int64_t rows, const std::string& csv);

// a shard as its manifest describes it, every field checked
struct ShardManifest {
  std::string folder;
  std::string model;  // as given to robustness (a name or a path)
  std::vector<std::string> scenarios;
  std::vector<std::string> configs;  // "solver" or "procedural:rule"
  std::vector<std::string> dts;      // format_dt of each
  int64_t starts = 0;
  uint64_t seed = 0;
  std::string replay, code;
  int64_t index = 0, count = 0, jobs = 0, rows = 0;
  int64_t csv_bytes = 0;
  std::string csv_checksum;
  // every field but the shard's place: what all shards of one sweep share
  std::string identity() const;
};

// Reads and checks FOLDER/shard.txt. `canonical_replay` returns the replay flags as the testbed
// writes them from what it parses of them (the command line's own checks), or throws ShardError:
// the flags must read back as themselves, so what reaches a replay command line is only what the
// testbed would have written. Throws ShardError.
ShardManifest read_shard_manifest(
    const std::string& folder,
    const std::function<std::string(const std::string& replay)>& canonical_replay);

// Reads FOLDER/robustness.csv and checks it against its manifest: size and checksum, row count,
// and every row is the job it claims (this shard's, in range, its scenario, solver, rule, dt,
// seed and start those of its job number; finite inputs; finite metrics where it is ok, a time
// and a reason where it diverged). Throws ShardError naming the file and the row's line.
std::vector<RobustnessRow> read_shard_rows(const ShardManifest& shard);

// Checks that the shards are one sweep, each place once and none missing; in shard order.
// Throws ShardError.
void check_shard_set(const std::vector<ShardManifest>& shards);

// the flags' words as a POSIX shell reads them: plain words, or single-quoted with '\'' for a
// quote (what shell_word writes); false for anything else
bool split_shell_words(const std::string& text, std::vector<std::string>* words);

}  // namespace puppet::compare
