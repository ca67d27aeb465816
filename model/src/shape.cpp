#include <algorithm>
#include <cmath>

#include "puppet/model/model.h"

namespace puppet {

double shape_volume(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return 4.0 / 3.0 * M_PI * std::pow(shape.radius, 3);
    case ShapeType::kCapsule:
      return M_PI * shape.radius * shape.radius * 2.0 * shape.half_length +
             4.0 / 3.0 * M_PI * std::pow(shape.radius, 3);
    case ShapeType::kBox:
      return 8.0 * shape.half_extents.prod();
    case ShapeType::kCylinder:
      return M_PI * shape.radius * shape.radius * 2.0 * shape.half_length;
  }
  return 0.0;
}

void derive_mass_terms(Segment& segment) {
  segment.inv_mass = 1.0 / segment.mass;
  segment.inv_inertia = segment.inertia.cwiseInverse();
}

bool is_principal_frame(const Segment& segment, const Quaterniond& frame) {
  const Matrix3d r = frame.toRotationMatrix();
  const Matrix3d inertia = r.transpose() * segment.inertia.asDiagonal() * r;
  const Matrix3d off = inertia - Matrix3d(inertia.diagonal().asDiagonal());
  return off.cwiseAbs().maxCoeff() <= 1e-9 * segment.inertia.maxCoeff();
}

Vector3d solid_inertia(const Shape& shape, double mass) {
  switch (shape.type) {
    case ShapeType::kSphere: {
      const double i = 0.4 * mass * shape.radius * shape.radius;
      return {i, i, i};
    }
    case ShapeType::kBox: {
      const Vector3d e = 2.0 * shape.half_extents;
      return {mass / 12.0 * (e.y() * e.y() + e.z() * e.z()),
              mass / 12.0 * (e.x() * e.x() + e.z() * e.z()),
              mass / 12.0 * (e.x() * e.x() + e.y() * e.y())};
    }
    case ShapeType::kCylinder: {
      const double r = shape.radius, h = shape.half_length;
      const double transverse = mass * (3.0 * r * r + 4.0 * h * h) / 12.0;
      return {transverse, transverse, 0.5 * mass * r * r};
    }
    case ShapeType::kCapsule: {
      // cylinder of height 2h plus two hemispherical caps, mass split by volume; each cap's
      // inertia about the centre by the parallel-axis theorem from its own centre of mass
      const double r = shape.radius, h = shape.half_length;
      const double v_cyl = M_PI * r * r * 2.0 * h;
      const double v_caps = 4.0 / 3.0 * M_PI * r * r * r;
      const double m_cyl = mass * v_cyl / (v_cyl + v_caps);
      const double m_cap = 0.5 * (mass - m_cyl);  // one hemisphere
      const double axial = 0.5 * m_cyl * r * r + 2.0 * (0.4 * m_cap * r * r);
      const double cap_com = 3.0 / 8.0 * r;  // hemisphere COM from its flat face
      const double cap_own = (0.4 - 9.0 / 64.0) * m_cap * r * r;  // about its own COM
      const double d = h + cap_com;
      const double transverse =
          m_cyl * (3.0 * r * r + 4.0 * h * h) / 12.0 + 2.0 * (cap_own + m_cap * d * d);
      return {transverse, transverse, axial};
    }
  }
  return {0, 0, 0};
}

Vector3d support_point(const Shape& shape, const Vector3d& direction) {
  const Vector3d d = direction.normalized();
  auto sign = [](double value) {
    return std::abs(value) < 1e-12 ? 0.0 : std::copysign(1.0, value);
  };
  switch (shape.type) {
    case ShapeType::kSphere:
      return shape.radius * d;
    case ShapeType::kCapsule:
      return Vector3d(0, 0, sign(d.z()) * shape.half_length) + shape.radius * d;
    case ShapeType::kBox:
      return Vector3d(sign(d.x()) * shape.half_extents.x(), sign(d.y()) * shape.half_extents.y(),
                      sign(d.z()) * shape.half_extents.z());
    case ShapeType::kCylinder: {
      // the rim of the end cap facing d; straight along the axis, the cap's centre
      const double radial = std::hypot(d.x(), d.y());
      const Vector3d rim = radial < 1e-12 ? Vector3d::Zero()
                                          : Vector3d(shape.radius * d.x() / radial,
                                                     shape.radius * d.y() / radial, 0.0);
      return rim + Vector3d(0, 0, sign(d.z()) * shape.half_length);
    }
  }
  return Vector3d::Zero();
}

double signed_distance(const Shape& shape, const Vector3d& p) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return p.norm() - shape.radius;
    case ShapeType::kCapsule: {
      const Vector3d on_axis(0, 0, std::clamp(p.z(), -shape.half_length, shape.half_length));
      return (p - on_axis).norm() - shape.radius;
    }
    case ShapeType::kBox: {
      const Vector3d q = p.cwiseAbs() - shape.half_extents;
      const double outside = q.cwiseMax(0.0).norm();
      const double inside = std::min(q.maxCoeff(), 0.0);
      return outside + inside;
    }
    case ShapeType::kCylinder: {
      const Eigen::Vector2d q(std::hypot(p.x(), p.y()) - shape.radius,
                              std::abs(p.z()) - shape.half_length);
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    }
  }
  return 0.0;
}

}  // namespace puppet
