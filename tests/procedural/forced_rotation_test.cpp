// The forced rotation and translation (forced_rotation.cpp, eq. 5, and each one-sided rule's R in
// rules/): eq. 5 closes any gap exactly whatever R a rule chose; r ∥ s leaves no axis; literal is
// eqs. 2–3 as written; smoothed never turns past the closing angle; weighted is, to first order,
// the least-energy correction computed here independently, from the body's inverse mass matrix.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry.h"
#include "puppet/model/rotation.h"
#include "rules/rules.h"
#include "stages.h"
#include "support/random.h"

namespace puppet::procedural {
namespace {

using test::random_rotation;
using test::random_vector;

struct Case {
  MovingBody body;
  Vector3d c_b, c_a;
};

// a body of 0.5–5 kg with principal moments 0.01–1 kg m², a diagonal one (a segment) or its
// tensor in a turned frame (a composite, as rule subtree builds it); its point 5–50 cm from its
// centre, the gap up to `gap` m
Case random_case(std::mt19937_64& rng, bool composite, double gap) {
  std::uniform_real_distribution<double> mass(0.5, 5.0), moment(0.01, 1.0), length(0.05, 0.5);
  Case c;
  MovingBody& b = c.body;
  b.mass = mass(rng);
  b.inv_mass = 1.0 / b.mass;
  b.centre = random_vector(rng, 1.0);
  b.frame = random_rotation(rng);
  const double i1 = moment(rng), i2 = moment(rng), i3 = moment(rng);
  const Vector3d moments(i1, i2, i3);
  if (composite) {
    const Matrix3d turn = random_rotation(rng).toRotationMatrix();
    b.diagonal = false;
    b.inertia = turn * moments.asDiagonal() * turn.transpose();
    b.inertia_inv = b.inertia.inverse();
  } else {
    b.diagonal = true;
    b.inertia_diag = moments;
  }
  const Vector3d direction = random_vector(rng, 1.0).normalized();
  c.c_b = b.centre + length(rng) * direction;
  c.c_a = c.c_b + random_vector(rng, gap);
  return c;
}

// the body's inertia tensor in world
Matrix3d world_inertia(const MovingBody& b) {
  const Matrix3d frame = b.frame.toRotationMatrix();
  const Matrix3d local = b.diagonal ? Matrix3d(b.inertia_diag.asDiagonal()) : b.inertia;
  return frame * local * frame.transpose();
}

// the rotation vector of a unit quaternion
Vector3d rotation_vector(const Quaterniond& q) { return quat_log(q); }

TEST(ForcedRotation, EquationFiveClosesTheGapWhateverTheRuleTurns) {
  std::mt19937_64 rng(11);
  for (Rule rule : {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted, Rule::kSubtree}) {
    SCOPED_TRACE(std::string(rule_name(rule)));
    // close_point's weighted reading is for a composite (rule subtree's); a single segment takes
    // close_segment_point() (below)
    const bool composite = rule == Rule::kWeighted || rule == Rule::kSubtree;
    double worst = 0.0;
    int rotated = 0;
    for (int k = 0; k < 2000; ++k) {
      const Case c = random_case(rng, composite, 0.2);
      const Correction correction = close_point(rule, c.body, c.c_b, c.c_a);
      EXPECT_NEAR(correction.rotation.norm(), 1.0, 1e-14);
      const Vector3d moved = correction.motion(c.body.centre).apply(c.c_b);
      worst = std::max(worst, (moved - c.c_a).norm());
      rotated += correction.rotates() ? 1 : 0;
    }
    EXPECT_LT(worst, 1e-14);
    EXPECT_GT(rotated, 1900);  // the cases do turn (literal's least: its θ decays with I |r × s|)
  }
}

TEST(ForcedRotation, LiteralNeverTurnsAPuppetSizedLink) {
  // θ = φ·exp(−1/(I_b |r × s|)): for moments up to 0.1 kg m², arms up to 30 cm and gaps up to
  // 1 cm the exponent is at least 3,300, and exp of it is exactly 0 in double precision
  std::mt19937_64 rng(16);
  for (int k = 0; k < 2000; ++k) {
    Case c = random_case(rng, false, 0.01);
    c.body.inertia_diag *= 0.1;
    const Vector3d r = c.c_b - c.body.centre;
    c.c_b = c.body.centre + std::min(1.0, 0.3 / r.norm()) * r;
    c.c_a = c.c_b + std::min(1.0, 0.01 / (c.c_a - c.c_b).norm()) * (c.c_a - c.c_b);
    const Correction correction = close_point(Rule::kLiteral, c.body, c.c_b, c.c_a);
    EXPECT_FALSE(correction.rotates());
    EXPECT_EQ(correction.translation, c.c_a - c.c_b);
  }
}

TEST(ForcedRotation, AGapAlongTheArmHasNoAxisAndTranslatesOnly) {
  std::mt19937_64 rng(12);
  for (Rule rule : {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted, Rule::kSubtree}) {
    Case c = random_case(rng, rule == Rule::kWeighted || rule == Rule::kSubtree, 0.1);
    const Vector3d r = c.c_b - c.body.centre;
    c.c_a = c.c_b + 0.3 * r;  // s ∥ r: r × s = 0 up to rounding
    const Correction correction = close_point(rule, c.body, c.c_b, c.c_a);
    EXPECT_FALSE(correction.rotates()) << rule_name(rule);
    EXPECT_LT((correction.translation - (c.c_a - c.c_b)).norm(), 1e-15) << rule_name(rule);
  }
}

TEST(ForcedRotation, LiteralIsEquationsTwoAndThree) {
  // a heavy, wide body and a long arm, so that 1/(I_b |r × s|) is of order one and θ is not 0:
  // θ = φ·exp(−1/(I_b |r × s|)) about r × s, φ = ∠(r, s)
  MovingBody body;
  body.mass = 80.0;
  body.inv_mass = 1.0 / body.mass;
  body.centre = Vector3d(0.1, -0.2, 0.3);
  body.frame = Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 2, 3).normalized()));
  body.diagonal = true;
  body.inertia_diag = Vector3d(30.0, 40.0, 50.0);
  const Vector3d r(0.6, 0.1, 0.0), s(-0.1, 0.08, 0.03);
  const Correction correction =
      close_point(Rule::kLiteral, body, body.centre + r, body.centre + r + s);
  const Vector3d axis = r.cross(s).normalized();
  const double inertia = axis.dot(world_inertia(body) * axis);
  const double phi = std::acos(r.dot(s) / (r.norm() * s.norm()));
  const double theta = phi * std::exp(-1.0 / (inertia * r.cross(s).norm()));
  ASSERT_GT(theta, 0.1);  // the case does turn
  EXPECT_LT((rotation_vector(correction.rotation) - theta * axis).norm(), 1e-12);
}

