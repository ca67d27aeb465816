// Water (update.cpp with the environment's buoyancy and drag): a floating cube against
// Archimedes and the analytic heave oscillation.
#include <gtest/gtest.h>

#include <cmath>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/procedural/solver.h"

namespace puppet::procedural {
namespace {

constexpr double kHalf = 0.1;  // the cube's half side (m)
constexpr double kDt = 1.0 / 240.0;

// a 0.2 m cube of half the water's density, its faces axis-aligned
Model cube() {
  const double mass = 0.5 * 1000.0 * std::pow(2 * kHalf, 3);
  return parse_model(
      R"({"name":"cube","segments":[{"name":"cube","mass":)" + std::to_string(mass) +
          R"(,"position":[0,0,0],"shape":{"type":"box","half_extents":[0.1,0.1,0.1]}}]})",
      "cube");
}

Environment water(double drag) {
  Environment environment;
  environment.water = true;
  environment.water_level = 0.0;
  environment.water_drag = drag;
  return environment;
}

TEST(Water, AHalfDensityCubeFloatsHalfSubmerged) {
  // Archimedes: it floats where it displaces its own mass, half its volume: centre at the surface
  const Model model = cube();
  for (Rule rule : kAllRules) {
    SCOPED_TRACE(std::string(rule_name(rule)));
    Settings settings;
    settings.rule = rule;
    Solver solver(model, settings, water(10.0));
    std::vector<BodyState> start = rest_pose(model);
    start[0].x.z() = 0.06;
    solver.reset(start);
    for (int k = 0; k < 240 * 20; ++k) solver.step(kDt);
    EXPECT_NEAR(solver.state().bodies[0].x.z(), 0.0, 1e-6);
    EXPECT_NEAR(solver.state().bodies[0].v.norm(), 0.0, 1e-6);
  }
}

TEST(Water, HeaveOscillatesAtTheBuoyancySpringsFrequency) {
  // between the faces the buoyancy is linear in depth, ρ g a² z: ω² = ρ g a² / m = 2 g / a for
  // a cube of side a and half the water's density. Without drag the solver keeps that period
  // (semi-implicit Euler: within (ω dt)²/24 ≈ 1.2e-5 of it; 1e-3 allows for the zero-crossing
  // interpolation over 10 periods)
  const Model model = cube();
  Solver solver(model, Settings{.rule = Rule::kWeighted}, water(0.0));
  std::vector<BodyState> start = rest_pose(model);
  start[0].x.z() = 0.05;  // inside the linear range |z| < a/2
  solver.reset(start);
  const double omega = std::sqrt(2.0 * 9.81 / (2 * kHalf));
  std::vector<double> upward_crossings;
  double previous = start[0].x.z();
  for (int k = 1; k <= 240 * 8; ++k) {
    solver.step(kDt);
    const double z = solver.state().bodies[0].x.z();
    if (previous < 0.0 && z >= 0.0) {
      upward_crossings.push_back((k - 1 + previous / (previous - z)) * kDt);
    }
    previous = z;
    ASSERT_LT(std::abs(z), kHalf);
  }
  ASSERT_GE(upward_crossings.size(), 5u);
  const double period = (upward_crossings.back() - upward_crossings.front()) /
                        static_cast<double>(upward_crossings.size() - 1);
  EXPECT_NEAR(period, 2 * M_PI / omega, 1e-3 * period);
}

}  // namespace
}  // namespace puppet::procedural
