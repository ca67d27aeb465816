#include "puppet/compare/sweep.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace puppet::compare {
namespace {

bool is_truth_solver(const SolverConfig& config) { return config.solver == kTruthSolver; }

std::unique_ptr<Simulator> make(const SolverConfig& config) {
  return make_simulator(config.solver, config.options);
}

double duration_of(const Scenario& scenario, const RunOptions& options) {
  return options.duration >= 0.0 ? options.duration : scenario.duration;
}

}  // namespace

const std::vector<double>& sweep_dts() {
  static const std::vector<double> dts{1.0 / 30, 1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480};
  return dts;
}

void parallel_for(size_t count, int threads, const std::function<void(size_t)>& job,
                  const std::function<void()>& after_each) {
  std::atomic<size_t> next{0};
  std::mutex mutex;
  std::exception_ptr failure;
  auto worker = [&] {
    for (size_t i = next++; i < count; i = next++) {
      try {
        job(i);
      } catch (...) {
        const std::lock_guard lock(mutex);
        if (!failure) failure = std::current_exception();
        next = count;  // stop handing out work
        return;
      }
      if (after_each) {
        const std::lock_guard lock(mutex);
        after_each();
      }
    }
  };
  const size_t n = std::min<size_t>(count, static_cast<size_t>(std::max(threads, 1)));
  std::vector<std::thread> pool;
  for (size_t t = 1; t < n; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

std::vector<RunResult> run_sweep(const SweepSpec& spec) {
  const Model& model = *spec.model;
  const size_t scenario_count = spec.scenarios.size(), config_count = spec.configs.size(),
               dt_count = spec.dts.size();
  auto judged = [&](double dt) { return spec.accuracy && divides_sample_interval(dt); };
  const bool any_judged = std::any_of(spec.dts.begin(), spec.dts.end(), judged);
  const auto truth_config = std::find_if(spec.configs.begin(), spec.configs.end(), is_truth_solver);
  const bool pairwise = truth_config != spec.configs.end();
  const SolverConfig truth_solver{kTruthSolver, pairwise ? truth_config->options : SolverOptions{}};

  // phases: [truth and its check] → [the check's rows, bullet-multibody runs] → [other runs];
  // each needs the trajectories of the one before
  const size_t run_count = scenario_count * config_count * dt_count;
  const size_t truth_jobs = any_judged ? 2 * scenario_count : 0;
  const size_t check_jobs = any_judged ? scenario_count : 0;
  const size_t timing_jobs = spec.run.timing ? run_count : 0;
  const size_t total = truth_jobs + check_jobs + run_count + timing_jobs;
  size_t done = 0;
  auto progress = [&] {
    ++done;
    if (spec.on_progress) spec.on_progress(done, total);
  };

  std::vector<Trajectory> truth(scenario_count), check(scenario_count);
  if (any_judged) {
    parallel_for(
        2 * scenario_count, spec.jobs,
        [&](size_t i) {
          const size_t s = i / 2;
          auto simulator = make(truth_solver);
          const double dt = i % 2 == 0 ? kTruthCheckDt : kTruthDt;  // the longer one first
          const double duration = duration_of(spec.scenarios[s], spec.run);
          (i % 2 == 0 ? check : truth)[s] =
              record_trajectory(*simulator, model, spec.scenarios[s], dt, duration);
        },
        progress);
  }

  std::vector<RunResult> results(run_count + check_jobs);
  auto index = [&](size_t s, size_t c, size_t d) { return (s * config_count + c) * dt_count + d; };
  // bullet-multibody's trajectory at every dt, for the pairwise rows
  std::vector<Trajectory> paired(scenario_count * dt_count);

  auto run_one = [&](size_t s, size_t c, size_t d) {
    const Scenario& scenario = spec.scenarios[s];
    const SolverConfig& config = spec.configs[c];
    RunOptions options = spec.run;
    options.dt = spec.dts[d];
    options.timing = false;
    options.record_trajectory = judged(options.dt);
    auto simulator = make(config);
    RunResult result = run_scenario(*simulator, model, scenario, options);
    if (options.record_trajectory) {
      auto rows = accuracy_rows(*simulator, model, scenario, options.dt, result.trajectory,
                                truth[s], "truth");
      result.summary.insert(result.summary.end(), rows.begin(), rows.end());
      if (pairwise && !is_truth_solver(config)) {
        rows = accuracy_rows(*simulator, model, scenario, options.dt, result.trajectory,
                             paired[s * dt_count + d], "pairwise");
        result.summary.insert(result.summary.end(), rows.begin(), rows.end());
      }
    }
    if (spec.on_run) spec.on_run(result);
    if (pairwise && is_truth_solver(config))
      paired[s * dt_count + d] = std::move(result.trajectory);
    result.trace = {};
    result.poses = {};
    result.trajectory = {};
    results[index(s, c, d)] = std::move(result);
  };

  // the truth's own error, and bullet-multibody at every dt
  std::vector<size_t> truth_runs;
  for (size_t s = 0; s < scenario_count; ++s) {
    for (size_t d = 0; d < dt_count && pairwise; ++d) {
      truth_runs.push_back(index(s, static_cast<size_t>(truth_config - spec.configs.begin()), d));
    }
  }
  parallel_for(
      check_jobs + truth_runs.size(), spec.jobs,
      [&](size_t i) {
        if (i < check_jobs) {
          RunResult& r = results[run_count + i];
          r.scenario = spec.scenarios[i].name;
          r.solver = kTruthSolver;
          r.dt = kTruthCheckDt;
          r.diverged = check[i].diverged;
          auto simulator = make(truth_solver);
          r.summary = accuracy_rows(*simulator, model, spec.scenarios[i], kTruthCheckDt, check[i],
                                    truth[i], "truth");
          return;
        }
        const size_t k = truth_runs[i - check_jobs];
        run_one(k / (config_count * dt_count), k / dt_count % config_count, k % dt_count);
      },
      progress);

  // every other run
  std::vector<size_t> rest;
  for (size_t k = 0; k < run_count; ++k) {
    if (!pairwise || !is_truth_solver(spec.configs[k / dt_count % config_count])) {
      rest.push_back(k);
    }
  }
  parallel_for(
      rest.size(), spec.jobs,
      [&](size_t i) {
        const size_t k = rest[i];
        run_one(k / (config_count * dt_count), k / dt_count % config_count, k % dt_count);
      },
      progress);

  // timing, one run at a time
  for (size_t k = 0; k < run_count && spec.run.timing; ++k) {
    RunOptions options = spec.run;
    options.dt = results[k].dt;
    auto simulator = make(spec.configs[k / dt_count % config_count]);
    time_scenario(*simulator, model, spec.scenarios[k / (config_count * dt_count)], options,
                  results[k]);
    progress();
  }
  return results;
}

}  // namespace puppet::compare
