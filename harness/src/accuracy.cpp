#include "puppet/compare/accuracy.h"

#include "puppet/compare/summary_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "puppet/compare/cancel.h"
#include "puppet/compare/metrics.h"

namespace puppet::compare {
namespace {

// steps from `t0` for `sample_count` sample intervals, appending the state after each; stops at
// the first sample that meets a divergence criterion
void advance(Simulator& simulator, const Model& model, const Scenario& scenario, double t0,
             double dt, int per_sample, int sample_count, Trajectory& out) {
  std::vector<Vector3d> targets;
  std::vector<BodyState> bodies(scenario.initial.size());
  const std::vector<Pin> pins = scenario.initial_pins();
  MetricsProbe probe(model, scenario.environment, pins, scenario.initial);
  for (int k = 0; k < sample_count && !out.diverged; ++k) {
    for (int s = 0; s < per_sample; ++s) {
      throw_if_cancelled();
      const int step = k * per_sample + s + 1;
      scenario.targets_at(t0 + step * dt, targets);
      simulator.set_pin_targets(targets);
      simulator.step(dt);
    }
    simulator.read_state(bodies);
    const double t = t0 + (k + 1) * per_sample * dt;
    if (simulator.diverged() || divergence_reason(probe.measure(t, bodies, targets))) {
      out.diverged = true;
      break;
    }
    out.samples.push_back(bodies);
  }
}

double mean_of_finite(const std::vector<double>& values) {
  double sum = 0.0;
  int count = 0;
  for (double v : values) {
    if (std::isfinite(v)) {
      sum += v;
      ++count;
    }
  }
  return count ? sum / count : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

bool divides_sample_interval(double dt) {
  const double ratio = kAccuracySampleInterval / dt;
  const double steps = std::round(ratio);
  return steps >= 1.0 && std::abs(ratio - steps) <= 1e-9 * ratio;
}

int steps_per_sample(double dt) {
  if (!divides_sample_interval(dt)) {
    throw ScenarioError("accuracy: dt " + std::to_string(dt) + " s does not divide 1/30 s");
  }
  return static_cast<int>(std::lround(kAccuracySampleInterval / dt));
}

Trajectory record_trajectory(Simulator& simulator, const Model& model, const Scenario& scenario,
                             double dt, double duration) {
  const int per_sample = steps_per_sample(dt);
  const int sample_count = static_cast<int>(std::lround(duration / kAccuracySampleInterval));
  Trajectory out;
  simulator.reset(model, scenario);
  out.samples.push_back(scenario.initial);
  advance(simulator, model, scenario, 0.0, dt, per_sample, sample_count, out);
  return out;
}

ErrorSeries trajectory_errors(const Model& model, const Trajectory& run, const Trajectory& truth) {
  ErrorSeries out;
  const size_t n = std::min(run.samples.size(), truth.samples.size());
  for (size_t k = 0; k < n; ++k) {
    out.pose_m.push_back(pose_error(run.samples[k], truth.samples[k]));
    out.joint_angle_deg.push_back(joint_angle_error_deg(model, run.samples[k], truth.samples[k]));
  }
  return out;
}

ReseededError reseeded_error(Simulator& simulator, const Model& model, const Scenario& scenario,
                             const Trajectory& truth, double dt, int seeds, double horizon) {
  const int per_sample = steps_per_sample(dt);
  const int horizon_samples = static_cast<int>(std::lround(horizon / kAccuracySampleInterval));
  const int last_seed = static_cast<int>(truth.samples.size()) - 1 - horizon_samples;
  ReseededError out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < seeds && last_seed >= 0; ++i) {
    const int k0 = seeds > 1 ? static_cast<int>(std::lround(1.0 * i * last_seed / (seeds - 1))) : 0;
    const double t0 = k0 * kAccuracySampleInterval;
    simulator.reset(model, scenario);
    std::vector<Vector3d> targets;
    scenario.targets_at(t0, targets);
    simulator.set_pin_targets(targets);  // before set_state: the state starts at these targets
    simulator.set_state(truth.samples[k0]);
    simulator.set_time(t0);  // the tremble reads the clock
    Trajectory run;
    advance(simulator, model, scenario, t0, dt, per_sample, horizon_samples, run);
    out.seed_times.push_back(t0);
    if (run.diverged) {
      out.pose_m.push_back(nan);
      out.joint_angle_deg.push_back(nan);
      continue;
    }
    const auto& end = truth.samples[k0 + horizon_samples];
    out.pose_m.push_back(pose_error(run.samples.back(), end));
    out.joint_angle_deg.push_back(joint_angle_error_deg(model, run.samples.back(), end));
  }
  out.mean_pose_m = mean_of_finite(out.pose_m);
  out.mean_joint_angle_deg = mean_of_finite(out.joint_angle_deg);
  return out;
}

double max_limit_violation_deg(const Model& model, const Trajectory& trajectory) {
  std::vector<double> violations(model.joint_count());
  double worst = 0.0;
  for (const auto& sample : trajectory.samples) {
    limit_violations_deg(model, sample, violations);
    for (double v : violations) worst = std::max(worst, v);
  }
  return worst;
}

PinGaps trajectory_pin_gaps(const Scenario& scenario, const Trajectory& trajectory) {
  const std::vector<Pin> pins = scenario.initial_pins();
  std::vector<Vector3d> targets;
  std::vector<double> gaps(pins.size());
  PinGaps out;
  double sum = 0.0;
  int count = 0;
  for (size_t k = 1; k < trajectory.samples.size(); ++k) {
    scenario.targets_at(static_cast<double>(k) * kAccuracySampleInterval, targets);
    pin_gaps(pins, targets, trajectory.samples[k], gaps);
    for (double g : gaps) {
      out.max = std::max(out.max, g);
      sum += g * g;
      ++count;
    }
  }
  out.rms = count ? std::sqrt(sum / count) : 0.0;
  return out;
}

std::vector<SummaryRow> accuracy_rows(Simulator& simulator, const Model& model,
                                      const Scenario& scenario, double dt, const Trajectory& run,
                                      const Trajectory& reference, const std::string& label) {
  std::vector<SummaryRow> rows;
  auto add = [&](const StatInfo& stat, double pose_m, double angle_deg) {
    if (!std::isfinite(pose_m) || !std::isfinite(angle_deg)) return;
    rows.push_back(summary_row(metric::kPoseError, stat, pose_m, label));
    rows.push_back(summary_row(metric::kJointAngleError, stat, angle_deg, label));
  };
  const ErrorSeries errors = trajectory_errors(model, run, reference);
  const int samples = static_cast<int>(errors.pose_m.size());
  constexpr struct {
    const StatInfo& stat;
    int sample;
  } kAt[] = {{stats::kAt267ms, 8}, {stats::kAt500ms, 15}, {stats::kAt1s, 30}};
  for (const auto& at : kAt) {
    if (at.sample < samples)
      add(at.stat, errors.pose_m[at.sample], errors.joint_angle_deg[at.sample]);
  }
  constexpr int kFirstSecond = 30;
  if (samples > kFirstSecond) {
    double pose = 0.0, angle = 0.0;
    for (int k = 1; k <= kFirstSecond; ++k) {
      pose += errors.pose_m[k];
      angle += errors.joint_angle_deg[k];
    }
    add(stats::kMean1s, pose / kFirstSecond, angle / kFirstSecond);
  }

  const ReseededError reseeded = reseeded_error(simulator, model, scenario, reference, dt);
  if (reseeded.seed_times.empty()) return rows;
  add(stats::kReseededMean, reseeded.mean_pose_m, reseeded.mean_joint_angle_deg);
  double worst_pose = -1.0, worst_angle = -1.0;
  int diverged = 0;
  for (size_t i = 0; i < reseeded.pose_m.size(); ++i) {
    if (std::isnan(reseeded.pose_m[i])) {
      ++diverged;
      continue;
    }
    worst_pose = std::max(worst_pose, reseeded.pose_m[i]);
    worst_angle = std::max(worst_angle, reseeded.joint_angle_deg[i]);
  }
  if (worst_pose >= 0.0) add(stats::kReseededMax, worst_pose, worst_angle);
  rows.push_back(
      summary_row(metric::kReseededDiverged, stats::kCount, static_cast<double>(diverged), label));
  return rows;
}

}  // namespace puppet::compare
