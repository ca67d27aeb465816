// The viewer's camera: it orbits a target point, z up, and converts between world points and
// window pixels. Pixels are (x right, y down) from the window's top-left corner, as GLFW reports
// the mouse. Pure maths, tested without a window.
#pragma once

#include <Eigen/Geometry>

namespace puppet::viewer {

using Eigen::Matrix4d;
using Eigen::Vector2d;
using Eigen::Vector3d;

// the time constant of OrbitCamera::follow (s): a third of a second, about a swing's quarter
inline constexpr double kFollowSeconds = 0.3;

// a half-line; direction is unit length
struct Ray {
  Vector3d origin{0, 0, 0};
  Vector3d direction{1, 0, 0};

  Vector3d at(double t) const { return origin + t * direction; }
};

class OrbitCamera {
 public:
  Vector3d target{0, 0, 1};
  double yaw = -0.87;     // rad, the eye's direction from the target about z, from +x
  double pitch = 0.17;    // rad, the eye's elevation above the target, |pitch| < 89°
  double distance = 3.0;  // m, eye to target
  double fov_y = 0.7;     // rad, vertical field of view
  double near_plane = 0.02, far_plane = 100.0;
  int width = 1280, height = 720;  // the window in pixels

  // unit vector from the target to the eye
  Vector3d back() const;
  Vector3d eye() const { return target + distance * back(); }
  // the camera's axes in world: right, up (screen up) and forward (into the screen)
  Vector3d right() const;
  Vector3d up() const;
  Vector3d forward() const { return -back(); }

  // OpenGL's conventions: column vectors, clip z in [−w, w]
  Matrix4d view() const;
  Matrix4d projection() const;

  // the ray from the eye through a pixel (its centre at half-integer coordinates)
  Ray ray(const Vector2d& pixel) const;
  // the pixel a world point falls on; false when it lies behind the eye
  bool project(const Vector3d& point, Vector2d* pixel) const;
  // metres in the plane at `depth` in front of the eye that one pixel spans
  double metres_per_pixel(double depth) const;

  // mouse gestures: orbit by a pixel motion, pan the target in the view plane so that the point
  // under the mouse at the target's depth follows it, zoom by wheel steps (each 10 %)
  void orbit(const Vector2d& pixels);
  void pan(const Vector2d& pixels);
  void zoom(double steps);
  // aims at the centre of a box and backs away until it fits the view
  void frame(const Vector3d& low, const Vector3d& high);
  // moves the target toward `point` over `seconds`, closing the distance as e^(−t/τ) with
  // τ = kFollowSeconds: the view keeps a falling or swinging figure in sight without jerking
  void follow(const Vector3d& point, double seconds);
};

}  // namespace puppet::viewer
