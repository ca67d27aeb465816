#include "verdict_contact.h"

#include <algorithm>
#include <cmath>

#include "puppet/compare/robustness.h"
#include "puppet/compare/start.h"

namespace puppet::compare {

JudgedRun judged_run(const SolverConfig& config, const Model& model, const std::string& name,
                     ScenarioOptions options, double dt, uint64_t seed, int64_t index) {
  if (index >= 0) options.start = random_start(model, seed, index);
  const Scenario scenario = make_scenario(name, model, options);
  auto simulator = make_simulator(config.solver, config.options);
  RunOptions run;
  run.dt = dt;
  run.timing = false;
  run.sample_hz = 1e-3;  // the first pose only: the trajectory's samples hold the rest
  run.record_trajectory = judged_by_contact(name);
  JudgedRun out{run_scenario(*simulator, model, scenario, run), {}};
  if (run.record_trajectory) out.outcome = contact_outcome(model, scenario, out.run);
  return out;
}

size_t contact_truth_runs(size_t truth_count, int64_t starts) {
  const size_t n = static_cast<size_t>(std::max<int64_t>(starts, 0));
  return truth_count > 1 ? 4 + 2 * n : 3 + n;
}

ContactScene contact_truths(const Model& model, const std::vector<Truth>& truths,
                            const std::string& name, const ScenarioOptions& options, int64_t starts,
                            uint64_t seed, int jobs, TruthFloor* floor, Trajectory* truth_run,
                            const std::function<void()>& after_each) {
  ContactScene scene;
  scene.scenario = name;
  const Truth& truth = truths[0];
  const bool second = truths.size() > 1;
  if (second) scene.second_truth = truths[1].solver;
  // the truth's own run and the runs its window floor compares with it (the truth at h/2 and at
  // 2h, and the second truth), then both truths from each start
  const SolverConfig truth_config{truth.solver, truth.options};
  const int compared = second ? 3 : 2;
  std::vector<JudgedRun> others(compared);
  std::vector<JudgedRun> truth_starts(starts), second_starts(second ? starts : 0);
  JudgedRun own;
  const size_t total =
      1 + static_cast<size_t>(compared) + truth_starts.size() + second_starts.size();
  parallel_for(
      total, jobs,
      [&](size_t i) {
        if (i == 0) {
          own = judged_run(truth_config, model, name, options, truth.dt, seed, -1);
          return;
        }
        --i;
        if (i < static_cast<size_t>(compared)) {
          const Truth& t = i < 2 ? truth : truths[1];
          const double dt = i == 0 ? truth.dt / 2 : i == 1 ? truth.dt * 2 : t.dt;
          others[i] = judged_run({t.solver, t.options}, model, name, options, dt, seed, -1);
          return;
        }
        i -= compared;
        if (i < truth_starts.size()) {
          truth_starts[i] = judged_run(truth_config, model, name, options, kContactOutcomeDt, seed,
                                       static_cast<int64_t>(i));
          return;
        }
        i -= truth_starts.size();
        second_starts[i] = judged_run({truths[1].solver, truths[1].options}, model, name, options,
                                      kContactOutcomeDt, seed, static_cast<int64_t>(i));
      },
      after_each);
  *truth_run = own.run.trajectory;
  const Scenario scenario = make_scenario(name, model, options);
  scene.truth_violations = contact_violations(model, scenario, own.run);
  scene.first_contact_s = first_contact_time(own.run);
  const double after = std::isnan(scene.first_contact_s) ? 0.0 : scene.first_contact_s;
  scene.window_end_s = std::ceil((after + kContactWindowAfter) / kAccuracySampleInterval - 1e-9) *
                       kAccuracySampleInterval;
  floor->scenario = name;
  floor->half_difference =
      window_error(others[0].run.trajectory, own.run.trajectory, scene.window_end_s);
  floor->double_difference =
      window_error(others[1].run.trajectory, own.run.trajectory, scene.window_end_s);
  if (second) {
    floor->agreement =
        window_error(others[2].run.trajectory, own.run.trajectory, scene.window_end_s);
    scene.second_violations = contact_violations(model, scenario, others[2].run);
  }
  floor->floor = truth_floor(floor->half_difference, floor->double_difference, floor->agreement);
  for (const JudgedRun& r : truth_starts) scene.truth_outcomes.push_back(r.outcome);
  for (const JudgedRun& r : second_starts) scene.second_outcomes.push_back(r.outcome);
  if (second)
    scene.truths_statistic = outcome_statistics(scene.second_outcomes, scene.truth_outcomes);
  scene.critical =
      ks_critical(scene.truth_outcomes.size(), scene.truth_outcomes.size(), kOutcomeAlpha);
  return scene;
}

void judge_contact_candidate(const SolverConfig& config, const Model& model,
                             const Scenario& scenario, const Trajectory& truth_run,
                             const ContactScene& scene, double dt, Candidate& candidate) {
  auto simulator = make_simulator(config.solver, config.options);
  RunOptions options;
  options.dt = dt;
  options.timing = false;
  options.sample_hz = 1e-3;
  options.record_trajectory = true;
  const RunResult run = run_scenario(*simulator, model, scenario, options);
  if (run.diverged) {
    candidate.diverged = true;
    candidate.reason = "its run of the scenario diverged (" + run.diverged_reason + ")";
    return;
  }
  candidate.violations = contact_violations(model, scenario, run);
  candidate.window_error_m = window_error(run.trajectory, truth_run, scene.window_end_s);
  candidate.error_m = candidate.window_error_m;
  candidate.measure = "first impact";
  if (!(candidate.violations.worst() <= candidate.error_m)) {
    candidate.error_m = candidate.violations.worst();
    candidate.measure = candidate.violations.worst_name();
  }
}

void compare_candidate_outcomes(const ContactScene& scene,
                                const std::vector<ContactOutcome>& outcomes, Candidate& candidate) {
  const OutcomeComparison c =
      compare_outcomes(outcomes, scene.truth_outcomes, scene.truths_statistic);
  candidate.outcome_ratio = c.worst_ratio;
  candidate.outcome_worst = c.worst;
}

}  // namespace puppet::compare
