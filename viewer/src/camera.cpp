#include "puppet/viewer/camera.h"

#include <algorithm>
#include <cmath>

namespace puppet::viewer {
namespace {

constexpr double kMaxPitch = 1.55;          // rad, just short of looking straight down
constexpr double kOrbitRadPerPixel = 0.01;  // a 628-pixel drag turns the camera once around
constexpr double kZoomPerStep = 0.9;
constexpr double kMinDistance = 0.2, kMaxDistance = 50.0;
const Vector3d kWorldUp{0, 0, 1};

}  // namespace

Vector3d OrbitCamera::back() const {
  return {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)};
}

Vector3d OrbitCamera::right() const { return forward().cross(kWorldUp).normalized(); }

Vector3d OrbitCamera::up() const { return right().cross(forward()); }

Matrix4d OrbitCamera::view() const {
  // rows: the camera's axes (OpenGL's eye space looks down −z)
  const Vector3d r = right(), u = up(), b = back(), e = eye();
  Matrix4d m = Matrix4d::Identity();
  m.block<1, 3>(0, 0) = r.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = b.transpose();
  m(0, 3) = -r.dot(e);
  m(1, 3) = -u.dot(e);
  m(2, 3) = -b.dot(e);
  return m;
}

Matrix4d OrbitCamera::projection() const {
  const double f = 1.0 / std::tan(0.5 * fov_y);
  const double aspect = static_cast<double>(width) / std::max(height, 1);
  Matrix4d m = Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far_plane + near_plane) / (near_plane - far_plane);
  m(2, 3) = 2.0 * far_plane * near_plane / (near_plane - far_plane);
  m(3, 2) = -1.0;
  return m;
}

double OrbitCamera::metres_per_pixel(double depth) const {
  return 2.0 * depth * std::tan(0.5 * fov_y) / std::max(height, 1);
}

Ray OrbitCamera::ray(const Vector2d& pixel) const {
  // the pixel's offset from the window's centre, in metres on the plane one metre ahead
  const double s = metres_per_pixel(1.0);
  const double x = (pixel.x() - 0.5 * width) * s;
  const double y = (0.5 * height - pixel.y()) * s;
  return {eye(), (forward() + x * right() + y * up()).normalized()};
}

bool OrbitCamera::project(const Vector3d& point, Vector2d* pixel) const {
  const Vector3d d = point - eye();
  const double depth = d.dot(forward());
  if (depth <= 0.0) return false;
  const double s = metres_per_pixel(depth);
  *pixel = {0.5 * width + d.dot(right()) / s, 0.5 * height - d.dot(up()) / s};
  return true;
}

void OrbitCamera::orbit(const Vector2d& pixels) {
  // dragging right turns the scene with the mouse: the eye moves the other way
  yaw -= kOrbitRadPerPixel * pixels.x();
  pitch = std::clamp(pitch + kOrbitRadPerPixel * pixels.y(), -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(const Vector2d& pixels) {
  const double s = metres_per_pixel(distance);
  target += s * (-pixels.x() * right() + pixels.y() * up());
}

void OrbitCamera::zoom(double steps) {
  distance = std::clamp(distance * std::pow(kZoomPerStep, steps), kMinDistance, kMaxDistance);
}

void OrbitCamera::frame(const Vector3d& low, const Vector3d& high) {
  target = 0.5 * (low + high);
  const double radius = 0.5 * (high - low).norm();
  // the bounding sphere fits the vertical field of view with a margin
  distance = std::clamp(1.15 * radius / std::sin(0.5 * fov_y), kMinDistance, kMaxDistance);
}

void OrbitCamera::follow(const Vector3d& point, double seconds) {
  if (!(seconds > 0.0)) return;
  target += (1.0 - std::exp(-seconds / kFollowSeconds)) * (point - target);
}

}  // namespace puppet::viewer
