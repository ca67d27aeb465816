// Sweeps: every scenario × solver configuration × dt, the runs in parallel, each judged against
// the truth and against bullet-multibody at the same dt, and timed afterwards one at a time
// (docs/design.md, "Metrics": accuracy, step_us).
#pragma once

#include <array>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/compare/run.h"
#include "puppet/compare/solver_config.h"

namespace puppet::compare {

// A truth: an engine at a fine dt h, run at 2h, h and h/2 in every judged scenario. Its run at h
// judges the others; the two differences (2h and h/2 against h) give its order of convergence
// and so a bound on its own error (docs/design.md, "Metrics"). Each engine's constraint model is
// refined with dt (MuJoCo's time constant 2·dt, Bullet's Baumgarte fraction per step), so the
// bound includes the constraint model's own error.
struct Truth {
  std::string solver;
  SolverOptions options;
  double dt = 0.0;        // h
  std::string reference;  // the rows' reference column: kTruthReference or kSecondTruthReference
};
inline constexpr const char* kTruthReference = "truth";
inline constexpr const char* kSecondTruthReference = "second-truth";
// the truths' engines and their h: MuJoCo with RK4 at 1/7680 s, bullet-multibody at 1/3840 s
// (it divides every dt of the sweep)
inline constexpr const char* kMujocoTruthSolver = "mujoco";
inline constexpr const char* kMujocoTruthText = "MuJoCo (RK4)";  // as the report names it
inline constexpr const char* kMujocoTruthRefined = "MuJoCo's time constant 2·dt";
constexpr double kMujocoTruthDt = 1.0 / 7680.0;
inline constexpr const char* kBulletTruthSolver = "bullet-multibody";
inline constexpr const char* kBulletTruthText = kBulletTruthSolver;  // its default settings
inline constexpr const char* kBulletTruthRefined = "Bullet's Baumgarte fraction per step";
constexpr double kBulletTruthDt = 1.0 / 3840.0;
// The truths for a model, the judging one first: MuJoCo RK4 where it builds every joint and
// limit exactly (hinges, box limits, unlimited balls: mjcf_inexact_joint), since it is
// the sharper of the two (its pins are exact or stiff springs, not iterated impulses); else
// bullet-multibody, whose rows hold the model's swing–twist limits. The other follows when it can
// build the model within `budget` (engines.h: engine_model_problem). Empty when neither can.
std::vector<Truth> truths_for(const Model& model, double budget);
// the engine and dt bullet-multibody's pairwise rows are measured against (the same dt)
inline constexpr const char* kPairwiseSolver = "bullet-multibody";
inline constexpr const char* kPairwiseReference = "pairwise";  // its rows' reference column

// The step rates the studies search, coarsest first, each twice the last (1/30 s to 1/960 s):
// a sweep (testbed run) runs all but the finest unless told, the verdict runs them all
inline constexpr std::array<int, 6> kStepRates{30, 60, 120, 240, 480, 960};
inline constexpr size_t kSweepStepRates = 5;
// the first `count` step rates as a --dt flag writes them: "1/30,1/60,..."
std::string dt_flag(size_t count = kStepRates.size());

struct SweepSpec {
  const Model* model = nullptr;
  std::vector<Scenario> scenarios;
  std::vector<SolverConfig> configs;
  std::vector<double> dts;
  RunOptions run;  // its dt is ignored: every dt of `dts` runs
  // truth rows where dt divides 1/30 s, and pairwise rows when bullet-multibody is a config
  bool accuracy = true;
  // judge against the first truth alone, at its h: no second truth and no error-bar runs
  // (quicker, for sweeps that only compare configurations, such as the ablation)
  bool first_truth_only = false;
  // a folder of truth trajectories (truth_cache.h): each truth run is read from it when there,
  // else computed and stored; empty: none
  std::string truth_cache;
  int jobs = 1;  // worker threads for the runs; timing always runs alone
  double engine_budget = kDefaultEngineBudget;  // what the truths' engines may cost (engines.h)
  // called once per finished run, on the thread that ran it (e.g. to write its trace), before
  // the trace and poses are dropped
  std::function<void(const RunResult&)> on_run;
  // called after every job, one call at a time
  std::function<void(size_t done, size_t total)> on_progress;
};

// Results in scenario × config × dt order. With accuracy, rows on the truths follow, per
// scenario and truth: its run at h/2 and its run at 2h against its run at h (reference its own:
// the two differences that bound its error; the h/2 row also carries its limit violation, its
// pin gaps and a "truth_dt" row holding h), and with two truths each one's run at h against the
// other (their agreement). Every run is judged against every truth.
std::vector<RunResult> run_sweep(const SweepSpec& spec);

// runs job(0) … job(count − 1) on `threads` threads (at most `count`), calling after_each (one
// call at a time) as each finishes; the first exception a job throws is rethrown here
void parallel_for(size_t count, int threads, const std::function<void(size_t)>& job,
                  const std::function<void()>& after_each = {});

}  // namespace puppet::compare
