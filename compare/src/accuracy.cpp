#include "puppet/compare/accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "puppet/compare/metrics.h"

namespace puppet::compare {
namespace {

// steps per sample interval, or throws when dt does not divide it
int steps_per_sample(double dt) {
  const double ratio = kAccuracySampleInterval / dt;
  const long steps = std::lround(ratio);
  if (steps < 1 || std::abs(ratio - static_cast<double>(steps)) > 1e-9 * ratio) {
    throw ScenarioError("accuracy: dt " + std::to_string(dt) + " s does not divide 1/30 s");
  }
  return static_cast<int>(steps);
}

bool finite(const std::vector<BodyState>& bodies) {
  return std::all_of(bodies.begin(), bodies.end(), [](const BodyState& b) { return is_finite(b); });
}

// steps from `t0` for `sample_count` sample intervals, appending the state after each
void advance(Simulator& simulator, const Scenario& scenario, double t0, double dt, int per_sample,
             int sample_count, Trajectory& out) {
  std::vector<Vector3d> targets;
  std::vector<BodyState> bodies(scenario.initial.size());
  for (int k = 0; k < sample_count && !out.diverged; ++k) {
    for (int s = 0; s < per_sample; ++s) {
      const int step = k * per_sample + s + 1;
      scenario.targets_at(t0 + step * dt, targets);
      simulator.set_pin_targets(targets);
      simulator.step(dt);
    }
    simulator.read_state(bodies);
    if (simulator.diverged() || !finite(bodies)) {
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

Trajectory record_trajectory(Simulator& simulator, const Model& model, const Scenario& scenario,
                             double dt, double duration) {
  const int per_sample = steps_per_sample(dt);
  const int sample_count = static_cast<int>(std::lround(duration / kAccuracySampleInterval));
  Trajectory out;
  simulator.reset(model, scenario);
  out.samples.push_back(scenario.initial);
  advance(simulator, scenario, 0.0, dt, per_sample, sample_count, out);
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
    Trajectory run;
    advance(simulator, scenario, t0, dt, per_sample, horizon_samples, run);
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

}  // namespace puppet::compare
