#include "puppet/compare/verdict.h"

#include <cstdio>

#include "puppet/compare/robustness.h"

namespace puppet::compare {

Choice cheapest(std::span<const Candidate> candidates, double budget_m, double robustness_ceiling) {
  Choice out;
  bool measured = false, held = false, within = false;
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
  } else {
    out.verdict = Verdict::kNotRobust;
  }
  return out;
}

std::string budget_problem(double budget_m, double truth_floor_m) {
  if (!(budget_m > 0.0) || !std::isfinite(budget_m)) return "a budget must be a positive length";
  if (budget_m < truth_floor_m) {
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

}  // namespace puppet::compare
