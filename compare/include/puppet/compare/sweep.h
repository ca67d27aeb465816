// Sweeps: every scenario × solver configuration × dt, the runs in parallel, each judged against
// the truth and against bullet-multibody at the same dt, and timed afterwards one at a time
// (docs/design.md, "Metrics": accuracy, step_us).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "puppet/compare/run.h"

namespace puppet::compare {

// the truth: bullet-multibody at 1/3840 s (it divides every dt of the sweep), checked against
// 1/7680 s; rows against it have reference "truth"
inline constexpr const char* kTruthSolver = "bullet-multibody";
constexpr double kTruthDt = 1.0 / 3840.0;
constexpr double kTruthCheckDt = 1.0 / 7680.0;
// the second truth, when the build has MuJoCo: mujoco with RK4 at 1/7680 s, checked against
// 1/15360 s, its constraints' time constant fixed at 2/3840 s so that both have the same
// constraint model; rows against it have reference "mujoco-truth"
inline constexpr const char* kSecondTruthSolver = "mujoco";
inline constexpr const char* kSecondTruthReference = "mujoco-truth";
constexpr double kSecondTruthDt = 1.0 / 7680.0;
constexpr double kSecondTruthCheckDt = 1.0 / 15360.0;
constexpr double kSecondTruthTimeConstant = 2.0 / 3840.0;
SolverOptions second_truth_options();
// whether this build has the second truth and MuJoCo can build the model
// (reference::mujoco_model_problem); a sweep without it judges against the first truth alone
bool have_second_truth(const Model& model);

// the dts of the default sweep
const std::vector<double>& sweep_dts();

// a solver and its options (for procedural, the rule among them)
struct SolverConfig {
  std::string solver;
  SolverOptions options;
};

struct SweepSpec {
  const Model* model = nullptr;
  std::vector<Scenario> scenarios;
  std::vector<SolverConfig> configs;
  std::vector<double> dts;
  RunOptions run;  // its dt is ignored: every dt of `dts` runs
  // truth rows where dt divides 1/30 s, and pairwise rows when bullet-multibody is a config
  bool accuracy = true;
  int jobs = 1;  // worker threads for the runs; timing always runs alone
  // called once per finished run, on the thread that ran it (e.g. to write its trace), before
  // the trace and poses are dropped
  std::function<void(const RunResult&)> on_run;
  // called after every job, one call at a time
  std::function<void(size_t done, size_t total)> on_progress;
};

// Results in scenario × config × dt order. With accuracy, one more result per scenario follows:
// bullet-multibody at kTruthCheckDt against the truth, whose rows say how far the truth itself
// can be trusted (it judges only errors more than ten times larger). With the second truth,
// three more per scenario: mujoco (RK4) at kSecondTruthCheckDt against the second truth, the
// second truth against the first (mujoco at kSecondTruthDt, reference "truth") and the first
// against the second (bullet-multibody at kTruthDt, reference "mujoco-truth"). Every run is
// judged against both truths.
std::vector<RunResult> run_sweep(const SweepSpec& spec);

// runs job(0) … job(count − 1) on `threads` threads (at most `count`), calling after_each (one
// call at a time) as each finishes; the first exception a job throws is rethrown here
void parallel_for(size_t count, int threads, const std::function<void(size_t)>& job,
                  const std::function<void()>& after_each = {});

}  // namespace puppet::compare
