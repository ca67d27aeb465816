// The stability frontier: how hard a user can yank a free puppet before a solver breaks. Per
// solver configuration, the largest circle frequency and the largest dt at which `yank` stays
// `ok` (docs/design.md, "status"), found by bisection, with no air drag to hide an instability.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "puppet/compare/output.h"
#include "puppet/compare/sweep.h"

namespace puppet::compare {

// the scenario the frontier searches: a free puppet held by one hand whose circle it speeds up
inline constexpr const char* kFrontierScenario = "yank";
// frontier.csv's quantities: the circle frequency searched, or the step
inline constexpr const char* kQuantityHz = "hz";
inline constexpr const char* kQuantityDt = "dt";

struct FrontierSpec {
  const Model* model = nullptr;
  std::vector<SolverConfig> configs;
  ScenarioOptions scenario;  // hz and air drag are set by the search
  // circle frequency searched in [hz_low, hz_high] at dt = hz_dt
  double hz_dt = 1.0 / 240.0, hz_low = 0.25, hz_high = 32.0;
  // dt searched in [dt_low, dt_high] at the scenario's default frequency
  double dt_low = 1.0 / 7680.0, dt_high = 1.0 / 15.0;
  double resolution = 1.05;  // the bracket is narrowed to this ratio
  int jobs = 1;
  std::function<void(size_t done, size_t total)> on_progress;
};

// one bisection. Stability is assumed to hold below one boundary: a solver that is ok at the top
// of the range has no first_diverged, one that diverges at the bottom has no largest_ok.
struct FrontierRow {
  std::string solver, rule;
  std::string quantity;  // "hz" or "dt"
  std::string unit;      // "Hz" or "s"
  double held = 0.0;     // the other quantity, fixed: dt for the hz search, hz for the dt search
  std::optional<double> largest_ok, first_diverged;
  // the hand pin's largest gap in the largest_ok run (m): a soft pin that lets go of the hand
  // keeps a run ok without following the yank
  double pin_gap_at_largest_ok = 0.0;
  std::string reason;        // why the first_diverged run diverged
  double diverged_at = 0.0;  // s, when it did
  int runs = 0;              // runs of yank the search took
};

std::vector<FrontierRow> find_frontier(const FrontierSpec& spec);

inline constexpr const char* kFrontierHeader =
    "solver,rule,quantity,unit,held,largest_ok,first_diverged,pin_gap_at_largest_ok_m,reason,"
    "diverged_at_s,runs,model,"
    "git_sha,machine";
std::string frontier_csv(const std::vector<FrontierRow>& rows, const OutputContext& context);

}  // namespace puppet::compare
