#include "puppet/compare/sweep.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace puppet::compare {
namespace {

// the dt of each truth slot: [0] the truth, [1] its check, [2] the second truth, [3] its check
constexpr double kTruthSlotDts[4] = {kTruthDt, kTruthCheckDt, kSecondTruthDt, kSecondTruthCheckDt};

bool is_truth_solver(const SolverConfig& config) { return config.solver == kTruthSolver; }

std::unique_ptr<Simulator> make(const SolverConfig& config) {
  return make_simulator(config.solver, config.options);
}

double duration_of(const Scenario& scenario, const RunOptions& options) {
  return options.duration >= 0.0 ? options.duration : scenario.duration;
}

}  // namespace

SolverOptions second_truth_options() {
  SolverOptions options;
  options.mujoco_integrator = reference::MujocoIntegrator::kRk4;
  options.mujoco_time_constant = kSecondTruthTimeConstant;
  return options;
}

bool have_second_truth(const Model& model) {
  return reference::have_mujoco() && reference::mujoco_model_problem(model).empty();
}

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

  const bool second = any_judged && have_second_truth(model);
  const SolverConfig second_solver{kSecondTruthSolver, second_truth_options()};

  // phases: [truths and their checks] → [the checks' rows, bullet-multibody runs] → [other runs];
  // each needs the trajectories of the one before
  const size_t run_count = scenario_count * config_count * dt_count;
  const size_t truths = any_judged ? (second ? 2 : 1) : 0;  // per scenario
  const size_t truth_jobs = 2 * truths * scenario_count;
  const size_t check_rows_per_scenario = second ? 4 : 1;
  const size_t check_jobs = any_judged ? check_rows_per_scenario * scenario_count : 0;
  const size_t timing_jobs = spec.run.timing ? run_count : 0;
  const size_t total = truth_jobs + check_jobs + run_count + timing_jobs;
  size_t done = 0;
  auto progress = [&] {
    ++done;
    if (spec.on_progress) spec.on_progress(done, total);
  };

  // per scenario: [0] the truth, [1] its check, [2] the second truth, [3] its check
  std::vector<std::array<Trajectory, 4>> truth(scenario_count);
  if (any_judged) {
    parallel_for(
        truth_jobs, spec.jobs,
        [&](size_t i) {
          const size_t s = i / (2 * truths), k = i % (2 * truths);
          // the longer check first
          const size_t slot = k == 0 ? 1 : k == 1 ? 0 : k;
          auto simulator = make(slot < 2 ? truth_solver : second_solver);
          const double dt = kTruthSlotDts[slot];
          const double duration = duration_of(spec.scenarios[s], spec.run);
          truth[s][slot] = record_trajectory(*simulator, model, spec.scenarios[s], dt, duration);
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
      auto add = [&](const Trajectory& reference, const char* label) {
        auto rows = accuracy_rows(*simulator, model, scenario, options.dt, result.trajectory,
                                  reference, label);
        result.summary.insert(result.summary.end(), rows.begin(), rows.end());
      };
      add(truth[s][0], "truth");
      if (second) add(truth[s][2], kSecondTruthReference);
      if (pairwise && !is_truth_solver(config)) add(paired[s * dt_count + d], "pairwise");
    }
    if (spec.on_run) spec.on_run(result);
    if (pairwise && is_truth_solver(config))
      paired[s * dt_count + d] = std::move(result.trajectory);
    result.trace = {};
    result.poses = {};
    result.trajectory = {};
    results[index(s, c, d)] = std::move(result);
  };

  // the truths' own errors and their agreement, and bullet-multibody at every dt
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
          const size_t s = i / check_rows_per_scenario, k = i % check_rows_per_scenario;
          // k: 0 the truth's check, 1 the second truth's check, 2 the second truth against the
          // first, 3 the first against the second
          const size_t run = k == 0 ? 1 : k == 1 ? 3 : k == 2 ? 2 : 0;
          const size_t against = k == 0 || k == 2 ? 0 : 2;
          const bool second_solver_run = run >= 2;
          RunResult& r = results[run_count + i];
          r.scenario = spec.scenarios[s].name;
          r.solver = second_solver_run ? kSecondTruthSolver : kTruthSolver;
          r.dt = kTruthSlotDts[run];
          r.diverged = truth[s][run].diverged;
          auto simulator = make(second_solver_run ? second_solver : truth_solver);
          const char* label = against == 0 ? "truth" : kSecondTruthReference;
          r.summary = accuracy_rows(*simulator, model, spec.scenarios[s], r.dt, truth[s][run],
                                    truth[s][against], label);
          // how far the truth itself leaves the model's limits (MuJoCo's differ)
          r.summary.push_back({"limit_violation_deg", "max",
                               max_limit_violation_deg(model, truth[s][run]), "deg", label});
          // and how well it holds its pins
          const PinGaps pin = trajectory_pin_gaps(spec.scenarios[s], truth[s][run]);
          r.summary.push_back({"pin_gap_m", "max", pin.max, "m", label});
          r.summary.push_back({"pin_gap_m", "rms", pin.rms, "m", label});
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
