#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <array>

#include "model_builder.h"
#include "puppet/model/model.h"

namespace puppet {

const char* shape_type_name(ShapeType type) {
  switch (type) {
    case ShapeType::kSphere:
      return "sphere";
    case ShapeType::kCapsule:
      return "capsule";
    case ShapeType::kBox:
      return "box";
    case ShapeType::kCylinder:
      return "cylinder";
    case ShapeType::kEllipsoid:
      return "ellipsoid";
  }
  return "?";
}

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
    case ShapeType::kEllipsoid:
      return 4.0 / 3.0 * M_PI * shape.half_extents.prod();
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
    case ShapeType::kEllipsoid: {
      const Vector3d e2 = shape.half_extents.cwiseAbs2();
      return {mass / 5.0 * (e2.y() + e2.z()), mass / 5.0 * (e2.x() + e2.z()),
              mass / 5.0 * (e2.x() + e2.y())};
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
    case ShapeType::kEllipsoid: {
      // the point where the normal, E⁻²p, is along d: p = E² d / |E d|
      const Vector3d scaled = shape.half_extents.cwiseProduct(d);
      return shape.half_extents.cwiseProduct(scaled) / scaled.norm();
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
    case ShapeType::kEllipsoid: {
      // |p/E| − 1 scaled by the smallest semi-axis: zero on the surface, of the right sign,
      // exact along the axes and never more than the true distance in magnitude
      const double k = p.cwiseQuotient(shape.half_extents).norm();
      return (k - 1.0) * shape.half_extents.minCoeff();
    }
  }
  return 0.0;
}

Vector3d to_shape(const Shape& shape, const Vector3d& in_segment) {
  return shape.orientation.conjugate() * (in_segment - shape.position);
}

Vector3d from_shape(const Shape& shape, const Vector3d& in_shape) {
  return shape.position + shape.orientation * in_shape;
}

Vector3d support_point(const Segment& segment, const Vector3d& direction) {
  Vector3d best = Vector3d::Zero();
  double reach = -std::numeric_limits<double>::infinity();
  for (const Shape& shape : segment.shapes) {
    const Vector3d p =
        from_shape(shape, support_point(shape, shape.orientation.conjugate() * direction));
    if (p.dot(direction) > reach) {
      reach = p.dot(direction);
      best = p;
    }
  }
  return best;
}

double signed_distance(const Segment& segment, const Vector3d& point) {
  double least = std::numeric_limits<double>::infinity();
  for (const Shape& shape : segment.shapes) {
    least = std::min(least, signed_distance(shape, to_shape(shape, point)));
  }
  return least;
}

double segment_volume(const Segment& segment) {
  double volume = 0.0;
  for (const Shape& shape : segment.shapes) volume += shape_volume(shape);
  return volume;
}

namespace detail {

void Composite::add(const Shape& shape, double solid_mass) {
  mass += solid_mass;
  weighted_sum += solid_mass * shape.position;
  const Matrix3d r = shape.orientation.toRotationMatrix();
  const Vector3d& c = shape.position;
  inertia_at_origin += r * solid_inertia(shape, solid_mass).asDiagonal() * r.transpose() +
                       solid_mass * (c.squaredNorm() * Matrix3d::Identity() - c * c.transpose());
}

Matrix3d Composite::inertia() const {
  const Vector3d c = centre();
  return inertia_at_origin - mass * (c.squaredNorm() * Matrix3d::Identity() - c * c.transpose());
}

void principal_frame(const Matrix3d& inertia, const Quaterniond& near, Quaterniond* frame,
                     Vector3d* moments) {
  const Matrix3d a = near.toRotationMatrix();
  const Matrix3d seen = a.transpose() * inertia * a;
  const Matrix3d off = seen - Matrix3d(seen.diagonal().asDiagonal());
  if (off.cwiseAbs().maxCoeff() <= 1e-12 * seen.diagonal().cwiseAbs().maxCoeff()) {
    *frame = near;
    *moments = seen.diagonal();
    return;
  }
  const Eigen::SelfAdjointEigenSolver<Matrix3d> solver(inertia);
  const Matrix3d v = solver.eigenvectors();
  const Vector3d values = solver.eigenvalues();
  // each permutation of the eigenvectors, signed to align with near's axes (the third sign
  // makes the frame right-handed): the one whose axes are nearest near's
  constexpr std::array<std::array<int, 3>, 6> kPermutations = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  double best = -INFINITY;
  for (const auto& p : kPermutations) {
    Matrix3d r;
    for (int k = 0; k < 2; ++k) {
      r.col(k) = v.col(p[k]);
      if (r.col(k).dot(a.col(k)) < 0.0) r.col(k) = -r.col(k);
    }
    r.col(2) = r.col(0).cross(r.col(1));
    const double alignment = (a.transpose() * r).trace();
    if (alignment > best) {
      best = alignment;
      *frame = Quaterniond(r).normalized();
      *moments = Vector3d(values[p[0]], values[p[1]], values[p[2]]);
    }
  }
}

void place_solids(const std::vector<Shape>& solids, const std::vector<double>& masses,
                  const Vector3d& x, const Quaterniond& q, Segment& segment) {
  segment.shapes.clear();
  if (solids.size() == 1) {
    segment.mass = masses[0];
    segment.inertia = solid_inertia(solids[0], masses[0]);
    segment.rest_position = x + q * solids[0].position;
    segment.rest_orientation = (q * solids[0].orientation).normalized();
    Shape centred = solids[0];
    centred.position.setZero();
    centred.orientation.setIdentity();
    segment.shapes.push_back(centred);
  } else {
    Composite composite;
    for (size_t k = 0; k < solids.size(); ++k) composite.add(solids[k], masses[k]);
    const Vector3d centre = composite.centre();
    Quaterniond frame;
    principal_frame(composite.inertia(), solids[0].orientation, &frame, &segment.inertia);
    segment.mass = composite.mass;
    segment.rest_position = x + q * centre;
    segment.rest_orientation = (q * frame).normalized();
    for (const Shape& solid : solids) {
      Shape placed = solid;
      placed.position = frame.conjugate() * (solid.position - centre);
      placed.orientation = (frame.conjugate() * solid.orientation).normalized();
      segment.shapes.push_back(placed);
    }
  }
  derive_mass_terms(segment);
}

}  // namespace detail

}  // namespace puppet
