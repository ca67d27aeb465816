// A free box spinning near its major axis without gravity for 10 s: no joint, no force, so its
// angular momentum is conserved exactly. Shared by the tests of every procedural rule.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "puppet/model/rotation.h"
#include "puppet/procedural/solver.h"

namespace puppet::test {

struct SpinResult {
  Vector3d end_velocity{0, 0, 0};
  double momentum_ratio = 0.0;   // |L(10 s)| / |L(0)|
  double direction_drift = 0.0;  // rad between L(10 s) and L(0)
};

inline SpinResult spin_box(const procedural::Settings& settings, double dt) {
  const Model model = parse_model(
      R"({"name":"box","segments":[{"name":"b","mass":3,"position":[0,0,0],"shape":{"type":"box","half_extents":[0.3,0.2,0.1]}}]})",
      "box");
  Environment space;
  space.gravity.setZero();
  procedural::Solver solver(model, settings, space);
  std::vector<BodyState> body(1);
  body[0].w = Vector3d(0.2, 0.1, 5.0);  // near the major axis (z: the largest inertia)
  solver.reset(body);
  const Vector3d l0 = world_inertia(model.segments[0], body[0].q) * body[0].w;
  for (int k = 0; k < std::lround(10.0 / dt); ++k) solver.step(dt);
  const BodyState& end = solver.state().bodies[0];
  const Vector3d l = world_inertia(model.segments[0], end.q) * end.w;
  return {end.v, l.norm() / l0.norm(),
          std::acos(std::min(1.0, l.normalized().dot(l0.normalized())))};
}

}  // namespace puppet::test
