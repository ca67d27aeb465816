// Two-sided corrections (two_sided.cpp), the bricks of relaxed's and xpbd's sweeps: a joint's
// correction is an equal and opposite impulse pair (the pair's centre of mass does not move, its
// angular momentum changes only by gap × impulse), it closes the gap to second order, and a
// compliant one leaves the spring's share α̃ (K + α̃E)⁻¹ of the gap; a limit's is an equal and
// opposite angular impulse that brings the joint back inside to second order.
#include <gtest/gtest.h>

#include <random>

#include "model_tables.h"
#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/model/rotation.h"
#include "puppet/procedural/solver.h"
#include "stages.h"
#include "support/random.h"

namespace puppet::procedural {
namespace {

using test::random_rotation;
using test::random_vector;

// a base and an arm on a ball joint (swing 40° × 20°, twist 30°)
Model pair() {
  return parse_model(
      R"({"name":"pair","segments":[
        {"name":"base","mass":2,"position":[0,0,1],"shape":{"type":"box","half_extents":[0.1,0.15,0.1]}},
        {"name":"arm","mass":0.7,"position":[0,0,0.7],"shape":{"type":"capsule","radius":0.03,"half_length":0.15}}],
       "joints":[{"name":"j","parent":"base","child":"arm","anchor":[0,0,0.9],
                  "type":"ball","swing_deg":[40,20],"twist_deg":30}]})",
      "pair");
}

// the world rotation vector that turned `before` into `after`
Vector3d turn(const BodyState& before, const BodyState& after) {
  return quat_log(after.q * before.q.conjugate());
}

struct Pair {
  Model model = pair();
  std::shared_ptr<const ModelTables> tables = make_model_tables(model);
  State state;

  // both bodies turned at random, the arm's joint point `gap` m off the base's
  explicit Pair(std::mt19937_64& rng, double gap) {
    state.bodies = rest_pose(model);
    const Joint& joint = model.joints[0];
    BodyState& base = state.bodies[joint.parent];
    BodyState& arm = state.bodies[joint.child];
    base.q = random_rotation(rng);
    arm.q = random_rotation(rng);
    const Vector3d c_p = world_point(base, joint.anchor_in_parent);
    arm.x = c_p + gap * random_vector(rng, 1.0).normalized() - arm.q * joint.anchor_in_child;
  }
  const Joint& joint() const { return model.joints[0]; }
  Vector3d gap() const {
    return world_point(state.bodies[joint().parent], joint().anchor_in_parent) -
           world_point(state.bodies[joint().child], joint().anchor_in_child);
  }
};

TEST(TwoSided, AJointCorrectionIsAnEqualAndOppositeImpulsePair) {
  std::mt19937_64 rng(31);
  for (int trial = 0; trial < 500; ++trial) {
    Pair p(rng, 1e-3);
    const std::vector<BodyState> before = p.state.bodies;
    const Vector3d gap = p.gap();
    share_joint_correction(p.model, p.tables->joints[0], p.joint(), 0.0, nullptr, nullptr, p.state);
    const Segment& ms = p.model.segments[p.joint().parent];
    const Segment& cs = p.model.segments[p.joint().child];
    const BodyState& parent = p.state.bodies[p.joint().parent];
    const BodyState& child = p.state.bodies[p.joint().child];
    const Vector3d impulse = cs.mass * (child.x - before[p.joint().child].x);
    // the pair's centre of mass stays put
    EXPECT_LT((ms.mass * (parent.x - before[p.joint().parent].x) + impulse).norm(), 1e-15);
    // angular momentum about the origin: Σ I Δθ + x × m Δx = (c_c − c_p) × λ, the gap's arm
    const Vector3d angular =
        world_inertia(ms, before[p.joint().parent].q) * turn(before[p.joint().parent], parent) +
        world_inertia(cs, before[p.joint().child].q) * turn(before[p.joint().child], child) +
        before[p.joint().parent].x.cross(ms.mass * (parent.x - before[p.joint().parent].x)) +
        before[p.joint().child].x.cross(impulse);
    EXPECT_LT((angular + gap.cross(impulse)).norm(), 1e-6 * impulse.norm() * gap.norm() + 1e-18);
  }
}

