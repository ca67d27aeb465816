#include "puppet/model/joint_springs.h"

#include <algorithm>
#include <cmath>

#include "puppet/model/euler_box.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"

namespace puppet {
namespace {

// the joint's frame in world as each segment carries it
Quaterniond parent_frame(const Joint& joint, const BodyState& parent) {
  return parent.q * joint.frame_in_parent;
}
Quaterniond child_frame(const Joint& joint, const BodyState& child) {
  return child.q * joint.frame_in_child;
}

// the world inverse inertia of relative rotation between the two segments, K = I_p⁻¹ + I_c⁻¹
// (the joint's point constraint only adds inertia, so K bounds what the joint sees)
Matrix3d relative_inverse_inertia(const Segment& parent, const BodyState& p, const Segment& child,
                                  const BodyState& c) {
  const Matrix3d rp = p.q.toRotationMatrix(), rc = c.q.toRotationMatrix();
  return rp * parent.inv_inertia.asDiagonal() * rp.transpose() +
         rc * child.inv_inertia.asDiagonal() * rc.transpose();
}

// whether the joint has a spring or a damper on any of its degrees of freedom
bool sprung(const Joint& joint) {
  return joint.type != JointType::kFixed &&
         std::any_of(joint.passive.begin(), joint.passive.end(), [](const JointPassive& dof) {
           return dof.stiffness != 0.0 || dof.damping != 0.0;
         });
}

// the damper's coefficient over a step of length h, integrated implicitly about one degree of
// freedom of inverse inertia k: d / (1 + h d k)
double implicit_damping(double damping, double h, double inverse_inertia) {
  return damping / (1.0 + h * damping * inverse_inertia);
}

}  // namespace

bool has_joint_springs(const Model& model) {
  return std::any_of(model.joints.begin(), model.joints.end(), sprung) ||
         std::any_of(
             model.root.passive.begin(), model.root.passive.end(),
             [](const JointPassive& dof) { return dof.stiffness != 0.0 || dof.damping != 0.0; });
}

bool has_armature(const Model& model) {
  const auto armed = [](const JointPassive& dof) { return dof.armature != 0.0; };
  return std::any_of(model.root.passive.begin(), model.root.passive.end(), armed) ||
         std::any_of(model.joints.begin(), model.joints.end(), [&](const Joint& joint) {
           return std::any_of(joint.passive.begin(), joint.passive.end(), armed);
         });
}

JointCoordinates joint_coordinates(const Joint& joint, const BodyState& parent,
                                   const BodyState& child) {
  JointCoordinates c;
  const Quaterniond fp = parent_frame(joint, parent), fc = child_frame(joint, child);
  Quaterniond relative = fp.conjugate() * fc;
  if (relative.w() < 0.0) relative.coeffs() = -relative.coeffs();
  const Vector3d omega = fc.conjugate() * (child.w - parent.w);  // in the child's joint frame
  if (joint.type == JointType::kHinge) {
    const Vector3d& a = joint.hinge_axis;
    c.angle[0] = 2.0 * std::atan2(a.dot(relative.vec()), relative.w());  // w ≥ 0: within ±π
    c.rate[0] = a.dot(omega);
  } else if (joint.type == JointType::kSlide) {
    // s = a·d, d the child's point less the parent's and a the direction the parent carries:
    // ṡ = a·ḋ + (ω_p × a)·d
    const Vector3d a = fp * joint.hinge_axis;
    const Vector3d r_parent = parent.q * joint.anchor_in_parent;
    const Vector3d r_child = child.q * joint.anchor_in_child;
    const Vector3d d = (child.x + r_child) - (parent.x + r_parent);
    const Vector3d d_rate =
        (child.v + child.w.cross(r_child)) - (parent.v + parent.w.cross(r_parent));
    c.angle[0] = a.dot(d);
    c.rate[0] = a.dot(d_rate) + parent.w.cross(a).dot(d);
  } else if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox) {
    c.angle = euler_angles(joint.box_order, relative);
    c.rate = euler_gradients(joint.box_order, c.angle) * omega;
  } else if (joint.type == JointType::kBall) {
    c.angle = quat_log(relative);
    c.rate = omega;
  }
  return c;
}

