#include "puppet/model/environment.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace puppet {

std::vector<BodyState> rest_pose(const Model& model) {
  std::vector<BodyState> bodies(model.segment_count());
  for (int i = 0; i < model.segment_count(); ++i) {
    bodies[i].x = model.segments[i].rest_position;
    bodies[i].q = model.segments[i].rest_orientation;
  }
  return bodies;
}

double half_height(const Shape& shape, const Vector3d& up) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return shape.radius;
    case ShapeType::kCapsule:
      return std::abs(up.z()) * shape.half_length + shape.radius;
    case ShapeType::kBox:
      return up.cwiseAbs().dot(shape.half_extents);
    case ShapeType::kCylinder:
      return std::abs(up.z()) * shape.half_length +
             shape.radius * std::sqrt(std::max(0.0, 1.0 - up.z() * up.z()));
    case ShapeType::kEllipsoid:
      return shape.half_extents.cwiseProduct(up).norm();
  }
  return 0.0;
}

void shape_reach(const Shape& shape, const Vector3d& up, double* below, double* above) {
  const double centre = shape.position.dot(up);
  const double half = half_height(shape, shape.orientation.conjugate() * up);
  *below = half - centre;
  *above = half + centre;
}

void vertical_extent(const Segment& segment, const Quaterniond& q, const Vector3d& x, double* low,
                     double* high) {
  const Vector3d up = up_in_frame(q);
  if (lone_shape(segment)) {
    const double half = half_height(segment.shapes[0], up);
    *low = x.z() - half;
    *high = x.z() + half;
    return;
  }
  double below = -std::numeric_limits<double>::infinity(), above = below;
  for (const Shape& shape : segment.shapes) {
    double b = 0.0, a = 0.0;
    shape_reach(shape, up, &b, &a);
    below = std::max(below, b);
    above = std::max(above, a);
  }
  *low = x.z() - below;
  *high = x.z() + above;
}

double submerged_fraction(const Segment& segment, const Environment& environment,
                          const BodyState& body) {
  if (!environment.water) return 0.0;
  double low = 0.0, high = 0.0;
  vertical_extent(segment, body.q, body.x, &low, &high);
  return std::clamp((environment.water_level - low) / (high - low), 0.0, 1.0);
}

EnvironmentForce environment_force(const Segment& segment, const Environment& environment,
                                   const BodyState& body, double h) {
  const double f = submerged_fraction(segment, environment, body);
  if (!(f > 0.0))
    return air_force(segment, environment, body, step_drag_rate(environment.air_drag, h));
  EnvironmentForce out;
  // air drag −c·m·v and −c·I·ω; in water, drag −k·f·m·v and −k·f·I·ω by the same reading; each
  // as the rate that decays the velocity exactly over the step
  out.drag = step_drag_rate(environment.air_drag + environment.water_drag * f, h);
  out.force = segment.mass * environment.gravity - out.drag * segment.mass * body.v;
  // buoyancy ρ·V·f·|g| against gravity
  out.force -= environment.water_density * segment_volume(segment) * f * environment.gravity;
  return out;
}

Wrench pin_spring_wrench(const Pin& pin, const BodyState& body) {
  const Vector3d arm = body.q * pin.local_point;
  Wrench wrench;
  wrench.force = (pin.target - (body.x + arm)) / pin.compliance;
  wrench.torque = arm.cross(wrench.force);
  return wrench;
}

Wrench environment_wrench(const Segment& segment, const Environment& environment,
                          const BodyState& body, double h) {
  const EnvironmentForce linear = environment_force(segment, environment, body, h);
  Wrench wrench;
  wrench.force = linear.force;
  if (linear.drag != 0.0) {
    // I·ω = q (I_body (q⁻¹ ω)): two rotations instead of a world inertia matrix
    const Vector3d w_body = body.q.conjugate() * body.w;
    wrench.torque = -linear.drag * (body.q * segment.inertia.cwiseProduct(w_body));
  }
  return wrench;
}

Matrix3d world_inertia_inv(const Segment& segment, const Quaterniond& q) {
  const Vector3d& d = segment.inv_inertia;
  Matrix3d out;
  if (d.x() == d.y()) {
    // R diag(a, a, c) Rᵀ = a E + (c − a) u uᵀ, u = R e_z (the third column of R)
    const Vector3d u(2.0 * (q.x() * q.z() + q.w() * q.y()), 2.0 * (q.y() * q.z() - q.w() * q.x()),
                     1.0 - 2.0 * (q.x() * q.x() + q.y() * q.y()));
    out.noalias() = (d.z() - d.x()) * u * u.transpose();
    out.diagonal().array() += d.x();
    return out;
  }
  // R D⁻¹ Rᵀ is symmetric: six entries, each Σₖ R_ik dₖ R_jk
  const Matrix3d rotation = q.toRotationMatrix();
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      out(i, j) = out(j, i) = rotation(i, 0) * d.x() * rotation(j, 0) +
                              rotation(i, 1) * d.y() * rotation(j, 1) +
                              rotation(i, 2) * d.z() * rotation(j, 2);
    }
  }
  return out;
}

}  // namespace puppet
