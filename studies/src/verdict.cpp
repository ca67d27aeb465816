#include "puppet/compare/verdict.h"
#include "puppet/compare/engines.h"

#include <time.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <sstream>

#include "puppet/compare/accuracy.h"
#include "puppet/compare/cancel.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/run.h"
#include "puppet/compare/start.h"
#include "verdict_contact.h"

namespace puppet::compare {

namespace {

// this thread's CPU time (s): the timing runs alone, and time another process takes from the
// core is not the solver's
double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Job {
  size_t scenario, solver;
  Setting setting;
  double dt;
};

// Of the random starts a scenario's candidates within the budget diverged from, those that led a
// hard pin further than the figure reaches (reach_shortfall): "; 3 of the 4 starts it diverged
// from asked for more than the figure's reach between its pins", empty when none did.
std::string out_of_reach_note(const Model& model, const VerdictSpec& spec, size_t s,
                              const std::vector<Candidate>& candidates, double budget) {
  std::vector<int64_t> starts;
  for (const Candidate& c : candidates) {
    if (c.diverged || c.diverged_starts == 0 || !(c.error_m <= budget)) continue;
    starts.push_back(c.starts - 1);  // the start it diverged from
  }
  std::sort(starts.begin(), starts.end());
  starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
  int out_of_reach = 0;
  for (const int64_t index : starts) {
    ScenarioOptions options = spec.scenario;
    options.start = random_start(model, spec.seed, index);
    if (reach_shortfall(model, make_scenario(spec.scenarios[s], model, options)) > 0.0) {
      ++out_of_reach;
    }
  }
  if (out_of_reach == 0) return {};
  return "; " + std::to_string(out_of_reach) + " of the " + std::to_string(starts.size()) +
         " starts it diverged from asked for more than the figure's reach between its pins";
}

// Puts a candidate within the budget through the scenario's own start and the random ones, until
// one diverges; in a contact scene, then compares its outcomes over them with the truth's
void run_starts(const Model& model, const VerdictSpec& spec, size_t s, const SolverConfig& config,
                const ContactScene* scene, Candidate& c) {
  const std::string& name = spec.scenarios[s];
  if (judged_run(config, model, name, spec.scenario, c.dt, spec.seed, -1).run.diverged) {
    c.diverged = true;
    c.reason = "its run of the scenario diverged";
    return;
  }
  std::vector<ContactOutcome> outcomes;
  for (int64_t i = 0; i < spec.starts; ++i) {
    c.starts = i + 1;
    const JudgedRun r = judged_run(config, model, name, spec.scenario, c.dt, spec.seed, i);
    if (r.run.diverged) {
      c.diverged_starts = 1;
      return;
    }
    outcomes.push_back(r.outcome);
  }
  if (scene != nullptr) compare_candidate_outcomes(*scene, outcomes, c);
}

// the why of a row that is not met
std::string why_not(const Choice& choice, const std::vector<Candidate>& all, const Model& model,
                    const VerdictSpec& spec, size_t s, double budget) {
  std::ostringstream why;
  why.precision(3);
  switch (choice.verdict) {
    case Verdict::kDiverges:
      why << "every configuration diverges";
      break;
    case Verdict::kErrorFloor: {
      why << "its least error is " << choice.best_error_m << " m";
      for (const Candidate& c : all) {
        if (c.error_m == choice.best_error_m && !c.diverged && !c.measure.empty()) {
          why << " (" << c.measure << ")";
          break;
        }
      }
      break;
    }
    case Verdict::kNotRobust:
      why << "every configuration within the budget diverged from a random start";
      why << out_of_reach_note(model, spec, s, all, budget);
      break;
    case Verdict::kUnlikeTruth: {
      // the one whose outcomes came nearest
      const Candidate* nearest = nullptr;
      for (const Candidate& c : all) {
        if (c.outcome_ratio > 1.0 && (!nearest || c.outcome_ratio < nearest->outcome_ratio)) {
          nearest = &c;
        }
      }
      why << "every configuration within the budget that survived the starts ended unlike the "
             "truth";
      if (nearest) {
        why << ": at best its " << kOutcomeNames[nearest->outcome_worst] << "'s KS statistic is "
            << nearest->outcome_ratio << " × its bar";
      }
      break;
    }
    default:
      why << "nothing was both timed and judged";
  }
  return why.str();
}

}  // namespace

namespace {

// What the verdict's phases share: the spec, the truths and their runs, the scenarios, every
// candidate's job, and the result as it fills in.
struct Search {
  Search(const VerdictSpec& spec_in, std::vector<Truth> truths_in)
      : spec(spec_in), model(*spec_in.model), truths(std::move(truths_in)) {}
  const VerdictSpec& spec;
  const Model& model;
  std::vector<Truth> truths;
  std::vector<Scenario> scenarios;
  std::vector<Trajectory> truth_runs;  // the first truth at its h, by scenario
  std::vector<int> scene_of;           // by scenario: its index into out.contact, −1 when none
  std::vector<Job> jobs;               // by candidate
  VerdictResult out;

