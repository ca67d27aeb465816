// Joint limits (joint_limits.cpp): the moved side's orientation brought inside the limits,
// checked with the model's own measure of violation (limit_violation) from random starts.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <random>

#include "joint_limits.h"
#include "model_tables.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/rotation.h"
#include "puppet/procedural/solver.h"
#include "support/box_faces.h"
#include "support/random.h"

namespace puppet::procedural {
namespace {

using test::random_rotation;

enum class Kind { kBall, kHinge, kBox };

// a base and an arm on a ball joint (swing 40° × 20°, twist 30°) with a turned joint frame, on a
// hinge (−30° to 60°), and on a ball with a box of Euler angles (z, x, y turns, each its own range)
Model two_segments(Kind kind) {
  const std::string joint =
      kind == Kind::kHinge ? R"("type":"hinge","axis":[0,1,0],"range_deg":[-30,60])"
      : kind == Kind::kBall
          ? R"("type":"ball","frame":[0.9,0.3,-0.2,0.1],"swing_deg":[40,20],"twist_deg":30)"
          : R"("type":"ball","frame":[0.9,0.3,-0.2,0.1],
               "box_deg":{"order":"zxy","lower":[-50,-30,-20],"upper":[70,40,25]})";
  return parse_model(
      R"({"name":"pair","segments":[
        {"name":"base","mass":2,"position":[0,0,1],"shape":{"type":"box","half_extents":[0.1,0.1,0.1]}},
        {"name":"arm","mass":1,"position":[0,0,0.7],"shape":{"type":"capsule","radius":0.03,"half_length":0.15}}],
       "joints":[{"name":"j","parent":"base","child":"arm","anchor":[0,0,0.9],)" +
          joint + "}]}",
      "pair");
}

TEST(JointLimits, TheLimitedSideIsInsideAndAnInsideOneIsLeftAlone) {
  for (Kind kind : {Kind::kBall, Kind::kHinge, Kind::kBox}) {
    SCOPED_TRACE(static_cast<int>(kind));
    const Model model = two_segments(kind);
    const Joint& joint = model.joints[0];
    const auto tables = make_model_tables(model);
    const JointTerms& terms = tables->joints[0];
    std::mt19937_64 rng(7);
    int outside = 0;
    for (int trial = 0; trial < 2000; ++trial) {
      const Quaterniond q_a = random_rotation(rng), q_b = random_rotation(rng);
      for (bool b_is_child : {true, false}) {
        const Quaterniond& parent = b_is_child ? q_a : q_b;
        const Quaterniond& child = b_is_child ? q_b : q_a;
        const double before = limit_violation(joint, joint_relative_rotation(joint, parent, child));
        Quaterniond limited = q_b;
        const bool moved = limited_orientation(joint, terms, b_is_child, q_a, q_b, &limited);
        EXPECT_EQ(moved, before > 0.0);
        if (!moved) {
          EXPECT_EQ(limited.coeffs(), q_b.coeffs());
          continue;
        }
        ++outside;
        limited = renormalized(limited);
        const Quaterniond& new_parent = b_is_child ? q_a : limited;
        const Quaterniond& new_child = b_is_child ? limited : q_a;
        EXPECT_LT(limit_violation(joint, joint_relative_rotation(joint, new_parent, new_child)),
                  1e-9);
        // the rotation that takes b there is the same move
        const Quaterniond turn = limit_correction(joint, terms, b_is_child, q_a, q_b);
        EXPECT_LT((turn * q_b).angularDistance(limited), 1e-9);
      }
    }
    EXPECT_GT(outside, 1000);  // random starts are mostly outside: the clamp was exercised
  }
}

// rule tree's limit rows read ball_excess's gradients: against central differences of its own
// limit functions at q exp(±hδ), over random rotations away from the functions' kinks (the
// twist's sign change, the swing's zero, the box's wrap at ±π and its middle angle near ±π/2);
// h = 1e-6 rad leaves ~1e-12 truncation and ~1e-10 rounding
TEST(JointLimits, BallExcessGradientsAreItsDerivatives) {
  std::mt19937_64 rng(5);
  constexpr double kStep = 1e-6;
  for (const Kind kind : {Kind::kBall, Kind::kBox}) {
    const Model model = two_segments(kind);
    const Joint& joint = model.joints[0];
    int checked = 0;
    for (int k = 0; k < 2000; ++k) {
      const Quaterniond q = random_rotation(rng);
      const BallExcess limit = ball_excess(joint, q);
      if (kind == Kind::kBall) {
        const SwingTwist parts = decompose_swing_twist(q, Vector3d::UnitZ());
        const double swing = quat_log(parts.swing).norm();
        if (std::abs(parts.twist_angle) < 1e-3 || swing < 1e-3 || swing > 3.1) continue;
      } else {
        const Vector3d angles = euler_angles(joint.box_order, q);
        if (std::abs(angles[1]) > 1.4 || angles.cwiseAbs().maxCoeff() > 3.1) continue;
        // at the middle of a range the excess switches between its two faces
        const Vector3d middle = 0.5 * (joint.box_lower + joint.box_upper);
        if ((angles - middle).cwiseAbs().minCoeff() < 1e-3) continue;
      }
      for (int axis = 0; axis < 3; ++axis) {
        const Vector3d turn = kStep * Vector3d::Unit(axis);
        const Vector3d numeric = (ball_excess(joint, times_exp(q, turn)).excess -
                                  ball_excess(joint, times_exp(q, -turn)).excess) /
                                 (2.0 * kStep);
        const int rows = kind == Kind::kBall ? 2 : 3;  // swing–twist's third is a constant
        EXPECT_LT((limit.gradients.col(axis) - numeric).head(rows).cwiseAbs().maxCoeff(), 1e-7)
            << (kind == Kind::kBall ? "swing-twist" : "box") << " axis " << axis << " q "
            << q.coeffs().transpose();
      }
      ++checked;
    }
    EXPECT_GT(checked, 1000);
  }
}

TEST(JointLimits, NoRotationBelowTheFreeAngleIsOutside) {
  // limit_free_w's promise: a relative rotation by less than the smallest limit angle is inside
  const Model model = two_segments(Kind::kBall);
  const Joint& joint = model.joints[0];
  const double free_angle = 2 * std::acos(limit_free_w(joint));
  EXPECT_NEAR(free_angle, 20.0 * M_PI / 180.0, 1e-12);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> fraction(0.0, 0.999);
  for (int trial = 0; trial < 2000; ++trial) {
    const Vector3d axis = random_rotation(rng).vec().normalized();
    const Quaterniond q_rel(Eigen::AngleAxisd(fraction(rng) * free_angle, axis));
    EXPECT_EQ(limit_violation(joint, q_rel), 0.0);
  }
}

// A box limit holds each Euler angle in its own range: the clamp keeps the angles that are inside
// and holds the others at their faces (euler_box.h), so the limited side reads its angles back
// clamped
TEST(JointLimits, ABoxHoldsEachAngleAtItsFace) {
  const Model model = two_segments(Kind::kBox);
  const Joint& joint = model.joints[0];
  EXPECT_EQ(joint.ball_limit, BallLimit::kEulerBox);
  EXPECT_GT(limit_free_w(joint), 1.0);  // no rotation is surely inside without its angles
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 2000; ++trial) {
    const Quaterniond q_rel = random_rotation(rng);
    const Vector3d angles = euler_angles(joint.box_order, q_rel);
    const Vector3d held = euler_angles(joint.box_order, clamp_to_limits(joint, q_rel));
    const Vector3d expected = angles.cwiseMax(joint.box_lower).cwiseMin(joint.box_upper);
    EXPECT_LT((held - expected).cwiseAbs().maxCoeff(), 1e-12);
    // the violation in the box's terms: the most an angle lies outside
    const double excess = std::max(
        {0.0, (angles - joint.box_upper).maxCoeff(), (joint.box_lower - angles).maxCoeff()});
    EXPECT_NEAR(limit_violation(joint, q_rel), excess, 1e-12);
  }
}

