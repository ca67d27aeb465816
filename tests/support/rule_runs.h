// Runs that the tests of the position-based rules (xpbd, tree) share: a physical pendulum's
// period, the double pendulum against its Lagrangian integration, a compliant grab's static
// deflection, a Pinocchio scenario's worst joint gap, and a pinned drag's state hash.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "puppet/compare/metrics.h"
#include "puppet/compare/scenario.h"
#include "puppet/procedural/solver.h"
#include "support/pendulum.h"
#include "support/source_dir.h"
#include "support/state_hash.h"

namespace puppet::test {

inline const std::string kPinocchioPath = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";
// Pinocchio with its swing–twist limits (the main model before the box limits): the tests written
// for those limits, and the pinned hashes, which stay the ones recorded on it
inline const std::string kPinocchioSwingTwistPath =
    std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio-swing-twist.json";

// one rod swinging by `amplitude` about its top for 12 s: the measured period over the analytic
inline double pendulum_period_ratio(const procedural::Settings& settings, double amplitude,
                                    double dt) {
  const Model model = rods(1);
  procedural::Solver solver(model, settings, Environment{});
  solver.reset(rods_at({amplitude}));
  const Pin pins[] = {top_pin()};
  solver.set_pins(pins);
  PeriodMeter meter;
  for (int k = 0; k < std::lround(12.0 / dt); ++k) {
    solver.step(dt);
    meter.add((k + 1) * dt, dt, solver.state().bodies[0].w.x());
  }
  return meter.period() / analytic_period(amplitude);
}

// mean distance of the two rods' centres to the Lagrangian double pendulum (RK4 at 1e-4 s) over
// 5 s from (0.3, −0.2) rad
inline double double_pendulum_error(const procedural::Settings& settings, double dt) {
  const Model model = rods(2);
  procedural::Solver solver(model, settings, Environment{});
  solver.reset(rods_at({0.3, -0.2}));
  const Pin pins[] = {top_pin()};
  solver.set_pins(pins);
  const DoublePendulum truth(model.segments[0].inertia.x());
  Eigen::Vector4d s(0.3, -0.2, 0, 0);
  const int rk4_steps = static_cast<int>(std::lround(dt / 1e-4));
  double sum = 0;
  const int steps = static_cast<int>(std::lround(5.0 / dt));
  for (int k = 0; k < steps; ++k) {
    solver.step(dt);
    for (int i = 0; i < rk4_steps; ++i) truth.advance(s, dt / rk4_steps);
    const auto expected = rods_at({s[0], s[1]});
    double sq = 0;
    for (int i = 0; i < 2; ++i) sq += (solver.state().bodies[i].x - expected[i].x).squaredNorm();
    sum += std::sqrt(sq / 2);
  }
  return sum / steps;
}

// two rods hanging still from a pin of compliance C at the top, air drag to settle the spring
// (20 s at 1/240): how far the pin point sags over the weight it holds times C
inline double static_deflection_ratio(const procedural::Settings& settings, double compliance) {
  const Model model = rods(2);
  Environment air;
  air.air_drag = 2.0;
  procedural::Solver solver(model, settings, air);
  solver.reset(rods_at({0.0, 0.0}));
  Pin pin = top_pin();
  pin.compliance = compliance;
  const Pin pins[] = {pin};
  solver.set_pins(pins);
  constexpr double kDt = 1.0 / 240.0;
  for (int k = 0; k < std::lround(20.0 / kDt); ++k) solver.step(kDt);
  const Vector3d point = solver.state().bodies[0].x + solver.state().bodies[0].q * pin.local_point;
  return -point.z() / (model.total_mass * 9.81 * compliance);
}

// the worst joint gap after any step of a scenario, and whether it diverged
struct ScenarioRun {
  double worst_gap = 0;
  bool diverged = false;
};
inline ScenarioRun run_scenario(const Model& model, const compare::Scenario& scenario,
                                procedural::Settings settings, double dt) {
  procedural::Solver solver(model, settings, scenario.environment);
  solver.reset(scenario.initial);
  solver.set_pins(scenario.initial_pins());
  std::vector<Vector3d> targets;
  std::vector<double> gaps(model.joint_count());
  ScenarioRun run;
  for (int k = 0; k < std::lround(scenario.duration / dt); ++k) {
    scenario.targets_at((k + 1) * dt, targets);
    solver.set_pin_targets(targets);
    solver.step(dt);
    compare::joint_gaps(model, solver.state().bodies, gaps);
    run.worst_gap = std::max(run.worst_gap, *std::max_element(gaps.begin(), gaps.end()));
  }
  run.diverged = solver.state().diverged;
  return run;
}

// a scenario whose grabbed hand is held by a hard pin on the same path instead (shake's hand as
// marionette's is)
inline compare::Scenario with_hard_hand(compare::Scenario scenario) {
  for (compare::PinPath& path : scenario.pins) path.pin.grab = {};
  return scenario;
}

// Pinocchio's (swing–twist) state after 1000 steps of `marionette` (the hand on a hard pin: the
// hashes were pinned when drag was that scenario) at 1/240, hashed
inline uint64_t drag_hash(const procedural::Settings& settings) {
  const Model model = load_model(kPinocchioSwingTwistPath);
  const compare::Scenario scenario = compare::make_scenario("marionette", model);
  procedural::Solver solver(model, settings, scenario.environment);
  solver.reset(scenario.initial);
  solver.set_pins(scenario.initial_pins());
  std::vector<Vector3d> targets;
  constexpr double kDt = 1.0 / 240.0;
  for (int k = 0; k < 1000; ++k) {
    scenario.targets_at((k + 1) * kDt, targets);
    solver.set_pin_targets(targets);
    solver.step(kDt);
  }
  return state_hash(solver.state().bodies);
}

}  // namespace puppet::test
