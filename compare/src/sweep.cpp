#include "puppet/compare/sweep.h"

#include "puppet/compare/engines.h"
#include "puppet/compare/summary_metrics.h"
#include "puppet/compare/truth_cache.h"
#include "puppet/model/mjcf.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace puppet::compare {
namespace {

bool is_pairwise_solver(const SolverConfig& config) { return config.solver == kPairwiseSolver; }

std::unique_ptr<Simulator> make(const SolverConfig& config) {
  return make_simulator(config.solver, config.options);
}

double duration_of(const Scenario& scenario, const RunOptions& options) {
  return options.duration >= 0.0 ? options.duration : scenario.duration;
}

// a truth's three runs: [0] at h, [1] at h/2, [2] at 2h
constexpr double kLevelScale[3] = {1.0, 0.5, 2.0};

}  // namespace

std::vector<Truth> truths_for(const Model& model) {
  std::vector<Truth> out;
  Truth mujoco{kMujocoTruthSolver, {}, kMujocoTruthDt, {}};
  mujoco.options.mujoco.integrator = reference::MujocoIntegrator::kRk4;
  // an engine this build lacks is "unknown" to the catalogue: a problem too
  const bool have_mujoco = engine_model_problem(kMujocoTruthSolver, model).empty();
  const bool have_bullet = engine_model_problem(kBulletTruthSolver, model).empty();
  const Truth bullet{kBulletTruthSolver, {}, kBulletTruthDt, {}};
  if (have_mujoco && mjcf_inexact_joint(model).empty()) {
    out.push_back(mujoco);
    if (have_bullet) out.push_back(bullet);
  } else {
    if (have_bullet) out.push_back(bullet);
    if (have_mujoco) out.push_back(mujoco);
  }
  for (size_t t = 0; t < out.size(); ++t) {
    out[t].reference = t == 0 ? kTruthReference : kSecondTruthReference;
  }
  return out;
}

std::string rule_of(const SolverConfig& config) {
  return has_rules(config.solver) ? std::string(procedural::rule_name(config.options.rule))
                                  : std::string();
}