using test::faces_and_corners;

// a solver of `rule` without gravity, the base held where it rests
std::unique_ptr<Solver> base_held(const Model& model, Rule rule) {
  Settings settings;
  settings.rule = rule;
  auto solver = std::make_unique<Solver>(model, settings, Environment{.gravity = Vector3d::Zero()});
  const Pin hold{.segment = 0, .target = solver->state().bodies[0].x};
  solver->set_pins({&hold, 1});
  return solver;
}

// A joint spun into each face of its box stops there in every rule: the arm turns at 4 rad/s
// about the face's axis, the base held, no gravity; over the second that follows the angle
// reaches its face and no angle is ever outside its range after a step by more than the rule's
// tolerance (the one-sided rules clamp exactly; the two-sided ones within their sweeps)
TEST(JointLimits, ABoxStopsAJointSpunIntoEachFace) {
  const Model model = two_segments(Kind::kBox);
  const Joint& joint = model.joints[0];
  for (const Rule rule : kAllRules) {
    double worst = 0.0;
    for (const Vector3d& push : faces_and_corners()) {
      if (push.cwiseAbs().sum() != 1.0) continue;  // a corner: the next test
      SCOPED_TRACE(std::string(rule_name(rule)) + " push " + std::to_string(push.x()) + "," +
                   std::to_string(push.y()) + "," + std::to_string(push.z()));
      const auto held = base_held(model, rule);
      Solver& solver = *held;
      // at rest an angle's rate is a turn about its axis of the joint frame
      std::vector<BodyState> bodies = solver.state().bodies;
      int k = 0;
      push.cwiseAbs().maxCoeff(&k);
      bodies[1].w = bodies[0].q * joint.frame_in_parent *
                    (4.0 * push[k] * Vector3d::Unit(joint.box_order.axes[k]));
      solver.reset(bodies);
      double reached = 0.0;  // how far the angle went in its push
      for (int step = 0; step < 240; ++step) {
        solver.step(1.0 / 240.0);
        const auto& s = solver.state().bodies;
        const Quaterniond q_rel = joint_relative_rotation(joint, s[0].q, s[1].q);
        worst = std::max(worst, limit_violation(joint, q_rel));
        reached = std::max(reached, push[k] * euler_angles(joint.box_order, q_rel)[k]);
      }
      const double face = push[k] > 0.0 ? joint.box_upper[k] : -joint.box_lower[k];
      EXPECT_GT(reached, face - 0.02);
    }
    EXPECT_LT(worst, 1.0 * M_PI / 180.0) << rule_name(rule);
  }
}

