// btMultiBody stepped, its pins set and moved, its state read, set, saved and loaded
// (multibody.h)
#include "multibody.h"
#include "puppet/model/root_joint.h"

namespace puppet::reference::detail {

void MultibodySolver::set_pins(std::span<const Pin> pins) {
  read_state(bodies_);
  auto alone = [&pins](int k) {
    for (int i = 0; i < static_cast<int>(pins.size()); ++i) {
      if (i != k && pins[i].segment == pins[k].segment && pins[i].is_hard()) return false;
    }
    return pins[k].is_hard();
  };
  Hang hang;  // none under a held root: the world's joint is the base's
  for (int k = 0; hang_.pin >= 0 && k < static_cast<int>(pins.size()); ++k) {
    const Pin& pin = pins[k];
    if (alone(k) && pin.segment == hang_.segment && pin.local_point == hang_.point &&
        pin.target == hang_.target) {
      hang = hang_;
      hang.pin = k;
    }
  }
  for (int k = 0;
       hang.pin < 0 && !held_ && !settings_.euler_ball_limits && k < static_cast<int>(pins.size());
       ++k) {
    const Pin& pin = pins[k];
    const BodyState& b = bodies_[pin.segment];
    if (alone(k) && (b.x + b.q * pin.local_point - pin.target).norm() <= 1e-9) {
      hang = Hang{k, pin.segment, pin.local_point, pin.target};
    }
  }
  pins_.assign(pins.begin(), pins.end());
  const bool same_tree =
      hang.segment == hang_.segment && hang.point == hang_.point && hang.target == hang_.target;
  hang_ = hang;
  if (same_tree) {
    build_pins();
  } else {
    assemble();
    set_state(bodies_);
  }
}

void MultibodySolver::set_pin_targets(std::span<const Vector3d> targets) {
  const int hung = hang_.pin;
  if (hung >= 0 && hung < static_cast<int>(targets.size()) && targets[hung] != hang_.target) {
    // the pin the tree hangs from moves: from now on it is rows, on the model's own tree
    read_state(bodies_);
    hang_ = Hang{};
    assemble();
    set_state(bodies_);
  }
  for (size_t k = 0; k < springs_.slots.size() && k < targets.size(); ++k) {
    pins_[k].target = targets[k];
    const int hard = springs_.retarget(k, targets[k]);
    if (hard >= 0 && hard_[hard]) hard_[hard]->set_target(targets[k]);
  }
}

void MultibodySolver::step(double dt) {
  if (diverged_) return;
  // the environment's forces on the state at the start of the step, as in the procedural
  // solver; world frame, at each COM
  read_state(bodies_);
  const std::span<const Wrench> wrenches = springs_.wrenches(model_, environment_, bodies_, dt);
  for (int s = 0; s < model_.segment_count(); ++s) {
    const Wrench& w = wrenches[s];
    const int link = link_of_[s];
    if (link < 0) {
      body_->addBaseForce(to_bt(w.force));
      body_->addBaseTorque(to_bt(w.torque));
    } else {
      body_->addLinkForce(link, to_bt(w.force));
      body_->addLinkTorque(link, to_bt(w.torque));
    }
  }
  // exactly one internal step of dt: maxSubSteps = 0 turns Bullet's fixed-step accumulator off
  world_->stepSimulation(dt, 0, dt);
  springs_.time += dt;
  for (auto& pin : hard_) {
    if (pin) pin->step_done();
  }
  diverged_ = !state_finite();
}

void MultibodySolver::read_state(std::span<BodyState> out) const {
  const int links = static_cast<int>(segment_of_.size());
  body_->compTreeLinkVelocities(&link_omega_[0], &link_velocity_[0]);
  const Quaterniond base_q = from_bt(body_->getWorldToBaseRot()).conjugate();
  const Vector3d base_x = from_bt(body_->getBasePos());
  if (link_of_[0] < 0) {  // the model's root is the floating base
    BodyState& root = out[0];
    root.q = base_q;
    root.x = base_x;
    root.v = base_q * from_bt(link_velocity_[0]);
    root.w = base_q * from_bt(link_omega_[0]);
  }
  // link frames in world, parent first
  for (int link = 0; link < links; ++link) {
    const int parent = parent_link_[link];
    const Quaterniond& qp = parent < 0 ? base_q : link_q_[parent];
    const Vector3d& xp = parent < 0 ? base_x : link_x_[parent];
    link_q_[link] = qp * from_bt(body_->getParentToLocalRot(link)).conjugate();
    link_x_[link] = xp + link_q_[link] * from_bt(body_->getRVector(link));
    if (segment_of_[link] < 0) continue;  // a planar hold's slide
    BodyState& b = out[segment_of_[link]];
    b.q = link_q_[link];
    b.x = link_x_[link];
    b.v = b.q * from_bt(link_velocity_[link + 1]);
    b.w = b.q * from_bt(link_omega_[link + 1]);
  }
}

// whether the state has the hanging pin's point on its target (else it cannot be written in
// coordinates hung from it)
bool MultibodySolver::hang_holds(std::span<const BodyState> bodies) const {
  const BodyState& b = bodies[hang_.segment];
  return (b.x + b.q * hang_.point - hang_.target).norm() <= 1e-9;
}

void MultibodySolver::set_state(std::span<const BodyState> bodies) {
  if (hang_.segment >= 0 && !hang_holds(bodies)) {
    // the state is kept as given, and the pin becomes rows on the model's own tree
    hang_ = Hang{};
    assemble();
  }
  if (link_of_[0] < 0) {
    const BodyState& root = bodies[0];
    body_->setBasePos(to_bt(root.x));
    body_->setWorldToBaseRot(to_bt(root.q.conjugate()));  // Bullet stores world-to-base
    body_->setBaseVel(to_bt(root.v));
    body_->setBaseOmega(to_bt(root.w));
  } else {
    body_->setBaseVel(btVector3(0, 0, 0));
    body_->setBaseOmega(btVector3(0, 0, 0));
  }
  if (held_) set_held_root(bodies[0]);
  for (int link = held_ ? root_link_ + 1 : 0; link < static_cast<int>(segment_of_.size()); ++link) {
    const BodyState& body = bodies[segment_of_[link]];
    const int parent = parent_link_[link];
    const bool from_base = parent < 0 && link_of_[0] >= 0;  // the fixed base: still, unturned
    const Quaterniond qp =
        from_base ? Quaterniond::Identity() : bodies[parent < 0 ? 0 : segment_of_[parent]].q;
    const Vector3d wp =
        from_base ? Vector3d::Zero() : bodies[parent < 0 ? 0 : segment_of_[parent]].w;
    const Quaterniond q_joint = (zero_[link] * qp.conjugate() * body.q).normalized();
    const Vector3d omega = body.q.conjugate() * (body.w - wp);
    const JointType type =
        joint_of_[link] < 0 ? JointType::kBall : model_.joints[joint_of_[link]].type;
    switch (type) {
      case JointType::kBall: {
        double q[4] = {q_joint.x(), q_joint.y(), q_joint.z(), q_joint.w()};
        double qd[3] = {omega.x(), omega.y(), omega.z()};
        body_->setJointPosMultiDof(link, q);
        body_->setJointVelMultiDof(link, qd);
        break;
      }
      case JointType::kHinge: {
        const Vector3d& axis = axis_[link];
        double theta = 2.0 * std::atan2(q_joint.vec().dot(axis), q_joint.w());
        if (theta > kPi) theta -= 2.0 * kPi;
        if (theta < -kPi) theta += 2.0 * kPi;
        double qd = omega.dot(axis);
        body_->setJointPosMultiDof(link, &theta);
        body_->setJointVelMultiDof(link, &qd);
        break;
      }
      case JointType::kSlide: {
        // its coordinate along the axis, the model's whichever way the link runs (from the
        // parent's side both the axis and the point's offset turn round)
        const Joint& joint = model_.joints[joint_of_[link]];
        const JointCoordinates c =
            joint_coordinates(joint, bodies[joint.parent], bodies[joint.child]);
        double s = c.angle[0], rate = c.rate[0];
        body_->setJointPosMultiDof(link, &s);
        body_->setJointVelMultiDof(link, &rate);
        break;
      }
      case JointType::kFixed:
        break;
    }
  }
  coordinates_changed();
}

// The root's link on the fixed base at the hold's anchor, unturned, or on a planar hold's slides
// (links 0 and 1): every coordinate is the model's (root_coordinates).
void MultibodySolver::set_held_root(const BodyState& root) {
  const RootJoint& hold = model_.root;
  const RootCoordinates c = root_coordinates(model_, root);
  switch (hold.hold) {
    case RootHold::kWeld:
      break;
    case RootHold::kHinge:
    case RootHold::kSlide:
    case RootHold::kPlanar:
      for (int k = 0; k < c.count; ++k) {
        double value = c.value[k], rate = c.rate[k];
        body_->setJointPosMultiDof(k, &value);
        body_->setJointVelMultiDof(k, &rate);
      }
      break;
    case RootHold::kFree:
    case RootHold::kBall: {
      const Quaterniond q_joint = (zero_[root_link_] * root.q).normalized();
      const Vector3d omega = root.q.conjugate() * root.w;  // the base is still
      double q[4] = {q_joint.x(), q_joint.y(), q_joint.z(), q_joint.w()};
      double qd[3] = {omega.x(), omega.y(), omega.z()};
      body_->setJointPosMultiDof(root_link_, q);
      body_->setJointVelMultiDof(root_link_, qd);
      break;
    }
  }
}

// The assembly's generation and the clock, then its coordinates and pin targets; then every
// segment's world pose and velocity, for a restore into another assembly.
std::vector<double> MultibodySolver::save() const {
  std::vector<double> saved;
  auto put = [&saved](const double* values, int count) {
    for (int k = 0; k < count; ++k) saved.push_back(values[k]);
  };
  saved.push_back(static_cast<double>(generation_));
  saved.push_back(springs_.time);
  const btVector3 x = body_->getBasePos();
  const btQuaternion q = body_->getWorldToBaseRot();
  const double pose[7] = {x.x(), x.y(), x.z(), q.x(), q.y(), q.z(), q.w()};
  put(pose, 7);
  put(body_->getVelocityVector(), 6 + body_->getNumDofs());
  for (int link = 0; link < body_->getNumLinks(); ++link) {
    put(body_->getJointPosMultiDof(link), body_->getLink(link).m_posVarCount);
  }
  for (const auto& pin : hard_) {
    if (!pin) continue;
    put(pin->target().data(), 3);
    put(pin->previous_target().data(), 3);
  }
  for (const Pin& spring : springs_.springs) put(spring.target.data(), 3);
  read_state(bodies_);
  append_world_poses(bodies_, saved);
  saved.push_back(diverged_ ? 1.0 : 0.0);
  return saved;
}

void MultibodySolver::load(std::span<const double> saved) {
  diverged_ = saved.back() != 0.0;
  springs_.time = saved[1];
  if (static_cast<long>(saved[0]) != generation_) {
    // saved under another assembly: only the world state (and the clock) carries over
    read_world_poses(saved, bodies_);
    set_state(bodies_);
    return;
  }
  const double* v = saved.data() + 2;
  body_->setBasePos(btVector3(v[0], v[1], v[2]));
  body_->setWorldToBaseRot(btQuaternion(v[3], v[4], v[5], v[6]));
  v += 7;
  body_->setBaseOmega(btVector3(v[0], v[1], v[2]));
  body_->setBaseVel(btVector3(v[3], v[4], v[5]));
  v += 6;
  for (int link = 0; link < body_->getNumLinks(); ++link) {
    body_->setJointVelMultiDof(link, v);
    v += body_->getLink(link).m_dofCount;
  }
  for (int link = 0; link < body_->getNumLinks(); ++link) {
    body_->setJointPosMultiDof(link, v);
    v += body_->getLink(link).m_posVarCount;
  }
  for (auto& pin : hard_) {
    if (!pin) continue;
    pin->restore(Vector3d(v[0], v[1], v[2]), Vector3d(v[3], v[4], v[5]));
    v += 6;
  }
  for (Pin& spring : springs_.springs) {
    spring.target = Vector3d(v[0], v[1], v[2]);
    v += 3;
  }
  coordinates_changed();
}

void MultibodySolver::coordinates_changed() {
  body_->updateCollisionObjectWorldTransforms(world_to_local_, local_origin_);
  clear_contact_caches(machinery_.dispatcher);
}

bool MultibodySolver::state_finite() const {
  const double* velocities = body_->getVelocityVector();
  for (int k = 0; k < 6 + body_->getNumDofs(); ++k) {
    if (!std::isfinite(velocities[k])) return false;
  }
  const btVector3 x = body_->getBasePos();
  const btQuaternion q = body_->getWorldToBaseRot();
  if (!std::isfinite(x.x() + x.y() + x.z() + q.x() + q.y() + q.z() + q.w())) return false;
  for (int link = 0; link < body_->getNumLinks(); ++link) {
    const double* position = body_->getJointPosMultiDof(link);
    for (int k = 0; k < body_->getLink(link).m_posVarCount; ++k) {
      if (!std::isfinite(position[k])) return false;
    }
  }
  return true;
}

void MultibodySolver::joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const {
  const Joint& j = model_.joints[joint];
  *on_parent = from_bt(body_->localPosToWorld(link_of_[j.parent], to_bt(j.anchor_in_parent)));
  *on_child = from_bt(body_->localPosToWorld(link_of_[j.child], to_bt(j.anchor_in_child)));
}

std::unique_ptr<Solver> make_multibody(const Model& model, const Environment& environment,
                                       const Settings& settings) {
  return std::make_unique<MultibodySolver>(model, environment, settings);
}

}  // namespace puppet::reference::detail
