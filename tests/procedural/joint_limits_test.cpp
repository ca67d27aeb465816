// Joint limits (joint_limits.cpp): the moved side's orientation brought inside the limits,
// checked with the model's own measure of violation (limit_violation) from random starts.
#include <gtest/gtest.h>

#include <random>

#include "joint_limits.h"
#include "model_tables.h"
#include "puppet/model/rotation.h"
#include "puppet/procedural/solver.h"
#include "support/random.h"

namespace puppet::procedural {
namespace {

using test::random_rotation;

// a base and an arm on a ball joint (swing 40° × 20°, twist 30°) with a turned joint frame, and on
// a hinge (−30° to 60°)
Model two_segments(bool hinge) {
  const std::string joint =
      hinge ? R"("type":"hinge","axis":[0,1,0],"range_deg":[-30,60])"
            : R"("type":"ball","frame":[0.9,0.3,-0.2,0.1],"swing_deg":[40,20],"twist_deg":30)";
  return parse_model(
      R"({"name":"pair","segments":[
        {"name":"base","mass":2,"position":[0,0,1],"shape":{"type":"box","half_extents":[0.1,0.1,0.1]}},
        {"name":"arm","mass":1,"position":[0,0,0.7],"shape":{"type":"capsule","radius":0.03,"half_length":0.15}}],
       "joints":[{"name":"j","parent":"base","child":"arm","anchor":[0,0,0.9],)" +
          joint + "}]}",
      "pair");
}

TEST(JointLimits, TheLimitedSideIsInsideAndAnInsideOneIsLeftAlone) {
  for (bool hinge : {false, true}) {
    SCOPED_TRACE(hinge ? "hinge" : "ball");
    const Model model = two_segments(hinge);
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

TEST(JointLimits, NoRotationBelowTheFreeAngleIsOutside) {
  // limit_free_w's promise: a relative rotation by less than the smallest limit angle is inside
  const Model model = two_segments(false);
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

}  // namespace
}  // namespace puppet::procedural