// A joint put past each face and each corner of its box is brought back in one step of every
// rule: the arm is turned about the joint point to 1.3 times the face's or corner's angles, at
// rest. The one-sided rules project it onto the face or corner (each of those angles at its face);
// the rules that derive velocities from the correction (relaxed, xpbd, tree) carry the jump back
// as a velocity, as position-based dynamics does, so they are asked only to be inside after the
// step
TEST(JointLimits, ABoxTakesAJointPastAFaceOrCornerBack) {
  const Model model = two_segments(Kind::kBox);
  const Joint& joint = model.joints[0];
  for (const Rule rule : kAllRules) {
    for (const Vector3d& push : faces_and_corners()) {
      SCOPED_TRACE(std::string(rule_name(rule)) + " push " + std::to_string(push.x()) + "," +
                   std::to_string(push.y()) + "," + std::to_string(push.z()));
      const auto held = base_held(model, rule);
      Solver& solver = *held;
      Vector3d past;
      for (int k = 0; k < 3; ++k) {
        past[k] = 1.3 * (push[k] > 0.0   ? joint.box_upper[k]
                         : push[k] < 0.0 ? joint.box_lower[k]
                                         : 0.0);
      }
      // the arm turned about the joint point so that q_rel = euler_rotation(past)
      std::vector<BodyState> bodies = solver.state().bodies;
      const Quaterniond parent_frame = bodies[0].q * joint.frame_in_parent;
      const Quaterniond child =
          parent_frame * euler_rotation(joint.box_order, past) * joint.frame_in_child.conjugate();
      const Vector3d anchor = bodies[0].x + bodies[0].q * joint.anchor_in_parent;
      bodies[1].q = child;
      bodies[1].x = anchor - child * joint.anchor_in_child;
      solver.reset(bodies);
      solver.step(1.0 / 240.0);
      // tree's one Newton iteration per substep linearises three limit rows at a corner 22° out:
      // measured, its first step can end 10° outside the (−, −, +) corner (inside with 4
      // iterations, or from 1.2 times the corner in), and the second step is inside
      if (rule == Rule::kTree) solver.step(1.0 / 240.0);
      const auto& s = solver.state().bodies;
      const Quaterniond q_rel = joint_relative_rotation(joint, s[0].q, s[1].q);
      EXPECT_LT(limit_violation(joint, q_rel), 1.0 * M_PI / 180.0);
      if (rule == Rule::kRelaxed || rule == Rule::kXpbd || rule == Rule::kTree) continue;
      const Vector3d angles = euler_angles(joint.box_order, q_rel);
      for (int k = 0; k < 3; ++k) {
        if (push[k] > 0.0) {
          EXPECT_NEAR(angles[k], joint.box_upper[k], 0.5 * M_PI / 180.0) << "angle " << k;
        } else if (push[k] < 0.0) {
          EXPECT_NEAR(angles[k], joint.box_lower[k], 0.5 * M_PI / 180.0) << "angle " << k;
        }
      }
    }
  }
}

