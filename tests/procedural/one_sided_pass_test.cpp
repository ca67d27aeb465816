// The seed's one-sided pass (one_sided_pass.cpp): from any disturbed pose it closes every joint
// and the anchor's pin exactly and leaves every joint inside its limits; a parent never feels
// its children; the pin closure says which pins it closes; a compliant pin's softened target is
// XPBD's first compliant step, computed here from the segment's world inverse mass matrix.
#include <gtest/gtest.h>

#include <cassert>
#include <random>

#include "model_tables.h"
#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/model/rotation.h"
#include "puppet/procedural/solver.h"
#include "stages.h"
#include "support/source_dir.h"
#include "workspace.h"

namespace puppet::procedural {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";
constexpr Rule kOneSided[] = {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted, Rule::kSubtree};

Quaterniond small_rotation(std::mt19937_64& rng, double angle) {
  std::uniform_real_distribution<double> u(-angle, angle);
  const double x = u(rng), y = u(rng), z = u(rng);
  return quat_exp(Vector3d(x, y, z));
}

Vector3d small_shift(std::mt19937_64& rng, double length) {
  std::uniform_real_distribution<double> u(-length, length);
  const double x = u(rng), y = u(rng), z = u(rng);
  return {x, y, z};
}

double joint_gap(const State& state, const Joint& joint) {
  return (world_point(state.bodies[joint.parent], joint.anchor_in_parent) -
          world_point(state.bodies[joint.child], joint.anchor_in_child))
      .norm();
}

double limit_violation_of(const State& state, const Joint& joint) {
  return limit_violation(joint, joint_relative_rotation(joint, state.bodies[joint.parent].q,
                                                        state.bodies[joint.child].q));
}

struct Fixture {
  Model model = load_model(kPinocchio);
  std::shared_ptr<const ModelTables> tables = make_model_tables(model);
  Workspace workspace{model, *tables};
  State state;
  PinTargets targets{};

  Fixture() { state.bodies = rest_pose(model); }

  // the head pinned at a point of its own (its top), at `target`
  void pin_head(const Vector3d& target, double compliance = 0.0) {
    Pin& pin = state.pins[state.pin_count];
    pin.segment = model.find_segment("head");
    assert(pin.segment >= 0);
    pin.local_point = Vector3d(0, 0, 0.1);
    pin.target = target;
    pin.compliance = compliance;
    targets[state.pin_count] = target;
    ++state.pin_count;
  }

