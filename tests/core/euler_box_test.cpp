// euler_box.cpp: intrinsic Euler angles in every Tait-Bryan order, against rotations composed
// here from Eigen's angle-axis turns, and the box clamp (MuJoCo's three hinges in one body are the
// independent answer in tests/reference/mujoco_test.cpp).
#include "puppet/model/euler_box.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "support/random.h"

namespace puppet {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<EulerOrder> every_order() {
  std::vector<EulerOrder> out;
  for (const char* name : {"xyz", "xzy", "yxz", "yzx", "zxy", "zyx"}) {
    EulerOrder order;
    EXPECT_TRUE(parse_euler_order(name, &order)) << name;
    EXPECT_EQ(euler_order_name(order), name);
    out.push_back(order);
  }
  return out;
}

// the turns one after the other, about the turned axes
Quaterniond turns(const EulerOrder& order, const Vector3d& angles) {
  Quaterniond q = Quaterniond::Identity();
  for (int k = 0; k < 3; ++k) {
    q = q * Quaterniond(Eigen::AngleAxisd(angles[k], Vector3d::Unit(order.axes[k])));
  }
  return q;
}

TEST(EulerBox, OrdersParseAsThreeDifferentAxes) {
  EulerOrder order;
  for (const char* bad : {"", "xy", "xyzz", "xxy", "xyx", "abc", "XYZ", "x z"}) {
    EXPECT_FALSE(parse_euler_order(bad, &order)) << bad;
  }
}

// angles in the canonical ranges compose as the turns do and read back as themselves
TEST(EulerBox, AnglesComposeAsIntrinsicTurnsAndReadBack) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> outer(-kPi + 1e-6, kPi - 1e-6), middle(-1.5, 1.5);
  for (const EulerOrder& order : every_order()) {
    for (int k = 0; k < 500; ++k) {
      const double a = outer(rng), b = middle(rng), c = outer(rng);
      const Vector3d angles(a, b, c);
      const Quaterniond q = euler_rotation(order, angles);
      EXPECT_LT(q.angularDistance(turns(order, angles)), 1e-14) << euler_order_name(order);
      EXPECT_LT((euler_angles(order, q) - angles).cwiseAbs().maxCoeff(), 1e-12)
          << euler_order_name(order) << " " << angles.transpose();
    }
    // any rotation: its angles are in range and give it back
    for (int k = 0; k < 500; ++k) {
      const Quaterniond q = test::random_rotation(rng);
      const Vector3d angles = euler_angles(order, q);
      EXPECT_LE(std::abs(angles[1]), kPi / 2 + 1e-15);
      EXPECT_LT(euler_rotation(order, angles).angularDistance(q), 1e-12);
    }
  }
}

// the analytic gradients against central differences of the angles of q exp(±hδ): the step
// 1e-6 rad leaves ~1e-12 truncation and ~1e-10 rounding, so 1e-8 holds with room
TEST(EulerBox, GradientsAreTheAnglesDerivativesUnderATurnOfTheFrame) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> outer(-3.0, 3.0), middle(-1.45, 1.45);
  constexpr double kStep = 1e-6;
  for (const EulerOrder& order : every_order()) {
    for (int k = 0; k < 200; ++k) {
      const Vector3d angles(outer(rng), middle(rng), outer(rng));
      const Quaterniond q = euler_rotation(order, angles);
      const Matrix3d gradients = euler_gradients(order, angles);
      for (int axis = 0; axis < 3; ++axis) {
        const Quaterniond plus = q * Quaterniond(Eigen::AngleAxisd(kStep, Vector3d::Unit(axis)));
        const Quaterniond minus = q * Quaterniond(Eigen::AngleAxisd(-kStep, Vector3d::Unit(axis)));
        const Vector3d numeric =
            (euler_angles(order, plus) - euler_angles(order, minus)) / (2.0 * kStep);
        EXPECT_LT((gradients.col(axis) - numeric).cwiseAbs().maxCoeff(), 1e-8)
            << euler_order_name(order) << " " << angles.transpose() << " axis " << axis;
      }
    }
  }
}

// inside the box the clamp returns the rotation itself; outside, each angle is held at its face
// and the others kept, so the result lies on the box
TEST(EulerBox, ClampHoldsEachAngleAtItsFace) {
  std::mt19937_64 rng(11);
  const Vector3d lower(-0.8, -0.5, -0.3), upper(1.2, 0.6, 0.4);
  for (const EulerOrder& order : every_order()) {
    for (int k = 0; k < 500; ++k) {
      const Quaterniond q = test::random_rotation(rng);
      const Vector3d angles = euler_angles(order, q);
      const Quaterniond clamped = clamp_to_box(order, lower, upper, q);
      const bool inside =
          (angles.array() >= lower.array()).all() && (angles.array() <= upper.array()).all();
      if (inside) {
        EXPECT_EQ(clamped.coeffs(), q.coeffs());
        continue;
      }
      const Vector3d held = euler_angles(order, clamped);
      for (int i = 0; i < 3; ++i) {
        const double expected = std::clamp(angles[i], lower[i], upper[i]);
        EXPECT_NEAR(held[i], expected, 1e-12) << euler_order_name(order) << " angle " << i;
      }
    }
  }
}

}  // namespace
}  // namespace puppet