std::vector<SolverConfig> solver_configs(const std::vector<std::string>& solvers,
                                         std::span<const procedural::Rule> rules,
                                         const SolverOptions& options) {
  std::vector<SolverConfig> out;
  for (const std::string& solver : solvers) {
    if (!has_rules(solver)) {
      out.push_back({solver, options});
      continue;
    }
    for (const procedural::Rule rule : rules) {
      out.push_back({solver, options});
      out.back().options.rule = rule;
    }
  }
  return out;
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
  const auto pairwise_config =
      std::find_if(spec.configs.begin(), spec.configs.end(), is_pairwise_solver);
  const bool pairwise = pairwise_config != spec.configs.end();
  std::vector<Truth> truth_list = any_judged ? truths_for(model) : std::vector<Truth>{};
  if (spec.first_truth_only && truth_list.size() > 1) truth_list.resize(1);
  const size_t truths = truth_list.size();
  const size_t levels = spec.first_truth_only ? 1 : 3;  // h, then h/2 and 2h
  auto truth_config = [&](size_t t) {
    return SolverConfig{truth_list[t].solver, truth_list[t].options};
  };

  // phases: [truths at three dts] → [the truths' rows, bullet-multibody runs] → [other runs];
  // each needs the trajectories of the one before
  const size_t run_count = scenario_count * config_count * dt_count;
  const size_t truth_jobs = levels * truths * scenario_count;
  // per scenario: each truth's h/2 and 2h against its h, and each against the other; with the
  // first truth alone, one result that names it (its truth_dt row)
  const size_t check_rows_per_scenario =
      spec.first_truth_only ? truths : 2 * truths + (truths == 2 ? 2 : 0);
  const size_t check_jobs = check_rows_per_scenario * scenario_count;
  const size_t timing_jobs = spec.run.timing ? run_count : 0;
  const size_t total = truth_jobs + check_jobs + run_count + timing_jobs;
  size_t done = 0;
  auto progress = [&] {
    ++done;
    if (spec.on_progress) spec.on_progress(done, total);
  };

  // per scenario, truth and level (h, h/2, 2h)
  std::vector<std::vector<std::array<Trajectory, 3>>> truth(
      scenario_count, std::vector<std::array<Trajectory, 3>>(truths));
  const TruthCache cache(spec.truth_cache);
  parallel_for(
      truth_jobs, spec.jobs,
      [&](size_t i) {
        const size_t s = i / (levels * truths), t = i % (levels * truths) / levels;
        // the finest first: the longest jobs start early
        const size_t level = levels == 1 ? 0 : std::array<size_t, 3>{1, 0, 2}[i % 3];
        const SolverConfig config = truth_config(t);
        const double dt = truth_list[t].dt * kLevelScale[level];
        const Scenario& scenario = spec.scenarios[s];
        const double duration = duration_of(scenario, spec.run);
        truth[s][t][level] =
            cache.get(truth_key(model, scenario, config.solver, config.options, dt, duration), [&] {
              auto simulator = make(config);
              return record_trajectory(*simulator, model, scenario, dt, duration);
            });
      },
      progress);

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
      for (size_t t = 0; t < truths; ++t) add(truth[s][t][0], truth_list[t].reference.c_str());
      if (pairwise && !is_pairwise_solver(config))
        add(paired[s * dt_count + d], kPairwiseReference);
    }
    if (spec.on_run) spec.on_run(result);
    if (pairwise && is_pairwise_solver(config))
      paired[s * dt_count + d] = std::move(result.trajectory);
    result.trace = {};
    result.poses = {};
    result.trajectory = {};
    results[index(s, c, d)] = std::move(result);
  };

  // the truths' own errors and their agreement, and bullet-multibody at every dt
  std::vector<size_t> pairwise_runs;
  for (size_t s = 0; s < scenario_count; ++s) {
    for (size_t d = 0; d < dt_count && pairwise; ++d) {
      pairwise_runs.push_back(
          index(s, static_cast<size_t>(pairwise_config - spec.configs.begin()), d));
    }
  }
  parallel_for(
      check_jobs + pairwise_runs.size(), spec.jobs,
      [&](size_t i) {
        if (i < check_jobs && spec.first_truth_only) {
          RunResult& r = results[run_count + i];
          r.scenario = spec.scenarios[i].name;
          r.solver = truth_list[0].solver;
          r.dt = truth_list[0].dt;
          r.diverged = truth[i][0][0].diverged;
          r.summary.push_back(
              summary_row(metric::kTruthDt, stats::kTruthStep, r.dt, truth_list[0].reference));
          return;
        }
        if (i < check_jobs) {
          const size_t s = i / check_rows_per_scenario, k = i % check_rows_per_scenario;
          // k < 2·truths: truth k/2 at h/2 (even k) or 2h (odd k) against itself at h; then
          // each truth at h against the other
          const bool own = k < 2 * truths;
          const size_t t = own ? k / 2 : k - 2 * truths;
          const size_t level = own ? (k % 2 == 0 ? 1 : 2) : 0;
          const size_t against = own ? t : 1 - t;
          const Truth& run = truth_list[t];
          const std::string& label = truth_list[against].reference;
          RunResult& r = results[run_count + i];
          r.scenario = spec.scenarios[s].name;
          r.solver = run.solver;
          r.dt = run.dt * kLevelScale[level];
          r.diverged = truth[s][t][level].diverged;
          auto simulator = make(truth_config(t));
          r.summary = accuracy_rows(*simulator, model, spec.scenarios[s], r.dt, truth[s][t][level],
                                    truth[s][against][0], label.c_str());
          if (level == 2) return;
          // how far the truth itself leaves the model's limits and holds its pins
          r.summary.push_back(summary_row(metric::kLimitViolation, stats::kMax,
                                          max_limit_violation_deg(model, truth[s][t][level]),
                                          label));
          const PinGaps pin = trajectory_pin_gaps(spec.scenarios[s], truth[s][t][level]);
          r.summary.push_back(summary_row(metric::kPinGap, stats::kMax, pin.max, label));
          r.summary.push_back(summary_row(metric::kPinGap, stats::kRms, pin.rms, label));
          if (own)
            r.summary.push_back(summary_row(metric::kTruthDt, stats::kTruthStep, run.dt, label));
          return;
        }
        const size_t k = pairwise_runs[i - check_jobs];
        run_one(k / (config_count * dt_count), k / dt_count % config_count, k % dt_count);
      },
      progress);

  // every other run
  std::vector<size_t> rest;
  for (size_t k = 0; k < run_count; ++k) {
    if (!pairwise || !is_pairwise_solver(spec.configs[k / dt_count % config_count])) {
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
