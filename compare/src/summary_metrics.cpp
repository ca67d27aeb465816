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
      stat::kMax,          stat::kRms,        stat::kFinal,   stat::kMaxAbs, stat::kLinearMax,
      stat::kAngularMax,   stat::kValue,      stat::kMedian,  stat::kP95,    stat::kCount,
      stat::kTruthStep,    stat::kAt267ms,    stat::kAt500ms, stat::kAt1s,   stat::kMean1s,
      stat::kReseededMean, stat::kReseededMax};
  return kAll;
}

std::string stage_metric(std::string_view stage) { return std::string(stage) + "_us"; }

SummaryRow summary_row(const MetricInfo& metric, const StatInfo& stat, double value,
                       std::string_view reference) {
  return {std::string(metric.name), std::string(stat.name), value, std::string(metric.unit),
          std::string(reference)};
}

}  // namespace puppet::compare
