#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet {
namespace {

TEST(Shape, CapsuleInertiaMatchesIntegration) {
  // independent answer: midpoint-rule integration of the solid capsule's density
  Shape capsule;
  capsule.type = ShapeType::kCapsule;
  capsule.radius = 0.05;
  capsule.half_length = 0.15;
  const double mass = 3.5;
  const int n = 120;
  const double r = capsule.radius, h = capsule.half_length;
  double volume = 0, ixx = 0, izz = 0;
  const double dx = 2 * r / n, dz = 2 * (h + r) / (2 * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < 2 * n; ++k) {
        const Vector3d p(-r + (i + 0.5) * dx, -r + (j + 0.5) * dx, -h - r + (k + 0.5) * dz);
        if (signed_distance(capsule, p) > 0) continue;
        const double dv = dx * dx * dz;
        volume += dv;
        ixx += (p.y() * p.y() + p.z() * p.z()) * dv;
        izz += (p.x() * p.x() + p.y() * p.y()) * dv;
      }
    }
  }
  const Vector3d inertia = solid_inertia(capsule, mass);
  EXPECT_NEAR(shape_volume(capsule), volume, 2e-3 * volume);
  EXPECT_NEAR(inertia.x(), mass * ixx / volume, 3e-3 * inertia.x());
  EXPECT_NEAR(inertia.z(), mass * izz / volume, 3e-3 * inertia.z());
}

TEST(Shape, EllipsoidInertiaSupportAndDistanceMatchIntegration) {
  // the same independent answer for a solid ellipsoid (semi-axes 4, 6 and 9 cm): its volume and
  // moments by the midpoint rule, its support points on its surface and furthest along their
  // direction among sampled surface points, and its distance's sign
  Shape egg;
  egg.type = ShapeType::kEllipsoid;
  egg.half_extents = {0.04, 0.06, 0.09};
  const double mass = 1.3;
  const Vector3d e = egg.half_extents;
  const int n = 90;
  double volume = 0;
  Vector3d second{0, 0, 0};  // ∫x², ∫y², ∫z²
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Vector3d p =
            (Vector3d(i + 0.5, j + 0.5, k + 0.5) * (2.0 / n) - Vector3d::Ones()).cwiseProduct(e);
        if (signed_distance(egg, p) > 0) continue;
        const double dv = 8.0 * e.prod() / (n * n * n);
        volume += dv;
        second += p.cwiseAbs2() * dv;
      }
    }
  }
  const Vector3d inertia = solid_inertia(egg, mass);
  EXPECT_NEAR(shape_volume(egg), volume, 3e-3 * volume);
  EXPECT_NEAR(inertia.x(), mass * (second.y() + second.z()) / volume, 3e-3 * inertia.x());
  EXPECT_NEAR(inertia.y(), mass * (second.x() + second.z()) / volume, 3e-3 * inertia.y());
  EXPECT_NEAR(inertia.z(), mass * (second.x() + second.y()) / volume, 3e-3 * inertia.z());
  std::mt19937_64 random(3);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 200; ++k) {
    const Vector3d d = Vector3d(normal(random), normal(random), normal(random)).normalized();
    const Vector3d support = support_point(egg, d);
    EXPECT_NEAR(support.cwiseQuotient(e).norm(), 1.0, 1e-12);  // on the surface
    EXPECT_NEAR(signed_distance(egg, support), 0.0, 1e-12);
    for (int m = 0; m < 50; ++m) {
      const Vector3d u = Vector3d(normal(random), normal(random), normal(random)).normalized();
      EXPECT_LE(u.cwiseProduct(e).dot(d), support.dot(d) + 1e-12);
    }
    // outside and inside: the distance's sign, and never more than the true distance (the
    // support point is a surface point, so the true distance is at most the way to it)
    EXPECT_GT(signed_distance(egg, 1.5 * support), 0.0);
    EXPECT_LE(signed_distance(egg, 1.5 * support), 0.5 * support.norm() + 1e-12);
    EXPECT_LT(signed_distance(egg, 0.5 * support), 0.0);
  }
}

