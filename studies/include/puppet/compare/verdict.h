// The verdict (`testbed verdict`): per solver and scenario, the cheapest configuration that
// simulates the scenario within an error budget against the truth without diverging in N random
// starts, its cost per simulated second, and why none does when none does (docs/verdict.md).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/compare/output.h"
#include "puppet/compare/sweep.h"
#include "puppet/compare/verdict_choice.h"

namespace puppet::compare {

struct VerdictSpec {
  const Model* model = nullptr;
  std::vector<std::string> scenarios;
  ScenarioOptions scenario;           // the base; a random start adds its own
  std::vector<SolverConfig> solvers;  // one per solver, procedural once per rule
  std::vector<double> dts;
  std::vector<double> budgets_m;
  double frame_hz = 60.0;
  int64_t starts = 32;  // random starts a chosen configuration must survive
  uint64_t seed = 1;
  int jobs = 1;                                 // worker threads; the timing runs alone
  double engine_budget = kDefaultEngineBudget;  // what the truths' engines may cost (engines.h)
  // the truth's floor per scenario as a sweep measured it (floors_from_summary); empty: measured
  // here (the truth at h/2 and 2h and the second truth, each re-seeded from the truth)
  std::vector<TruthFloor> floors;
  std::function<void(const char* phase, size_t done, size_t total)> on_progress;
};

/// one row of the verdict: a solver in a scenario at a budget, in one view
struct VerdictRow {
  std::string scenario, solver, rule;
  std::string view;  ///< kViewSecond (any dt) or kViewFrame (a whole number of steps per frame)
  double budget_m = 0.0;
  std::string verdict;  ///< met, refused, diverges, error-floor, not-robust, not-measured
  std::string why;      ///< one line, empty when met
  int chosen = -1;      ///< index into VerdictResult::candidates when met
  double divergence_upper = NAN;
  double best_error_m = NAN;
  double truth_floor_m = NAN;
};

struct VerdictResult {
  std::string truth;                  ///< the judging truth's engine
  std::vector<TruthFloor> floors;     ///< per scenario
  std::vector<ContactScene> contact;  ///< per contact scene
  std::vector<Candidate> candidates;  ///< scenario × solver × setting × dt
  std::vector<VerdictRow> rows;       ///< scenario × solver × view × budget
};

/// Measures every candidate (cost in one thread, interleaved; error and divergence on `jobs`
/// threads) and searches each solver's for each budget, running the random starts of the cheapest
/// candidates within budget until one survives them all. Throws ScenarioError when the model has
/// no truth.
VerdictResult run_verdict(const VerdictSpec& spec);

/// The floors of `scenarios` from a sweep's summary.csv (a contact scene's are measured by the
/// verdict itself, of its window error) (testbed run, both truths at three
/// dts): its rows of the truth at h/2 and 2h and of the second truth, each against the truth at
/// h. Throws std::runtime_error naming the file and what it lacks when the summary is of
/// another model, truth or commit (`git_sha`), or misses a scenario's rows. The truths are the
/// model's within the engine `budget` (truths_for).
std::vector<TruthFloor> floors_from_summary(const std::string& text, const std::string& source,
                                            const Model& model,
                                            const std::vector<std::string>& scenarios,
                                            const std::string& git_sha, double budget);

inline constexpr const char* kCandidatesHeader =
    "scenario,solver,rule,setting,dt,cost_us_per_s,error_m,status,reason,starts,"
    "diverged_starts,truth_floor_m,measure,window_error_m,penetration_m,joint_gap_m,"
    "limit_overshoot_m,energy_gain_m,outcome_ratio,truth,model,git_sha,machine";
inline constexpr const char* kVerdictHeader =
    "scenario,solver,rule,view,frame_hz,budget_m,verdict,setting,dt,steps_per_frame,"
    "cost_us_per_s,us_per_frame,puppets_per_core,error_m,starts,divergence_upper,"
    "best_error_m,truth_floor_m,why,truth,model,git_sha,machine";
std::string verdict_candidates_csv(const VerdictResult& result, const OutputContext& context);
/// contact.csv: per contact scene, the truths' window, floor, violations and outcomes, one row
/// per truth and measure
inline constexpr const char* kContactHeader =
    "scenario,truth_role,solver,measure,stat,value,unit,truth,model,git_sha,machine";
std::string verdict_contact_csv(const VerdictResult& result, const OutputContext& context);
std::string verdict_csv(const VerdictResult& result, const VerdictSpec& spec,
                        const OutputContext& context);

}  // namespace puppet::compare