TEST(ForcedRotation, SmoothedNeverTurnsPastTheClosingAngle) {
  // φ_max = ∠(r, r + s): the angle that would point the arm at c_a; a light body turns nearly
  // that far, and never further
  std::mt19937_64 rng(13);
  for (int k = 0; k < 2000; ++k) {
    Case c = random_case(rng, false, 0.5);
    c.body.inertia_diag *= (k % 2 == 0) ? 1e-3 : 1.0;
    const Vector3d r = c.c_b - c.body.centre, s = c.c_a - c.c_b;
    const double phi_max = std::atan2(r.cross(s).norm(), r.dot(r + s));
    const Correction correction = close_point(Rule::kSmoothed, c.body, c.c_b, c.c_a);
    const Vector3d turn = rotation_vector(correction.rotation);
    EXPECT_LE(turn.norm(), phi_max * (1 + 1e-12));
    EXPECT_GT(turn.dot(r.cross(s)), 0.0);  // towards the target
  }
}

TEST(ForcedRotation, WeightedIsTheLeastEnergyCorrectionToFirstOrder) {
  // the impulse λ that moves the point by s at least kinetic energy, from the mass matrix of the
  // point, written here with the inverse of the world tensor: K = E/m − [r]× I⁻¹ [r]×, λ = K⁻¹ s,
  // rotation vector I⁻¹ (r × λ). For a gap of ε the rule's exact correction agrees to O(ε²).
  std::mt19937_64 rng(14);
  for (const Rule rule : {Rule::kWeighted, Rule::kSubtree}) {
    SCOPED_TRACE(std::string(rule_name(rule)));
    for (int k = 0; k < 500; ++k) {
      Case c = random_case(rng, true, 1.0);
      const Vector3d r = c.c_b - c.body.centre;
      const Vector3d s = 1e-6 * (c.c_a - c.c_b);
      const Matrix3d inertia_inv = world_inertia(c.body).inverse();
      Matrix3d cross;
      cross << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
      const Matrix3d k_point = Matrix3d::Identity() / c.body.mass - cross * inertia_inv * cross;
      const Vector3d lambda = k_point.inverse() * s;
      const Vector3d expected_turn = inertia_inv * r.cross(lambda);
      const Vector3d expected_shift = lambda / c.body.mass;

      const Correction correction = close_point(rule, c.body, c.c_b, c.c_b + s);
      ASSERT_TRUE(correction.rotates());
      const Vector3d turn = rotation_vector(correction.rotation);
      EXPECT_LT((turn - expected_turn).norm(), 1e-6 * expected_turn.norm() + 1e-15);
      // the centre moves by T = s − θ × r (a single segment takes it directly): λ/m to first
      // order, where the point's motion s is shared between the two
      EXPECT_LT((correction.translation - expected_shift).norm(), 1e-5 * s.norm());
    }
  }
}

TEST(ForcedRotation, TheSegmentShortcutIsTheWeightedCorrection) {
  // close_segment_point() and a joint's constant gain are the weighted rule's correction of a
  // single segment written without a MovingBody: the same pose but for rounding
  std::mt19937_64 rng(15);
  Segment segment;
  for (int k = 0; k < 500; ++k) {
    const Case c = random_case(rng, false, 0.1);
    segment.mass = c.body.mass;
    segment.inv_mass = c.body.inv_mass;
    segment.inertia = c.body.inertia_diag;
    segment.inv_inertia = c.body.inertia_diag.cwiseInverse();
    BodyState body;
    body.x = c.body.centre;
    body.q = c.body.frame;
    const Vector3d r_frame = body.q.conjugate() * (c.c_b - body.x);

    BodyState shortcut = body;
    close_segment_point(segment, r_frame, c.c_a, shortcut);
    // the general path: a composite with the segment's tensor
    MovingBody composite = c.body;
    composite.diagonal = false;
    composite.inertia = c.body.inertia_diag.asDiagonal();
    composite.inertia_inv = composite.inertia.inverse();
    BodyState general = body;
    close_point(Rule::kWeighted, composite, c.c_b, c.c_a).apply(general);

    EXPECT_LT((shortcut.x - general.x).norm(), 1e-12);
    EXPECT_LT(shortcut.q.angularDistance(general.q), 1e-12);
    EXPECT_LT((world_point(shortcut, r_frame) - c.c_a).norm(), 1e-14);
  }
}

}  // namespace
}  // namespace puppet::procedural