void add_joint_spring_wrenches(const Model& model, std::span<const BodyState> bodies, double h,
                               std::span<Wrench> out) {
  for (const Joint& joint : model.joints) {
    if (!sprung(joint)) continue;
    const JointPassive* spring = joint.passive.data();
    const BodyState& parent = bodies[static_cast<size_t>(joint.parent)];
    const BodyState& child = bodies[static_cast<size_t>(joint.child)];
    const JointCoordinates c = joint_coordinates(joint, parent, child);
    if (joint.type == JointType::kSlide) {
      // a force along the slide at each side's point (their line is the slide's, so the pair
      // turns nothing), the damper implicit in the two masses
      const Segment& p = model.segments[static_cast<size_t>(joint.parent)];
      const Segment& q = model.segments[static_cast<size_t>(joint.child)];
      const double f = -spring[0].stiffness * (c.angle[0] - spring[0].spring_ref) -
                       implicit_damping(spring[0].damping, h, p.inv_mass + q.inv_mass) * c.rate[0];
      const Vector3d force = f * (parent.q * (joint.frame_in_parent * joint.hinge_axis));
      Wrench& on_child = out[static_cast<size_t>(joint.child)];
      Wrench& on_parent = out[static_cast<size_t>(joint.parent)];
      on_child.force += force;
      on_child.torque += (child.q * joint.anchor_in_child).cross(force);
      on_parent.force -= force;
      on_parent.torque -= (parent.q * joint.anchor_in_parent).cross(force);
      continue;
    }
    const Matrix3d r = child_frame(joint, child).toRotationMatrix();  // the child's joint frame
    // K in the child's joint frame, where the coordinates' rates are taken
    const Matrix3d k =
        r.transpose() *
        relative_inverse_inertia(model.segments[static_cast<size_t>(joint.parent)], parent,
                                 model.segments[static_cast<size_t>(joint.child)], child) *
        r;
    Vector3d torque_in_joint{0, 0, 0};  // on the child, in its joint frame
    if (joint.type == JointType::kHinge) {
      const JointPassive& s = spring[0];
      const Vector3d& a = joint.hinge_axis;
      const double f = -s.stiffness * (c.angle[0] - s.spring_ref) -
                       implicit_damping(s.damping, h, a.dot(k * a)) * c.rate[0];
      torque_in_joint = f * a;
    } else if (joint.ball_limit == BallLimit::kEulerBox) {
      // f·θ̇ = f·(G ω) = (Gᵀ f)·ω: the torque is Gᵀ f; angle a's inverse inertia g_a K g_aᵀ
      const Matrix3d g = euler_gradients(joint.box_order, c.angle);
      Vector3d f;
      for (int a = 0; a < 3; ++a) {
        const JointPassive& s = spring[a];
        const double k_a = g.row(a) * k * g.row(a).transpose();
        f[a] = -s.stiffness * (c.angle[a] - s.spring_ref) -
               implicit_damping(s.damping, h, k_a) * c.rate[a];
      }
      torque_in_joint = g.transpose() * f;
    } else {
      // the three rates together: ω' = (1 + h d K)⁻¹ ω, the damper's torque d ω'
      const JointPassive& s = spring[0];
      const Vector3d rate =
          s.damping == 0.0
              ? c.rate
              : Vector3d((Matrix3d::Identity() + h * s.damping * k).ldlt().solve(c.rate));
      torque_in_joint = -s.stiffness * c.angle - s.damping * rate;
    }
    const Vector3d torque = r * torque_in_joint;
    out[static_cast<size_t>(joint.child)].torque += torque;
    out[static_cast<size_t>(joint.parent)].torque -= torque;
  }
  add_root_spring_wrench(model, bodies[0], h, out[0]);
}

