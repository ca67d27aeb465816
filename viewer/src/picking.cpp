#include "puppet/viewer/picking.h"

#include <cmath>
#include <limits>

namespace puppet::viewer {
namespace {

// entry distance of a ray into a sphere of radius r about c (the smaller root, 0 when inside)
std::optional<double> intersect_sphere(const Ray& ray, const Vector3d& c, double r) {
  const Vector3d m = ray.origin - c;
  const double b = m.dot(ray.direction);
  const double cc = m.squaredNorm() - r * r;
  if (cc <= 0.0) return 0.0;         // inside
  if (b > 0.0) return std::nullopt;  // outside and pointing away
  const double disc = b * b - cc;
  if (disc < 0.0) return std::nullopt;
  return -b - std::sqrt(disc);
}

// a capsule along z: the nearest of its cylinder's side and its two cap spheres
std::optional<double> intersect_capsule(const Ray& ray, double r, double h) {
  std::optional<double> best;
  auto keep = [&](std::optional<double> t) {
    if (t && (!best || *t < *best)) best = t;
  };
  keep(intersect_sphere(ray, {0, 0, h}, r));
  keep(intersect_sphere(ray, {0, 0, -h}, r));
  // the infinite cylinder x² + y² = r², kept where |z| ≤ h
  const double a = ray.direction.x() * ray.direction.x() + ray.direction.y() * ray.direction.y();
  const double b = ray.origin.x() * ray.direction.x() + ray.origin.y() * ray.direction.y();
  const double c = ray.origin.x() * ray.origin.x() + ray.origin.y() * ray.origin.y() - r * r;
  if (a > 1e-300) {
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double t = c <= 0.0 ? 0.0 : (-b - std::sqrt(disc)) / a;
      if (t >= 0.0 && std::abs(ray.at(t).z()) <= h) keep(t);
    }
  }
  return best;
}

// the side where |z| ≤ h and the two end caps
std::optional<double> intersect_cylinder(const Ray& ray, double r, double h) {
  std::optional<double> best;
  auto keep = [&](std::optional<double> t) {
    if (t && (!best || *t < *best)) best = t;
  };
  const double a = ray.direction.x() * ray.direction.x() + ray.direction.y() * ray.direction.y();
  const double b = ray.origin.x() * ray.direction.x() + ray.origin.y() * ray.direction.y();
  const double c = ray.origin.x() * ray.origin.x() + ray.origin.y() * ray.origin.y() - r * r;
  if (c <= 0.0 && std::abs(ray.origin.z()) <= h) return 0.0;  // starts inside
  if (a > 1e-300) {
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double t = (-b - std::sqrt(disc)) / a;
      if (t >= 0.0 && std::abs(ray.at(t).z()) <= h) keep(t);
    }
  }
  if (std::abs(ray.direction.z()) > 1e-300) {
    for (const double z : {h, -h}) {
      const double t = (z - ray.origin.z()) / ray.direction.z();
      const Vector3d p = ray.at(t);
      if (t >= 0.0 && p.x() * p.x() + p.y() * p.y() <= r * r) keep(t);
    }
  }
  return best;
}

// slabs: the latest entry and the earliest exit over the three axes
std::optional<double> intersect_box(const Ray& ray, const Vector3d& half) {
  double enter = 0.0, leave = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const double o = ray.origin[i], d = ray.direction[i];
    if (std::abs(d) < 1e-300) {
      if (std::abs(o) > half[i]) return std::nullopt;
      continue;
    }
    double t0 = (-half[i] - o) / d, t1 = (half[i] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return std::nullopt;
  }
  return enter;
}

}  // namespace

std::optional<double> intersect(const Shape& shape, const Ray& local_ray) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return intersect_sphere(local_ray, Vector3d::Zero(), shape.radius);
    case ShapeType::kCapsule:
      return intersect_capsule(local_ray, shape.radius, shape.half_length);
    case ShapeType::kBox:
      return intersect_box(local_ray, shape.half_extents);
    case ShapeType::kCylinder:
      return intersect_cylinder(local_ray, shape.radius, shape.half_length);
    case ShapeType::kEllipsoid: {
      // the unit sphere in coordinates scaled by the semi-axes, where the ray keeps its t but
      // not its unit direction: a t² + 2 b t + c = 0
      const Vector3d scale = shape.half_extents.cwiseInverse();
      const Vector3d m = local_ray.origin.cwiseProduct(scale);
      const Vector3d d = local_ray.direction.cwiseProduct(scale);
      const double a = d.squaredNorm(), b = m.dot(d), c = m.squaredNorm() - 1.0;
      if (c <= 0.0) return 0.0;
      if (b > 0.0) return std::nullopt;
      const double disc = b * b - a * c;
      if (disc < 0.0) return std::nullopt;
      return (-b - std::sqrt(disc)) / a;
    }
  }
  return std::nullopt;
}

Hit pick(const Model& model, std::span<const BodyState> bodies, const Ray& ray) {
  Hit hit;
  for (int s = 0; s < model.segment_count(); ++s) {
    const BodyState& body = bodies[s];
    const Quaterniond to_local = body.q.conjugate();
    const Ray local{to_local * (ray.origin - body.x), to_local * ray.direction};
    for (const Shape& shape : model.segments[s].shapes) {
      const Ray in_shape{to_shape(shape, local.origin),
                         shape.orientation.conjugate() * local.direction};
      const std::optional<double> t = intersect(shape, in_shape);
      if (t && (hit.segment < 0 || *t < hit.distance)) {
        hit.segment = s;
        hit.distance = *t;
        hit.local_point = local.at(*t);
      }
    }
  }
  if (hit.segment >= 0) hit.world_point = ray.at(hit.distance);
  return hit;
}

std::optional<Vector3d> DragPlane::intersect(const Ray& ray) const {
  const double along = ray.direction.dot(normal);
  if (std::abs(along) < 1e-9) return std::nullopt;
  const double t = (point - ray.origin).dot(normal) / along;
  if (t < 0.0) return std::nullopt;
  return ray.at(t);
}

}  // namespace puppet::viewer