  size_t scenario_count() const { return spec.scenarios.size(); }
  const Truth& truth() const { return truths[0]; }
  // the progress callback of a phase
  std::function<void(size_t, size_t)> progress(const char* phase) const {
    return [this, phase](size_t done, size_t total) {
      if (spec.on_progress) spec.on_progress(phase, done, total);
    };
  }
};

// The truth at h in every scenario but the contact scenes, then (unless the spec has them) its
// floor: its runs at h/2 and 2h and the other truth, each re-seeded from it. One progress line.
void run_truths_and_floors(Search& search) {
  const VerdictSpec& spec = search.spec;
  const Truth& truth = search.truth();
  const size_t count = search.scenario_count();
  const bool measure_floors = spec.floors.empty();
  size_t done = 0;
  auto tick = search.progress("truth");
  const size_t per_scenario = !measure_floors ? 0 : search.truths.size() > 1 ? 3 : 2;
  const size_t total = count * (1 + per_scenario);
  search.truth_runs.assign(count, Trajectory{});
  parallel_for(
      count, spec.jobs,
      [&](size_t s) {
        if (judged_by_contact(spec.scenarios[s])) return;
        auto simulator = make_simulator(truth.solver, truth.options);
        const Scenario& scenario = search.scenarios[s];
        search.truth_runs[s] =
            record_trajectory(*simulator, search.model, scenario, truth.dt, scenario.duration);
      },
      [&] { tick(++done, total); });
  if (!measure_floors) {
    search.out.floors = spec.floors;
    return;
  }
  search.out.floors.resize(count);
  std::vector<double> values(count * 3, NAN);
  parallel_for(
      count * per_scenario, spec.jobs,
      [&](size_t i) {
        const size_t s = i / per_scenario, k = i % per_scenario;
        if (judged_by_contact(spec.scenarios[s])) return;
        const Truth& judged = k < 2 ? truth : search.truths[1];
        const double dt = k == 0 ? truth.dt / 2 : k == 1 ? truth.dt * 2 : judged.dt;
        auto simulator = make_simulator(judged.solver, judged.options);
        values[3 * s + k] =
            reseeded_error(*simulator, search.model, search.scenarios[s], search.truth_runs[s], dt)
                .mean_pose_m;
      },
      [&] { tick(++done, total); });
  for (size_t s = 0; s < count; ++s) {
    TruthFloor& f = search.out.floors[s];
    f.scenario = spec.scenarios[s];
    f.half_difference = values[3 * s];
    f.double_difference = values[3 * s + 1];
    f.agreement = values[3 * s + 2];
    f.floor = truth_floor(f.half_difference, f.double_difference, f.agreement);
  }
}

// A contact scene's truths (contact_truths): its first truth's run, the floor of its window and
// the truths' outcomes over the starts
void run_contact_truths(Search& search) {
  const VerdictSpec& spec = search.spec;
  search.scene_of.assign(search.scenario_count(), -1);
  const size_t contact_count = static_cast<size_t>(
      std::count_if(spec.scenarios.begin(), spec.scenarios.end(), judged_by_contact));
  const size_t total = contact_count * contact_truth_runs(search.truths.size(), spec.starts);
  size_t done = 0;
  auto tick = search.progress("contact truths");
  for (size_t s = 0; s < search.scenario_count(); ++s) {
    if (!judged_by_contact(spec.scenarios[s])) continue;
    search.scene_of[s] = static_cast<int>(search.out.contact.size());
    search.out.contact.push_back(contact_truths(
        search.model, search.truths, spec.scenarios[s], spec.scenario, spec.starts, spec.seed,
        spec.jobs, &search.out.floors[s], &search.truth_runs[s], [&] { tick(++done, total); }));
  }
}

// every candidate, scenario × solver × setting × dt
void list_candidates(Search& search) {
  const VerdictSpec& spec = search.spec;
  for (size_t s = 0; s < search.scenario_count(); ++s) {
    for (size_t k = 0; k < spec.solvers.size(); ++k) {
      for (const Setting& setting :
           settings_searched(spec.solvers[k].solver, spec.solvers[k].options)) {
        for (double dt : spec.dts) {
          search.jobs.push_back({s, k, setting, dt});
          Candidate c;
          c.scenario = spec.scenarios[s];
          c.solver = spec.solvers[k].solver;
          c.rule = rule_of(spec.solvers[k]);
          c.setting = setting.flags;
          c.dt = dt;
          search.out.candidates.push_back(std::move(c));
        }
      }
    }
  }
}

// the jobs of scenario s (and of solver k, when given)
std::vector<size_t> jobs_of(const Search& search, size_t s, size_t k = SIZE_MAX) {
  std::vector<size_t> mine;
  for (size_t j = 0; j < search.jobs.size(); ++j) {
    const Job& job = search.jobs[j];
    if (job.scenario == s && (k == SIZE_MAX || job.solver == k)) mine.push_back(j);
  }
  return mine;
}

// Cost: one thread, one scenario at a time, every candidate of it alive at once and stepped
// through the scenario in slices of kSlice simulated seconds taken in turn, so that whatever
// slows the machine for a while slows them all alike. A candidate that meets a non-finite value
// is not timed further (its cost is left unknown: it is not a candidate). Returns its job count.
size_t time_scenario_candidates(Search& search, size_t s) {
  constexpr double kSlice = 0.25;
  const Scenario& scenario = search.scenarios[s];
  const std::vector<size_t> mine = jobs_of(search, s);
  std::vector<std::unique_ptr<Simulator>> simulators;
  std::vector<double> seconds(mine.size(), 0.0);
  std::vector<int> steps_taken(mine.size(), 0);
  for (size_t j : mine) {
    const SolverConfig& solver = search.spec.solvers[search.jobs[j].solver];
    simulators.push_back(make_simulator(solver.solver, search.jobs[j].setting.options));
    simulators.back()->reset(search.model, scenario);
  }
  std::vector<Vector3d> targets;
  const int slices = static_cast<int>(std::ceil(scenario.duration / kSlice - 1e-9));
  for (int slice = 0; slice < slices; ++slice) {
    for (size_t m = 0; m < mine.size(); ++m) {
      Simulator& simulator = *simulators[m];
      const double dt = search.jobs[mine[m]].dt;
      const int total = static_cast<int>(std::lround(scenario.duration / dt));
      const int end = std::min(total, static_cast<int>(std::lround((slice + 1) * kSlice / dt)));
      if (simulator.diverged()) continue;
      const double begin = thread_seconds();
      // an engine that runs out of this process (jolt) times its own steps: this thread's clock
      // would see only the requests
      double own = 0.0;
      bool timed_by_itself = false;
      for (int k = steps_taken[m]; k < end; ++k) {
        throw_if_cancelled();
        scenario.targets_at((k + 1) * dt, targets);
        simulator.set_pin_targets(targets);
        simulator.step(dt);
        const double step_seconds = simulator.own_step_seconds();
        if (step_seconds >= 0.0) {
          own += step_seconds;
          timed_by_itself = true;
        }
      }
      seconds[m] += timed_by_itself ? own : thread_seconds() - begin;
      steps_taken[m] = end;
    }
  }
  for (size_t m = 0; m < mine.size(); ++m) {
    if (!simulators[m]->diverged()) {
      search.out.candidates[mine[m]].cost_us_per_s = 1e6 * seconds[m] / scenario.duration;
    }
  }
  return mine.size();
}

void time_candidates(Search& search) {
  auto tick = search.progress("cost");
  size_t done = 0;
  for (size_t s = 0; s < search.scenario_count(); ++s) {
    done += time_scenario_candidates(search, s);
    tick(done, search.jobs.size());
  }
}

// Error: the re-seeded pose error against the truth (a contact scene's: its judge's), the finest
// dts first so that the longest jobs start early; a re-seeded run that diverges puts the
// candidate out
void judge_candidates(Search& search) {
  const std::vector<Job>& jobs = search.jobs;
  std::vector<size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return jobs[a].dt < jobs[b].dt; });
  size_t done = 0;
  auto tick = search.progress("error");
  parallel_for(
      order.size(), search.spec.jobs,
      [&](size_t i) {
        const Job& job = jobs[order[i]];
        Candidate& c = search.out.candidates[order[i]];
        const SolverConfig& solver = search.spec.solvers[job.solver];
        const Scenario& scenario = search.scenarios[job.scenario];
        const Trajectory& truth_run = search.truth_runs[job.scenario];
        if (search.scene_of[job.scenario] >= 0) {
          judge_contact_candidate({solver.solver, job.setting.options}, search.model, scenario,
                                  truth_run, search.out.contact[search.scene_of[job.scenario]],
                                  job.dt, c);
          return;
        }
        auto simulator = make_simulator(solver.solver, job.setting.options);
        const ReseededError e =
            reseeded_error(*simulator, search.model, scenario, truth_run, job.dt);
        const auto lost =
            std::count_if(e.pose_m.begin(), e.pose_m.end(), [](double v) { return std::isnan(v); });
        if (lost > 0 || e.pose_m.empty()) {
          c.diverged = true;
          c.reason = std::to_string(lost) + " of " + std::to_string(e.pose_m.size()) +
                     " re-seeded runs diverged";
          return;
        }
        c.error_m = e.mean_pose_m;
      },
      [&] { tick(++done, order.size()); });
}

