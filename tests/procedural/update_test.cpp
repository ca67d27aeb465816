// Stage 1, update (update.cpp): each segment alone under its forces, checked against the closed
// forms of the scheme it states: semi-implicit Euler's free fall step for step, drag that decays
// v and ω by exactly e^(−c·h) at any rate, the exact exponential map for a steady spin, an
// implicit gyroscopic term that never gains energy, and the seed's ground spring.
#include <gtest/gtest.h>

#include <cmath>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

// one free box (1 × 0.6 × 0.2 m half extents: three different moments), centre 2 m up
Model box(double mass = 3.0) {
  return parse_model(R"({"name":"box","segments":[{"name":"b","mass":)" + std::to_string(mass) +
                         R"(,"position":[0,0,2],
          "shape":{"type":"box","half_extents":[1.0,0.6,0.2]}}],"joints":[]})",
                     "box");
}

State state_of(const Model& model) {
  State state;
  state.bodies = rest_pose(model);
  const size_t n = model.segments.size();
  state.x_prev.resize(n);
  state.q_prev.resize(n);
  state.user_force.assign(n, Vector3d::Zero());
  state.user_torque.assign(n, Vector3d::Zero());
  return state;
}

// no grab and no tremble: the update's user forces are zero
std::span<const Wrench> no_user_forces(const Model& model) {
  static std::vector<Wrench> zeros;
  zeros.assign(model.segment_count(), Wrench{});
  return zeros;
}

TEST(Update, FreeFallIsSemiImplicitEulerStepForStep) {
  // v_n = v_0 + n h g, x_n = x_0 + n h v_0 + h² g n(n+1)/2: the scheme's own closed form
  const Model model = box();
  State state = state_of(model);
  Environment environment;
  const Vector3d v0(0.3, -0.2, 1.5);
  state.bodies[0].v = v0;
  const Vector3d x0 = state.bodies[0].x;
  const double h = 1.0 / 240.0;
  for (int n = 1; n <= 480; ++n) {
    update(model, environment, no_user_forces(model), state, h);
    const Vector3d v = v0 + n * h * environment.gravity;
    const Vector3d x = x0 + n * h * v0 + h * h * environment.gravity * (n * (n + 1) / 2.0);
    ASSERT_LT((state.bodies[0].v - v).norm(), 1e-12) << n;
    ASSERT_LT((state.bodies[0].x - x).norm(), 1e-12) << n;
  }
  EXPECT_EQ(state.x_prev[0], state.bodies[0].x - h * state.bodies[0].v);
}

TEST(Update, DragDecaysByExactlyItsExponentialAtAnyRate) {
  const Model model = box();
  for (const double c : {0.5, 40.0, 1e4}) {  // c·h from 0.002 to 42
    State state = state_of(model);
    Environment environment;
    environment.gravity = Vector3d::Zero();
    environment.air_drag = c;
    const Vector3d v0(2.0, -1.0, 0.5), w0(0.0, 0.0, 3.0);
    state.bodies[0].v = v0;
    state.bodies[0].w = w0;  // about a principal axis: no gyroscopic coupling
    const double h = 1.0 / 240.0;
    for (int n = 1; n <= 240; ++n) {
      update(model, environment, no_user_forces(model), state, h);
      const double decay = std::exp(-c * n * h);
      ASSERT_LT((state.bodies[0].v - decay * v0).norm(), 1e-12 * v0.norm()) << c << " " << n;
      ASSERT_LT((state.bodies[0].w - decay * w0).norm(), 1e-12 * w0.norm()) << c << " " << n;
    }
  }
}

TEST(Update, ASteadySpinTurnsByExactlyOmegaT) {
  // about a principal axis nothing couples: q(t) = exp(t ω) q(0), by the exact exponential map
  const Model model = box();
  State state = state_of(model);
  Environment environment;
  environment.gravity = Vector3d::Zero();
  const Vector3d w(0.0, 2.5, 0.0);
  state.bodies[0].w = w;
  const double h = 1.0 / 60.0;
  for (int n = 1; n <= 600; ++n) {
    update(model, environment, no_user_forces(model), state, h);
    const Quaterniond expected = quat_exp(n * h * w);
    ASSERT_LT(state.bodies[0].q.angularDistance(expected), 1e-12) << n;
  }
}

TEST(Update, TheImplicitGyroscopicTermNeverGainsEnergy) {
  // torque-free, near the unstable intermediate axis, where explicit Euler gains energy: the
  // implicit step may lose a little, never gain, and keeps |L| close
  const Model model = box();
  const Segment& segment = model.segments[0];
  State state = state_of(model);
  Environment environment;
  environment.gravity = Vector3d::Zero();
  state.bodies[0].w = Vector3d(0.05, 4.0, 0.05);
  const auto energy = [&] {
    const Vector3d w_body = state.bodies[0].q.conjugate() * state.bodies[0].w;
    return 0.5 * w_body.dot(segment.inertia.cwiseProduct(w_body));
  };
  const auto momentum = [&] {
    return (world_inertia(segment, state.bodies[0].q) * state.bodies[0].w).norm();
  };
  const double e0 = energy(), l0 = momentum();
  double previous = e0;
  for (int n = 0; n < 2400; ++n) {
    update(model, environment, no_user_forces(model), state, 1.0 / 240.0);
    const double e = energy();
    ASSERT_LE(e, previous * (1 + 1e-12)) << n;
    previous = e;
  }
  EXPECT_GT(previous, 0.9 * e0);
  EXPECT_NEAR(momentum() / l0, 1.0, 0.05);
}

TEST(Update, UserForcesAndTorquesAreImpulsesOverTheStep) {
  const Model model = box(2.0);
  const Segment& segment = model.segments[0];
  State state = state_of(model);
  Environment environment;
  environment.gravity = Vector3d::Zero();
  state.user_force[0] = Vector3d(4.0, 0.0, -2.0);
  state.user_torque[0] = Vector3d(0.0, 0.0, 0.6);
  const double h = 0.01;
  update(model, environment, no_user_forces(model), state, h);
  EXPECT_LT((state.bodies[0].v - h * state.user_force[0] / segment.mass).norm(), 1e-15);
  // from rest the gyroscopic term is zero: Δω = h I⁻¹ τ
  EXPECT_LT((state.bodies[0].w - Vector3d(0, 0, h * 0.6 / segment.inertia.z())).norm(), 1e-14);
}

TEST(Update, TheSeedsGroundSpringPushesTheDeepestPointUp) {
  // a spring of (2π·5 Hz)² per unit mass on the depth of the lowest point below z = 0
  const Model model = box();
  State state = state_of(model);
  Environment environment;
  environment.ground = true;
  const double depth = 0.01;
  state.bodies[0].x.z() = 0.2 - depth;  // half height 0.2 m
  const double h = 1.0 / 240.0;
  update(model, environment, no_user_forces(model), state, h);
  const double stiffness = std::pow(2 * M_PI * 5.0, 2);
  EXPECT_NEAR(state.bodies[0].v.z(), h * (environment.gravity.z() + stiffness * depth),
              1e-3 * h * stiffness * depth);
  // and nothing above the ground
  State above = state_of(model);
  update(model, environment, no_user_forces(model), above, h);
  EXPECT_NEAR(above.bodies[0].v.z(), h * environment.gravity.z(), 1e-15);
}

}  // namespace
}  // namespace puppet::procedural
