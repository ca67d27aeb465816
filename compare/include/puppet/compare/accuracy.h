// How wrong a solver is: its states against a truth trajectory at the same times, along a whole
// run and re-seeded from the truth (Erez, Tassa & Todorov 2015; shared/DESIGN.md, "Metrics").
#pragma once

#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"

namespace puppet::compare {

// errors are taken at multiples of this: every dt of the sweeps divides it
constexpr double kAccuracySampleInterval = 1.0 / 30.0;

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
struct ReseededError {
  std::vector<double> seed_times;
  std::vector<double> pose_m, joint_angle_deg;           // per seed; NaN when that run diverged
  double mean_pose_m = 0.0, mean_joint_angle_deg = 0.0;  // over the seeds that did not
};
ReseededError reseeded_error(Simulator& simulator, const Model& model, const Scenario& scenario,
                             const Trajectory& truth, double dt, int seeds = 8,
                             double horizon = 0.5);

}  // namespace puppet::compare