// One row: scenario s, solver k, a view and a budget. The candidates within the budget in order of
// cost, each put through the random starts until one survives them all, then the choice among
// all of the pair's (`mine`) or why there is none.
VerdictRow choose_row(Search& search, size_t s, size_t k, const std::vector<size_t>& mine,
                      const char* view, double budget) {
  const VerdictSpec& spec = search.spec;
  std::vector<Candidate>& candidates = search.out.candidates;
  const bool frame = std::string_view(view) == kViewFrame;
  VerdictRow row;
  row.scenario = spec.scenarios[s];
  row.solver = spec.solvers[k].solver;
  row.rule = rule_of(spec.solvers[k]);
  row.view = view;
  row.budget_m = budget;
  row.truth_floor_m = search.out.floors[s].floor;
  const std::string problem = budget_problem(budget, row.truth_floor_m);
  if (!problem.empty()) {
    row.verdict = kRefused;
    row.why = problem;
    return row;
  }
  std::vector<size_t> within;
  for (size_t j : mine) {
    const Candidate& c = candidates[j];
    const bool in_view = !frame || steps_per_frame(search.jobs[j].dt, spec.frame_hz) > 0;
    if (in_view && !c.diverged && c.error_m <= budget && std::isfinite(c.cost_us_per_s)) {
      within.push_back(j);
    }
  }
  std::stable_sort(within.begin(), within.end(), [&](size_t a, size_t b) {
    const Candidate &x = candidates[a], &y = candidates[b];
    return x.cost_us_per_s != y.cost_us_per_s ? x.cost_us_per_s < y.cost_us_per_s : x.dt > y.dt;
  });
  const ContactScene* scene =
      search.scene_of[s] >= 0 ? &search.out.contact[search.scene_of[s]] : nullptr;
  for (size_t j : within) {
    Candidate& c = candidates[j];
    if (c.starts == 0 && !c.diverged) {
      run_starts(search.model, spec, s, {spec.solvers[k].solver, search.jobs[j].setting.options},
                 scene, c);
    }
    if (!c.diverged && c.diverged_starts == 0 && !(c.outcome_ratio > 1.0)) break;
  }
  std::vector<Candidate> all;
  for (size_t j : mine) all.push_back(candidates[j]);
  const double ceiling = no_divergence_ceiling(spec.starts);
  const Choice choice = frame ? cheapest_per_frame(all, budget, ceiling, spec.frame_hz)
                              : cheapest(all, budget, ceiling);
  row.verdict = verdict_name(choice.verdict);
  row.best_error_m = choice.best_error_m;
  row.divergence_upper = choice.divergence_upper;
  if (choice.verdict == Verdict::kMet) {
    row.chosen = static_cast<int>(mine[choice.index]);
  } else {
    row.why = why_not(choice, all, search.model, spec, s, budget);
  }
  return row;
}

