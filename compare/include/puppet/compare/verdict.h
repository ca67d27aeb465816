// The verdict: per solver and scenario, the cheapest measured configuration that meets an
// error budget against the truth and a robustness bar, and why none does when none does.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>

namespace puppet::compare {

/// one configuration of one solver in one scenario, as measured
struct Candidate {
  std::string solver, rule;
  double dt = 0.0;
  int substeps = 1;             ///< the rule's substeps or iterations; 1 where it has none
  double cost_us_per_s = NAN;   ///< CPU time per simulated second (µs); NaN: not timed
  double error_m = NAN;         ///< re-seeded pose error against the truth; NaN: not judged
  bool diverged = false;        ///< the scenario's own run diverged
  int64_t starts = 0;           ///< random starts run (robustness)
  int64_t diverged_starts = 0;  ///< of them, diverged
};

/// what a search found
enum class Verdict {
  kMet,          ///< a configuration meets the budget and the bar
  kDiverges,     ///< every measured configuration diverges
  kErrorFloor,   ///< none that holds together comes within the budget
  kNotRobust,    ///< some come within the budget, none with the robustness bar
  kNotMeasured,  ///< no configuration was both timed and judged
};

struct Choice {
  Verdict verdict = Verdict::kNotMeasured;
  int index = -1;                 ///< the chosen candidate (kMet), else −1
  double best_error_m = NAN;      ///< the smallest error of a configuration that did not diverge
  double divergence_upper = NAN;  ///< the chosen candidate's 95 % Wilson upper bound
};

/// The cheapest candidate whose error is within `budget_m` and whose divergence rate over its
/// random starts has a 95 % Wilson upper bound within `robustness_ceiling` (a candidate without
/// starts never meets a bar below 1). Ties in cost go to the larger dt.
Choice cheapest(std::span<const Candidate> candidates, double budget_m, double robustness_ceiling);

/// empty when a budget can be judged; else why not: a budget below the truth's floor (its
/// error bar, or the two truths' disagreement) is finer than the truth can tell
std::string budget_problem(double budget_m, double truth_floor_m);

/// a cost per simulated second seen at a frame rate: µs per frame, and puppets one core keeps
/// at that rate
struct FrameCost {
  double us_per_frame = NAN;
  double puppets_per_core = NAN;
};
FrameCost at_frame_rate(double cost_us_per_s, double hz = 60.0);

}  // namespace puppet::compare
