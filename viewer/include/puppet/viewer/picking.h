// What the mouse grabs: a ray against the model's shapes, and the camera-facing plane the
// grabbed point then moves in. Pure geometry, tested without a window.
#pragma once

#include <optional>
#include <span>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/viewer/camera.h"

namespace puppet::viewer {

// distance along a ray (given in the shape's segment frame) to where it enters the shape; a ray
// starting inside hits at 0
std::optional<double> intersect(const Shape& shape, const Ray& local_ray);

struct Hit {
  int segment = -1;               // -1: nothing hit
  double distance = 0.0;          // along the ray (m)
  Vector3d world_point{0, 0, 0};  // where the ray enters the segment
  Vector3d local_point{0, 0, 0};  // the same point in the segment frame
};

// the nearest segment along the ray
Hit pick(const Model& model, std::span<const BodyState> bodies, const Ray& ray);

// a plane through a point; a grabbed point is dragged in the plane facing the camera
struct DragPlane {
  Vector3d point{0, 0, 0};
  Vector3d normal{0, 0, 1};  // unit

  // where the ray meets the plane; nullopt when it runs parallel or away from it
  std::optional<Vector3d> intersect(const Ray& ray) const;
};

inline DragPlane facing_plane(const OrbitCamera& camera, const Vector3d& point) {
  return {point, camera.forward()};
}

}  // namespace puppet::viewer
