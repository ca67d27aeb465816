// How a contact scene is judged (docs/verdict.md, "Contact scenes"). After an impact the motion is
// chaotic and the engines' contact models differ, so a trajectory error measures which contact
// model an engine has, not how well it steps (Chung & Pollard 2016; Acosta, Yang & Posa 2022).
// The verdict holds a scene on the ground (drop, collapse) to three things instead:
//   (a) the physical violations every engine can be held to, each as a length (ContactViolations);
//   (b) the motion up to and just after the first contact, while the truths still agree
//       (up to kContactWindowAfter past the truth's first contact): the mean pose error there;
//   (c) the outcome over random starts (ContactOutcome) against the truth's own over the same
//       starts, by the two-sample Kolmogorov–Smirnov statistic of each outcome.
#pragma once

#include <array>
#include <span>
#include <string>

#include "puppet/compare/accuracy.h"
#include "puppet/compare/run.h"
#include "puppet/compare/scenario.h"

namespace puppet::compare {

// (a) a run's largest violations, each a length (m) so that one budget holds them all
struct ContactViolations {
  double penetration_m = 0.0;      ///< the deepest point below the ground
  double joint_gap_m = 0.0;        ///< the widest joint gap
  double limit_overshoot_m = 0.0;  ///< the largest limit overshoot (rad) × contact_lever()
  double energy_gain_m = 0.0;      ///< the largest rise of E over its running minimum, / (M g₀)
  double worst() const;
  const char* worst_name() const;  ///< "penetration", "joint gap", ...
};
// the longest distance from a joint to its child segment's centre of mass (m): an overshoot of θ
// puts that centre out of place by at most θ times it
double contact_lever(const Model& model);
// from a run with its per-step trace (run_scenario); E's rises read from the trace's energy drift
ContactViolations contact_violations(const Model& model, const Scenario& scenario,
                                     const RunResult& run);

// (b) the window: the truth's first contact (the first step with a point below the ground) plus
// this much, ended at a sample of the trajectory. The truths part ways at the impact (MuJoCo's soft
// contact against Bullet's impulses): in drop their mean pose error over the window is 0.5 mm
// ending at the first sample after the contact, 6 mm at 1/30 s after it and 2.7 cm at 0.1 s
// (docs/tried.md, "The fall judged by contact"), so the window holds the impact's first 1/30 s.
inline constexpr double kContactWindowAfter = 1.0 / 30.0;  // s
// the first time the run's trace has a point below the ground (NaN: never)
double first_contact_time(const RunResult& run);
// the mean pose error over the samples t in (0, t_end] both trajectories have (NaN: none)
double window_error(const Trajectory& run, const Trajectory& truth, double t_end);

// (c) a run's outcome
struct ContactOutcome {
  double com_height_m = 0.0;  ///< the centre of mass's height at the end
  double com_travel_m = 0.0;  ///< how far it moved over the ground from where it started
  double rest_time_s = 0.0;   ///< the last time a segment moved faster than kRestSpeed
};
inline constexpr double kRestSpeed = 0.1;  // m/s
// the truths' step for their outcomes over the starts: four times MuJoCo's h (RK4) and twice
// bullet-multibody's, since 32 starts at h would take minutes; what that costs in the outcomes is
// measured in docs/tried.md ("The fall judged by its outcomes")
inline constexpr double kContactOutcomeDt = 1.0 / 1920.0;
inline constexpr int kOutcomeCount = 3;
inline constexpr std::array<const char*, kOutcomeCount> kOutcomeNames = {
    "centre of mass height", "centre of mass travel", "time to rest"};
ContactOutcome contact_outcome(const Model& model, const Scenario& scenario, const RunResult& run);
double outcome_value(const ContactOutcome& outcome, int which);

// the two-sample Kolmogorov–Smirnov statistic: the largest gap between the samples' empirical
// distribution functions
double ks_statistic(std::span<const double> a, std::span<const double> b);
// the statistic two samples of n and m from one distribution exceed with probability alpha
// (asymptotic: √(−ln(α/2)/2) · √((n+m)/(n m)))
double ks_critical(size_t n, size_t m, double alpha);
// the test's level: 5 % over the three outcomes together (Bonferroni)
inline constexpr double kOutcomeAlpha = 0.05 / kOutcomeCount;

// a sample of outcomes against the truth's: each statistic against its bar, the larger of the
// test's critical value and the truths' own statistic (they are never told apart more finely
// than the two truths tell each other apart)
struct OutcomeComparison {
  std::array<double, kOutcomeCount> statistic{}, bar{};
  double worst_ratio = 0.0;  ///< the largest statistic / bar: at most 1 when alike
  int worst = 0;             ///< which outcome
  bool alike() const { return worst_ratio <= 1.0; }
};
OutcomeComparison compare_outcomes(std::span<const ContactOutcome> runs,
                                   std::span<const ContactOutcome> truth,
                                   const std::array<double, kOutcomeCount>& truths_statistic);
// the statistics of one truth's outcomes against the other's (NaN where there is no second)
std::array<double, kOutcomeCount> outcome_statistics(std::span<const ContactOutcome> a,
                                                     std::span<const ContactOutcome> b);

}  // namespace puppet::compare
