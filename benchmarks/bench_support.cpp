#include "bench_support.h"

#include <filesystem>

#include "puppet/compare/engines.h"
#include "puppet/compare/metrics.h"
#include "puppet/compare/simulator.h"

#include <map>
#include <memory>

namespace puppet::bench {

std::vector<SolverConfig> solver_configs() {
  // in the catalogue's order; not one out of this process (jolt): its cost is WebAssembly's,
  // timed by itself (the testbed's step_us and the verdict report it apart), never ranked
  // against native code's here
  std::vector<std::string> native;
  for (const std::string& solver : compare::solver_names()) {
    if (compare::find_engine(solver)->native) native.push_back(solver);
  }
  return compare::solver_configs(native, procedural::kAllRules);
}

Workload make_workload(const Model& model, const std::string& scenario, int batch_steps,
                       double dt) {
  Workload workload;
  workload.model = &model;
  workload.scenario = compare::make_scenario(scenario, model);
  workload.dt = dt;
  workload.warm_up_steps = static_cast<int>(kWarmUpSeconds / dt + 0.5);
  workload.batch_targets.resize(batch_steps);
  for (int k = 0; k < batch_steps; ++k) {
    workload.scenario.targets_at((workload.warm_up_steps + k + 1) * dt, workload.batch_targets[k]);
  }
  return workload;
}

const Model& pinocchio() {
  static const Model model = compare::load_named_model(
      (std::filesystem::path(compare::builtin_model_path()).parent_path() /
       "pinocchio-swing-twist.json")
          .string());
  return model;
}

const Model& chain(int n) {
  static std::map<int, Model> models;
  auto it = models.find(n);
  if (it == models.end()) {
    it = models.emplace(n, compare::load_named_model("chain:" + std::to_string(n))).first;
  }
  return it->second;
}

namespace {

// the testbed's verdict on a warm-up step ending at t (compare::divergence_reason), or nullptr
// while the run is fine: a benchmark of a run the testbed calls diverged would time a broken
// simulation, so it is skipped with the reason
const char* divergence(compare::MetricsProbe& probe, double t, std::span<const BodyState> bodies,
                       std::span<const Vector3d> targets, bool non_finite) {
  if (non_finite) return "non-finite";
  return compare::divergence_reason(probe.measure(t, bodies, targets));
}

compare::MetricsProbe make_probe(const Workload& workload) {
  const compare::Scenario& scenario = workload.scenario;
  return compare::MetricsProbe(*workload.model, scenario.environment, scenario.initial_pins(),
                               scenario.initial);
}

void skip_diverged(benchmark::State& state, const char* reason) {
  state.SkipWithError((std::string("diverged during the warm-up (") + reason +
                       "): the testbed calls this run diverged, there is nothing to time")
                          .c_str());
}

}  // namespace

bool warm_up(benchmark::State& state, compare::Simulator& simulator, const Workload& workload) {
  simulator.reset(*workload.model, workload.scenario);
  compare::MetricsProbe probe = make_probe(workload);
  std::vector<BodyState> bodies(workload.model->segment_count());
  std::vector<Vector3d> targets;
  for (int k = 0; k < workload.warm_up_steps; ++k) {
    const double t = (k + 1) * workload.dt;
    workload.scenario.targets_at(t, targets);
    simulator.set_pin_targets(targets);
    simulator.step(workload.dt);
    simulator.read_state(bodies);
    if (const char* reason = divergence(probe, t, bodies, targets, simulator.diverged())) {
      skip_diverged(state, reason);
      return false;
    }
  }
  return true;
}

procedural::Settings procedural_settings(procedural::Rule rule) {
  compare::SolverOptions options;
  options.procedural.rule = rule;
  return compare::procedural_settings(options);
}

std::unique_ptr<procedural::Solver> warmed_up_solver(benchmark::State& state,
                                                     const Workload& workload,
                                                     procedural::Rule rule) {
  const compare::Scenario& scenario = workload.scenario;
  auto solver = std::make_unique<procedural::Solver>(*workload.model, procedural_settings(rule),
                                                     scenario.environment);
  solver->reset(scenario.initial);
  solver->set_pins(scenario.initial_pins());
  compare::MetricsProbe probe = make_probe(workload);
  std::vector<Vector3d> targets;
  for (int k = 0; k < workload.warm_up_steps; ++k) {
    const double t = (k + 1) * kDt;
    scenario.targets_at(t, targets);
    solver->set_pin_targets(targets);
    solver->step(kDt);
    if (const char* reason =
            divergence(probe, t, solver->state().bodies, targets, solver->state().diverged)) {
      skip_diverged(state, reason);
      break;
    }
  }
  return solver;
}

void run_batches(benchmark::State& state, compare::Simulator& simulator, const Workload& workload,
                 int64_t items_per_batch) {
  if (!warm_up(state, simulator, workload)) return;
  const std::unique_ptr<compare::Snapshot> snapshot = simulator.snapshot();
  const int steps = static_cast<int>(workload.batch_targets.size());
  for (auto _ : state) {
    simulator.restore(*snapshot);
    state.SetIterationTime(seconds_of([&] {
      for (int k = 0; k < steps; ++k) {
        simulator.set_pin_targets(workload.batch_targets[k]);
        simulator.step(workload.dt);
      }
    }));
  }
  if (simulator.diverged()) state.SkipWithError("diverged in a timed batch");
  state.SetItemsProcessed(state.iterations() * (items_per_batch > 0 ? items_per_batch : steps));
}

}  // namespace puppet::bench
