// What every benchmark shares: the harness's scenarios at a warmed-up instant, and batches of
// steps timed by hand so that restoring the snapshot between batches is never timed.
//
// Each benchmark iteration restores the snapshot taken after the warm-up, then times kBatchSteps
// steps (0.25 s of simulated time at 1/240 s) with the scenario's pin targets precomputed.
// Items are steps, so items_per_second is steps per second and 1/items_per_second the time of
// one step.
#pragma once

#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/compare/solver_config.h"
#include "puppet/procedural/solver.h"

namespace puppet::bench {

inline constexpr double kDt = 1.0 / 240.0;
inline constexpr int kBatchSteps = 60;
// the scenarios that gate the speed claims (the hang, drag, drop)
inline const std::vector<std::string> kStepScenarios = {"hang", "drag", "drop"};

// every solver configuration the comparison runs: one per procedural rule, then the references
using compare::SolverConfig;
// every rule of procedural, then every other engine this build has that runs in this process,
// each labelled by config_label ("literal", …, "bullet-multibody", "bullet-rigid")
std::vector<SolverConfig> solver_configs();

// seconds stepped before the snapshot: past the targets' 0.5 s ramp, and in `drop` past the
// landing (the lowest point starts 1 m up: it lands at 0.45 s), so contacts are timed
inline constexpr double kWarmUpSeconds = 1.0;

// a scenario on a model, with the pin targets of one batch of steps of dt from the warm-up instant
struct Workload {
  const Model* model = nullptr;
  compare::Scenario scenario;
  double dt = kDt;
  int warm_up_steps = 0;
  std::vector<std::vector<Vector3d>> batch_targets;  // [step of the batch][pin]
};
Workload make_workload(const Model& model, const std::string& scenario, int batch_steps,
                       double dt = kDt);

// Pinocchio with its swing–twist limits (models/pinocchio-swing-twist.json), loaded once: the
// figure the gate's thresholds (results/gate.json) were measured on. The main model's box limits
// cost the procedural rules more per step (the main job's timing: xpbd 1.6 times in hang), which
// a full benchmark run must measure before the gate moves to it.
const Model& pinocchio();
// chain:N, loaded once per N
const Model& chain(int n);

// Resets the simulator into the workload and steps the warm-up; false (and the benchmark
// skipped with the reason) when it diverged on the way.
bool warm_up(benchmark::State& state, compare::Simulator& simulator, const Workload& workload);

// The settings the harness gives the procedural solver with this rule,
// and such a solver stepped through the warm-up (the benchmark skipped if it diverged).
procedural::Settings procedural_settings(procedural::Rule rule);
std::unique_ptr<procedural::Solver> warmed_up_solver(benchmark::State& state,
                                                     const Workload& workload,
                                                     procedural::Rule rule);

// the time of `body` in seconds, for UseManualTime()
template <typename Body>
double seconds_of(Body&& body) {
  const auto begin = std::chrono::steady_clock::now();
  body();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

// The standard loop: restore, then one timed batch of the workload's steps per iteration. Items
// are steps, or with `items_per_batch` > 0 that many per batch.
void run_batches(benchmark::State& state, compare::Simulator& simulator, const Workload& workload,
                 int64_t items_per_batch = 0);

}  // namespace puppet::bench
