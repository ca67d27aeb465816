// The verdict's files: verdict.csv, candidates.csv and contact.csv as it writes them, and the
// truths' floors read back from a summary.csv (--floors-from)
#include <algorithm>
#include <map>
#include <numeric>
#include <sstream>
#include <tuple>

#include "puppet/compare/number.h"
#include "puppet/compare/summary_metrics.h"
#include "puppet/compare/verdict.h"

namespace puppet::compare {

std::vector<TruthFloor> floors_from_summary(const std::string& text, const std::string& source,
                                            const Model& model,
                                            const std::vector<std::string>& scenarios,
                                            const std::string& git_sha, double budget) {
  const std::vector<Truth> truths = truths_for(model, budget);
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
