#include "puppet/compare/verdict.h"
#include "puppet/compare/engines.h"

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <tuple>

#include "puppet/compare/accuracy.h"
#include "puppet/compare/cancel.h"
#include "puppet/compare/number.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/run.h"
#include "puppet/compare/start.h"
#include "puppet/compare/summary_metrics.h"
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

VerdictResult run_verdict(const VerdictSpec& spec) {
  const Model& model = *spec.model;
  std::vector<Truth> truths = truths_for(model);
  if (truths.empty()) throw ScenarioError("no engine can build this model as a truth", "model");
  const Truth& truth = truths[0];
  VerdictResult out;
  out.truth = truth.solver;
  if (!spec.floors.empty() && spec.floors.size() != spec.scenarios.size()) {
    throw ScenarioError("a floor for each scenario, or none", "floors_from");
  }
  auto progress = [&](const char* phase) {
    return [&spec, phase](size_t done, size_t total) {
      if (spec.on_progress) spec.on_progress(phase, done, total);
    };
  };
  const size_t scenario_count = spec.scenarios.size();
  std::vector<Scenario> scenarios;
  for (const std::string& name : spec.scenarios) {
    scenarios.push_back(make_scenario(name, model, spec.scenario));
  }

  // the truth at h in every scenario, then (unless the spec has them) its floor: its runs at h/2
  // and 2h and the other truth, each re-seeded from it; a contact scene's after them
  // (contact_truths: the floor of its window, and the truths' outcomes over the starts)
  std::vector<Trajectory> truth_runs(scenario_count);
  std::vector<int> scene_of(scenario_count, -1);  // index into out.contact
  {
    const bool measure_floors = spec.floors.empty();
    size_t done = 0;
    auto tick = progress("truth");
    const size_t per_scenario = !measure_floors ? 0 : truths.size() > 1 ? 3 : 2;
    const size_t total = scenario_count * (1 + per_scenario);
    parallel_for(
        scenario_count, spec.jobs,
        [&](size_t s) {
          if (judged_by_contact(spec.scenarios[s])) return;
          auto simulator = make_simulator(truth.solver, truth.options);
          truth_runs[s] =
              record_trajectory(*simulator, model, scenarios[s], truth.dt, scenarios[s].duration);
        },
        [&] { tick(++done, total); });
    if (!measure_floors) {
      out.floors = spec.floors;
    } else {
      out.floors.resize(scenario_count);
      std::vector<double> values(scenario_count * 3, NAN);
      parallel_for(
          scenario_count * per_scenario, spec.jobs,
          [&](size_t i) {
            const size_t s = i / per_scenario, k = i % per_scenario;
            if (judged_by_contact(spec.scenarios[s])) return;
            const Truth& judged = k < 2 ? truth : truths[1];
            const double dt = k == 0 ? truth.dt / 2 : k == 1 ? truth.dt * 2 : judged.dt;
            auto simulator = make_simulator(judged.solver, judged.options);
            values[3 * s + k] =
                reseeded_error(*simulator, model, scenarios[s], truth_runs[s], dt).mean_pose_m;
          },
          [&] { tick(++done, total); });
      for (size_t s = 0; s < scenario_count; ++s) {
        TruthFloor& f = out.floors[s];
        f.scenario = spec.scenarios[s];
        f.half_difference = values[3 * s];
        f.double_difference = values[3 * s + 1];
        f.agreement = values[3 * s + 2];
        f.floor = truth_floor(f.half_difference, f.double_difference, f.agreement);
      }
    }
    const size_t contact_count = static_cast<size_t>(
        std::count_if(spec.scenarios.begin(), spec.scenarios.end(), judged_by_contact));
    const size_t contact_total = contact_count * contact_truth_runs(truths.size(), spec.starts);
    size_t contact_done = 0;
    auto contact_tick = progress("contact truths");
    for (size_t s = 0; s < scenario_count; ++s) {
      if (!judged_by_contact(spec.scenarios[s])) continue;
      scene_of[s] = static_cast<int>(out.contact.size());
      out.contact.push_back(contact_truths(
          model, truths, spec.scenarios[s], spec.scenario, spec.starts, spec.seed, spec.jobs,
          &out.floors[s], &truth_runs[s], [&] { contact_tick(++contact_done, contact_total); }));
    }
  }

  // every candidate, scenario × solver × setting × dt
  std::vector<Job> jobs;
  for (size_t s = 0; s < scenario_count; ++s) {
    for (size_t k = 0; k < spec.solvers.size(); ++k) {
      for (const Setting& setting :
           settings_searched(spec.solvers[k].solver, spec.solvers[k].options)) {
        for (double dt : spec.dts) {
          jobs.push_back({s, k, setting, dt});
          Candidate c;
          c.scenario = spec.scenarios[s];
          c.solver = spec.solvers[k].solver;
          c.rule = rule_of(spec.solvers[k]);
          c.setting = setting.flags;
          c.dt = dt;
          out.candidates.push_back(std::move(c));
        }
      }
    }
  }

  // Cost: one thread, one scenario at a time, every candidate of it alive at once and stepped
  // through the scenario in slices of kSlice simulated seconds taken in turn, so that whatever
  // slows the machine for a while slows them all alike. A candidate that meets a non-finite value
  // is not timed further (its cost is left unknown: it is not a candidate).
  {
    constexpr double kSlice = 0.25;
    auto tick = progress("cost");
    size_t done = 0;
    std::vector<Vector3d> targets;
    for (size_t s = 0; s < scenario_count; ++s) {
      const Scenario& scenario = scenarios[s];
      std::vector<size_t> mine;
      for (size_t j = 0; j < jobs.size(); ++j) {
        if (jobs[j].scenario == s) mine.push_back(j);
      }
      std::vector<std::unique_ptr<Simulator>> simulators;
      std::vector<double> seconds(mine.size(), 0.0);
      std::vector<int> steps_taken(mine.size(), 0);
      for (size_t j : mine) {
        const SolverConfig& solver = spec.solvers[jobs[j].solver];
        simulators.push_back(make_simulator(solver.solver, jobs[j].setting.options));
        simulators.back()->reset(model, scenario);
      }
      const int slices = static_cast<int>(std::ceil(scenario.duration / kSlice - 1e-9));
      for (int slice = 0; slice < slices; ++slice) {
        for (size_t m = 0; m < mine.size(); ++m) {
          Simulator& simulator = *simulators[m];
          const double dt = jobs[mine[m]].dt;
          const int total = static_cast<int>(std::lround(scenario.duration / dt));
          const int end = std::min(total, static_cast<int>(std::lround((slice + 1) * kSlice / dt)));
          if (simulator.diverged()) continue;
          const double begin = thread_seconds();
          for (int k = steps_taken[m]; k < end; ++k) {
            throw_if_cancelled();
            scenario.targets_at((k + 1) * dt, targets);
            simulator.set_pin_targets(targets);
            simulator.step(dt);
          }
          seconds[m] += thread_seconds() - begin;
          steps_taken[m] = end;
        }
      }
      for (size_t m = 0; m < mine.size(); ++m) {
        if (!simulators[m]->diverged()) {
          out.candidates[mine[m]].cost_us_per_s = 1e6 * seconds[m] / scenario.duration;
        }
      }
      done += mine.size();
      tick(done, jobs.size());
    }
  }

  // error: the re-seeded pose error against the truth, the finest dts first so that the longest
  // jobs start early; a re-seeded run that diverges puts the candidate out
  {
    std::vector<size_t> order(jobs.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return jobs[a].dt < jobs[b].dt; });
    size_t done = 0;
    auto tick = progress("error");
    parallel_for(
        order.size(), spec.jobs,
        [&](size_t i) {
          const Job& job = jobs[order[i]];
          Candidate& c = out.candidates[order[i]];
          const SolverConfig& solver = spec.solvers[job.solver];
          if (scene_of[job.scenario] >= 0) {
            judge_contact_candidate({solver.solver, job.setting.options}, model,
                                    scenarios[job.scenario], truth_runs[job.scenario],
                                    out.contact[scene_of[job.scenario]], job.dt, c);
            return;
          }
          auto simulator = make_simulator(solver.solver, job.setting.options);
          const ReseededError e = reseeded_error(*simulator, model, scenarios[job.scenario],
                                                 truth_runs[job.scenario], job.dt);
          const auto lost = std::count_if(e.pose_m.begin(), e.pose_m.end(),
                                          [](double v) { return std::isnan(v); });
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

  // the search, per scenario and solver: for each view and budget, the candidates within budget
  // in order of cost, each put through the random starts until one survives them all
  {
    const double ceiling = no_divergence_ceiling(spec.starts);
    const size_t pairs = scenario_count * spec.solvers.size();
    std::vector<std::vector<VerdictRow>> rows(pairs);
    size_t done = 0;
    auto tick = progress("starts");
    parallel_for(
        pairs, spec.jobs,
        [&](size_t p) {
          const size_t s = p / spec.solvers.size(), k = p % spec.solvers.size();
          std::vector<size_t> mine;
          for (size_t j = 0; j < jobs.size(); ++j) {
            if (jobs[j].scenario == s && jobs[j].solver == k) mine.push_back(j);
          }
          for (const char* view : {kViewSecond, kViewFrame}) {
            const bool frame = std::string_view(view) == kViewFrame;
            std::vector<size_t> in_view;
            for (size_t j : mine) {
              if (!frame || steps_per_frame(jobs[j].dt, spec.frame_hz) > 0) in_view.push_back(j);
            }
            for (double budget : spec.budgets_m) {
              VerdictRow row;
              row.scenario = spec.scenarios[s];
              row.solver = spec.solvers[k].solver;
              row.rule = rule_of(spec.solvers[k]);
              row.view = view;
              row.budget_m = budget;
              row.truth_floor_m = out.floors[s].floor;
              const std::string problem = budget_problem(budget, row.truth_floor_m);
              if (!problem.empty()) {
                row.verdict = kRefused;
                row.why = problem;
                rows[p].push_back(row);
                continue;
              }
              std::vector<size_t> within;
              for (size_t j : in_view) {
                const Candidate& c = out.candidates[j];
                if (!c.diverged && c.error_m <= budget && std::isfinite(c.cost_us_per_s)) {
                  within.push_back(j);
                }
              }
              std::stable_sort(within.begin(), within.end(), [&](size_t a, size_t b) {
                const Candidate &x = out.candidates[a], &y = out.candidates[b];
                return x.cost_us_per_s != y.cost_us_per_s ? x.cost_us_per_s < y.cost_us_per_s
                                                          : x.dt > y.dt;
              });
              for (size_t j : within) {
                Candidate& c = out.candidates[j];
                if (c.starts == 0 && !c.diverged) {
                  run_starts(model, spec, s, {spec.solvers[k].solver, jobs[j].setting.options},
                             scene_of[s] >= 0 ? &out.contact[scene_of[s]] : nullptr, c);
                }
                if (!c.diverged && c.diverged_starts == 0 && !(c.outcome_ratio > 1.0)) break;
              }
              std::vector<Candidate> all;
              for (size_t j : mine) all.push_back(out.candidates[j]);
              const Choice choice = frame ? cheapest_per_frame(all, budget, ceiling, spec.frame_hz)
                                          : cheapest(all, budget, ceiling);
              row.verdict = verdict_name(choice.verdict);
              row.best_error_m = choice.best_error_m;
              row.divergence_upper = choice.divergence_upper;
              if (choice.verdict == Verdict::kMet) {
                row.chosen = static_cast<int>(mine[choice.index]);
              } else {
                row.why = why_not(choice, all, model, spec, s, budget);
              }
              rows[p].push_back(row);
            }
          }
        },
        [&] { tick(++done, pairs); });
    for (auto& r : rows) out.rows.insert(out.rows.end(), r.begin(), r.end());
  }
  return out;
}

std::vector<TruthFloor> floors_from_summary(const std::string& text, const std::string& source,
                                            const Model& model,
                                            const std::vector<std::string>& scenarios,
                                            const std::string& git_sha) {
  const std::vector<Truth> truths = truths_for(model);
  if (truths.empty()) throw std::runtime_error(source + ": the model has no truth");
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  if (line != kSummaryHeader) throw std::runtime_error(source + ": not a summary.csv (its header)");
  // (scenario, solver, dt as written, reference) → the re-seeded mean pose error
  std::map<std::tuple<std::string, std::string, std::string, std::string>, double> errors;
  std::string truth_dt;
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    const std::vector<std::string> f = split_commas(line);
    // scenario,solver,rule,dt,substeps,metric,stat,value,unit,model,reference,...
    if (f.size() < 13) throw std::runtime_error(source + ":" + std::to_string(row) + ": too short");
    if (f[12] != git_sha) {
      throw std::runtime_error(source + ":" + std::to_string(row) + ": written at commit " + f[12] +
                               ", this is " + git_sha);
    }
    if (f[9] != model.name) {
      throw std::runtime_error(source + ":" + std::to_string(row) + ": a run of model " + f[9] +
                               ", not " + model.name);
    }
    if (f[5] == metric::kTruthDt.name && f[10] == kTruthReference) {
      if (f[1] != truths[0].solver) {
        throw std::runtime_error(source + ": judged by " + f[1] + ", not " + truths[0].solver);
      }
      truth_dt = f[7];
    }
    if (f[5] == metric::kPoseError.name && f[6] == stats::kReseededMean.name &&
        f[10] == kTruthReference) {
      double value = NAN;
      if (!parse_finite(f[7], &value)) value = NAN;
      errors[{f[0], f[1], f[3], f[10]}] = value;
    }
  }
  if (truth_dt != format_dt(truths[0].dt)) {
    throw std::runtime_error(source + ": no truth rows at h = " + format_dt(truths[0].dt) +
                             " s (a run with both truths at three dts writes them)");
  }
  std::vector<TruthFloor> out;
  for (const std::string& scenario : scenarios) {
    auto find = [&](const Truth& t, double dt) {
      const auto it = errors.find({scenario, t.solver, format_dt(dt), kTruthReference});
      if (it == errors.end()) {
        throw std::runtime_error(source + ": no re-seeded error of " + t.solver + " at " +
                                 format_dt(dt) + " s in " + scenario);
      }
      return it->second;
    };
    TruthFloor f;
    f.scenario = scenario;
    f.half_difference = find(truths[0], truths[0].dt / 2);
    f.double_difference = find(truths[0], truths[0].dt * 2);
    if (truths.size() > 1) f.agreement = find(truths[1], truths[1].dt);
    f.floor = truth_floor(f.half_difference, f.double_difference, f.agreement);
    out.push_back(f);
  }
  return out;
}

namespace {

const char* status_of(const Candidate& c) {
  if (c.diverged) return kCandidateDiverged;
  if (std::isnan(c.cost_us_per_s)) return kCandidateNotTimed;
  return kCandidateOk;
}

}  // namespace

std::string verdict_candidates_csv(const VerdictResult& result, const OutputContext& context) {
  std::ostringstream out;
  out << kCandidatesHeader << '\n';
  for (const Candidate& c : result.candidates) {
    double floor = NAN;
    for (const TruthFloor& f : result.floors) {
      if (f.scenario == c.scenario) floor = f.floor;
    }
    out << csv_field(c.scenario) << ',' << csv_field(c.solver) << ',' << csv_field(c.rule) << ','
        << csv_field(c.setting) << ',' << format_dt(c.dt) << ',' << csv_number(c.cost_us_per_s)
        << ',' << csv_number(c.error_m) << ',' << status_of(c) << ',' << csv_field(c.reason) << ','
        << c.starts << ',' << c.diverged_starts << ',' << csv_number(floor) << ','
        << csv_field(c.measure) << ',' << csv_number(c.window_error_m) << ',';
    if (c.measure.empty() || c.diverged) {
      out << ",,,,";
    } else {
      out << csv_number(c.violations.penetration_m) << ',' << csv_number(c.violations.joint_gap_m)
          << ',' << csv_number(c.violations.limit_overshoot_m) << ','
          << csv_number(c.violations.energy_gain_m) << ',';
    }
    out << csv_number(c.outcome_ratio) << ',' << csv_field(result.truth) << ','
        << csv_field(context.model) << ',' << csv_field(context.git_sha) << ','
        << csv_field(context.machine) << '\n';
  }
  return out.str();
}

std::string verdict_csv(const VerdictResult& result, const VerdictSpec& spec,
                        const OutputContext& context) {
  std::ostringstream out;
  out << kVerdictHeader << '\n';
  for (const VerdictRow& r : result.rows) {
    const Candidate* c = r.chosen >= 0 ? &result.candidates[r.chosen] : nullptr;
    const bool frame = r.view == kViewFrame;
    FrameCost cost;
    if (c) cost = at_frame_rate(c->cost_us_per_s, spec.frame_hz);
    out << csv_field(r.scenario) << ',' << csv_field(r.solver) << ',' << csv_field(r.rule) << ','
        << r.view << ',' << csv_number(spec.frame_hz) << ',' << csv_number(r.budget_m) << ','
        << r.verdict << ',' << (c ? csv_field(c->setting) : "") << ','
        << (c ? format_dt(c->dt) : "") << ','
        << (c && frame ? std::to_string(steps_per_frame(c->dt, spec.frame_hz)) : "") << ','
        << csv_number(c ? c->cost_us_per_s : NAN) << ','
        << csv_number(c && frame ? cost.us_per_frame : NAN) << ','
        << csv_number(c ? cost.puppets_per_core : NAN) << ',' << csv_number(c ? c->error_m : NAN)
        << ',' << (c ? std::to_string(c->starts) : "") << ',' << csv_number(r.divergence_upper)
        << ',' << csv_number(r.best_error_m) << ',' << csv_number(r.truth_floor_m) << ','
        << csv_field(r.why) << ',' << csv_field(result.truth) << ',' << csv_field(context.model)
        << ',' << csv_field(context.git_sha) << ',' << csv_field(context.machine) << '\n';
  }
  return out.str();
}

std::string verdict_contact_csv(const VerdictResult& result, const OutputContext& context) {
  std::ostringstream out;
  out << kContactHeader << '\n';
  const std::string tail = ',' + csv_field(result.truth) + ',' + csv_field(context.model) + ',' +
                           csv_field(context.git_sha) + ',' + csv_field(context.machine) + '\n';
  auto row = [&](const std::string& scenario, const char* role, const std::string& solver,
                 const std::string& measure, const char* stat, double value, const char* unit) {
    out << csv_field(scenario) << ',' << role << ',' << csv_field(solver) << ','
        << csv_field(measure) << ',' << stat << ',' << csv_number(value) << ',' << unit << tail;
  };
  for (const ContactScene& scene : result.contact) {
    const std::string& name = scene.scenario;
    const TruthFloor* floor = nullptr;
    for (const TruthFloor& f : result.floors) {
      if (f.scenario == name) floor = &f;
    }
    row(name, "truth", result.truth, "first_contact", "value", scene.first_contact_s, "s");
    row(name, "truth", result.truth, "window_end", "value", scene.window_end_s, "s");
    if (floor) {
      row(name, "truth", result.truth, "window_error", "half_difference", floor->half_difference,
          "m");
      row(name, "truth", result.truth, "window_error", "double_difference",
          floor->double_difference, "m");
      row(name, "second", scene.second_truth, "window_error", "agreement", floor->agreement, "m");
      row(name, "truth", result.truth, "window_error", "floor", floor->floor, "m");
    }
    auto solver_of = [&](const char* role) {
      return std::string(role) == "truth" ? result.truth : scene.second_truth;
    };
    auto violations = [&](const char* role, const ContactViolations& v) {
      row(name, role, solver_of(role), "penetration", "max", v.penetration_m, "m");
      row(name, role, solver_of(role), "joint_gap", "max", v.joint_gap_m, "m");
      row(name, role, solver_of(role), "limit_overshoot", "max", v.limit_overshoot_m, "m");
      row(name, role, solver_of(role), "energy_gain", "max", v.energy_gain_m, "m");
    };
    violations("truth", scene.truth_violations);
    if (!scene.second_truth.empty()) violations("second", scene.second_violations);
    for (int k = 0; k < kOutcomeCount; ++k) {
      auto column = [&](const std::vector<ContactOutcome>& outcomes, const char* role) {
        if (outcomes.empty()) return;
        std::vector<double> v;
        for (const ContactOutcome& o : outcomes) v.push_back(outcome_value(o, k));
        std::sort(v.begin(), v.end());
        const double mean =
            std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
        const char* unit = k == 2 ? "s" : "m";
        row(name, role, solver_of(role), kOutcomeNames[k], "mean", mean, unit);
        row(name, role, solver_of(role), kOutcomeNames[k], "min", v.front(), unit);
        row(name, role, solver_of(role), kOutcomeNames[k], "median", v[v.size() / 2], unit);
        row(name, role, solver_of(role), kOutcomeNames[k], "max", v.back(), unit);
      };
      column(scene.truth_outcomes, "truth");
      column(scene.second_outcomes, "second");
      row(name, "second", scene.second_truth, kOutcomeNames[k], "ks_statistic",
          scene.truths_statistic[k], "1");
      row(name, "truth", result.truth, kOutcomeNames[k], "ks_critical", scene.critical, "1");
    }
  }
  return out.str();
}

}  // namespace puppet::compare