  void pass(Rule rule, PinClosure closure) {
    const AnchorOrder order = make_anchor_order(model, state.pins[0].segment);
    one_sided_pass(model, tables->joints, rule, order, closure, targets, state, workspace);
  }
};

TEST(OneSidedPass, ClosesEveryJointAndTheAnchorsPinFromAnyDisturbedPose) {
  std::mt19937_64 rng(21);
  for (const Rule rule : kOneSided) {
    SCOPED_TRACE(std::string(rule_name(rule)));
    for (int trial = 0; trial < 50; ++trial) {
      Fixture f;
      f.pin_head(Vector3d(0.05, -0.02, 1.9));
      for (BodyState& body : f.state.bodies) {
        body.x += small_shift(rng, 0.03);
        body.q = (small_rotation(rng, 0.3) * body.q).normalized();
      }
      f.pass(rule, PinClosure::kAll);
      const Pin& pin = f.state.pins[0];
      EXPECT_LT((world_point(f.state.bodies[pin.segment], pin.local_point) - pin.target).norm(),
                1e-14);
      for (const Joint& joint : f.model.joints) {
        EXPECT_LT(joint_gap(f.state, joint), 1e-14) << joint.name;
        EXPECT_LT(limit_violation_of(f.state, joint), 1e-9) << joint.name;
      }
    }
  }
}

TEST(OneSidedPass, AParentNeverFeelsItsChild) {
  // only the right elbow is open (the forearm, a leaf, moved off it): the pass moves the forearm
  // back and nothing else, where a two-sided correction would share the gap with the arm
  for (const Rule rule : kOneSided) {
    SCOPED_TRACE(std::string(rule_name(rule)));
    Fixture f;
    const int head = f.model.find_segment("head");
    f.pin_head(world_point(f.state.bodies[head], Vector3d(0, 0, 0.1)));
    const std::vector<BodyState> before = f.state.bodies;
    const int hand = f.model.find_segment("r_forearm");
    ASSERT_GE(hand, 0);
    f.state.bodies[hand].x += Vector3d(0.04, -0.03, 0.05);
    f.pass(rule, PinClosure::kAll);
    for (int s = 0; s < f.model.segment_count(); ++s) {
      if (s == hand) continue;
      EXPECT_LT((f.state.bodies[s].x - before[s].x).norm(), 1e-14) << f.model.segments[s].name;
      EXPECT_LT(f.state.bodies[s].q.angularDistance(before[s].q), 1e-14)
          << f.model.segments[s].name;
    }
    for (const Joint& joint : f.model.joints) {
      EXPECT_LT(joint_gap(f.state, joint), 1e-14) << joint.name;
    }
  }
}

TEST(OneSidedPass, ThePinClosureSaysWhichPinsAreClosed) {
  for (const Rule rule : kOneSided) {
    SCOPED_TRACE(std::string(rule_name(rule)));
    const int head_index = Fixture{}.model.find_segment("head");
    for (const PinClosure closure : {PinClosure::kNone, PinClosure::kAll, PinClosure::kRigidOnly}) {
      for (const double compliance : {0.0, 1e-3}) {
        Fixture f;
        const Vector3d top = world_point(f.state.bodies[head_index], Vector3d(0, 0, 0.1));
        f.pin_head(top + Vector3d(0.1, 0, 0), compliance);
        const BodyState head_before = f.state.bodies[head_index];
        f.pass(rule, closure);
        const Pin& pin = f.state.pins[0];
        const double gap =
            (world_point(f.state.bodies[head_index], pin.local_point) - pin.target).norm();
        const bool closed =
            closure == PinClosure::kAll || (closure == PinClosure::kRigidOnly && compliance == 0.0);
        if (closed) {
          EXPECT_LT(gap, 1e-14);
        } else {
          // the anchor stays where the update put it
          EXPECT_EQ(f.state.bodies[head_index].x, head_before.x);
          EXPECT_EQ(f.state.bodies[head_index].q.coeffs(), head_before.q.coeffs());
        }
      }
    }
  }
}

TEST(OneSidedPass, ASoftenedTargetIsTheFirstCompliantStep) {
  // XPBD's first iteration on a compliant pin (λ = 0) moves the point by K (K + α̃E)⁻¹ (t − p),
  // K the segment's point mass matrix in world: the one-sided rules close the pin exactly onto
  // that point instead of t. Rigid pins keep their targets; a very soft one stays at the point.
  std::mt19937_64 rng(22);
  for (int trial = 0; trial < 200; ++trial) {
    Fixture f;
    const int head = f.model.find_segment("head");
    BodyState& body = f.state.bodies[head];
    body.q = (small_rotation(rng, 1.0) * body.q).normalized();
    const Vector3d point = world_point(body, Vector3d(0, 0, 0.1));
    const Vector3d target = point + small_shift(rng, 0.2);
    const double compliance = std::pow(10.0, -6.0 + 4.0 * (trial % 5) / 4.0);  // 1e-6 … 1e-2
    f.pin_head(target, compliance);
    f.pin_head(target + Vector3d(0, 0, 0.3), 0.0);  // a rigid one beside it
    const double h = 1.0 / 240.0;
    soften_compliant_targets(f.model, f.state, h, f.targets);

    const Segment& segment = f.model.segments[head];
    const Matrix3d frame = body.q.toRotationMatrix();
    const Matrix3d inertia_inv =
        frame * segment.inertia.cwiseInverse().asDiagonal() * frame.transpose();
    const Vector3d r = point - body.x;
    Matrix3d cross;
    cross << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    const Matrix3d k = Matrix3d::Identity() / segment.mass - cross * inertia_inv * cross;
    const double alpha_tilde = compliance / (h * h);
    const Vector3d expected =
        point + k * (k + alpha_tilde * Matrix3d::Identity()).inverse() * (target - point);
    EXPECT_LT((f.targets[0] - expected).norm(), 1e-12 * (1 + (target - point).norm()));
    EXPECT_EQ(f.targets[1], target + Vector3d(0, 0, 0.3));
  }
}

}  // namespace
}  // namespace puppet::procedural
