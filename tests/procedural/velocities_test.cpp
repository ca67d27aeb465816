// Stage 4, velocities (velocities.cpp): v and ω from the corrected poses, against the motion
// that produced them.
#include <gtest/gtest.h>

#include <cmath>

#include "puppet/model/rotation.h"
#include "stages.h"
#include "support/pendulum.h"

namespace puppet::procedural {
namespace {

TEST(Velocities, AreTheExactMotionBetweenThePoses) {
  // a turn of 2.5 rad in one step (past π/2, where the small-angle form 2 vec(Δq)/h is 40 % off)
  const Model model = test::rods(1);
  const double h = 0.01;
  const Vector3d axis = Vector3d(1, 2, -2).normalized();
  State state;
  state.bodies.resize(1);
  state.x_prev = {Vector3d(0.1, 0.2, 0.3)};
  state.q_prev = {Quaterniond(Eigen::AngleAxisd(0.3, Vector3d::UnitZ()))};
  state.bodies[0].x = state.x_prev[0] + Vector3d(0.01, -0.02, 0.005);
  state.bodies[0].q = Quaterniond(Eigen::AngleAxisd(2.5, axis)) * state.q_prev[0];
  const std::vector<Vector3d> no_tremble = {Vector3d::Zero()};
  derive_velocities(model, state, no_tremble, h);
  EXPECT_LT((state.bodies[0].v - Vector3d(1.0, -2.0, 0.5)).norm(), 1e-12);
  EXPECT_LT((state.bodies[0].w - (2.5 / h) * axis).norm(), 1e-10);
}

TEST(Velocities, TakeTheTrembleOffsetOut) {
  // the tremble displaces positions only: it must not become momentum
  const Model model = test::rods(1);
  State state;
  state.bodies.resize(1);
  state.x_prev = {Vector3d::Zero()};
  state.q_prev = {Quaterniond::Identity()};
  state.bodies[0].x = Vector3d(0.002, 0.0, 0.0);
  const std::vector<Vector3d> tremble = {Vector3d(0.002, 0.0, 0.0)};
  derive_velocities(model, state, tremble, 1.0 / 240);
  EXPECT_EQ(state.bodies[0].v, Vector3d::Zero());
}

}  // namespace
}  // namespace puppet::procedural
