// Runs one scenario in one solver and turns it into measurements: a trace per step, sampled
// poses, and the tidy summary rows of docs/design.md ("Outputs").
#pragma once

#include <string>
#include <vector>

#include "puppet/compare/accuracy.h"
#include "puppet/compare/metrics.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/compare/summary_metrics.h"

namespace puppet::compare {

struct RunOptions {
  double dt = 1.0 / 240.0;
  double duration = -1.0;  // < 0: the scenario's own
  double sample_hz = 0.0;  // poses kept per second of simulated time; 0: every step
  bool timing = true;      // add a separate timing pass (step_us, stage times, realtime factor)
  // keep the states at multiples of kAccuracySampleInterval (when dt divides it)
  bool record_trajectory = false;
};

struct PoseSample {
  double t;
  int segment;
  BodyState body;
};

struct RunResult {
  std::string scenario, solver, rule;
  double dt = 0.0;
  int substeps = 1;
  bool diverged = false;
  int steps = 0;                   // steps taken, the one that diverged included
  double diverged_at = 0.0;        // s
  std::string diverged_reason;     // "non-finite", "engine error", "joint gap" or "energy"
  std::vector<StepMetrics> trace;  // one per step, plus t = 0
  std::vector<PoseSample> poses;
  std::vector<SummaryRow> summary;
  Trajectory trajectory;  // with RunOptions::record_trajectory

  // the summary value of a metric/stat, NaN when absent
  double value(const std::string& metric, const std::string& stat) const;
  // the same, named from the catalogues (summary_metrics.h)
  double value(const MetricInfo& metric, const StatInfo& stat) const {
    return value(std::string(metric.name), std::string(stat.name));
  }
};

// the measured run, then (with options.timing) the timing pass
RunResult run_scenario(Simulator& simulator, const Model& model, const Scenario& scenario,
                       const RunOptions& options);

// The timing pass alone: steps the scenario again (only up to the divergence of a diverged
// result) and appends step_us, realtime_factor and the per-stage times to result.summary. Run it
// with nothing else busy on the machine: sweeps run their jobs in parallel and time them after.
void time_scenario(Simulator& simulator, const Model& model, const Scenario& scenario,
                   const RunOptions& options, RunResult& result);

}  // namespace puppet::compare
