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

// the stat column: which figure of a metric a row holds
struct StatInfo {
  std::string_view name;  // summary.csv's stat column
  std::string_view meaning;
};

namespace stats {
inline constexpr StatInfo kMax{"max", "the largest over the run"};
inline constexpr StatInfo kRms{"rms", "the root mean square over the run"};
inline constexpr StatInfo kFinal{"final", "at the run's last step"};
inline constexpr StatInfo kMaxAbs{"max_abs", "the largest magnitude over the run"};
inline constexpr StatInfo kLinearMax{"linear_max", "the linear part's largest over the run"};
inline constexpr StatInfo kAngularMax{"angular_max", "the angular part's largest over the run"};
inline constexpr StatInfo kValue{"value", "the one value of the run"};
inline constexpr StatInfo kMedian{"median", "the median over the timed steps"};
inline constexpr StatInfo kP95{"p95", "the 95th percentile over the timed steps"};
inline constexpr StatInfo kCount{"count", "how many"};
inline constexpr StatInfo kTruthStep{"h", "the truth's step h, for a row of its own runs"};
inline constexpr StatInfo kAt267ms{"at_0.267s", "along the run, at 0.267 s"};
inline constexpr StatInfo kAt500ms{"at_0.5s", "along the run, at 0.5 s"};
inline constexpr StatInfo kAt1s{"at_1s", "along the run, at 1 s"};
inline constexpr StatInfo kMean1s{"mean_1s", "along the run, the mean over its first second"};
inline constexpr StatInfo kReseededMean{
    "reseeded_mean", "the mean of the half-second runs re-seeded from the reference's states"};
inline constexpr StatInfo kReseededMax{"reseeded_max",
                                       "the largest of the re-seeded half-second runs"};
}  // namespace stats

// every metric, in the order the docs list them
std::span<const MetricInfo> summary_metrics();
// every stat
std::span<const StatInfo> summary_stats();
// a stage's time metric's name ("adjust_us")
std::string stage_metric(std::string_view stage);
// a summary row of the metric, in its unit
SummaryRow summary_row(const MetricInfo& metric, const StatInfo& stat, double value,
                       std::string_view reference = {});

}  // namespace puppet::compare