TEST(TwoSided, ARigidCorrectionClosesTheGapToSecondOrder) {
  // Gauss–Seidel on a linearised constraint: the gap left is O(gap²); a tenth of the gap leaves
  // about a hundredth
  std::mt19937_64 rng(32);
  for (int trial = 0; trial < 200; ++trial) {
    const uint64_t seed = rng();
    double left[2];
    for (int k = 0; k < 2; ++k) {
      std::mt19937_64 same(seed);
      Pair p(same, k == 0 ? 1e-2 : 1e-3);
      share_joint_correction(p.model, p.tables->joints[0], p.joint(), 0.0, nullptr, nullptr,
                             p.state);
      left[k] = p.gap().norm();
    }
    EXPECT_LT(left[0], 1e-2 * 0.05);
    EXPECT_NEAR(left[1] / left[0], 0.01, 0.003);
  }
}

TEST(TwoSided, ACompliantPinLeavesTheSpringsShareOfTheGap) {
  // one compliant correction from λ = 0: the point moves by K (K + α̃E)⁻¹ g to first order, so
  // α̃ (K + α̃E)⁻¹ g of the gap g is left (K the segment's point mass matrix in world)
  std::mt19937_64 rng(33);
  for (int trial = 0; trial < 200; ++trial) {
    Pair p(rng, 0.0);
    Pin pin;
    pin.segment = p.joint().child;
    pin.local_point = Vector3d(0.01, -0.02, -0.15);
    const BodyState& arm = p.state.bodies[pin.segment];
    const Vector3d point = world_point(arm, pin.local_point);
    const Vector3d gap = 1e-4 * random_vector(rng, 1.0);
    const double alpha_tilde = std::pow(10.0, -2.0 + trial % 5);  // 0.01 … 100 (kg⁻¹)
    Vector3d lambda(0, 0, 0);
    const BodyState before = arm;
    share_pin_correction(p.model, pin, point + gap, alpha_tilde, &lambda, nullptr, p.state);

    const Segment& segment = p.model.segments[pin.segment];
    const Vector3d r = point - before.x;
    Matrix3d cross;
    cross << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    const Matrix3d k = Matrix3d::Identity() / segment.mass -
                       cross * world_inertia(segment, before.q).inverse() * cross;
    const Vector3d expected_left =
        alpha_tilde * (k + alpha_tilde * Matrix3d::Identity()).inverse() * gap;
    const Vector3d left = point + gap - world_point(p.state.bodies[pin.segment], pin.local_point);
    EXPECT_LT((left - expected_left).norm(), 1e-3 * gap.norm());
    // the multiplier is the impulse the segment took
    EXPECT_LT((lambda - segment.mass * (p.state.bodies[pin.segment].x - before.x)).norm(),
              1e-9 * lambda.norm());  // Δx read back from positions near 1 m
  }
}

TEST(TwoSided, ALimitCorrectionIsAnAngularImpulsePairThatBringsTheJointBack) {
  std::mt19937_64 rng(34);
  int outside = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Pair p(rng, 0.0);
    const Joint& joint = p.joint();
    const auto violation = [&] {
      return limit_violation(joint, joint_relative_rotation(joint, p.state.bodies[joint.parent].q,
                                                            p.state.bodies[joint.child].q));
    };
    const double before_violation = violation();
    const std::vector<BodyState> before = p.state.bodies;
    LimitRows rows;
    share_limit_correction(p.model, p.tables->joints[0], joint, 0.0, nullptr, &rows, false,
                           p.state);
    if (before_violation == 0.0) {
      EXPECT_EQ(p.state.bodies[joint.child].q.coeffs(), before[joint.child].q.coeffs());
      continue;
    }
    ++outside;
    const Segment& ps = p.model.segments[joint.parent];
    const Segment& cs = p.model.segments[joint.child];
    // no centre moves, and I_p Δθ_p + I_c Δθ_c = 0: an internal torque pair
    EXPECT_EQ(p.state.bodies[joint.parent].x, before[joint.parent].x);
    EXPECT_EQ(p.state.bodies[joint.child].x, before[joint.child].x);
    const Vector3d l_child = world_inertia(cs, before[joint.child].q) *
                             turn(before[joint.child], p.state.bodies[joint.child]);
    const Vector3d l_parent = world_inertia(ps, before[joint.parent].q) *
                              turn(before[joint.parent], p.state.bodies[joint.parent]);
    EXPECT_LT((l_child + l_parent).norm(), 1e-9 * l_child.norm());
    // a small violation is closed to second order; a large one at least halved
    const double after_violation = violation();
    if (before_violation < 0.05) {
      EXPECT_LT(after_violation, 0.5 * before_violation * before_violation + 1e-12);
    } else {
      EXPECT_LT(after_violation, 0.5 * before_violation);
    }
  }
  EXPECT_GT(outside, 1000);  // random rotations are mostly outside a 40° × 20° cone
}

}  // namespace
}  // namespace puppet::procedural
