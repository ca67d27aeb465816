// The orbit camera: its pixels, rays and OpenGL matrices agree with each other.
#include "puppet/viewer/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace puppet::viewer {
namespace {

// in a stated order (a call's arguments are evaluated in the compiler's): z, y, x, as GCC did
template <typename Distribution, typename Engine>
Vector3d random_vector(Distribution& u, Engine& rng) {
  const double z = u(rng), y = u(rng), x = u(rng);
  return {x, y, z};
}

OrbitCamera test_camera() {
  OrbitCamera camera;
  camera.target = {0.1, -0.2, 1.0};
  camera.yaw = 0.4;
  camera.pitch = 0.3;
  camera.distance = 2.5;
  camera.width = 800;
  camera.height = 600;
  return camera;
}

TEST(OrbitCamera, AxesAreOrthonormalAndRightHanded) {
  const OrbitCamera camera = test_camera();
  EXPECT_NEAR(camera.right().norm(), 1.0, 1e-12);
  EXPECT_NEAR(camera.up().norm(), 1.0, 1e-12);
  EXPECT_NEAR(camera.right().dot(camera.up()), 0.0, 1e-12);
  EXPECT_TRUE(camera.right().cross(camera.up()).isApprox(camera.back(), 1e-12));
  // z up: screen up has a positive z component, screen right none
  EXPECT_GT(camera.up().z(), 0.0);
  EXPECT_NEAR(camera.right().z(), 0.0, 1e-12);
  EXPECT_NEAR((camera.eye() - camera.target).norm(), camera.distance, 1e-12);
}

TEST(OrbitCamera, TheTargetIsAtTheCentreAndPixelsRoundTripThroughRays) {
  const OrbitCamera camera = test_camera();
  Vector2d pixel;
  ASSERT_TRUE(camera.project(camera.target, &pixel));
  EXPECT_NEAR(pixel.x(), 400.0, 1e-9);
  EXPECT_NEAR(pixel.y(), 300.0, 1e-9);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const Vector3d p = camera.target + random_vector(u, rng);
    ASSERT_TRUE(camera.project(p, &pixel));
    const Ray ray = camera.ray(pixel);
    // the ray through the point's pixel passes through the point
    const Vector3d d = p - ray.origin;
    EXPECT_LE((d - d.dot(ray.direction) * ray.direction).norm(), 1e-9);
    EXPECT_GT(d.dot(ray.direction), 0.0);
  }
  // behind the eye there is no pixel
  EXPECT_FALSE(camera.project(camera.eye() + camera.back(), &pixel));
}

// what OpenGL draws (projection · view, then the viewport) lands where project() says
TEST(OrbitCamera, MatricesAgreeWithProject) {
  const OrbitCamera camera = test_camera();
  const Eigen::Matrix4d pv = camera.projection() * camera.view();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const Vector3d p = camera.target + random_vector(u, rng);
    const Eigen::Vector4d clip = pv * p.homogeneous();
    const Vector3d ndc = clip.head<3>() / clip.w();
    Vector2d pixel;
    ASSERT_TRUE(camera.project(p, &pixel));
    EXPECT_NEAR((ndc.x() + 1.0) * 0.5 * camera.width, pixel.x(), 1e-7);
    EXPECT_NEAR((1.0 - ndc.y()) * 0.5 * camera.height, pixel.y(), 1e-7);
    EXPECT_GT(ndc.z(), -1.0);
    EXPECT_LT(ndc.z(), 1.0);
  }
}

TEST(OrbitCamera, GesturesOrbitPanAndZoom) {
  OrbitCamera camera = test_camera();
  const double distance = camera.distance;
  camera.orbit({100.0, 0.0});
  EXPECT_NEAR(camera.yaw, 0.4 - 1.0, 1e-12);
  camera.orbit({0.0, 1e6});
  EXPECT_LT(camera.pitch, M_PI / 2);  // never over the pole
  EXPECT_NEAR(camera.distance, distance, 1e-12);

  // panning drags the scene with the mouse: the old target moves by the mouse's motion
  camera = test_camera();
  const Vector3d old_target = camera.target;
  camera.pan({30.0, -20.0});
  Vector2d pixel;
  ASSERT_TRUE(camera.project(old_target, &pixel));
  EXPECT_NEAR(pixel.x(), 400.0 + 30.0, 1e-9);
  EXPECT_NEAR(pixel.y(), 300.0 - 20.0, 1e-9);

  camera.zoom(1.0);
  EXPECT_NEAR(camera.distance, 0.9 * distance, 1e-12);
  camera.zoom(-1000.0);
  EXPECT_LE(camera.distance, 50.0);
  camera.zoom(1000.0);
  EXPECT_GE(camera.distance, 0.2);
}

TEST(OrbitCamera, FrameShowsTheWholeBox) {
  OrbitCamera camera = test_camera();
  const Vector3d low{-0.3, -0.4, 0.0}, high{0.3, 0.4, 1.8};
  camera.frame(low, high);
  for (int corner = 0; corner < 8; ++corner) {
    const Vector3d p{corner & 1 ? high.x() : low.x(), corner & 2 ? high.y() : low.y(),
                     corner & 4 ? high.z() : low.z()};
    Vector2d pixel;
    ASSERT_TRUE(camera.project(p, &pixel));
    EXPECT_GE(pixel.x(), 0.0);
    EXPECT_LE(pixel.x(), camera.width);
    EXPECT_GE(pixel.y(), 0.0);
    EXPECT_LE(pixel.y(), camera.height);
  }
}

// Following a point, the target closes the distance as e^(−t/τ) whatever the frame rate: after
// τ, 1 − 1/e of it in one call or in sixty, to rounding; it never passes the point; a still
// point is reached to 1e-6 after 14 τ; a frame of no time moves nothing
TEST(OrbitCamera, FollowsAPointAtItsTimeConstantAtAnyFrameRate) {
  const Vector3d point(1.0, -2.0, 0.5);
  OrbitCamera once = test_camera(), sixty = test_camera();
  const Vector3d start = once.target;
  const double yaw = once.yaw, distance = once.distance;
  once.follow(point, kFollowSeconds);
  for (int k = 0; k < 60; ++k) sixty.follow(point, kFollowSeconds / 60);
  const Vector3d expected = start + (1.0 - std::exp(-1.0)) * (point - start);
  EXPECT_LT((once.target - expected).norm(), 1e-12);
  EXPECT_LT((sixty.target - expected).norm(), 1e-12);
  EXPECT_EQ(once.yaw, yaw);  // only the target moves: the view keeps its angle and distance
  EXPECT_EQ(once.distance, distance);
  for (int k = 0; k < 14 * 60; ++k) {
    sixty.follow(point, kFollowSeconds / 60);
    ASSERT_LE((sixty.target - start).dot(point - start), (point - start).squaredNorm());
  }
  EXPECT_LT((sixty.target - point).norm(), 1e-6 * (point - start).norm());
  const Vector3d held = once.target;
  once.follow(point, 0.0);
  EXPECT_EQ(once.target, held);
}

}  // namespace
}  // namespace puppet::viewer
