// The environment's forces (environment.cpp), the same formulas in every solver: Archimedes'
// buoyancy for a submerged body, a submerged fraction linear in depth across the body's vertical
// extent, drag at the rate that decays velocity by exactly e^(−c·h), and a compliant pin as a
// zero-length spring.
#include "puppet/model/environment.h"

#include <gtest/gtest.h>

#include <cmath>

#include "puppet/model/model.h"
#include "puppet/model/rotation.h"

namespace puppet {
namespace {

// a vertical capsule (radius 0.1, half length 0.3: 0.8 m tip to tip), centre at z = 0
Model capsule() {
  return parse_model(R"({"name":"c","segments":[{"name":"s","mass":5,"position":[0,0,0],
          "shape":{"type":"capsule","radius":0.1,"half_length":0.3}}],"joints":[]})",
                     "c");
}

TEST(Environment, TheSubmergedFractionIsLinearInDepthAcrossTheBody) {
  const Model model = capsule();
  const Segment& segment = model.segments[0];
  BodyState body;
  Environment water;
  water.water = true;
  for (const double level : {-1.0, -0.4, -0.2, 0.0, 0.1, 0.4, 2.0}) {
    water.water_level = level;
    const double expected = std::clamp((level + 0.4) / 0.8, 0.0, 1.0);
    EXPECT_NEAR(submerged_fraction(segment, water, body), expected, 1e-15) << level;
  }
  // lying flat, the extent is its diameter: half submerged at the centre's level either way
  body.q = Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()));
  water.water_level = 0.05;
  EXPECT_NEAR(submerged_fraction(segment, water, body), 0.75, 1e-12);
  Environment dry;
  EXPECT_EQ(submerged_fraction(segment, dry, body), 0.0);
}

TEST(Environment, ASubmergedBodyFeelsArchimedes) {
  const Model model = capsule();
  const Segment& segment = model.segments[0];
  BodyState body;
  Environment water;
  water.water = true;
  water.water_level = 5.0;
  const EnvironmentForce f = environment_force(segment, water, body, 1.0 / 240.0);
  const double volume = segment_volume(segment);
  EXPECT_NEAR(volume, M_PI * 0.01 * 0.6 + 4.0 / 3.0 * M_PI * 0.001, 1e-15);
  const Vector3d expected =
      segment.mass * water.gravity - water.water_density * volume * water.gravity;
  EXPECT_LT((f.force - expected).norm(), 1e-12 * expected.norm());
  // half out: half the buoyancy
  water.water_level = 0.0;
  const EnvironmentForce half = environment_force(segment, water, body, 1.0 / 240.0);
  EXPECT_NEAR(half.force.z() - segment.mass * water.gravity.z(),
              -0.5 * water.water_density * volume * water.gravity.z(), 1e-9);
}

TEST(Environment, DragIsTheRateThatDecaysByTheExponential) {
  const Model model = capsule();
  const Segment& segment = model.segments[0];
  BodyState body;
  body.v = Vector3d(1.0, -2.0, 0.5);
  body.w = Vector3d(0.3, 0.2, -4.0);
  Environment air;
  air.gravity = Vector3d::Zero();
  air.air_drag = 3.0;
  air.water = true;
  air.water_drag = 5.0;
  air.water_level = 0.0;  // half submerged: c = 3 + 5/2
  for (const double h : {1e-4, 1.0 / 240.0, 0.1, 10.0}) {
    const double c = 3.0 + 2.5;
    const double rate = step_drag_rate(c, h);
    EXPECT_NEAR(1.0 - h * rate, std::exp(-c * h), 1e-15) << h;
    EXPECT_LE(rate, 1.0 / h);
    const EnvironmentForce f = environment_force(segment, air, body, h);
    EXPECT_NEAR(f.drag, rate, 1e-15 * rate);
    const Vector3d buoyancy = -0.5 * air.water_density * segment_volume(segment) * air.gravity;
    EXPECT_LT((f.force - buoyancy + rate * segment.mass * body.v).norm(), 1e-12) << h;
    const Wrench wrench = environment_wrench(segment, air, body, h);
    const Vector3d torque = -rate * (world_inertia(segment, body.q) * body.w);
    EXPECT_LT((wrench.torque - torque).norm(), 1e-12 * torque.norm()) << h;
  }
  EXPECT_EQ(step_drag_rate(0.0, 0.01), 0.0);
  EXPECT_NEAR(step_drag_rate(2.0, 1e-9), 2.0, 1e-8);
}

TEST(Environment, ACompliantPinIsAZeroLengthSpring) {
  const Model model = capsule();
  BodyState body;
  body.x = Vector3d(0.1, 0.2, 0.3);
  body.q = Quaterniond(Eigen::AngleAxisd(0.7, Vector3d(1, 1, 0).normalized()));
  Pin pin;
  pin.segment = 0;
  pin.local_point = Vector3d(0.0, 0.0, 0.4);
  pin.target = Vector3d(0.5, -0.1, 1.0);
  pin.compliance = 0.02;
  const Vector3d point = body.x + body.q * pin.local_point;
  const Wrench w = pin_spring_wrench(pin, body);
  const Vector3d force = (pin.target - point) / pin.compliance;
  EXPECT_LT((w.force - force).norm(), 1e-12 * force.norm());
  EXPECT_LT((w.torque - (point - body.x).cross(force)).norm(), 1e-12 * force.norm());
}

TEST(Environment, TheRestPoseIsTheModelAtRest) {
  const Model model = parse_model(
      R"({"name":"two","segments":[
        {"name":"a","mass":1,"position":[0,0,1],"orientation":[0.8,0.6,0,0],"shape":{"type":"sphere","radius":0.25}},
        {"name":"b","mass":1,"position":[0,0,0.5],"shape":{"type":"sphere","radius":0.25}}],
       "joints":[{"name":"j","parent":"a","child":"b","anchor":[0,0,0.75],"type":"ball","swing_deg":[30,30],"twist_deg":20}]})",
      "two");
  const std::vector<BodyState> rest = rest_pose(model);
  ASSERT_EQ(rest.size(), 2u);
  EXPECT_EQ(rest[1].x, Vector3d(0, 0, 0.5));
  EXPECT_LT(rest[0].q.angularDistance(Quaterniond(0.8, 0.6, 0, 0)), 1e-15);
  for (const BodyState& b : rest) {
    EXPECT_EQ(b.v, Vector3d::Zero());
    EXPECT_EQ(b.w, Vector3d::Zero());
  }
}

}  // namespace
}  // namespace puppet