// surely_inside_box never says inside for a rotation whose Euler angles (Eigen's, as the clamp
// reads them) are not all in range, and says it for nearly every rotation inside by more than a
// thousandth of a radian, for every order of the axes, narrow and wide ranges (a wide first range
// of 220°), random rotations and rotations put within a hair of a face
TEST(JointLimits, TheBoxTestNeverCallsAnOutsideRotationInside) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const char* orders[] = {"xyz", "yzx", "zxy", "xzy", "yxz", "zyx"};
  int inside = 0, told = 0, near_face = 0;
  for (const char* name : orders) {
    Joint joint;
    joint.type = JointType::kBall;
    joint.ball_limit = BallLimit::kEulerBox;
    ASSERT_TRUE(parse_euler_order(name, &joint.box_order));
    for (int trial = 0; trial < 4000; ++trial) {
      const bool wide = trial % 2 == 1;
      joint.box_lower = Vector3d(wide ? -1.9 : -0.2 - unit(random), -0.1 - unit(random),
                                 -0.1 - 2.0 * unit(random));
      joint.box_upper =
          Vector3d(wide ? 1.95 : 0.1 + unit(random), 0.05 + unit(random), 0.1 + 2.0 * unit(random));
      const BoxTest box = make_box_test(joint);
      ASSERT_TRUE(box.enabled);
      // a random rotation, or one of angles drawn across the box, one of them moved onto a face
      Vector3d angles;
      for (int k = 0; k < 3; ++k) {
        angles[k] = joint.box_lower[k] +
                    (joint.box_upper[k] - joint.box_lower[k]) * (1.2 * unit(random) - 0.1);
      }
      if (trial % 3 == 0) {
        const int k = trial % 9 / 3;
        angles[k] =
            (trial % 2 ? joint.box_upper[k] : joint.box_lower[k]) + 1e-10 * (unit(random) - 0.5);
        ++near_face;
      }
      const Quaterniond q =
          trial % 5 == 0 ? test::random_rotation(random) : euler_rotation(joint.box_order, angles);
      const Vector3d read = euler_angles(joint.box_order, q);
      const bool in_range = (read.array() >= joint.box_lower.array()).all() &&
                            (read.array() <= joint.box_upper.array()).all();
      const bool well_inside = (read.array() >= joint.box_lower.array() + 1e-3).all() &&
                               (read.array() <= joint.box_upper.array() - 1e-3).all();
      const bool said = surely_inside_box(box, q);
      if (said) {
        EXPECT_TRUE(in_range) << name << " " << read.transpose();
        EXPECT_EQ(clamp_to_box(joint.box_order, joint.box_lower, joint.box_upper, q).coeffs(),
                  q.coeffs());
      }
      if (well_inside) {
        ++inside;
        if (said) ++told;
      }
    }
  }
  EXPECT_GT(near_face, 1000);
  // every rotation well inside is told (the margin is 1e-9)
  EXPECT_EQ(told, inside);
  EXPECT_GT(inside, 5000);
}

// a box the test cannot read is left to the clamp
TEST(JointLimits, TheBoxTestIsOffWhereItCannotRead) {
  Joint joint;
  joint.type = JointType::kBall;
  joint.ball_limit = BallLimit::kEulerBox;
  joint.box_lower = Vector3d(-0.5, -0.5, -0.5);
  joint.box_upper = Vector3d(0.5, 0.5, 0.5);
  EXPECT_TRUE(make_box_test(joint).enabled);
  joint.box_lower[2] = 0.1;  // a range without 0
  EXPECT_FALSE(make_box_test(joint).enabled);
  joint.box_lower[2] = -0.5;
  joint.ball_limit = BallLimit::kSwingTwist;
  EXPECT_FALSE(make_box_test(joint).enabled);
  joint.type = JointType::kHinge;
  EXPECT_FALSE(make_box_test(joint).enabled);
}

}  // namespace
}  // namespace puppet::procedural
