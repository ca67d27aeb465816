#include "puppet/compare/run.h"

#include "puppet/compare/summary_metrics.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "puppet/compare/cancel.h"

namespace puppet::compare {
namespace {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(p * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

int step_count(const Scenario& scenario, const RunOptions& options) {
  const double duration = options.duration >= 0.0 ? options.duration : scenario.duration;
  return static_cast<int>(std::llround(duration / options.dt));
}

void summarise(const Scenario& scenario, RunResult& result) {
  const auto& trace = result.trace;
  double gap_max = 0, gap_sum2 = 0, pin_max = 0, pin_sum2 = 0, limit_max = 0, energy_abs = 0;
  double lin_max = 0, ang_max = 0, pen_max = 0, speed_max = 0;
  for (const StepMetrics& m : trace) {
    gap_max = std::max(gap_max, m.joint_gap_max);
    gap_sum2 += m.joint_gap_rms * m.joint_gap_rms;
    pin_max = std::max(pin_max, m.pin_gap_max);
    pin_sum2 += m.pin_gap_max * m.pin_gap_max;
    limit_max = std::max(limit_max, m.limit_violation_max_deg);
    energy_abs = std::max(energy_abs, std::abs(m.energy_drift));
    lin_max = std::max(lin_max, m.linear_momentum_drift);
    ang_max = std::max(ang_max, m.angular_momentum_drift);
    pen_max = std::max(pen_max, m.penetration);
    speed_max = std::max(speed_max, m.peak_speed);
  }
  const double n = static_cast<double>(std::max<size_t>(trace.size(), 1));
  auto add = [&](const MetricInfo& metric, const StatInfo& stat, double value) {
    result.summary.push_back(summary_row(metric, stat, value));
  };
  add(metric::kJointGap, stats::kMax, gap_max);
  add(metric::kJointGap, stats::kRms, std::sqrt(gap_sum2 / n));
  add(metric::kJointGap, stats::kFinal, trace.empty() ? 0.0 : trace.back().joint_gap_max);
  if (!scenario.pins.empty()) {
    add(metric::kPinGap, stats::kMax, pin_max);
    add(metric::kPinGap, stats::kRms, std::sqrt(pin_sum2 / n));
  }
  add(metric::kLimitViolation, stats::kMax, limit_max);
  add(metric::kEnergyDrift, stats::kFinal, trace.empty() ? 0.0 : trace.back().energy_drift);
  add(metric::kEnergyDrift, stats::kMaxAbs, energy_abs);
  if (scenario.conserves_momentum()) {
    add(metric::kMomentumDrift, stats::kLinearMax, lin_max);
    add(metric::kMomentumDrift, stats::kAngularMax, ang_max);
  }
  if (scenario.environment.ground) add(metric::kPenetration, stats::kMax, pen_max);
  add(metric::kPeakSpeed, stats::kMax, speed_max);
  if (result.diverged) add(metric::kDivergedAt, stats::kValue, result.diverged_at);
}

}  // namespace

double RunResult::value(const std::string& metric, const std::string& stat) const {
  for (const SummaryRow& row : summary) {
    if (row.metric == metric && row.stat == stat) return row.value;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

RunResult run_scenario(Simulator& simulator, const Model& model, const Scenario& scenario,
                       const RunOptions& options) {
  RunResult result;
  result.scenario = scenario.name;
  result.solver = simulator.name();
  result.rule = simulator.rule();
  result.dt = options.dt;
  result.substeps = simulator.substeps();
  const int steps = step_count(scenario, options);
  const int sample_every =
      options.sample_hz > 0.0
          ? std::max(1, static_cast<int>(std::lround(1.0 / (options.sample_hz * options.dt))))
          : 1;

  simulator.reset(model, scenario);
  const std::vector<Pin> pins = scenario.initial_pins();
  std::vector<BodyState> bodies(model.segment_count());
  std::vector<Vector3d> targets;
  simulator.read_state(bodies);
  MetricsProbe probe(model, scenario.environment, pins, bodies);
  scenario.targets_at(0.0, targets);
  result.trace.reserve(steps + 1);
  result.trace.push_back(probe.measure(0.0, bodies, targets));
  auto keep_poses = [&](double t) {
    for (int i = 0; i < model.segment_count(); ++i) result.poses.push_back({t, i, bodies[i]});
  };
  keep_poses(0.0);
  const int per_sample = options.record_trajectory && divides_sample_interval(options.dt)
                             ? steps_per_sample(options.dt)
                             : 0;
  if (per_sample) result.trajectory.samples.push_back(bodies);

  for (int k = 0; k < steps; ++k) {
    throw_if_cancelled();
    result.steps = k + 1;
    const double t = (k + 1) * options.dt;
    scenario.targets_at(t, targets);
    simulator.set_pin_targets(targets);
    simulator.step(options.dt);
    simulator.read_state(bodies);
    const StepMetrics m = probe.measure(t, bodies, targets);
    const char* reason = simulator.engine_error() ? "engine error"
                         : simulator.diverged()   ? "non-finite"
                                                  : divergence_reason(m);
    if (reason) {
      result.diverged = true;
      result.diverged_at = t;
      result.diverged_reason = reason;
      result.trajectory.diverged = per_sample > 0;
      break;
    }
    result.trace.push_back(m);
    if ((k + 1) % sample_every == 0) keep_poses(t);
    if (per_sample && (k + 1) % per_sample == 0) result.trajectory.samples.push_back(bodies);
  }
  summarise(scenario, result);
  if (options.timing) time_scenario(simulator, model, scenario, options, result);
  return result;
}

// a pass that only steps and reads the clock: nothing else runs between the clock reads
void time_scenario(Simulator& simulator, const Model& model, const Scenario& scenario,
                   const RunOptions& options, RunResult& result) {
  // a diverged run is timed only up to its divergence: what a solver does after it is noise
  const int steps = result.steps;
  using Clock = std::chrono::steady_clock;
  std::vector<Vector3d> targets;
  std::vector<double> step_seconds;
  step_seconds.reserve(steps);
  simulator.set_stage_timing(false);
  simulator.reset(model, scenario);
  for (int k = 0; k < steps && !simulator.diverged(); ++k) {
    throw_if_cancelled();
    scenario.targets_at((k + 1) * options.dt, targets);
    simulator.set_pin_targets(targets);
    const auto begin = Clock::now();
    simulator.step(options.dt);
    const double seconds = std::chrono::duration<double>(Clock::now() - begin).count();
    // an engine that steps ahead of the calls (jolt) times its own steps
    const double own = simulator.own_step_seconds();
    step_seconds.push_back(own >= 0.0 ? own : seconds);
  }
  if (step_seconds.empty()) return;
  double total = 0.0;
  for (double s : step_seconds) total += s;
  result.summary.push_back(
      summary_row(metric::kStepTime, stats::kMedian, 1e6 * percentile(step_seconds, 0.5)));
  result.summary.push_back(
      summary_row(metric::kStepTime, stats::kP95, 1e6 * percentile(step_seconds, 0.95)));
  result.summary.push_back(summary_row(metric::kRealtimeFactor, stats::kValue,
                                       step_seconds.size() * options.dt / total));

  // per stage, from its own pass (the stage clocks cost time of their own)
  const auto names = simulator.stage_names();
  if (names.empty()) return;
  std::vector<std::vector<double>> stages(names.size());
  simulator.set_stage_timing(true);
  simulator.reset(model, scenario);
  for (int k = 0; k < steps && !simulator.diverged(); ++k) {
    throw_if_cancelled();
    scenario.targets_at((k + 1) * options.dt, targets);
    simulator.set_pin_targets(targets);
    simulator.step(options.dt);
    const auto seconds = simulator.stage_seconds();
    for (size_t s = 0; s < names.size(); ++s) stages[s].push_back(seconds[s]);
  }
  simulator.set_stage_timing(false);
  for (size_t s = 0; s < names.size(); ++s) {
    const std::string metric = stage_metric(names[s]);
    const std::string unit(metric::kStageTime.unit);
    result.summary.push_back(
        {metric, std::string(stats::kMedian.name), 1e6 * percentile(stages[s], 0.5), unit, ""});
    result.summary.push_back(
        {metric, std::string(stats::kP95.name), 1e6 * percentile(stages[s], 0.95), unit, ""});
  }
}

}  // namespace puppet::compare