void add_root_spring_wrench(const Model& model, const BodyState& body, double h, Wrench& out) {
  const RootCoordinates c = root_coordinates(model, body);
  const RootJoint& root = model.root;
  const Segment& segment = model.segments[0];
  const Vector3d arm = body.q * root.anchor_in_root;
  for (int k = 0; k < c.count; ++k) {
    const JointPassive& s = root.passive[static_cast<size_t>(k)];
    if (s.stiffness == 0.0 && s.damping == 0.0) continue;
    const Vector3d& a = root.axes[static_cast<size_t>(k)];
    if (k < root_slide_count(root.hold)) {
      // a force along the slide at the anchor: a generalized force on the slide alone (its lever
      // about a planar root's hinge is the hinge's own); the damper implicit in the mass
      const double f = -s.stiffness * (c.value[k] - s.spring_ref) -
                       implicit_damping(s.damping, h, segment.inv_mass) * c.rate[k];
      out.force += f * a;
      out.torque += arm.cross(f * a);
    } else {
      // a torque about the hinge; the damper implicit in the inertia about the hinge's line
      const Matrix3d rotation = body.q.toRotationMatrix();
      const double about_centre =
          a.dot(rotation * segment.inertia.cwiseProduct(rotation.transpose() * a));
      const double about_line = about_centre + segment.mass * a.cross(arm).squaredNorm();
      const double f = -s.stiffness * (c.value[k] - s.spring_ref) -
                       implicit_damping(s.damping, h, 1.0 / about_line) * c.rate[k];
      out.torque += f * a;
    }
  }
}

double joint_spring_energy(const Model& model, std::span<const BodyState> bodies) {
  double energy = 0.0;
  for (const Joint& joint : model.joints) {
    if (joint.type == JointType::kFixed) continue;
    const JointPassive* spring = joint.passive.data();
    if (std::all_of(spring, spring + 3, [](const JointPassive& s) { return s.stiffness == 0.0; })) {
      continue;
    }
    const JointCoordinates c = joint_coordinates(joint, bodies[static_cast<size_t>(joint.parent)],
                                                 bodies[static_cast<size_t>(joint.child)]);
    if (joint.type == JointType::kHinge || joint.type == JointType::kSlide) {
      const double stretch = c.angle[0] - spring[0].spring_ref;
      energy += 0.5 * spring[0].stiffness * stretch * stretch;
    } else if (joint.ball_limit == BallLimit::kEulerBox) {
      for (int a = 0; a < 3; ++a) {
        const double stretch = c.angle[a] - spring[a].spring_ref;
        energy += 0.5 * spring[a].stiffness * stretch * stretch;
      }
    } else {
      energy += 0.5 * spring[0].stiffness * c.angle.squaredNorm();
    }
  }
  // the world's joint on the root: one spring per coordinate
  const RootCoordinates root = root_coordinates(model, bodies[0]);
  for (int k = 0; k < root.count; ++k) {
    const JointPassive& spring = model.root.passive[static_cast<size_t>(k)];
    const double stretch = root.value[k] - spring.spring_ref;
    energy += 0.5 * spring.stiffness * stretch * stretch;
  }
  return energy;
}

const Model& armature_in_inertia(const Model& model, std::optional<Model>& holder) {
  if (!has_armature(model)) return model;
  holder = model;
  for (const Joint& joint : model.joints) {
    Segment& child = holder->segments[static_cast<size_t>(joint.child)];
    const auto add_about = [&](const Vector3d& axis_in_joint, double armature) {
      const Vector3d a = joint.frame_in_child * axis_in_joint;  // in the child's frame
      child.inertia += armature * a.cwiseProduct(a);
    };
    if (joint.type == JointType::kHinge) {
      add_about(joint.hinge_axis, joint.passive[0].armature);
    } else if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox) {
      for (size_t k = 0; k < 3; ++k) {
        add_about(Vector3d::Unit(joint.box_order.axes[k]), joint.passive[k].armature);
      }
    } else if (joint.type == JointType::kBall) {
      child.inertia += Vector3d::Constant(joint.passive[0].armature);
    }
    derive_mass_terms(child);
  }
  // (a slide's armature, on the root or below it, is refused by the engines that take this model:
  // no inertia of a body gives it)
  // the world's hinge on the root: its rotor about the hinge's axis
  const RootJoint& root = model.root;
  const int hinge = root_hinge_index(root.hold);
  if (hinge >= 0) {
    Segment& base = holder->segments[0];
    const Vector3d a = base.rest_orientation.conjugate() * root.axes[static_cast<size_t>(hinge)];
    base.inertia += root.passive[static_cast<size_t>(hinge)].armature * a.cwiseProduct(a);
    derive_mass_terms(base);
  }
  return *holder;
}

}  // namespace puppet
