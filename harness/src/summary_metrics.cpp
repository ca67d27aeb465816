#include "puppet/compare/summary_metrics.h"

#include <array>

namespace puppet::compare {

std::span<const MetricInfo> summary_metrics() {
  static constexpr std::array kAll = {
      metric::kJointGap,        metric::kPinGap,           metric::kLimitViolation,
      metric::kEnergyDrift,     metric::kMomentumDrift,    metric::kPenetration,
      metric::kPeakSpeed,       metric::kDivergedAt,       metric::kStepTime,
      metric::kRealtimeFactor,  metric::kStageTime,        metric::kPoseError,
      metric::kJointAngleError, metric::kReseededDiverged, metric::kTruthDt};
  return kAll;
}

std::span<const StatInfo> summary_stats() {
  static constexpr std::array kAll = {
      stats::kMax,          stats::kRms,        stats::kFinal,   stats::kMaxAbs, stats::kLinearMax,
      stats::kAngularMax,   stats::kValue,      stats::kMedian,  stats::kP95,    stats::kCount,
      stats::kTruthStep,    stats::kAt267ms,    stats::kAt500ms, stats::kAt1s,   stats::kMean1s,
      stats::kReseededMean, stats::kReseededMax};
  return kAll;
}

std::string stage_metric(std::string_view stage) { return std::string(stage) + "_us"; }

SummaryRow summary_row(const MetricInfo& metric, const StatInfo& stat, double value,
                       std::string_view reference) {
  return {std::string(metric.name), std::string(stat.name), value, std::string(metric.unit),
          std::string(reference)};
}

}  // namespace puppet::compare
