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

std::vector<Truth> truths_for(const Model& model, double budget) {
  std::vector<Truth> out;
  Truth mujoco{kMujocoTruthSolver, {}, kMujocoTruthDt, {}};
  mujoco.options.mujoco.integrator = reference::MujocoIntegrator::kRk4;
  // an engine this build lacks is "unknown" to the catalogue: a problem too
  const bool have_mujoco = engine_model_problem(kMujocoTruthSolver, model, {}, budget).empty();
  const bool have_bullet = engine_model_problem(kBulletTruthSolver, model, {}, budget).empty();
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

std::string dt_flag(size_t count) {
  std::string out;
  for (size_t k = 0; k < count && k < kStepRates.size(); ++k) {
    out += (k == 0 ? "1/" : ",1/") + std::to_string(kStepRates[k]);
  }
  return out;
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

namespace {

// What the sweep's phases share: the spec, the truths and their trajectories, the results as
// they fill in, and one progress count over every phase.
//   phases: [truths at three dts] → [the truths' rows, bullet-multibody runs] → [other runs]
//           → [timing]; each needs the trajectories of the one before
struct Sweep {
  explicit Sweep(const SweepSpec& spec_in) : spec(spec_in), model(*spec_in.model) {}
  const SweepSpec& spec;
  const Model& model;
  std::vector<Truth> truth_list;
  size_t truths = 0, levels = 1;  // truths, and their levels: h, then h/2 and 2h
  bool pairwise = false;          // bullet-multibody's runs are the pairwise rows' reference
  size_t pairwise_config = 0;
  size_t run_count = 0, truth_jobs = 0, check_rows_per_scenario = 0, check_jobs = 0;
  // per scenario, truth and level (h, h/2, 2h)
  std::vector<std::vector<std::array<Trajectory, 3>>> truth;
  std::vector<RunResult> results;  // the runs by index(), then the truths' check rows
  std::vector<Trajectory> paired;  // bullet-multibody's trajectory by scenario and dt
  size_t done = 0, total = 0;

  size_t configs() const { return spec.configs.size(); }
  size_t dts() const { return spec.dts.size(); }
  size_t index(size_t s, size_t c, size_t d) const { return (s * configs() + c) * dts() + d; }
  bool judged(double dt) const { return spec.accuracy && divides_sample_interval(dt); }
  SolverConfig truth_config(size_t t) const {
    return SolverConfig{truth_list[t].solver, truth_list[t].options};
  }
  void progress() {
    ++done;
    if (spec.on_progress) spec.on_progress(done, total);
  }
  std::function<void()> ticker() {
    return [this] { progress(); };
  }
};

// the truths, their levels, the phases' job counts and the result slots
void plan(Sweep& sweep) {
  const SweepSpec& spec = sweep.spec;
  const size_t scenario_count = spec.scenarios.size();
  const bool any_judged =
      std::any_of(spec.dts.begin(), spec.dts.end(), [&](double dt) { return sweep.judged(dt); });
  const auto pairwise_config =
      std::find_if(spec.configs.begin(), spec.configs.end(), is_pairwise_solver);
  sweep.pairwise = pairwise_config != spec.configs.end();
  sweep.pairwise_config = static_cast<size_t>(pairwise_config - spec.configs.begin());
  sweep.truth_list =
      any_judged ? truths_for(sweep.model, spec.engine_budget) : std::vector<Truth>{};
  if (spec.first_truth_only && sweep.truth_list.size() > 1) sweep.truth_list.resize(1);
  sweep.truths = sweep.truth_list.size();
  sweep.levels = spec.first_truth_only ? 1 : 3;
  sweep.run_count = scenario_count * sweep.configs() * sweep.dts();
  sweep.truth_jobs = sweep.levels * sweep.truths * scenario_count;
  // per scenario: each truth's h/2 and 2h against its h, and each against the other; with the
  // first truth alone, one result that names it (its truth_dt row)
  sweep.check_rows_per_scenario =
      spec.first_truth_only ? sweep.truths : 2 * sweep.truths + (sweep.truths == 2 ? 2 : 0);
  sweep.check_jobs = sweep.check_rows_per_scenario * scenario_count;
  const size_t timing_jobs = spec.run.timing ? sweep.run_count : 0;
  sweep.total = sweep.truth_jobs + sweep.check_jobs + sweep.run_count + timing_jobs;
  sweep.truth.assign(scenario_count, std::vector<std::array<Trajectory, 3>>(sweep.truths));
  sweep.results.resize(sweep.run_count + sweep.check_jobs);
  sweep.paired.resize(scenario_count * sweep.dts());
}

// every truth at every level, through the truth cache
void run_truths(Sweep& sweep) {
  const SweepSpec& spec = sweep.spec;
  const TruthCache cache(spec.truth_cache);
  const size_t levels = sweep.levels, truths = sweep.truths;
  parallel_for(
      sweep.truth_jobs, spec.jobs,
      [&](size_t i) {
        const size_t s = i / (levels * truths), t = i % (levels * truths) / levels;
        // the finest first: the longest jobs start early
        const size_t level = levels == 1 ? 0 : std::array<size_t, 3>{1, 0, 2}[i % 3];
        const SolverConfig config = sweep.truth_config(t);
        const double dt = sweep.truth_list[t].dt * kLevelScale[level];
        const Scenario& scenario = spec.scenarios[s];
        const double duration = duration_of(scenario, spec.run);
        sweep.truth[s][t][level] = cache.get(
            truth_key(sweep.model, scenario, config.solver, config.options, dt, duration), [&] {
              auto simulator = make(config);
              return record_trajectory(*simulator, sweep.model, scenario, dt, duration);
            });
      },
      sweep.ticker());
}

// one run of scenario s by configuration c at dt d, judged against the truths (and against
// bullet-multibody's run at that dt for the pairwise rows)
void run_one(Sweep& sweep, size_t s, size_t c, size_t d) {
  const SweepSpec& spec = sweep.spec;
  const Scenario& scenario = spec.scenarios[s];
  const SolverConfig& config = spec.configs[c];
  RunOptions options = spec.run;
  options.dt = spec.dts[d];
  options.timing = false;
  options.record_trajectory = sweep.judged(options.dt);
  auto simulator = make(config);
  RunResult result = run_scenario(*simulator, sweep.model, scenario, options);
  if (options.record_trajectory) {
    auto add = [&](const Trajectory& reference, const char* label) {
      auto rows = accuracy_rows(*simulator, sweep.model, scenario, options.dt, result.trajectory,
                                reference, label);
      result.summary.insert(result.summary.end(), rows.begin(), rows.end());
    };
    for (size_t t = 0; t < sweep.truths; ++t) {
      add(sweep.truth[s][t][0], sweep.truth_list[t].reference.c_str());
    }
    if (sweep.pairwise && !is_pairwise_solver(config)) {
      add(sweep.paired[s * sweep.dts() + d], kPairwiseReference);
    }
  }
  if (spec.on_run) spec.on_run(result);
  if (sweep.pairwise && is_pairwise_solver(config)) {
    sweep.paired[s * sweep.dts() + d] = std::move(result.trajectory);
  }
  result.trace = {};
  result.poses = {};
  result.trajectory = {};
  sweep.results[sweep.index(s, c, d)] = std::move(result);
}

// check row i: a truth's own error (at h/2 or 2h against itself at h), or one truth against the
// other; with the first truth alone, the row that names it
void check_truth(Sweep& sweep, size_t i) {
  const SweepSpec& spec = sweep.spec;
  RunResult& r = sweep.results[sweep.run_count + i];
  if (spec.first_truth_only) {
    r.scenario = spec.scenarios[i].name;
    r.solver = sweep.truth_list[0].solver;
    r.dt = sweep.truth_list[0].dt;
    r.diverged = sweep.truth[i][0][0].diverged;
    r.summary.push_back(
        summary_row(metric::kTruthDt, stats::kTruthStep, r.dt, sweep.truth_list[0].reference));
    return;
  }
  const size_t s = i / sweep.check_rows_per_scenario, k = i % sweep.check_rows_per_scenario;
  // k < 2·truths: truth k/2 at h/2 (even k) or 2h (odd k) against itself at h; then each truth
  // at h against the other
  const bool own = k < 2 * sweep.truths;
  const size_t t = own ? k / 2 : k - 2 * sweep.truths;
  const size_t level = own ? (k % 2 == 0 ? 1 : 2) : 0;
  const size_t against = own ? t : 1 - t;
  const Truth& run = sweep.truth_list[t];
  const std::string& label = sweep.truth_list[against].reference;
  const Trajectory& trajectory = sweep.truth[s][t][level];
  r.scenario = spec.scenarios[s].name;
  r.solver = run.solver;
  r.dt = run.dt * kLevelScale[level];
  r.diverged = trajectory.diverged;
  auto simulator = make(sweep.truth_config(t));
  r.summary = accuracy_rows(*simulator, sweep.model, spec.scenarios[s], r.dt, trajectory,
                            sweep.truth[s][against][0], label.c_str());
  if (level == 2) return;
  // how far the truth itself leaves the model's limits and holds its pins
  r.summary.push_back(summary_row(metric::kLimitViolation, stats::kMax,
                                  max_limit_violation_deg(sweep.model, trajectory), label));
  const PinGaps pin = trajectory_pin_gaps(spec.scenarios[s], trajectory);
  r.summary.push_back(summary_row(metric::kPinGap, stats::kMax, pin.max, label));
  r.summary.push_back(summary_row(metric::kPinGap, stats::kRms, pin.rms, label));
  if (own) r.summary.push_back(summary_row(metric::kTruthDt, stats::kTruthStep, run.dt, label));
}

// the runs k (indices of index()) on the spec's threads
void run_all(Sweep& sweep, const std::vector<size_t>& runs, size_t checks) {
  const size_t configs = sweep.configs(), dts = sweep.dts();
  parallel_for(
      checks + runs.size(), sweep.spec.jobs,
      [&](size_t i) {
        if (i < checks) {
          check_truth(sweep, i);
          return;
        }
        const size_t k = runs[i - checks];
        run_one(sweep, k / (configs * dts), k / dts % configs, k % dts);
      },
      sweep.ticker());
}

// the truths' own errors and their agreement, and bullet-multibody at every dt; then every
// other run, which the pairwise rows judge against bullet-multibody's
void run_configurations(Sweep& sweep) {
  std::vector<size_t> pairwise_runs, rest;
  for (size_t s = 0; s < sweep.spec.scenarios.size(); ++s) {
    for (size_t d = 0; d < sweep.dts() && sweep.pairwise; ++d) {
      pairwise_runs.push_back(sweep.index(s, sweep.pairwise_config, d));
    }
  }
  for (size_t k = 0; k < sweep.run_count; ++k) {
    const SolverConfig& config = sweep.spec.configs[k / sweep.dts() % sweep.configs()];
    if (!sweep.pairwise || !is_pairwise_solver(config)) rest.push_back(k);
  }
  run_all(sweep, pairwise_runs, sweep.check_jobs);
  run_all(sweep, rest, 0);
}

// timing, one run at a time
void time_runs(Sweep& sweep) {
  const SweepSpec& spec = sweep.spec;
  for (size_t k = 0; k < sweep.run_count && spec.run.timing; ++k) {
    RunOptions options = spec.run;
    options.dt = sweep.results[k].dt;
    auto simulator = make(spec.configs[k / sweep.dts() % sweep.configs()]);
    time_scenario(*simulator, sweep.model, spec.scenarios[k / (sweep.configs() * sweep.dts())],
                  options, sweep.results[k]);
    sweep.progress();
  }
}

}  // namespace

std::vector<RunResult> run_sweep(const SweepSpec& spec) {
  Sweep sweep(spec);
  plan(sweep);                // the truths, the jobs of each phase, the result slots
  run_truths(sweep);          // every truth at h, h/2 and 2h
  run_configurations(sweep);  // the truths' own rows and every configuration at every dt
  time_runs(sweep);           // one run at a time, when the spec times them
  return std::move(sweep.results);
}

}  // namespace puppet::compare
