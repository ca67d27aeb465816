// Runs one scenario in one solver and turns it into measurements: a trace per step, sampled
// poses, and the tidy summary rows of shared/DESIGN.md ("Outputs").
#pragma once

#include <string>
#include <vector>

#include "puppet/compare/metrics.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"

namespace puppet::compare {

struct RunOptions {
  double dt = 1.0 / 240.0;
  double duration = -1.0;  // < 0: the scenario's own
  double sample_hz = 0.0;  // poses kept per second of simulated time; 0: every step
  bool timing = true;      // add a separate timing pass (step_us, stage times, realtime factor)
};

// the divergence criteria of DESIGN.md ("status")
constexpr double kDivergedJointGap = 0.5;    // m
constexpr double kDivergedEnergyDrift = 10;  // × E_ref

struct SummaryRow {
  std::string metric, stat;
  double value = 0.0;
  std::string unit;
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
  double diverged_at = 0.0;        // s
  std::vector<StepMetrics> trace;  // one per step, plus t = 0
  std::vector<PoseSample> poses;
  std::vector<SummaryRow> summary;

  // the summary value of a metric/stat, NaN when absent
  double value(const std::string& metric, const std::string& stat) const;
};

RunResult run_scenario(Simulator& simulator, const Model& model, const Scenario& scenario,
                       const RunOptions& options);

}  // namespace puppet::compare
