// Runs that every reference (Bullet's and MuJoCo's, all behind reference::Solver) is put
// through, on the rods of pendulum.h, so that each is held to the same independent answer.
#pragma once

#include <cmath>
#include <vector>

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

}  // namespace puppet::test
