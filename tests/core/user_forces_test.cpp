// The user's forces (user_forces.cpp), the same formulas in every engine: a grab moves the point
// of a free segment as a damped oscillator of its frequency and ratio, its force never passes its
// cap, and the tremble is bounded, silent without a pull and a function of its inputs alone.
#include "puppet/model/user_forces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "puppet/model/model.h"

namespace puppet {
namespace {

// a tilted capsule, 1.5 kg, like a forearm
Model forearm() {
  return parse_model(R"({"name":"f","segments":[{"name":"f","mass":1.5,"position":[0,0,1],
          "shape":{"type":"capsule","radius":0.04,"half_length":0.1}}],"joints":[]})",
                     "f");
}

Pin grab_at(const Vector3d& local_point, const Vector3d& target, double cap) {
  Pin pin;
  pin.segment = 0;
  pin.local_point = local_point;
  pin.target = target;
  pin.grab = {.hz = 2.0, .damping_ratio = 1.0, .max_force = cap};
  return pin;
}

BodyState moving_body() {
  BodyState body;
  body.x = {0.1, -0.2, 1.0};
  body.q = Quaterniond(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()));
  body.v = {0.3, -0.1, 0.5};
  body.w = {1.0, -2.0, 0.5};
  return body;
}

// Under its cap, the force gives the point of the segment alone the acceleration of the law,
// ω²(t − p) − 2ζω ṗ: the force's own effect, Newton–Euler at the point (a = F/m + α × r with
// α = I⁻¹ (r × F), the gyroscopic and centripetal terms being the state's, not the force's)
TEST(UserForces, AGrabMovesTheFreePointAsItsOscillator) {
  const Model model = forearm();
  const Segment& segment = model.segments[0];
  const BodyState body = moving_body();
  const Vector3d tip(0.0, 0.0, -0.14);
  const Pin pin = grab_at(tip, Vector3d(0.2, 0.1, 0.8), 1e9);
  const Vector3d force = grab_force(pin, segment, body);
  const Vector3d arm = body.q * tip;
  const Vector3d alpha = world_inertia_inv(segment, body.q) * arm.cross(force);
  const Vector3d acceleration = force / segment.mass + alpha.cross(arm);
  const double omega = 2.0 * M_PI * 2.0;
  const Vector3d point = body.x + arm, point_velocity = body.v + body.w.cross(arm);
  const Vector3d law = omega * omega * (pin.target - point) - 2.0 * omega * point_velocity;
  EXPECT_LT((acceleration - law).norm(), 1e-12 * law.norm());
  // at the COM the effective mass is the mass
  const Pin at_com = grab_at(Vector3d::Zero(), pin.target, 1e9);
  const Vector3d central = grab_force(at_com, segment, body);
  const Vector3d central_law = omega * omega * (pin.target - body.x) - 2.0 * omega * body.v;
  EXPECT_LT((central - segment.mass * central_law).norm(), 1e-12 * central.norm());
}

TEST(UserForces, AGrabsForceNeverPassesItsCap) {
  const Model model = forearm();
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int capped = 0;
  for (int k = 0; k < 10000; ++k) {
    BodyState body = moving_body();
    body.x = 3.0 * Vector3d(u(random), u(random), u(random));
    body.v = 5.0 * Vector3d(u(random), u(random), u(random));
    body.w = 10.0 * Vector3d(u(random), u(random), u(random));
    const double cap = 20.0;
    const Pin pin = grab_at(Vector3d(0.0, 0.0, -0.14), Vector3d(u(random), u(random), 1), cap);
    const double length = grab_force(pin, model.segments[0], body).norm();
    ASSERT_LE(length, cap * (1.0 + 1e-15)) << k;
    if (length > cap * (1.0 - 1e-12)) ++capped;
  }
  EXPECT_GT(capped, 1000);  // the cap was reached, so the bound was tested
}

TEST(UserForces, TheTrembleIsBoundedSilentWithoutAPullAndItsInputsAlone) {
  const Model model = forearm();
  const double mass = model.segments[0].mass;
  const double bound = mass * std::pow(2.0 * M_PI * kTrembleHz, 2) * kTrembleAmplitude;
  BodyState body = moving_body();
  EXPECT_EQ(tremble_force(mass, 0, body, 0.7, 0.0, 2001), Vector3d::Zero());  // no pull
  body.v.setZero();
  EXPECT_EQ(tremble_force(mass, 0, body, 0.7, 1.0, 2001), Vector3d::Zero());  // γ = 0
  body = moving_body();
  double largest = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const double t = k / 240.0;
    const Vector3d f = tremble_force(mass, 0, body, t, 1.2, 2001);
    largest = std::max(largest, f.cwiseAbs().maxCoeff());
    EXPECT_EQ(f, tremble_force(mass, 0, body, t, 1.2, 2001));  // a function of its inputs
  }
  EXPECT_LE(largest, bound);
  EXPECT_GT(largest, 0.05 * bound);  // it trembles
  EXPECT_NE(tremble_force(mass, 0, body, 0.3, 1.2, 2001),
            tremble_force(mass, 0, body, 0.3, 1.2, 7));
}

// user_wrenches: a grab's force at its point is a wrench at the COM with the torque r × F, and a
// pin that is not a grab adds nothing
TEST(UserForces, WrenchesCarryTheGrabsTorqueAndSkipPins) {
  const Model model = forearm();
  const std::vector<BodyState> bodies = {moving_body()};
  Pin grab = grab_at(Vector3d(0.0, 0.0, -0.14), Vector3d(0.2, 0.1, 0.8), 1e9);
  Pin hard;
  hard.segment = 0;
  hard.target = {5, 5, 5};
  const std::vector<Pin> pins = {hard, grab};
  std::vector<Wrench> out(1);
  Environment still;
  const double pull = user_wrenches(model, still, pins, bodies, 0.0, out);
  const Vector3d force = grab_force(grab, model.segments[0], bodies[0]);
  EXPECT_EQ(out[0].force, force);
  EXPECT_EQ(out[0].torque, (bodies[0].q * grab.local_point).cross(force));
  EXPECT_DOUBLE_EQ(pull, force.norm() / (1.5 * kStandardGravity));
}

}  // namespace
}  // namespace puppet
