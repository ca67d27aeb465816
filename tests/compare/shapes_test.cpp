// Every shape on the ground in every solver: a cylinder, the one shape whose contact is an edge
// or a face, comes to rest standing on its face (its centre half its height up) and lying on
// its side (its radius up). Tolerance 1 mm, for each solver's contact softness (measured: all
// within 2e-5 m; MuJoCo's soft contacts and Bullet's speculative ones sink least at rest).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"

namespace puppet::compare {
namespace {

Model one_cylinder() {
  return parse_model(R"({"name": "can", "segments": [{"name": "can", "mass": 2.0,
      "position": [0, 0, 1], "shape": {"type": "cylinder", "radius": 0.06, "half_length": 0.1}}]})",
                     "can");
}

// the cylinder 5 cm above the ground, axis up or along x, after 2 s at 1/240 s
BodyState settled(const std::string& solver, const Model& model, bool lying) {
  Scenario s = make_scenario("drop", model);
  const double r = model.segments[0].shapes[0].radius, h = model.segments[0].shapes[0].half_length;
  s.initial[0] = BodyState{};
  s.initial[0].q = lying ? Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 2, Vector3d::UnitY()))
                         : Quaterniond::Identity();
  s.initial[0].x = Vector3d(0, 0, (lying ? r : h) + 0.05);
  auto simulator = make_simulator(solver, {});
  simulator->reset(model, s);
  for (int k = 0; k < 480; ++k) simulator->step(1.0 / 240.0);
  EXPECT_FALSE(simulator->diverged()) << solver;
  std::vector<BodyState> out(1);
  simulator->read_state(out);
  return out[0];
}

TEST(Shapes, ACylinderRestsOnItsFaceAndOnItsSideInEverySolver) {
  const Model can = one_cylinder();
  const double r = 0.06, h = 0.1;
  for (const std::string& solver : solver_names()) {
    SCOPED_TRACE(solver);
    const BodyState standing = settled(solver, can, false);
    const BodyState lying = settled(solver, can, true);
    std::printf("[ shapes ] %s: standing %.5f m (h %.3f), lying %.5f m (r %.3f)\n", solver.c_str(),
                standing.x.z(), h, lying.x.z(), r);
    EXPECT_NEAR(standing.x.z(), h, 1e-3);
    EXPECT_NEAR(lying.x.z(), r, 1e-3);
    // still standing, still lying: the axis stayed where it was
    EXPECT_GT(std::abs((standing.q * Vector3d::UnitZ()).z()), 0.999);
    EXPECT_LT(std::abs((lying.q * Vector3d::UnitZ()).z()), 0.01);
    EXPECT_LT(standing.v.norm() + lying.v.norm(), 0.01);
  }
}

}  // namespace
}  // namespace puppet::compare
