// Air and water drag decay a velocity by exactly e^(−c·h) per step in every solver
// (step_drag_rate), so that no drag rate can make a step unstable: checked against the analytic
// decay, and at c = 1e9 (c·h = 1.7e7 at 1/60 s), where the explicit factor 1 − c·h would have
// multiplied every velocity by −1.7e7 per step.
#include <gtest/gtest.h>

#include <cmath>

#include "puppet/compare/engines.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/environment.h"

namespace puppet::compare {
namespace {

// one sphere, weightless, moving and spinning freely
Model ball() {
  return parse_model(R"({"name": "ball", "segments": [{"name": "ball", "mass": 2,
      "position": [0, 0, 1], "shape": {"type": "sphere", "radius": 0.1}}]})",
                     "ball.json");
}

Scenario drifting(const Model& model, double air_drag) {
  Scenario scenario = make_scenario("spin", model);
  scenario.environment.gravity = Vector3d::Zero();
  scenario.environment.air_drag = air_drag;
  scenario.pins.clear();
  scenario.initial = rest_pose(model);
  scenario.initial[0].v = {1.0, -0.5, 0.25};
  scenario.initial[0].w = {0.0, 0.0, 3.0};
  return scenario;
}

TEST(Drag, DecaysExactlyForAnyRate) {
  const Model model = ball();
  constexpr double kDt = 1.0 / 60.0;
  constexpr int kSteps = 60;
  for (const std::string& solver : solver_names()) {
    for (const double c : {0.5, 50.0, 1e9}) {
      SCOPED_TRACE(solver + " c = " + std::to_string(c));
      const Scenario scenario = drifting(model, c);
      auto simulator = make_simulator(solver, SolverOptions{});
      simulator->reset(model, scenario);
      std::vector<BodyState> state(1);
      for (int k = 0; k < kSteps; ++k) simulator->step(kDt);
      simulator->read_state(state);
      ASSERT_FALSE(simulator->diverged());
      ASSERT_TRUE(all_finite(state));
      // e^(−c·t) after t = 1 s; the references integrate the same per-step force
      const double decay = std::exp(-c * kDt * kSteps);
      const Vector3d v = decay * scenario.initial[0].v, w = decay * scenario.initial[0].w;
      // in single precision (jolt) each step's decay rounds once: kSteps float epsilons at most
      const double relative = find_engine(solver)->single_precision ? kSteps * 1.2e-7 : 1e-9;
      EXPECT_NEAR((state[0].v - v).norm(), 0.0, 1e-9 + relative * v.norm());
      EXPECT_NEAR((state[0].w - w).norm(), 0.0, 1e-9 + relative * w.norm());
      // and the ball went as far as ∫v dt of the discrete decay, bounded by the undamped path
      EXPECT_LT((state[0].x - scenario.initial[0].x).norm(),
                scenario.initial[0].v.norm() * kDt * kSteps);
    }
  }
}

}  // namespace
}  // namespace puppet::compare
