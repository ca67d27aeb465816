#include "puppet/compare/metrics.h"

#include <algorithm>
#include <cmath>

#include "puppet/model/euler_box.h"
#include "puppet/model/joint_springs.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"

namespace puppet::compare {

void joint_gaps(const Model& model, std::span<const BodyState> b, std::span<double> out) {
  for (int j = 0; j < model.joint_count(); ++j) {
    const Joint& joint = model.joints[j];
    const BodyState &parent = b[joint.parent], &child = b[joint.child];
    const Vector3d c_parent = parent.x + parent.q * parent_anchor(joint, parent.q, child.q);
    const Vector3d c_child = b[joint.child].x + b[joint.child].q * joint.anchor_in_child;
    Vector3d d = c_child - c_parent;
    if (joint.type == JointType::kSlide) {
      // a slide's point may move along its direction, within its range
      const Vector3d a = parent.q * (joint.frame_in_parent * joint.hinge_axis);
      d -= std::clamp(a.dot(d), joint.lower, joint.upper) * a;
    }
    out[j] = d.norm();
  }
}

void pin_gaps(std::span<const Pin> pins, std::span<const Vector3d> targets,
              std::span<const BodyState> b, std::span<double> out) {
  for (size_t i = 0; i < pins.size(); ++i) {
    const BodyState& body = b[pins[i].segment];
    // a grab's distance to its target is its law's stretch, not a violation
    out[i] = pins[i].is_grab() ? 0.0 : (body.x + body.q * pins[i].local_point - targets[i]).norm();
  }
}

void limit_violations_deg(const Model& model, std::span<const BodyState> b, std::span<double> out) {
  for (int j = 0; j < model.joint_count(); ++j) {
    const Joint& joint = model.joints[j];
    const Quaterniond q_rel = joint_relative_rotation(joint, b[joint.parent].q, b[joint.child].q);
    out[j] = limit_violation(joint, q_rel) * 180.0 / M_PI;
  }
}

double kinetic_energy(const Model& model, std::span<const BodyState> b) {
  double energy = 0.0;
  for (int i = 0; i < model.segment_count(); ++i) {
    const Segment& s = model.segments[i];
    const Vector3d w_body = b[i].q.conjugate() * b[i].w;
    energy +=
        0.5 * s.mass * b[i].v.squaredNorm() + 0.5 * w_body.dot(s.inertia.cwiseProduct(w_body));
  }
  return energy;
}

double mechanical_energy(const Model& model, const Environment& environment,
                         std::span<const BodyState> b) {
  double potential = 0.0;
  for (int i = 0; i < model.segment_count(); ++i) {
    potential -= model.segments[i].mass * environment.gravity.dot(b[i].x);
  }
  return kinetic_energy(model, b) + potential + joint_spring_energy(model, b);
}

Vector3d centre_of_mass(const Model& model, std::span<const BodyState> b) {
  Vector3d sum{0, 0, 0};
  for (int i = 0; i < model.segment_count(); ++i) sum += model.segments[i].mass * b[i].x;
  return sum / model.total_mass;
}

Vector3d linear_momentum(const Model& model, std::span<const BodyState> b) {
  Vector3d p{0, 0, 0};
  for (int i = 0; i < model.segment_count(); ++i) p += model.segments[i].mass * b[i].v;
  return p;
}

Vector3d angular_momentum(const Model& model, std::span<const BodyState> b) {
  const Vector3d com = centre_of_mass(model, b);
  Vector3d l{0, 0, 0};
  for (int i = 0; i < model.segment_count(); ++i) {
    const Segment& s = model.segments[i];
    l += (b[i].x - com).cross(s.mass * b[i].v) + world_inertia(s, b[i].q) * b[i].w;
  }
  return l;
}

double ground_penetration(const Model& model, std::span<const BodyState> b) {
  double deepest = 0.0;
  for (int i = 0; i < model.segment_count(); ++i) {
    double low = 0.0, high = 0.0;
    vertical_extent(model.segments[i], b[i].q, b[i].x, &low, &high);
    deepest = std::max(deepest, -low);
  }
  return deepest;
}

double peak_speed(std::span<const BodyState> b) {
  double peak = 0.0;
  for (const BodyState& body : b) peak = std::max(peak, body.v.norm());
  return peak;
}

double energy_reference(const Model& model, const Environment& environment,
                        std::span<const BodyState> initial) {
  return model.total_mass * std::max(environment.gravity.norm(), kStandardGravity) *
             model.rest_height +
         kinetic_energy(model, initial);
}

double pose_error(std::span<const BodyState> bodies, std::span<const BodyState> truth) {
  double sum = 0.0;
  for (size_t i = 0; i < bodies.size(); ++i) sum += (bodies[i].x - truth[i].x).squaredNorm();
  return bodies.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(bodies.size()));
}

