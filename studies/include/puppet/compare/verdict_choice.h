// The verdict's choice (verdict.h): a candidate configuration as measured, the rule that picks the
// cheapest one within a budget and a robustness bar, the truth's floor below which a budget is
// refused, and what the truths give in a contact scene. The verdict's search (verdict.cpp) and
// its contact scenes (verdict_contact.cpp) both read these; neither reads the other's.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "puppet/compare/contact_judge.h"
#include "puppet/compare/simulator.h"

namespace puppet::compare {

/// one configuration of one solver in one scenario, as measured
struct Candidate {
  std::string scenario, solver, rule;
  std::string setting;  ///< the testbed flags beyond the dt ("--substeps 4"); empty: none
  double dt = 0.0;
  double cost_us_per_s = NAN;   ///< CPU time per simulated second (µs); NaN: not timed
  double error_m = NAN;         ///< re-seeded pose error against the truth; NaN: not judged
  bool diverged = false;        ///< the scenario's run, or a re-seeded run, diverged
  std::string reason;           ///< why it diverged
  int64_t starts = 0;           ///< random starts run (robustness); 0: not run
  int64_t diverged_starts = 0;  ///< of them, diverged (the run stops at the first)
  // a contact scene's (judged_by_contact): error_m is the largest of the first impact's window
  // error and the violations, `measure` names which; its outcomes over the starts against the
  // truth's: the largest statistic over its bar (NaN: not compared; above 1: unlike the truth's)
  std::string measure;
  double window_error_m = NAN;
  ContactViolations violations;
  double outcome_ratio = NAN;
  int outcome_worst = 0;
};

/// what a search found
enum class Verdict {
  kMet,          ///< a configuration meets the budget and the bar
  kDiverges,     ///< every measured configuration diverges
  kErrorFloor,   ///< none that holds together comes within the budget
  kNotRobust,    ///< some come within the budget, none with the robustness bar
  kUnlikeTruth,  ///< (a contact scene) some pass both, none with outcomes like the truth's
  kNotMeasured,  ///< no configuration was both timed and judged
};
inline constexpr std::array kAllVerdicts = {Verdict::kMet,         Verdict::kDiverges,
                                            Verdict::kErrorFloor,  Verdict::kNotRobust,
                                            Verdict::kUnlikeTruth, Verdict::kNotMeasured};
const char* verdict_name(Verdict verdict);
/// verdict.csv's verdict of a row not judged: its budget is finer than the truth's floor
inline constexpr const char* kRefused = "refused";
/// verdict.csv's views: cost per simulated second at any dt, or per frame in whole steps
inline constexpr const char* kViewSecond = "second";
inline constexpr const char* kViewFrame = "frame";
/// candidates.csv's status: ran and was timed, diverged, or ran but was not timed
inline constexpr const char* kCandidateOk = "ok";
inline constexpr const char* kCandidateDiverged = "diverged";
inline constexpr const char* kCandidateNotTimed = "not-timed";

struct Choice {
  Verdict verdict = Verdict::kNotMeasured;
  int index = -1;                 ///< the chosen candidate (kMet), else −1
  double best_error_m = NAN;      ///< the smallest error of a configuration that did not diverge
  double divergence_upper = NAN;  ///< the chosen candidate's 95 % Wilson upper bound
};

/// The cheapest candidate whose error is within `budget_m`, whose divergence rate over its
/// random starts has a 95 % Wilson upper bound within `robustness_ceiling` (a candidate without
/// starts never meets a bar below 1) and whose outcomes, where compared, are like the truth's.
/// Ties in cost go to the larger dt.
Choice cheapest(std::span<const Candidate> candidates, double budget_m, double robustness_ceiling);

/// cheapest() among the candidates whose dt takes a frame of 1/hz in whole steps (the frame
/// view); the index is into `candidates`
Choice cheapest_per_frame(std::span<const Candidate> candidates, double budget_m,
                          double robustness_ceiling, double hz);

/// the ceiling that "no divergence in `starts` random starts" sets: the Wilson upper bound of
/// 0 of `starts`, which 1 of `starts` exceeds
double no_divergence_ceiling(int64_t starts);

/// A truth's floor: the smallest error it can judge. Its own error bar, BAR_MARGIN ×
/// 2^p/(2^p − 1) × its h/2 difference with p the order its 2h and h/2 differences give (at least
/// kMinOrder), and never below the other truth's error against it (NaN when there is none).
inline constexpr double kBarMargin = 1.5;
inline constexpr double kMinOrder = 0.5;
double truth_floor(double half_difference, double double_difference, double agreement);

/// empty when a budget can be judged; else why not: a budget below the truth's floor is finer
/// than the truth can tell
std::string budget_problem(double budget_m, double truth_floor_m);

/// a cost per simulated second seen at a frame rate: µs per frame, and puppets one core keeps
/// at that rate
struct FrameCost {
  double us_per_frame = NAN;
  double puppets_per_core = NAN;
};
FrameCost at_frame_rate(double cost_us_per_s, double hz = 60.0);

/// whether a step of dt fits a frame of 1/hz a whole number of times (steps per frame, else 0)
int steps_per_frame(double dt, double hz);

/// the options of a candidate named as candidates.csv and verdict.csv name it: its solver, rule
/// and setting; throws ScenarioError when no setting searched for it has those flags
SolverOptions candidate_options(const std::string& solver, const std::string& rule,
                                const std::string& setting);

/// a budget as tables show it: 1mm, 1cm, 5cm, 50um
std::string budget_text(double budget_m);

struct TruthFloor {
  std::string scenario;
  double half_difference = NAN, double_difference = NAN, agreement = NAN, floor = NAN;
};

/// what the truths give in a contact scene (contact_judge.h): the window of its first impact, the
/// floor there (TruthFloor, of the window error), both truths' violations and their outcomes over
/// the verdict's random starts
struct ContactScene {
  std::string scenario;
  std::string second_truth;  ///< the second truth's engine; empty: none
  double first_contact_s = NAN, window_end_s = NAN;
  ContactViolations truth_violations, second_violations;
  std::vector<ContactOutcome> truth_outcomes, second_outcomes;
  std::array<double, kOutcomeCount> truths_statistic{NAN, NAN, NAN};  ///< KS, truth vs second
  double critical = NAN;  ///< the KS critical value at kOutcomeAlpha for the starts
};

}  // namespace puppet::compare
