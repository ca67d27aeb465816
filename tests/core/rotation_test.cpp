#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdint>
#include <limits>

#include "puppet/model/rotation.h"

namespace puppet {
namespace {

Quaterniond about(const Vector3d& axis, double angle) {
  return Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// the small-angle series agree with sin, cos and atan2 to rounding on both sides of the switch
TEST(Rotation, SeriesMatchTheClosedFormsAtTheSwitch) {
  for (double angle : {1e-9, 1e-3, 0.05, 0.0999999, 0.1000001, 0.3}) {
    const Vector3d axis = Vector3d(1, -2, 0.5).normalized();
    const Quaterniond q = quat_exp(angle * axis);
    const Quaterniond expected(Eigen::AngleAxisd(angle, axis));
    EXPECT_NEAR(q.w(), expected.w(), 1e-16) << angle;
    EXPECT_LT((q.vec() - expected.vec()).norm(), 2e-17 + 1e-15 * angle) << angle;
    EXPECT_LT((quat_log(expected) - angle * axis).norm(), 1e-15 * angle) << angle;
  }
}

TEST(Rotation, ExpLogRoundTrip) {
  for (const Vector3d& v : {Vector3d(0.3, -0.2, 0.1), Vector3d(1e-10, 0, 0), Vector3d(0, 3.0, 0)}) {
    EXPECT_LT((quat_log(quat_exp(v)) - v).norm(), 1e-12);
  }
  // shortest arc: a rotation written with w < 0 is the same rotation
  Quaterniond q = quat_exp(Vector3d(0, 0, 0.5));
  q.coeffs() *= -1;
  EXPECT_LT((quat_log(q) - Vector3d(0, 0, 0.5)).norm(), 1e-12);
  // blind to the length of its argument (the solvers log unnormalised products), on both sides
  // of the series' switch
  for (const Vector3d& v : {Vector3d(0.01, -0.02, 0.03), Vector3d(0.3, -0.2, 0.1)}) {
    const Quaterniond scaled((1.0 + 1e-6) * quat_exp(v).coeffs());
    EXPECT_LT((quat_log(scaled) - v).norm(), 1e-15);
  }
}

// q ⊗ exp(r) written out is the product with exp(r), and one Newton step brings a product of unit
// quaternions back to unit length as a square root and a division would
TEST(Rotation, TimesExpAndRenormalisationAgreeWithTheirDefinitions) {
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  uint64_t seed = 7;
  const auto uniform = [&seed] {  // deterministic, in [−1, 1)
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) * 0x1p-52 - 1.0;
  };
  for (int trial = 0; trial < 200; ++trial) {
    const Quaterniond q = Quaterniond(uniform(), uniform(), uniform(), uniform()).normalized();
    const Vector3d r = (trial % 2 == 0 ? 0.05 : 2.0) * Vector3d(uniform(), uniform(), uniform());
    const Quaterniond expected = q * quat_exp(r);
    EXPECT_LT((times_exp(q, r).coeffs() - expected.coeffs()).norm(), 1e-15) << trial;

    const Quaterniond product = expected * q * expected;
    const Quaterniond unit = renormalized(product);
    // a squared norm of four rounded terms is 1 to a few units of rounding
    EXPECT_LE(std::abs(unit.squaredNorm() - 1.0), 4 * kEpsilon) << trial;
    EXPECT_LT((unit.coeffs() - product.normalized().coeffs()).norm(), 1e-15) << trial;
  }
  // a length off by 1e-8 (far more than rounding) is still restored, to second order
  const Quaterniond off((1.0 + 1e-8) * about(Vector3d(1, 2, 3), 0.7).coeffs());
  EXPECT_LE(std::abs(renormalized(off).squaredNorm() - 1.0), 4 * kEpsilon);
}

TEST(Rotation, SwingTwistRecomposes) {
  const Quaterniond q = about(Vector3d(1, 0, 0), 0.4) * about(Vector3d(0, 0, 1), -0.7);
  const SwingTwist st = decompose_swing_twist(q, Vector3d::UnitZ());
  EXPECT_NEAR(st.twist_angle, -0.7, 1e-12);
  EXPECT_LT(angle_between(st.swing, about(Vector3d(1, 0, 0), 0.4)), 1e-12);
}

// a ball joint with these swing half-angles and twist limit (rad)
Joint ball_radians(double swing_x, double swing_y, double twist) {
  Joint j;
  j.type = JointType::kBall;
  j.swing_x = swing_x;
  j.swing_y = swing_y;
  j.twist = twist;
  derive_limit_terms(j);
  return j;
}

Joint ball(double sx_deg, double sy_deg, double twist_deg) {
  return ball_radians(sx_deg * M_PI / 180, sy_deg * M_PI / 180, twist_deg * M_PI / 180);
}

TEST(Rotation, BallLimitsAlongTheAxes) {
  const Joint j = ball(30, 60, 20);
  const double d = M_PI / 180;
  // inside: untouched
  EXPECT_EQ(limit_violation(j, about(Vector3d(1, 0, 0), 25 * d)), 0.0);
  // along each swing axis the ellipse is the half-angle
  EXPECT_NEAR(limit_violation(j, about(Vector3d(1, 0, 0), 40 * d)), 10 * d, 1e-12);
  EXPECT_NEAR(limit_violation(j, about(Vector3d(0, 1, 0), -70 * d)), 10 * d, 1e-12);
  EXPECT_NEAR(limit_violation(j, about(Vector3d(0, 0, 1), 35 * d)), 15 * d, 1e-12);
  // the clamped rotation sits on the boundary
  const Quaterniond clamped = clamp_to_limits(j, about(Vector3d(1, 0, 0), 40 * d));
  EXPECT_NEAR(angle_between(clamped, about(Vector3d(1, 0, 0), 30 * d)), 0.0, 1e-12);
}

// the trigonometry-free early "inside" of a ball limit agrees with the exact swing–twist test on
// random rotations around the limits (an asymmetric ellipse, both signs of w)
TEST(Rotation, BallInsideShortcutAgreesWithTheExactTest) {
  const Joint j = ball_radians(0.3, 0.8, 0.4);
  uint64_t seed = 12345;
  auto uniform = [&seed] {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) * 0x1.0p-53;
  };
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vector3d v(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5);
    Quaterniond q = quat_exp(2.0 * v);  // up to ~1.7 rad
    if (k % 2) q.coeffs() *= -1.0;
    const SwingTwist st = decompose_swing_twist(q, Vector3d::UnitZ());
    const Vector3d swing = quat_log(st.swing);
    const bool exact_inside = std::abs(st.twist_angle) <= j.twist &&
                              std::hypot(swing.x() / j.swing_x, swing.y() / j.swing_y) <= 1.0;
    const bool kept = clamp_to_limits(j, q).coeffs() == q.coeffs();
    EXPECT_EQ(kept, exact_inside) << q.coeffs().transpose();
    inside += exact_inside;
  }
  EXPECT_GT(inside, 1000);  // both outcomes are sampled
  EXPECT_LT(inside, 19000);
}