TEST(Shape, CylinderInertiaMatchesIntegration) {
  // the same independent answer for a solid cylinder, and its support points and distances
  Shape cylinder;
  cylinder.type = ShapeType::kCylinder;
  cylinder.radius = 0.06;
  cylinder.half_length = 0.1;
  const double mass = 2.0, r = cylinder.radius, h = cylinder.half_length;
  const int n = 100;
  double volume = 0, ixx = 0, izz = 0;
  const double dx = 2 * r / n, dz = 2 * h / n;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Vector3d p(-r + (i + 0.5) * dx, -r + (j + 0.5) * dx, -h + (k + 0.5) * dz);
        if (signed_distance(cylinder, p) > 0) continue;
        const double dv = dx * dx * dz;
        volume += dv;
        ixx += (p.y() * p.y() + p.z() * p.z()) * dv;
        izz += (p.x() * p.x() + p.y() * p.y()) * dv;
      }
    }
  }
  const Vector3d inertia = solid_inertia(cylinder, mass);
  EXPECT_NEAR(shape_volume(cylinder), volume, 2e-3 * volume);
  EXPECT_NEAR(inertia.x(), mass * ixx / volume, 3e-3 * inertia.x());
  EXPECT_NEAR(inertia.z(), mass * izz / volume, 3e-3 * inertia.z());
  // the rim of the cap facing the direction; along the axis, the cap's centre
  EXPECT_LT((support_point(cylinder, Vector3d(1, 0, -1)) - Vector3d(r, 0, -h)).norm(), 1e-15);
  EXPECT_LT((support_point(cylinder, Vector3d(0, 0, 1)) - Vector3d(0, 0, h)).norm(), 1e-15);
  EXPECT_NEAR(signed_distance(cylinder, Vector3d(0, 0, 0)), -r, 1e-15);
  EXPECT_NEAR(signed_distance(cylinder, Vector3d(0, 0, 0.3)), 0.3 - h, 1e-15);
  EXPECT_NEAR(signed_distance(cylinder, Vector3d(0.1, 0, 0.13)), std::hypot(0.04, 0.03), 1e-15);
}

TEST(Shape, SupportAndDistance) {
  Shape box;
  box.type = ShapeType::kBox;
  box.half_extents = Vector3d(1, 2, 3);
  EXPECT_EQ(support_point(box, Vector3d(1, -1, 1)), Vector3d(1, -2, 3));
  EXPECT_EQ(support_point(box, Vector3d(0, 0, -1)), Vector3d(0, 0, -3));  // ties: the middle
  EXPECT_DOUBLE_EQ(signed_distance(box, Vector3d(0, 0, 4)), 1.0);
  EXPECT_DOUBLE_EQ(signed_distance(box, Vector3d(0, 0, 0)), -1.0);
  Shape capsule;
  capsule.type = ShapeType::kCapsule;
  capsule.radius = 0.1;
  capsule.half_length = 0.5;
  EXPECT_TRUE(support_point(capsule, Vector3d(0, 0, 1)).isApprox(Vector3d(0, 0, 0.6)));
  EXPECT_NEAR(signed_distance(capsule, Vector3d(0.3, 0, 0.2)), 0.2, 1e-15);
}

// the world inverse inertia (and its shortcut for segments symmetric about z) is the inverse of
// the world inertia, for every shape, in random orientations
TEST(Shape, WorldInverseInertiaInvertsTheWorldInertia) {
  Segment segment;
  segment.mass = 2.0;
  const Vector3d half_extents(0.1, 0.05, 0.2);
  const Shape shapes[] = {{ShapeType::kCapsule, 0.04, 0.15, {0, 0, 0}},
                          {ShapeType::kSphere, 0.1, 0.0, {0, 0, 0}},
                          {ShapeType::kBox, 0.0, 0.0, half_extents}};
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  for (const Shape& shape : shapes) {
    segment.shapes = {shape};
    segment.inertia = solid_inertia(shape, segment.mass);
    derive_mass_terms(segment);
    for (int k = 0; k < 200; ++k) {
      const Quaterniond q =
          Quaterniond(normal(random), normal(random), normal(random), normal(random)).normalized();
      const Matrix3d product = world_inertia_inv(segment, q) * world_inertia(segment, q);
      EXPECT_LT((product - Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-13)
          << static_cast<int>(shape.type);
    }
  }
}

// every component of every body is checked: one inf or NaN anywhere makes the state not finite
TEST(BodyState, AllFiniteFindsAnyNonFiniteComponent) {
  std::vector<BodyState> bodies(3);
  bodies[1].x = Vector3d(1e3, -2.0, 0.5);
  bodies[2].w = Vector3d(0.0, -7.0, 1e-300);
  EXPECT_TRUE(all_finite(bodies));
  for (int body = 0; body < 3; ++body) {
    for (int component = 0; component < 13; ++component) {
      for (double bad :
           {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::quiet_NaN()}) {
        std::vector<BodyState> broken = bodies;
        BodyState& b = broken[body];
        double* slot = component < 3    ? &b.x[component]
                       : component < 7  ? &b.q.coeffs()[component - 3]
                       : component < 10 ? &b.v[component - 7]
                                        : &b.w[component - 10];
        *slot = bad;
        EXPECT_FALSE(all_finite(broken)) << body << " " << component << " " << bad;
      }
    }
  }
}

}  // namespace
}  // namespace puppet
