// Stage 3, contacts (contacts.cpp): the ground as a position constraint, and each rule's policy.
#include <gtest/gtest.h>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/procedural/solver.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

constexpr double kDt = 1.0 / 240.0;

Model box() {
  return parse_model(
      R"({"name":"box","segments":[{"name":"box","mass":2,"position":[0,0,1],
          "shape":{"type":"box","half_extents":[0.2,0.1,0.05]}}]})",
      "box");
}

double lowest_corner(const BodyState& body) {
  double low = 1e9;
  for (int c = 0; c < 8; ++c) {
    const Vector3d corner((c & 1 ? 0.2 : -0.2), (c & 2 ? 0.1 : -0.1), (c & 4 ? 0.05 : -0.05));
    low = std::min(low, (body.x + body.q * corner).z());
  }
  return low;
}

TEST(Contacts, ADroppedBoxComesToRestOnTheGroundInEveryRule) {
  // dropped tilted from 0.5 m: no restitution, Coulomb friction; it ends resting on a face
  // (centre at its half height, 0.05 m). The push-out is two Gauss–Seidel passes over the
  // corners, not an exact projection: each step's gravity sinks a resting box by g h² = 0.17 mm,
  // of which about 1 µm is left; at the landing at most 0.1 mm (measured 0.08 mm for the
  // one-sided rules, 0.06 µm for xpbd and tree)
  const Model model = box();
  Environment environment;
  environment.ground = true;
  for (Rule rule : kAllRules) {
    SCOPED_TRACE(std::string(rule_name(rule)));
    Solver solver(model, Settings{.rule = rule}, environment);
    std::vector<BodyState> start = rest_pose(model);
    start[0].x = Vector3d(0, 0, 0.5);
    start[0].q = Quaterniond(Eigen::AngleAxisd(0.3, Vector3d(1, 1, 0).normalized()));
    solver.reset(start);
    double deepest = 0.0;
    for (int k = 0; k < 240 * 4; ++k) {
      solver.step(kDt);
      deepest = std::min(deepest, lowest_corner(solver.state().bodies[0]));
    }
    const BodyState& body = solver.state().bodies[0];
    EXPECT_FALSE(solver.state().diverged);
    EXPECT_GT(deepest, -1e-4);
    EXPECT_NEAR(body.x.z(), 0.05, 1e-5);
    EXPECT_LT(body.v.norm(), 1e-3);
    EXPECT_LT(body.w.norm(), 1e-2);
  }
}

TEST(Contacts, EachRuleHasItsPolicy) {
  EXPECT_EQ(contact_policy(Rule::kXpbd), ContactPolicy::kInAdjust);
  EXPECT_EQ(contact_policy(Rule::kTree), ContactPolicy::kInAdjust);
  EXPECT_EQ(contact_policy(Rule::kRelaxed), ContactPolicy::kPushOut);
  for (Rule rule : {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted, Rule::kSubtree}) {
    EXPECT_EQ(contact_policy(rule), ContactPolicy::kPushOutAndRepass);
    EXPECT_FALSE(needs_ground_velocity_pass(rule));
  }
  EXPECT_TRUE(needs_ground_velocity_pass(Rule::kXpbd));
  EXPECT_TRUE(needs_ground_velocity_pass(Rule::kTree));
}

TEST(Contacts, ResolveReturnsTheDeepestSegment) {
  const Model model = box();
  Environment environment;
  environment.ground = true;
  State state;
  state.bodies = rest_pose(model);
  state.bodies[0].x = Vector3d(0, 0, 0.01);  // 4 cm below the plane
  state.x_prev = {state.bodies[0].x};
  state.q_prev = {state.bodies[0].q};
  EXPECT_EQ(resolve_contacts(model, environment, state), 0);
  // four corners 4 cm deep, each moved in turn (which turns the box a little): two passes leave
  // 34 µm, a thousandth of the depth
  EXPECT_LT(std::abs(lowest_corner(state.bodies[0])), 4e-5);
  state.bodies[0].x = Vector3d(0, 0, 1.0);
  EXPECT_EQ(resolve_contacts(model, environment, state), -1);
}

}  // namespace
}  // namespace puppet::procedural
