// The metric catalogue: every metric a run writes to summary.csv, with its unit and meaning
// (docs/design.md, "Metrics"). The code that writes a row names its metric from here, and
// `testbed list --json` gives the list to the scripts that read the CSVs.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "puppet/compare/metrics.h"

namespace puppet::compare {

struct MetricInfo {
  std::string_view name;  // summary.csv's metric column
  std::string_view unit;  // its unit column ("1": a ratio)
  std::string_view meaning;
};

namespace metric {
inline constexpr MetricInfo kJointGap{"joint_gap_m", "m", "the widest joint gap of a step"};
inline constexpr MetricInfo kPinGap{"pin_gap_m", "m", "the widest gap of a pin to its target"};
inline constexpr MetricInfo kLimitViolation{"limit_violation_deg", "deg",
                                            "how far a joint is past its limits"};
inline constexpr MetricInfo kEnergyDrift{"energy_drift", "1",
                                         "(E − E₀)/|E₀|, where nothing external does work"};
inline constexpr MetricInfo kMomentumDrift{"momentum_drift", "1",
                                           "linear and angular momentum's drift, where no force"};
inline constexpr MetricInfo kPenetration{"penetration_m", "m", "the deepest point below ground"};
inline constexpr MetricInfo kPeakSpeed{"peak_speed_mps", "m/s", "the fastest segment's speed"};
inline constexpr MetricInfo kDivergedAt{"diverged_at_s", "s", "when the solver diverged"};
inline constexpr MetricInfo kStepTime{"step_us", "us", "wall time of one step"};
inline constexpr MetricInfo kRealtimeFactor{"realtime_factor", "1",
                                            "simulated time over wall time"};
inline constexpr MetricInfo kStageTime{"{stage}_us", "us",
                                       "wall time of one stage per step (procedural)"};
inline constexpr MetricInfo kPoseError{"pose_err_m", "m",
                                       "mean segment position error against a reference"};
inline constexpr MetricInfo kJointAngleError{"joint_angle_err_deg", "deg",
                                             "mean joint angle error against a reference"};
inline constexpr MetricInfo kReseededDiverged{"reseeded_diverged", "1",
                                              "reseeded runs that diverged"};
inline constexpr MetricInfo kTruthDt{"truth_dt", "s", "the step of a truth's run"};
}  // namespace metric

// every metric, in the order the docs list them
std::span<const MetricInfo> summary_metrics();
// a stage's time metric's name ("adjust_us")
std::string stage_metric(std::string_view stage);
// a summary row of the metric, in its unit
SummaryRow summary_row(const MetricInfo& metric, std::string_view stat, double value,
                       std::string_view reference = {});

}  // namespace puppet::compare
