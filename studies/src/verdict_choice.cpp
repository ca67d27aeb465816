#include "puppet/compare/verdict_choice.h"

#include <algorithm>
#include <cstdio>

#include "puppet/compare/engines.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/sweep.h"

namespace puppet::compare {

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::kMet:
      return "met";
    case Verdict::kDiverges:
      return "diverges";
    case Verdict::kErrorFloor:
      return "error-floor";
    case Verdict::kNotRobust:
      return "not-robust";
    case Verdict::kUnlikeTruth:
      return "unlike-truth";
    case Verdict::kNotMeasured:
      return "not-measured";
  }
  return "not-measured";
}

Choice cheapest(std::span<const Candidate> candidates, double budget_m, double robustness_ceiling) {
  Choice out;
  bool measured = false, held = false, within = false, robust = false;
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    const Candidate& c = candidates[i];
    if (std::isnan(c.cost_us_per_s)) continue;
    if (c.diverged) {
      measured = true;
      continue;
    }
    if (std::isnan(c.error_m)) continue;
    measured = held = true;
    if (std::isnan(out.best_error_m) || c.error_m < out.best_error_m) out.best_error_m = c.error_m;
    if (c.error_m > budget_m) continue;
    within = true;
    const double upper = c.starts > 0 ? wilson_interval(c.diverged_starts, c.starts).high : 1.0;
    if (upper > robustness_ceiling) continue;
    robust = true;
    if (c.outcome_ratio > 1.0) continue;
    const Candidate* best = out.index >= 0 ? &candidates[out.index] : nullptr;
    if (best == nullptr || c.cost_us_per_s < best->cost_us_per_s ||
        (c.cost_us_per_s == best->cost_us_per_s && c.dt > best->dt)) {
      out.index = i;
      out.divergence_upper = upper;
    }
  }
  if (out.index >= 0) {
    out.verdict = Verdict::kMet;
  } else if (!measured) {
    out.verdict = Verdict::kNotMeasured;
  } else if (!held) {
    out.verdict = Verdict::kDiverges;
  } else if (!within) {
    out.verdict = Verdict::kErrorFloor;
  } else if (!robust) {
    out.verdict = Verdict::kNotRobust;
  } else {
    out.verdict = Verdict::kUnlikeTruth;
  }
  return out;
}

Choice cheapest_per_frame(std::span<const Candidate> candidates, double budget_m,
                          double robustness_ceiling, double hz) {
  std::vector<Candidate> in_frames;
  std::vector<int> index;
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    if (steps_per_frame(candidates[i].dt, hz) > 0) {
      in_frames.push_back(candidates[i]);
      index.push_back(i);
    }
  }
  Choice choice = cheapest(in_frames, budget_m, robustness_ceiling);
  if (choice.index >= 0) choice.index = index[choice.index];
  return choice;
}

double no_divergence_ceiling(int64_t starts) {
  // halfway between the bounds of 0 and of 1 divergence in `starts`: exact comparisons are safe
  const double none = wilson_interval(0, starts).high, one = wilson_interval(1, starts).high;
  return 0.5 * (none + one);
}

double truth_floor(double half_difference, double double_difference, double agreement) {
  double p = kMinOrder;
  if (half_difference > 0.0 && double_difference > 0.0) {
    p = std::max(kMinOrder, std::log2(double_difference / half_difference));
  }
  const double bar = kBarMargin * std::exp2(p) / (std::exp2(p) - 1.0) * half_difference;
  return std::isnan(agreement) ? bar : std::max(bar, agreement);
}

std::string budget_problem(double budget_m, double truth_floor_m) {
  if (!(budget_m > 0.0) || !std::isfinite(budget_m)) return "a budget must be a positive length";
  if (!(budget_m >= truth_floor_m)) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "a budget of %.3g m is below the truth's floor of %.3g m: finer than the truth "
                  "can tell",
                  budget_m, truth_floor_m);
    return text;
  }
  return {};
}

FrameCost at_frame_rate(double cost_us_per_s, double hz) {
  FrameCost out;
  out.us_per_frame = cost_us_per_s / hz;
  // a frame lasts 1e6/hz µs of the core's time; each puppet takes us_per_frame of it
  out.puppets_per_core = (1e6 / hz) / out.us_per_frame;
  return out;
}

int steps_per_frame(double dt, double hz) {
  const double n = std::round(1.0 / (hz * dt));
  return n >= 1.0 && std::abs(n * dt * hz - 1.0) < 1e-9 ? static_cast<int>(n) : 0;
}

SolverOptions candidate_options(const std::string& solver, const std::string& rule,
                                const std::string& setting) {
  SolverConfig base{solver, {}};
  if (has_rules(solver)) {
    const auto parsed = procedural::parse_rule(rule);
    if (!parsed) throw ScenarioError("unknown rule " + rule, "rule");
    base.options.procedural.rule = *parsed;
  }
  for (const Setting& s : settings_searched(base.solver, base.options)) {
    if (s.flags == setting) return s.options;
  }
  throw ScenarioError("no setting \"" + setting + "\" is searched for " + solver, "setting");
}

std::string budget_text(double budget_m) {
  char text[32];
  if (budget_m >= 0.01 - 1e-12) {
    std::snprintf(text, sizeof text, "%gcm", budget_m * 100);
  } else if (budget_m >= 0.001 - 1e-12) {
    std::snprintf(text, sizeof text, "%gmm", budget_m * 1000);
  } else {
    std::snprintf(text, sizeof text, "%gum", budget_m * 1e6);
  }
  return text;
}

}  // namespace puppet::compare
