// Picking: rays against each shape (checked against the model's own signed distance) and against
// the puppet, and the plane a grabbed point moves in.
#include "puppet/viewer/picking.h"

#include <gtest/gtest.h>

#include <random>

#include "puppet/compare/scenario.h"

namespace puppet::viewer {
namespace {

// in a stated order (a call's arguments are evaluated in the compiler's): z, y, x, as GCC did
template <typename Distribution, typename Engine>
Vector3d random_vector(Distribution& u, Engine& rng) {
  const double z = u(rng), y = u(rng), x = u(rng);
  return {x, y, z};
}

Shape sphere(double r) { return {ShapeType::kSphere, r, 0.0, {0, 0, 0}}; }
Shape capsule(double r, double h) { return {ShapeType::kCapsule, r, h, {0, 0, 0}}; }
Shape box(const Vector3d& half) { return {ShapeType::kBox, 0.0, 0.0, half}; }

TEST(Intersect, KnownHitsAndMisses) {
  const Ray along_x{{-5, 0, 0}, {1, 0, 0}};
  EXPECT_NEAR(*intersect(sphere(0.5), along_x), 4.5, 1e-12);
  EXPECT_NEAR(*intersect(capsule(0.1, 0.3), along_x), 4.9, 1e-12);  // the side
  EXPECT_NEAR(*intersect(box({0.2, 0.3, 0.4}), along_x), 4.8, 1e-12);
  // down the capsule's axis: the tip of the upper cap
  EXPECT_NEAR(*intersect(capsule(0.1, 0.3), Ray{{0, 0, 2}, {0, 0, -1}}), 2.0 - 0.4, 1e-12);
  // beside the cylinder part but through a cap: the cap sphere, not the infinite cylinder
  const Ray past_end{{-5, 0, 0.35}, {1, 0, 0}};
  EXPECT_NEAR(*intersect(capsule(0.1, 0.3), past_end), 5.0 - std::sqrt(0.01 - 0.0025), 1e-12);
  // misses, and a shape behind the ray's start
  EXPECT_FALSE(intersect(sphere(0.5), Ray{{-5, 0.6, 0}, {1, 0, 0}}));
  EXPECT_FALSE(intersect(capsule(0.1, 0.3), Ray{{-5, 0, 0.41}, {1, 0, 0}}));
  EXPECT_FALSE(intersect(box({0.2, 0.3, 0.4}), Ray{{-5, 0.31, 0}, {1, 0, 0}}));
  EXPECT_FALSE(intersect(sphere(0.5), Ray{{5, 0, 0}, {1, 0, 0}}));
  // from inside: at once
  EXPECT_EQ(*intersect(box({0.2, 0.3, 0.4}), Ray{{0, 0, 0}, {0, 1, 0}}), 0.0);
}

// the entry point of every random ray lies on the surface as the model measures it, and the ray
// is outside just before it
TEST(Intersect, EntryPointsLieOnTheSurface) {
  const Shape shapes[] = {sphere(0.3), capsule(0.08, 0.2), box({0.1, 0.2, 0.3})};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Shape& shape : shapes) {
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vector3d origin = 2.0 * random_vector(u, rng).normalized();
      const Vector3d aim = 0.3 * random_vector(u, rng);
      const Ray ray{origin, (aim - origin).normalized()};
      const auto t = intersect(shape, ray);
      if (!t) {
        // a miss: no sampled point along the ray is inside
        for (double s = 0.0; s < 4.0; s += 0.01) ASSERT_GT(signed_distance(shape, ray.at(s)), 0.0);
        continue;
      }
      ++hits;
      EXPECT_NEAR(signed_distance(shape, ray.at(*t)), 0.0, 1e-9);
      EXPECT_GT(signed_distance(shape, ray.at(*t - 1e-6)), 0.0);
    }
    EXPECT_GT(hits, 200);
  }
}

TEST(Pick, TheNearestSegmentOfThePuppet) {
  const Model model = compare::load_named_model("pinocchio");
  const std::vector<BodyState> rest = rest_pose(model);
  // through both forearms along y: the right one (y = −0.22) comes first from −y
  const Ray ray{{0, -2, 1.03}, {0, 1, 0}};
  const Hit hit = pick(model, rest, ray);
  ASSERT_EQ(hit.segment, model.find_segment("r_forearm"));
  EXPECT_NEAR(hit.distance, 2.0 - 0.22 - 0.04, 1e-12);
  EXPECT_TRUE(hit.world_point.isApprox(Vector3d(0, -0.26, 1.03), 1e-12));
  // local_point is the same point in the segment frame
  const BodyState& b = rest[hit.segment];
  EXPECT_LE((b.x + b.q * hit.local_point - hit.world_point).norm(), 1e-12);
  // and from +y the left one
  EXPECT_EQ(pick(model, rest, Ray{{0, 2, 1.03}, {0, -1, 0}}).segment,
            model.find_segment("l_forearm"));
  // beside the puppet: nothing
  EXPECT_EQ(pick(model, rest, Ray{{0, -2, 2.5}, {0, 1, 0}}).segment, -1);
}

TEST(DragPlane, FollowsTheRayAndRefusesParallelOnes) {
  OrbitCamera camera;
  const DragPlane plane = facing_plane(camera, {0.2, 0.1, 1.3});
  const Ray ray = camera.ray({700, 200});
  const auto p = plane.intersect(ray);
  ASSERT_TRUE(p);
  EXPECT_NEAR((*p - plane.point).dot(plane.normal), 0.0, 1e-12);
  EXPECT_FALSE(plane.intersect(Ray{{0, 0, 0}, camera.right()}));
  EXPECT_FALSE(plane.intersect(Ray{camera.eye(), camera.back()}));  // pointing away
}

}  // namespace
}  // namespace puppet::viewer