// the clamps, which compare half-angle sines and build the limit rotations from precomputed
// sines and cosines, against the clamp written with angles: twist angle by atan2, clamped angle,
// exp of the clamped swing and twist vectors; random rotations, limits, axes, both signs of w
TEST(Rotation, ClampsAgreeWithTheClampWrittenWithAngles) {
  uint64_t seed = 777;
  auto uniform = [&seed] {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) * 0x1.0p-53;
  };
  auto by_angles = [](const Joint& j, const Quaterniond& q) -> Quaterniond {
    if (j.type == JointType::kHinge) {
      const SwingTwist st = decompose_swing_twist(q, j.hinge_axis);
      return quat_exp(std::clamp(st.twist_angle, j.lower, j.upper) * j.hinge_axis);
    }
    const SwingTwist st = decompose_swing_twist(q, Vector3d::UnitZ());
    const double twist = std::clamp(st.twist_angle, -j.twist, j.twist);
    Vector3d s = quat_log(st.swing);
    s.z() = 0.0;
    const double e = std::hypot(s.x() / j.swing_x, s.y() / j.swing_y);
    if (e > 1.0) s /= e;
    return quat_exp(s) * quat_exp(Vector3d(0, 0, twist));
  };
  int clamped = 0;
  for (int k = 0; k < 20000; ++k) {
    Joint j;
    j.type = k % 3 == 0 ? JointType::kHinge : JointType::kBall;
    j.swing_x = 0.05 + 1.5 * uniform();
    j.swing_y = 0.05 + 1.5 * uniform();
    j.twist = 3.0 * uniform();
    j.lower = -3.0 * uniform();
    j.upper = 3.0 * uniform();
    j.hinge_axis = Vector3d(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5).normalized();
    derive_limit_terms(j);
    Quaterniond q = quat_exp(2.0 * Vector3d(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5));
    if (k % 2) q.coeffs() *= -1.0;
    const Quaterniond fast = clamp_to_limits(j, q);
    EXPECT_LE(angle_between(fast, by_angles(j, q)), 1e-12) << k;
    clamped += angle_between(fast, q) > 1e-9;
  }
  EXPECT_GT(clamped, 5000);  // most samples are clamped, some are not
  EXPECT_LT(clamped, 19000);
}

