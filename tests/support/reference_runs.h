// Runs and checks that every reference (Bullet's, MuJoCo's and ODE's behind reference::Solver,
// Jolt's behind a Simulator) is put through, on the rods of pendulum.h and on the model it was
// built from, so that each is held to the same independent answer.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <thread>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/rotation.h"
#include "puppet/reference/bullet.h"
#include "support/pendulum.h"

namespace puppet::test {

// one rod (rods(1)) released at 10° from its pinned top, 12 s at dt: its measured period
inline double released_rod_period(reference::Solver& solver, double dt) {
  solver.set_state(rods_at({10.0 * M_PI / 180.0}));
  const Pin pins[] = {top_pin()};
  solver.set_pins(pins);
  std::vector<BodyState> bodies(1);
  PeriodMeter meter;
  for (int k = 0; k < std::lround(12.0 / dt); ++k) {
    solver.step(dt);
    solver.read_state(bodies);
    meter.add((k + 1) * dt, dt, bodies[0].w.x());
  }
  return meter.period();
}

// two rods (rods(2), 2 kg, in air that settles them) hanging from a compliant pin for 20 s at
// dt: the pin point's sag over weight × C (1 at the static deflection)
inline double compliant_sag_ratio(reference::Solver& solver, double compliance, double dt) {
  solver.set_state(rods_at({0.0, 0.0}));
  Pin pin = top_pin();
  pin.compliance = compliance;
  const Pin pins[] = {pin};
  solver.set_pins(pins);
  for (int k = 0; k < std::lround(20.0 / dt); ++k) solver.step(dt);
  std::vector<BodyState> bodies(2);
  solver.read_state(bodies);
  const double sag = -(bodies[0].x + bodies[0].q * pin.local_point).z();
  return sag / (2.0 * 9.81 * compliance);
}

// the same bits in every pose and velocity
inline bool bitwise_equal(const std::vector<BodyState>& a, const std::vector<BodyState>& b) {
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].x != b[i].x || a[i].q.coeffs() != b[i].q.coeffs() || a[i].v != b[i].v ||
        a[i].w != b[i].w)
      return false;
  }
  return true;
}

// steps a simulator through steps [from, to) of the scenario at dt, its targets moved by `offset`,
// and returns the state it ends in
inline std::vector<BodyState> run_steps(compare::Simulator& simulator,
                                        const compare::Scenario& scenario, int from, int to,
                                        double dt, const Vector3d& offset = Vector3d::Zero()) {
  std::vector<Vector3d> targets;
  for (int k = from; k < to; ++k) {
    scenario.targets_at((k + 1) * dt, targets);
    for (Vector3d& t : targets) t += offset;
    simulator.set_pin_targets(targets);
    simulator.step(dt);
  }
  std::vector<BodyState> bodies(scenario.initial.size());
  simulator.read_state(bodies);
  return bodies;
}

// The same inputs give the same bits: 200 steps at dt from `fresh()` (a simulator reset to the
// scenario) twice, the last 100 again from a snapshot restored at step 100, and a run beside
// another on a second thread. Returns the state after the 200 steps.
template <typename Fresh>
std::vector<BodyState> expect_runs_agree_bitwise(Fresh&& fresh, const compare::Scenario& scenario,
                                                 double dt) {
  auto a = fresh();
  run_steps(*a, scenario, 0, 100, dt);
  const auto snapshot = a->snapshot();
  const auto first = run_steps(*a, scenario, 100, 200, dt);
  auto b = fresh();
  EXPECT_TRUE(bitwise_equal(first, run_steps(*b, scenario, 0, 200, dt))) << "two runs";
  a->restore(*snapshot);
  EXPECT_TRUE(bitwise_equal(first, run_steps(*a, scenario, 100, 200, dt))) << "restored snapshot";
  std::vector<BodyState> beside;
  std::thread other([&] {
    auto c = fresh();
    beside = run_steps(*c, scenario, 0, 200, dt);
  });
  auto d = fresh();
  const auto here = run_steps(*d, scenario, 0, 200, dt);
  other.join();
  EXPECT_TRUE(bitwise_equal(first, here)) << "beside another";
  EXPECT_TRUE(bitwise_equal(first, beside)) << "on a second thread";
  return first;
}

// What the engine holds is what the model says, read back from its own objects: each segment's
// mass, inertia and rest pose, and each joint's anchor as both its segments carry it (to 1e-12)
inline void expect_holds_the_model(const reference::Solver& solver, const Model& model) {
  const std::vector<BodyState> rest = rest_pose(model);
  std::vector<BodyState> read(model.segment_count());
  solver.read_state(read);
  for (int s = 0; s < model.segment_count(); ++s) {
    const Segment& segment = model.segments[s];
    EXPECT_NEAR(solver.segment_mass(s), segment.mass, 1e-12 * segment.mass);
    EXPECT_LE((solver.segment_inertia(s) - segment.inertia).cwiseAbs().maxCoeff(),
              1e-12 * segment.inertia.maxCoeff());
    EXPECT_LE((read[s].x - rest[s].x).norm(), 1e-12) << segment.name;
    EXPECT_LE(angle_between(read[s].q, rest[s].q), 1e-12) << segment.name;
  }
  for (int j = 0; j < model.joint_count(); ++j) {
    Vector3d on_parent, on_child;
    solver.joint_anchors(j, &on_parent, &on_child);
    EXPECT_LE((on_parent - model.joints[j].anchor_world).norm(), 1e-12) << j;
    EXPECT_LE((on_child - model.joints[j].anchor_world).norm(), 1e-12) << j;
  }
}

}  // namespace puppet::test
