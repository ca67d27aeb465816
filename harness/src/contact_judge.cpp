#include "puppet/compare/contact_judge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "puppet/compare/metrics.h"

namespace puppet::compare {

namespace {
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
}

double ContactViolations::worst() const {
  return std::max({penetration_m, joint_gap_m, limit_overshoot_m, energy_gain_m});
}

const char* ContactViolations::worst_name() const {
  const double w = worst();
  if (w == penetration_m) return "penetration";
  if (w == joint_gap_m) return "joint gap";
  if (w == limit_overshoot_m) return "limit overshoot";
  return "energy gained";
}

double contact_lever(const Model& model) {
  double lever = 0.0;
  for (const Joint& joint : model.joints) lever = std::max(lever, joint.anchor_in_child.norm());
  return lever;
}

ContactViolations contact_violations(const Model& model, const Scenario& scenario,
                                     const RunResult& run) {
  ContactViolations out;
  if (run.trace.empty()) return out;
  // E = E(0) + drift · E_ref (MetricsProbe); the gain is E over the least E of the steps with no
  // point below the ground so far (while a point is in the ground a soft contact holds energy the
  // sum does not count, and gives it back)
  const double e_ref = energy_reference(model, scenario.environment, scenario.initial);
  const double weight = model.total_mass * kStandardGravity;
  double least_free = run.trace.front().energy_drift, gain = 0.0, overshoot_deg = 0.0;
  for (const StepMetrics& m : run.trace) {
    out.penetration_m = std::max(out.penetration_m, m.penetration);
    out.joint_gap_m = std::max(out.joint_gap_m, m.joint_gap_max);
    overshoot_deg = std::max(overshoot_deg, m.limit_violation_max_deg);
    if (m.penetration <= 0.0) least_free = std::min(least_free, m.energy_drift);
    gain = std::max(gain, m.energy_drift - least_free);
  }
  out.limit_overshoot_m = overshoot_deg * M_PI / 180.0 * contact_lever(model);
  out.energy_gain_m = weight > 0.0 ? gain * e_ref / weight : 0.0;
  return out;
}

double first_contact_time(const RunResult& run) {
  for (const StepMetrics& m : run.trace) {
    if (m.penetration > 0.0) return m.t;
  }
  return kNan;
}

double window_error(const Trajectory& run, const Trajectory& truth, double t_end) {
  const size_t n = std::min(run.samples.size(), truth.samples.size());
  double sum = 0.0;
  int count = 0;
  for (size_t k = 1; k < n && static_cast<double>(k) * kAccuracySampleInterval <= t_end + 1e-9;
       ++k) {
    sum += pose_error(run.samples[k], truth.samples[k]);
    ++count;
  }
  return count > 0 ? sum / count : kNan;
}

ContactOutcome contact_outcome(const Model& model, const Scenario& scenario, const RunResult& run) {
  ContactOutcome out;
  const std::vector<BodyState>& last =
      run.trajectory.samples.empty() ? scenario.initial : run.trajectory.samples.back();
  const Vector3d start = centre_of_mass(model, scenario.initial);
  const Vector3d end = centre_of_mass(model, last);
  out.com_height_m = end.z();
  out.com_travel_m = std::hypot(end.x() - start.x(), end.y() - start.y());
  for (const StepMetrics& m : run.trace) {
    if (m.peak_speed > kRestSpeed) out.rest_time_s = m.t;
  }
  return out;
}

double outcome_value(const ContactOutcome& outcome, int which) {
  switch (which) {
    case 0:
      return outcome.com_height_m;
    case 1:
      return outcome.com_travel_m;
    default:
      return outcome.rest_time_s;
  }
}

double ks_statistic(std::span<const double> a, std::span<const double> b) {
  if (a.empty() || b.empty()) return kNan;
  std::vector<double> x(a.begin(), a.end()), y(b.begin(), b.end());
  std::sort(x.begin(), x.end());
  std::sort(y.begin(), y.end());
  const double n = static_cast<double>(x.size()), m = static_cast<double>(y.size());
  size_t i = 0, j = 0;
  double d = 0.0;
  // walk the merged values; at each distinct value both distribution functions have taken every
  // sample up to it
  while (i < x.size() || j < y.size()) {
    const double v = j == y.size() || (i < x.size() && x[i] <= y[j]) ? x[i] : y[j];
    while (i < x.size() && x[i] <= v) ++i;
    while (j < y.size() && y[j] <= v) ++j;
    d = std::max(d, std::abs(static_cast<double>(i) / n - static_cast<double>(j) / m));
  }
  return d;
}

double ks_critical(size_t n, size_t m, double alpha) {
  const double nn = static_cast<double>(n), mm = static_cast<double>(m);
  return std::sqrt(-std::log(alpha / 2.0) / 2.0) * std::sqrt((nn + mm) / (nn * mm));
}

namespace {
std::vector<double> column(std::span<const ContactOutcome> runs, int which) {
  std::vector<double> out;
  out.reserve(runs.size());
  for (const ContactOutcome& o : runs) out.push_back(outcome_value(o, which));
  return out;
}
}  // namespace

std::array<double, kOutcomeCount> outcome_statistics(std::span<const ContactOutcome> a,
                                                     std::span<const ContactOutcome> b) {
  std::array<double, kOutcomeCount> out;
  for (int k = 0; k < kOutcomeCount; ++k) out[k] = ks_statistic(column(a, k), column(b, k));
  return out;
}

OutcomeComparison compare_outcomes(std::span<const ContactOutcome> runs,
                                   std::span<const ContactOutcome> truth,
                                   const std::array<double, kOutcomeCount>& truths_statistic) {
  OutcomeComparison out;
  out.statistic = outcome_statistics(runs, truth);
  const double critical = ks_critical(runs.size(), truth.size(), kOutcomeAlpha);
  out.worst_ratio = -1.0;
  for (int k = 0; k < kOutcomeCount; ++k) {
    out.bar[k] =
        std::isnan(truths_statistic[k]) ? critical : std::max(critical, truths_statistic[k]);
    const double ratio = out.statistic[k] / out.bar[k];
    // a statistic that is not a number (no runs) is never alike
    if (!(ratio <= out.worst_ratio)) {
      out.worst_ratio = std::isnan(ratio) ? INFINITY : ratio;
      out.worst = k;
    }
  }
  return out;
}

}  // namespace puppet::compare