// half a turn of swing has no twist (w = z = 0), the one case where swing and twist are not
// read from n = |(w, z)|: the clamp still lands on the ellipse along the swing's direction, and a
// zero half-angle removes its direction
TEST(Rotation, BallClampsAHalfTurnOfSwingOntoTheEllipse) {
  Joint j = ball_radians(0.3, 0.8, 0.4);
  for (int k = 0; k < 16; ++k) {
    const double angle = 2.0 * M_PI * k / 16;
    const Vector3d u(std::cos(angle), std::sin(angle), 0.0);
    const Quaterniond q(0.0, u.x(), u.y(), 0.0);  // a half turn about u
    const Vector3d on_ellipse =
        M_PI * u / std::hypot(M_PI * u.x() / j.swing_x, M_PI * u.y() / j.swing_y);
    EXPECT_LE(angle_between(clamp_to_limits(j, q), quat_exp(on_ellipse)), 1e-12) << k;
  }
  // no swing about x at all: a half turn about x + y keeps 0.8 rad about y
  j = ball_radians(0.0, 0.8, 0.4);
  const Quaterniond q(0.0, std::sqrt(0.5), std::sqrt(0.5), 0.0);
  EXPECT_LE(angle_between(clamp_to_limits(j, q), quat_exp(Vector3d(0, 0.8, 0))), 1e-12);
}

TEST(Rotation, HingeKeepsOnlyItsAxis) {
  Joint j;
  j.type = JointType::kHinge;
  j.hinge_axis = Vector3d(0, 1, 0);
  j.lower = -0.1;
  j.upper = 2.0;
  derive_limit_terms(j);
  const Quaterniond bent = about(Vector3d(0, 1, 0), 1.0);
  EXPECT_NEAR(limit_violation(j, bent), 0.0, 1e-12);
  EXPECT_NEAR(limit_violation(j, about(Vector3d(0, 1, 0), -0.5)), 0.4, 1e-12);
  // any rotation off the axis is a violation of its own size
  EXPECT_NEAR(limit_violation(j, about(Vector3d(1, 0, 0), 0.2) * bent), 0.2, 1e-9);
}

TEST(Rotation, FixedAllowsNothing) {
  Joint j;
  j.type = JointType::kFixed;
  EXPECT_NEAR(limit_violation(j, about(Vector3d(1, 2, 3), 0.3)), 0.3, 1e-12);
}

}  // namespace
}  // namespace puppet
