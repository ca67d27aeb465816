// How wrong a solver is: its states against a truth trajectory at the same times, along a whole
// run and re-seeded from the truth (Erez, Tassa & Todorov 2015; docs/design.md, "Metrics").
#pragma once

#include <string>
#include <vector>

#include "puppet/compare/metrics.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"

namespace puppet::compare {

// errors are taken at multiples of this: every dt of the sweeps divides it
constexpr double kAccuracySampleInterval = 1.0 / 30.0;

// whether dt divides the sample interval, and how many steps make one sample interval (throws
// ScenarioError when dt does not divide it)
bool divides_sample_interval(double dt);
int steps_per_sample(double dt);

// a run's states at t = k · kAccuracySampleInterval, k = 0, 1, ... (shorter when it diverged)
struct Trajectory {
  std::vector<std::vector<BodyState>> samples;
  bool diverged = false;
};

// steps the simulator through the scenario from its initial state; dt must divide the sample
// interval (throws ScenarioError otherwise)
Trajectory record_trajectory(Simulator& simulator, const Model& model, const Scenario& scenario,
                             double dt, double duration);

// pose_err_m and joint_angle_err_deg at every sample both trajectories have
struct ErrorSeries {
  std::vector<double> pose_m, joint_angle_deg;
};
ErrorSeries trajectory_errors(const Model& model, const Trajectory& run, const Trajectory& truth);

// Re-seeded error: from `seeds` states evenly spread along the truth (the first at t = 0, the
// last `horizon` before its end), the simulator is set to the truth's state, runs `horizon`
// seconds under the scenario's pin targets, and its error against the truth is taken at the end.
// A re-seeded run that meets a divergence criterion of docs/design.md ("status") counts as
// diverged.
struct ReseededError {
  std::vector<double> seed_times;
  std::vector<double> pose_m, joint_angle_deg;           // per seed; NaN when that run diverged
  double mean_pose_m = 0.0, mean_joint_angle_deg = 0.0;  // over the seeds that did not
};
ReseededError reseeded_error(Simulator& simulator, const Model& model, const Scenario& scenario,
                             const Trajectory& truth, double dt, int seeds = 8,
                             double horizon = 0.5);

// the largest violation of the model's limits over a trajectory's samples (deg; docs/design.md's
// swing ellipse and twist, the metrics' measure)
double max_limit_violation_deg(const Model& model, const Trajectory& trajectory);
// the largest and the RMS distance of a pin point from its target over a trajectory's samples
// (m; the scenario's pins and targets at the sample times; 0 without pins)
struct PinGaps {
  double max = 0.0, rms = 0.0;
};
PinGaps trajectory_pin_gaps(const Scenario& scenario, const Trajectory& trajectory);

// The accuracy rows of summary.csv for one run (metrics pose_err_m, joint_angle_err_deg):
//   at_0.267s, at_0.5s, at_1s   the error at that sample (0.25 s is not a multiple of 1/30 s, so
//                               the sample nearest to it after it stands in)
//   mean_1s                     the mean over the samples of the first second, t = 0 excluded
//   reseeded_mean               the re-seeded mean: the headline figure
//   reseeded_max                the worst seed
// and reseeded_diverged/count, the number of re-seeded runs that diverged. A stat the run did not
// reach (it diverged, or is shorter) is left out. `reference` labels the rows ("truth" or
// "pairwise"); the simulator is used for the re-seeded runs.
std::vector<SummaryRow> accuracy_rows(Simulator& simulator, const Model& model,
                                      const Scenario& scenario, double dt, const Trajectory& run,
                                      const Trajectory& reference, const std::string& label);

}  // namespace puppet::compare
