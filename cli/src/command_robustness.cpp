// testbed robustness: every scenario × solver × rule × dt from N random starts; writes
// robustness.csv, the divergence rates with 95 % Wilson intervals and the worst starts as replay
// commands, and with --shard I/N one shard of the sweep and its manifest (shard.txt) for merge.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli.h"
#include "commands.h"
#include "flags.h"
#include "progress.h"
#include "puppet/compare/output.h"
#include "puppet/compare/output_folder.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/shard.h"
#include "puppet/compare/start.h"
#include "puppet/model/text.h"
#include "robustness_files.h"
#include "tables.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

int robustness(const Flags& f) {
  RobustnessSpec spec;
  spec.dts = parse_dts(f.dt);
  if (!f.duration.empty()) spec.duration = parse_in("--duration", f.duration, 0.0, 3600.0, " s");
  spec.scenario = parse_scenario_options(f);
  spec.configs = parse_solver_configs(f);
  spec.scenarios = expand("--scenario", f.scenario, scenario_names());
  spec.starts = parse_starts(f.starts, 1e6);
  spec.seed = parse_seed(f.seed);
  if (!f.shard.empty()) {
    uint64_t i = 0, n = 0;
    if (!parse_shard(f.shard, &i, &n)) {
      throw UsageError("--shard: expected I/N, got " + shown(f.shard));
    }
    if (n < 1 || n > static_cast<uint64_t>(kMaxShards) || i >= n) {
      throw UsageError("--shard: expected I/N with 0 <= I < N <= " + std::to_string(kMaxShards) +
                       ", got " + shown(f.shard));
    }
    spec.shard = static_cast<int>(i);
    spec.shards = static_cast<int>(n);
  }
  spec.jobs = f.jobs;
  // what a shard's manifest carries, merge reads back: its model's name too
  if (std::string problem = shard_model_problem(f.model); spec.shards > 1 && !problem.empty()) {
    throw UsageError("--model: " + shown(f.model) + ": " + problem);
  }
  const Model model = parse_model(f.model, f.reading);
  spec.model = &model;
  spec.model_name = f.model;
  apply_engine_verdicts(spec.configs, model, f);
  // the bounds merge reads a shard within (shard.h)
  const int64_t jobs = robustness_job_count(spec);
  const int64_t per_shard = (jobs + spec.shards - 1) / spec.shards;
  if (jobs > kMaxSweepRuns || per_shard > kMaxShardRuns) {
    throw UsageError("--starts: " + std::to_string(jobs) + " runs in all, " +
                     std::to_string(per_shard) + " in this shard (at most " +
                     std::to_string(kMaxShardRuns) + " per shard, " +
                     std::to_string(kMaxSweepRuns) + " in all): use more shards");
  }
  // every scenario builds with a start, and no run is longer than a sweep's
  double longest = 0.0;
  for (const std::string& name : spec.scenarios) {
    ScenarioOptions options = spec.scenario;
    options.start = random_start(model, spec.seed, 0);
    const Scenario scenario = make_scenario(name, model, options);
    longest = std::max(longest, spec.duration >= 0.0 ? spec.duration : scenario.duration);
  }
  check_steps_per_run(longest, spec.dts, spec.duration >= 0.0);
  spec.replay_flags = replay_flags(f);
  spec.code = current_git_sha();
  OutputFolder folder("--out", f.out,
                      {"robustness.csv", "robustness_summary.csv", "worst.csv", "shard.txt"});
  spec.on_progress = Progress("robustness");
  const auto begin = std::chrono::steady_clock::now();
  const std::vector<RobustnessRow> rows = run_robustness(spec);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  const std::string csv = write_robustness(folder, rows, spec);
  if (spec.shards > 1) {
    write_file_atomically((folder.staging() / "shard.txt").string(),
                          shard_manifest(spec, static_cast<int64_t>(rows.size()), csv));
  }
  folder.commit();
  print_rates(rows);
  std::printf("\n%zu runs in %.1f s on %d threads: %.1f runs/s, %.1f per thread\n", rows.size(),
              seconds, spec.jobs, rows.size() / seconds, rows.size() / seconds / spec.jobs);
  std::printf("wrote %s: robustness.csv, robustness_summary.csv, worst.csv%s\n",
              folder.path().c_str(), spec.shards > 1 ? ", shard.txt" : "");
  return 0;
}

}  // namespace

Command add_robustness_command(CLI::App& app) {
  auto f = std::make_shared<Flags>();
  CLI::App* command = app.add_subcommand(
      "robustness",
      "run every scenario x solver x rule x dt from N random starts (--seed); write "
      "robustness.csv, the divergence rates with 95 % Wilson intervals and the worst starts as "
      "replay commands");
  add_robustness_flags(command, *f);
  return {command, [f] { return robustness(*f); }};
}

}  // namespace puppet::testbed
