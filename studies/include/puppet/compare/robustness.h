// Stability as a statistic (`testbed robustness`): every chosen scenario × solver configuration ×
// dt from N random starts (start.h), each run judged by the testbed's divergence criteria; per
// configuration the divergence rate with its 95 % Wilson interval, and the worst starts as
// command lines that replay them. A run is one job; jobs are numbered scenario-major, then
// configuration, dt and start, and shard I of N runs the jobs j with j mod N = I, so that shards
// merge into exactly what one unsharded run writes (docs/robustness.md).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/compare/sweep.h"

namespace puppet::compare {

struct RobustnessSpec {
  const Model* model = nullptr;
  std::string model_name;  // as given (pinocchio, chain:8, a file): the replay commands repeat it
  std::vector<std::string> scenarios;
  ScenarioOptions scenario;  // the base; each run adds its start
  std::vector<SolverConfig> configs;
  std::vector<double> dts;
  int64_t starts = 100;
  uint64_t seed = 1;
  double duration = -1.0;  // < 0: each scenario's own
  int shard = 0, shards = 1;
  int jobs = 1;
  // the testbed flags a replay repeats beyond which run it is (" --duration 3 --iterations 8"),
  // and the code's identity (its commit): shards of one sweep agree on both
  std::string replay_flags;
  std::string code;
  std::function<void(size_t done, size_t total)> on_progress;
};

struct RobustnessRow {
  int64_t job = 0;
  std::string scenario, solver, rule;
  double dt = 0.0;
  uint64_t seed = 0;
  int64_t start = 0;
  double tilt_deg = 0.0, hz = 0.0, phase_deg = 0.0;
  std::string grab_segment;  // empty without a grab
  Vector3d grab_point{0, 0, 0};
  double joint_angle_rms_deg = 0.0, joint_speed_rms = 0.0;
  bool diverged = false;
  std::string reason;
  double diverged_at = 0.0, peak_speed = 0.0, joint_gap_max = 0.0, pin_gap_max = 0.0;
  int steps = 0;
};

// one run of a scenario for its status alone (no timing, no poses kept but the first and last);
// duration < 0: the scenario's own
RunResult run_for_divergence(const SolverConfig& config, const Model& model,
                             const Scenario& scenario, double dt, double duration = -1.0);

// the number of jobs of the whole (unsharded) spec, and whether job j is this shard's
int64_t robustness_job_count(const RobustnessSpec& spec);
inline bool in_shard(const RobustnessSpec& spec, int64_t job) {
  return job % spec.shards == spec.shard;
}

// this shard's runs, in job order
std::vector<RobustnessRow> run_robustness(const RobustnessSpec& spec);

// the 95 % Wilson score interval of k successes in n trials (Wilson 1927)
struct Interval {
  double low = 0.0, high = 1.0;
};
Interval wilson_interval(int64_t k, int64_t n, double z = 1.959963984540054);

// per scenario and configuration, in job order: the runs, the diverged ones, the rate and its
// interval
struct RobustnessRate {
  std::string scenario, solver, rule;
  double dt = 0.0;
  int64_t runs = 0, diverged = 0;
  Interval ci95;
  double rate() const { return static_cast<double>(diverged) / runs; }
};
std::vector<RobustnessRate> robustness_rates(const std::vector<RobustnessRow>& rows);

// The files one run writes, from its rows in job order (a merge writes the same from all
// shards' rows): robustness.csv, a row per run; robustness_summary.csv, per scenario and
// configuration the rate and its interval; worst.csv, per configuration up to `worst` starts
// (diverged first, earliest first; then the largest joint gap) with the command lines that
// replay them
inline constexpr const char* kRobustnessHeader =
    "job,scenario,solver,rule,dt,seed,start,tilt_deg,hz,phase_deg,grab_segment,grab_x,grab_y,"
    "grab_z,joint_angle_rms_deg,joint_speed_rms,status,reason,diverged_at_s,peak_speed_mps,"
    "joint_gap_max_m,pin_gap_max_m,steps";
inline constexpr const char* kRobustnessSummaryHeader =
    "scenario,solver,rule,dt,runs,diverged,rate,ci95_low,ci95_high";
inline constexpr const char* kWorstHeader =
    "scenario,solver,rule,dt,seed,start,status,diverged_at_s,joint_gap_max_m,peak_speed_mps,"
    "testbed,viewer";
std::string robustness_csv(const std::vector<RobustnessRow>& rows);
std::string robustness_summary_csv(const std::vector<RobustnessRow>& rows);
std::string worst_csv(const std::vector<RobustnessRow>& rows, const RobustnessSpec& spec,
                      int worst = 3);

// a word as a POSIX shell reads it back: as it is when it is plain (letters, digits, _ . / : = ,
// + -), else in single quotes, a quote inside as '\'' (so "$(id)" or "a; b" stay one inert word)
std::string shell_word(const std::string& text);

// reads what robustness_csv wrote back (the merge): numbers as csv_number writes them (no hex,
// no "nan"), counts as plain digits; throws std::runtime_error naming the line
std::vector<RobustnessRow> parse_robustness_csv(const std::string& text, const std::string& source);

}  // namespace puppet::compare
