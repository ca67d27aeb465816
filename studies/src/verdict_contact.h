// The verdict's side of a contact scene (contact_judge.h; docs/verdict.md, "Contact scenes"): the
// truths' runs, window, floor, violations and outcomes, and a candidate's measures.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "puppet/compare/sweep.h"
#include "puppet/compare/verdict_choice.h"

namespace puppet::compare {

// A run of a scenario for the verdict: its status, and in a contact scene its violations, its
// trajectory's samples and its outcome. `index` ≥ 0: from that random start (seed `seed`).
struct JudgedRun {
  RunResult run;
  ContactOutcome outcome;
};
JudgedRun judged_run(const SolverConfig& config, const Model& model, const std::string& name,
                     ScenarioOptions options, double dt, uint64_t seed, int64_t index);

// The truths in a contact scene: the first truth's run (its trajectory into `truth_run`), the
// window of its first impact, the floor of the window error (the first truth at h/2 and 2h and
// the second truth against it, into `floor`), both truths' violations, and their outcomes over
// `starts` random starts, on `jobs` threads, calling `after_each` as each run ends (one call at a
// time; contact_truth_runs of them). Cancellable (throw_if_cancelled).
ContactScene contact_truths(const Model& model, const std::vector<Truth>& truths,
                            const std::string& name, const ScenarioOptions& options, int64_t starts,
                            uint64_t seed, int jobs, TruthFloor* floor, Trajectory* truth_run,
                            const std::function<void()>& after_each = {});
// the runs contact_truths makes, for a progress line
size_t contact_truth_runs(size_t truth_count, int64_t starts);

// A candidate's measures in a contact scene, from its run of the scenario at `dt`: its window
// error against the truth's and its violations; error_m is the largest, `measure` names it
void judge_contact_candidate(const SolverConfig& config, const Model& model,
                             const Scenario& scenario, const Trajectory& truth_run,
                             const ContactScene& scene, double dt, Candidate& candidate);

// the candidate's outcomes over the starts against the truth's: outcome_ratio and outcome_worst
void compare_candidate_outcomes(const ContactScene& scene,
                                const std::vector<ContactOutcome>& outcomes, Candidate& candidate);

}  // namespace puppet::compare