double joint_angle_error_deg(const Model& model, std::span<const BodyState> bodies,
                             std::span<const BodyState> truth) {
  if (model.joints.empty()) return 0.0;
  double sum = 0.0;
  for (const Joint& j : model.joints) {
    const Quaterniond q = joint_relative_rotation(j, bodies[j.parent].q, bodies[j.child].q);
    const Quaterniond q_truth = joint_relative_rotation(j, truth[j.parent].q, truth[j.child].q);
    const double angle = angle_between(q, q_truth);
    sum += angle * angle;
  }
  return std::sqrt(sum / model.joint_count()) * 180.0 / M_PI;
}

MetricsProbe::MetricsProbe(const Model& model, const Environment& environment,
                           std::span<const Pin> pins, std::span<const BodyState> initial)
    : model_(model),
      environment_(environment),
      pins_(pins.begin(), pins.end()),
      kinetic0_(kinetic_energy(model, initial)),
      spring0_(joint_spring_energy(model, initial)),
      energy_ref_(energy_reference(model, environment, initial)),
      momentum0_(linear_momentum(model, initial)),
      angular0_(angular_momentum(model, initial)),
      joint_buffer_(model.joint_count()),
      pin_buffer_(pins.size()) {
  for (const BodyState& b : initial) initial_x_.push_back(b.x);
  // M·v_rms(0), v_rms² = Σ m v² / M
  double mv2 = 0.0;
  for (int i = 0; i < model.segment_count(); ++i) {
    mv2 += model.segments[i].mass * initial[i].v.squaredNorm();
  }
  momentum_scale_ = std::sqrt(mv2 * model.total_mass);
}

StepMetrics MetricsProbe::measure(double t, std::span<const BodyState> bodies,
                                  std::span<const Vector3d> targets) {
  StepMetrics m;
  m.t = t;
  if (!all_finite(bodies)) {
    m.finite = false;
    return m;
  }
  joint_gaps(model_, bodies, joint_buffer_);
  double sum2 = 0.0;
  for (double g : joint_buffer_) {
    m.joint_gap_max = std::max(m.joint_gap_max, g);
    sum2 += g * g;
  }
  if (!joint_buffer_.empty()) m.joint_gap_rms = std::sqrt(sum2 / joint_buffer_.size());
  // the world's hold on the root is a joint too: its point's stray
  m.joint_gap_max = std::max(m.joint_gap_max, root_gap(model_, bodies[0]).distance);
  pin_gaps(pins_, targets, bodies, pin_buffer_);
  for (double g : pin_buffer_) m.pin_gap_max = std::max(m.pin_gap_max, g);
  limit_violations_deg(model_, bodies, joint_buffer_);
  for (double v : joint_buffer_) m.limit_violation_max_deg = std::max(m.limit_violation_max_deg, v);
  double potential_change = 0.0;
  for (int i = 0; i < model_.segment_count(); ++i) {
    potential_change -=
        model_.segments[i].mass * environment_.gravity.dot(bodies[i].x - initial_x_[i]);
  }
  // the joints' springs hold energy of their own (their dampers take it away, as drag does)
  potential_change += joint_spring_energy(model_, bodies) - spring0_;
  m.energy_drift = (kinetic_energy(model_, bodies) - kinetic0_ + potential_change) / energy_ref_;
  if (momentum_scale_ > 0.0) {
    m.linear_momentum_drift =
        (linear_momentum(model_, bodies) - momentum0_).norm() / momentum_scale_;
  }
  if (angular0_.norm() > 0.0) {
    m.angular_momentum_drift =
        (angular_momentum(model_, bodies) - angular0_).norm() / angular0_.norm();
  }
  if (environment_.ground) m.penetration = ground_penetration(model_, bodies);
  m.peak_speed = peak_speed(bodies);
  return m;
}

}  // namespace puppet::compare