// The search, per scenario and solver (in parallel): a row for each view and budget
void choose_configurations(Search& search) {
  const VerdictSpec& spec = search.spec;
  const size_t pairs = search.scenario_count() * spec.solvers.size();
  std::vector<std::vector<VerdictRow>> rows(pairs);
  size_t done = 0;
  auto tick = search.progress("starts");
  parallel_for(
      pairs, spec.jobs,
      [&](size_t p) {
        const size_t s = p / spec.solvers.size(), k = p % spec.solvers.size();
        const std::vector<size_t> mine = jobs_of(search, s, k);
        for (const char* view : {kViewSecond, kViewFrame}) {
          for (double budget : spec.budgets_m) {
            rows[p].push_back(choose_row(search, s, k, mine, view, budget));
          }
        }
      },
      [&] { tick(++done, pairs); });
  for (auto& r : rows) search.out.rows.insert(search.out.rows.end(), r.begin(), r.end());
}

}  // namespace

VerdictResult run_verdict(const VerdictSpec& spec) {
  std::vector<Truth> truths = truths_for(*spec.model, spec.engine_budget);
  if (truths.empty()) throw ScenarioError("no engine can build this model as a truth", "model");
  if (!spec.floors.empty() && spec.floors.size() != spec.scenarios.size()) {
    throw ScenarioError("a floor for each scenario, or none", "floors_from");
  }
  Search search(spec, std::move(truths));
  search.out.truth = search.truth().solver;
  for (const std::string& name : spec.scenarios) {
    search.scenarios.push_back(make_scenario(name, search.model, spec.scenario));
  }
  run_truths_and_floors(search);  // the truth's runs and, unless given, their floors
  run_contact_truths(search);     // a contact scene's truths, floor and outcomes
  list_candidates(search);        // scenario × solver × setting × dt
  time_candidates(search);        // CPU µs per simulated second, one thread
  judge_candidates(search);       // the re-seeded error against the truth
  choose_configurations(search);  // the cheapest within each budget that survives the starts
  return std::move(search.out);
}

}  // namespace puppet::compare
