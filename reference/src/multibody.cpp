// The model as one btMultiBody (Featherstone's articulated-body algorithm, reduced coordinates).
//
// Frames. The base is the root segment in its segment frame. Every other link's frame sits at the
// child's COM (Bullet's link origin) and must be a principal frame of the child, since Bullet
// takes a diagonal inertia: it is the joint's frame when that is principal, else the child's
// segment frame, with the joint expressed in it (as Bullet's URDF importer does). With q_L the
// world orientation of a link frame, q_L0 its rest value and A = the joint frame in the child's
// link frame (the identity when they coincide),
//   zero rotation  z = q_L0(this)⁻¹ · q_L0(parent)            (Bullet's rotParentToThis)
//   spherical      q_L(this) = q_L(parent) · z⁻¹ · q_joint      (the model's q_rel = A⁻¹·q_joint·A)
//   revolute       q_joint = rotation by θ about A·(the hinge axis), θ right-handed as the model's
// and a spherical joint's three velocities are ω_child − ω_parent in the child's link frame.
// Segment frames are recovered as q_segment = q_L · (segment_to_link)⁻¹.
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <BulletDynamics/Featherstone/btMultiBodyPoint2Point.h>
#include <BulletDynamics/Featherstone/btMultiBodySphericalJointLimit.h>

#include <cmath>
#include <numbers>

#include "bullet_common.h"
#include "limit_rows.h"

namespace puppet::reference::detail {
namespace {

constexpr double kPi = std::numbers::pi;

class MultibodySolver final : public Solver {
 public:
  MultibodySolver(const Model& model, const Environment& environment, const Settings& settings);
  ~MultibodySolver() override;

  Kind kind() const override { return Kind::kMultibody; }
  void set_pins(std::span<const Pin> pins) override;
  void set_pin_targets(std::span<const Vector3d> targets) override;
  void step(double dt) override;
  void read_state(std::span<BodyState> out) const override;
  void set_state(std::span<const BodyState> bodies) override;
  std::vector<double> save() const override;
  void load(std::span<const double> saved) override;
  bool diverged() const override { return diverged_; }

  double segment_mass(int segment) const override {
    return segment == 0 ? body_->getBaseMass() : body_->getLinkMass(segment - 1);
  }
  Vector3d segment_inertia(int segment) const override;
  void joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const override;

 private:
  void build_links();
  void build_limits();
  void build_colliders();
  // after the coordinates changed from outside a step: colliders follow, contacts forget
  void coordinates_changed();
  bool state_finite() const;

  const Model& model_;
  Environment environment_;
  bool euler_ball_limits_;
  // link frame seen from the segment frame (identity for the root), and its rest orientation
  std::vector<Quaterniond> segment_to_link_;
  std::vector<Quaterniond> link_rest_;
  std::vector<Quaterniond> joint_in_link_;  // A above, per segment

  // Bullet objects: the world is declared last so that it is destroyed first
  CollisionMachinery machinery_;
  btMultiBodyConstraintSolver constraint_solver_;
  std::unique_ptr<btMultiBody> body_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders_;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> limits_;
  std::vector<std::unique_ptr<btMultiBodyPoint2Point>> pins_;
  PinSprings springs_;  // which pins are hard, and the compliant ones
  Ground ground_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_;

  // scratch, sized once
  mutable std::vector<BodyState> bodies_;
  mutable btAlignedObjectArray<btVector3> link_omega_, link_velocity_;
  btAlignedObjectArray<btQuaternion> world_to_local_;
  btAlignedObjectArray<btVector3> local_origin_;
  bool diverged_ = false;
};

MultibodySolver::MultibodySolver(const Model& model, const Environment& environment,
                                 const Settings& settings)
    : model_(model), environment_(environment), euler_ball_limits_(settings.euler_ball_limits) {
  const int n = model.segment_count();
  segment_to_link_.resize(n);
  link_rest_.resize(n);
  segment_to_link_[0] = Quaterniond::Identity();
  link_rest_[0] = model.segments[0].rest_orientation;
  joint_in_link_.resize(n);
  joint_in_link_[0] = Quaterniond::Identity();
  for (int i = 1; i < n; ++i) {
    const Joint& joint = model.joints[i - 1];
    const bool principal = is_principal_frame(model.segments[i], joint.frame_in_child);
    segment_to_link_[i] = principal ? joint.frame_in_child : Quaterniond::Identity();
    joint_in_link_[i] = principal ? Quaterniond::Identity() : joint.frame_in_child;
    link_rest_[i] = model.segments[i].rest_orientation * segment_to_link_[i];
  }

  // a floating base: the root is free (fixedBase = false). canSleep = false: a sleeping body
  // stops moving and stops costing time, which would falsify both motion and timings
  const Segment& root = model.segments[0];
  body_ = std::make_unique<btMultiBody>(n - 1, root.mass, to_bt(root.inertia), false, false);
  build_links();
  // Bullet defaults to 0.04 linear and angular damping on every link: the references must
  // conserve what the physics conserves, so no damping at all
  body_->setLinearDamping(0.0);
  body_->setAngularDamping(0.0);
  // Bullet clamps joint velocities at 100 rad/s by default; a clamp changes the motion it
  // touches, so it is raised out of reach (a diverging run is caught by the harness instead)
  body_->setMaxCoordinateVelocity(1e6);
  // contacts' impulse cap (default 1000 N·s), see kMaxImpulse
  body_->setMaxAppliedImpulse(kMaxImpulse);
  // the gyroscopic (velocity-product) term belongs to rigid-body dynamics
  body_->setUseGyroTerm(true);
  // no self-collision (docs/design.md); segments touch the ground only
  body_->setHasSelfCollision(false);
  body_->finalizeMultiDof();  // after every setup* call, or the dof buffers are wrong

  world_ =
      std::make_unique<btMultiBodyDynamicsWorld>(&machinery_.dispatcher, &machinery_.broadphase,
                                                 &constraint_solver_, &machinery_.configuration);
  // gravity comes with the other environment forces through environment_wrench, from the
  // same formula as the procedural solver's
  world_->setGravity(btVector3(0, 0, 0));
  btContactSolverInfo& info = world_->getSolverInfo();
  info.m_numIterations = settings.iterations;
  // multibody pins and limits read m_erp (not m_erp2): 0.2 closes a fifth of a gap per step
  info.m_erp = settings.erp;
  // Split impulse hands deep violations to a position pass that the multibody solver does not
  // run: with it on, Bullet's btMultiBodyJointLimitConstraint never corrected a hinge more than
  // 0.04 rad (m_splitImpulsePenetrationThreshold) past its limit (measured: an elbow left 25°
  // past its stop stayed there). Off, every row is Baumgarte-corrected with m_erp.
  info.m_splitImpulse = false;
  world_->addMultiBody(body_.get());
  build_colliders();
  build_limits();
  if (environment.ground) {
    ground_ = make_ground();
    world_->addRigidBody(ground_.body.get(), kGroundGroup, kSegmentGroup);
  }

  bodies_.resize(n);
  link_omega_.resize(n);
  link_velocity_.resize(n);
  world_to_local_.resize(n);
  local_origin_.resize(n);
  set_state(rest_pose(model));
}

MultibodySolver::~MultibodySolver() {
  for (auto& pin : pins_) world_->removeMultiBodyConstraint(pin.get());
  for (auto& limit : limits_) world_->removeMultiBodyConstraint(limit.get());
  for (auto& collider : colliders_) world_->removeCollisionObject(collider.get());
  if (ground_.body) world_->removeRigidBody(ground_.body.get());
  world_->removeMultiBody(body_.get());
}

void MultibodySolver::build_links() {
  for (int s = 1; s < model_.segment_count(); ++s) {
    const Joint& joint = model_.joints[s - 1];
    const Segment& child = model_.segments[s];
    const int p = joint.parent;
    const int link = s - 1;
    const int parent_link = p - 1;
    const btQuaternion zero = to_bt(link_rest_[s].conjugate() * link_rest_[p]);
    // the joint point from the parent's COM (parent link frame) and to the child's COM (this
    // link frame)
    const Vector3d e = segment_to_link_[p].conjugate() * joint.anchor_in_parent;
    const Vector3d d = -(segment_to_link_[s].conjugate() * joint.anchor_in_child);
    // the child's inertia in its link frame (diagonal: the loader checked the frame is
    // principal); the model's inertia, never Bullet's calculateLocalInertia
    const Matrix3d f = segment_to_link_[s].toRotationMatrix();
    const Vector3d inertia = (f.transpose() * child.inertia.asDiagonal() * f).diagonal();
    switch (joint.type) {
      case JointType::kBall:
        body_->setupSpherical(link, child.mass, to_bt(inertia), parent_link, zero, to_bt(e),
                              to_bt(d), true);
        break;
      case JointType::kHinge:
        body_->setupRevolute(link, child.mass, to_bt(inertia), parent_link, zero,
                             to_bt(joint_in_link_[s] * joint.hinge_axis), to_bt(e), to_bt(d), true);
        break;
      case JointType::kFixed:
        body_->setupFixed(link, child.mass, to_bt(inertia), parent_link, zero, to_bt(e), to_bt(d),
                          true);
        break;
    }
  }
}

// Limits are the model's (limit_rows.cpp: a hinge's range, a swing ellipse and twist, or a box)
// unless Bullet's own Euler-angle box is asked for a swing–twist joint. Limits of half a turn or
// more never act and are not built.
void MultibodySolver::build_limits() {
  for (int j = 0; j < model_.joint_count(); ++j) {
    const Joint& joint = model_.joints[j];
    std::unique_ptr<btMultiBodyConstraint> limit;
    if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox) {
      limit = make_limit(body_.get(), j, joint, joint_in_link_[j + 1]);
    } else if (joint.type == JointType::kBall) {
      if (joint.swing_x >= kPi && joint.swing_y >= kPi && joint.twist >= kPi) continue;
      if (!euler_ball_limits_) {
        limit = make_limit(body_.get(), j, joint, joint_in_link_[j + 1]);
      } else {
        // a box of Euler angles about the link frame's axes (the joint frame's when it is
        // principal), agreeing with the model's ellipse only along the axes
        auto spherical = std::make_unique<btMultiBodySphericalJointLimit>(
            body_.get(), j, joint.swing_x, joint.swing_y, joint.twist, kMaxImpulse);
        // its position gain kp multiplies m_erp; Bullet's default 0.2 would make the ball
        // limits five times softer than the hinge limits and the pins: 1 makes them all alike
        spherical->setPositionTarget(btQuaternion::getIdentity(), 1.0);
        limit = std::move(spherical);
      }
    } else if (joint.type == JointType::kHinge) {
      if (joint.lower <= -kPi && joint.upper >= kPi) continue;
      limit = make_limit(body_.get(), j, joint, joint_in_link_[j + 1]);
    } else {
      continue;
    }
    limit->finalizeMultiDof();
    world_->addMultiBodyConstraint(limit.get());
    limits_.push_back(std::move(limit));
  }
}

// Every link gets a collider even without a ground: Bullet silently ignores a multibody
// constraint on a link without one. Without a ground the mask is 0 and nothing collides.
void MultibodySolver::build_colliders() {
  const int mask = segment_mask(environment_);
  for (int s = 0; s < model_.segment_count(); ++s) {
    std::unique_ptr<btCollisionShape> shape = make_shape(model_.segments[s].shape);
    btCollisionShape* collider_shape = shape.get();
    shapes_.push_back(std::move(shape));
    // the shape lives in the segment frame; the collider sits in the link frame
    if (!segment_to_link_[s].isApprox(Quaterniond::Identity(), 1e-15)) {
      auto compound = std::make_unique<btCompoundShape>(false, 1);
      compound->addChildShape(
          btTransform(to_bt(segment_to_link_[s].conjugate()), btVector3(0, 0, 0)), collider_shape);
      collider_shape = compound.get();
      shapes_.push_back(std::move(compound));
    }
    auto collider = std::make_unique<btMultiBodyLinkCollider>(body_.get(), s - 1);
    collider->setCollisionShape(collider_shape);
    // Bullet multiplies the two frictions; the ground's is 1
    collider->setFriction(environment_.friction);
    collider->setRestitution(0.0);
    world_->addCollisionObject(collider.get(), kSegmentGroup, mask);
    if (s == 0) {
      body_->setBaseCollider(collider.get());
    } else {
      body_->getLink(s - 1).m_collider = collider.get();
    }
    colliders_.push_back(std::move(collider));
  }
}

void MultibodySolver::set_pins(std::span<const Pin> pins) {
  for (auto& pin : pins_) world_->removeMultiBodyConstraint(pin.get());
  pins_.clear();
  springs_.clear();
  for (const Pin& pin : pins) {
    if (!springs_.add(pin, static_cast<int>(pins_.size()))) continue;
    const Vector3d pivot = segment_to_link_[pin.segment].conjugate() * pin.local_point;
    // bodyB = null: the pin holds the point at a world position, pivotInB
    auto p2p = std::make_unique<btMultiBodyPoint2Point>(body_.get(), pin.segment - 1, nullptr,
                                                        to_bt(pivot), to_bt(pin.target));
    p2p->setMaxAppliedImpulse(kMaxImpulse);
    p2p->finalizeMultiDof();
    world_->addMultiBodyConstraint(p2p.get());
    pins_.push_back(std::move(p2p));
  }
}

void MultibodySolver::set_pin_targets(std::span<const Vector3d> targets) {
  for (size_t k = 0; k < springs_.slots.size() && k < targets.size(); ++k) {
    const int hard = springs_.retarget(k, targets[k]);
    if (hard >= 0) pins_[hard]->setPivotInB(to_bt(targets[k]));
  }
}

void MultibodySolver::step(double dt) {
  if (diverged_) return;
  // the environment's forces on the state at the start of the step, as in the procedural
  // solver; world frame, at each COM
  read_state(bodies_);
  for (int s = 0; s < model_.segment_count(); ++s) {
    const Wrench w = springs_.wrench(model_.segments[s], environment_, s, bodies_[s], dt);
    if (s == 0) {
      body_->addBaseForce(to_bt(w.force));
      body_->addBaseTorque(to_bt(w.torque));
    } else {
      body_->addLinkForce(s - 1, to_bt(w.force));
      body_->addLinkTorque(s - 1, to_bt(w.torque));
    }
  }
  // exactly one internal step of dt: maxSubSteps = 0 turns Bullet's fixed-step accumulator off
  world_->stepSimulation(dt, 0, dt);
  diverged_ = !state_finite();
}

void MultibodySolver::read_state(std::span<BodyState> out) const {
  const int n = model_.segment_count();
  body_->compTreeLinkVelocities(&link_omega_[0], &link_velocity_[0]);
  // link frames in world, parent before child: origin at the COM
  out[0].q = from_bt(body_->getWorldToBaseRot()).conjugate();
  out[0].x = from_bt(body_->getBasePos());
  for (int s = 1; s < n; ++s) {
    const int p = model_.segments[s].parent;
    // out[p].q still holds the parent's link frame: segments are ordered parent first and
    // converted to segment frames in a second pass
    out[s].q = out[p].q * from_bt(body_->getParentToLocalRot(s - 1)).conjugate();
    out[s].x = out[p].x + out[s].q * from_bt(body_->getRVector(s - 1));
  }
  for (int s = 0; s < n; ++s) {
    out[s].v = out[s].q * from_bt(link_velocity_[s]);
    out[s].w = out[s].q * from_bt(link_omega_[s]);
  }
  for (int s = 1; s < n; ++s) out[s].q = out[s].q * segment_to_link_[s].conjugate();
}

void MultibodySolver::set_state(std::span<const BodyState> bodies) {
  const BodyState& root = bodies[0];
  body_->setBasePos(to_bt(root.x));
  body_->setWorldToBaseRot(to_bt(root.q.conjugate()));  // Bullet stores world-to-base
  body_->setBaseVel(to_bt(root.v));
  body_->setBaseOmega(to_bt(root.w));
  for (int s = 1; s < model_.segment_count(); ++s) {
    const Joint& joint = model_.joints[s - 1];
    const int p = joint.parent;
    const Quaterniond link = bodies[s].q * segment_to_link_[s];
    const Quaterniond parent_link = bodies[p].q * segment_to_link_[p];
    const Quaterniond zero = link_rest_[s].conjugate() * link_rest_[p];
    const Quaterniond q_joint = (zero * parent_link.conjugate() * link).normalized();
    const Vector3d omega = link.conjugate() * (bodies[s].w - bodies[p].w);
    switch (joint.type) {
      case JointType::kBall: {
        double q[4] = {q_joint.x(), q_joint.y(), q_joint.z(), q_joint.w()};
        double qd[3] = {omega.x(), omega.y(), omega.z()};
        body_->setJointPosMultiDof(s - 1, q);
        body_->setJointVelMultiDof(s - 1, qd);
        break;
      }
      case JointType::kHinge: {
        const Vector3d axis = joint_in_link_[s] * joint.hinge_axis;
        double theta = 2.0 * std::atan2(q_joint.vec().dot(axis), q_joint.w());
        if (theta > kPi) theta -= 2.0 * kPi;
        if (theta < -kPi) theta += 2.0 * kPi;
        double qd = omega.dot(axis);
        body_->setJointPosMultiDof(s - 1, &theta);
        body_->setJointVelMultiDof(s - 1, &qd);
        break;
      }
      case JointType::kFixed:
        break;
    }
  }
  coordinates_changed();
}

std::vector<double> MultibodySolver::save() const {
  std::vector<double> saved;
  auto put = [&saved](const double* values, int count) {
    for (int k = 0; k < count; ++k) saved.push_back(values[k]);
  };
  const btVector3 x = body_->getBasePos();
  const btQuaternion q = body_->getWorldToBaseRot();
  const double pose[7] = {x.x(), x.y(), x.z(), q.x(), q.y(), q.z(), q.w()};
  put(pose, 7);
  put(body_->getVelocityVector(), 6 + body_->getNumDofs());
  for (int link = 0; link < body_->getNumLinks(); ++link) {
    put(body_->getJointPosMultiDof(link), body_->getLink(link).m_posVarCount);
  }
  for (const auto& pin : pins_) {
    const btVector3& target = pin->getPivotInB();
    const double xyz[3] = {target.x(), target.y(), target.z()};
    put(xyz, 3);
  }
  for (const Pin& spring : springs_.springs) put(spring.target.data(), 3);
  saved.push_back(diverged_ ? 1.0 : 0.0);
  return saved;
}

void MultibodySolver::load(std::span<const double> saved) {
  const double* v = saved.data();
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
  for (auto& pin : pins_) {
    pin->setPivotInB(btVector3(v[0], v[1], v[2]));
    v += 3;
  }
  for (Pin& spring : springs_.springs) {
    spring.target = Vector3d(v[0], v[1], v[2]);
    v += 3;
  }
  diverged_ = v[0] != 0.0;
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

Vector3d MultibodySolver::segment_inertia(int segment) const {
  if (segment == 0) return from_bt(body_->getBaseInertia());
  const Matrix3d f = segment_to_link_[segment].toRotationMatrix();
  const Vector3d link = from_bt(body_->getLinkInertia(segment - 1));
  return (f * link.asDiagonal() * f.transpose()).diagonal();
}

void MultibodySolver::joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const {
  const int link = joint;  // joint j places segment j + 1, which is link j
  const btMultibodyLink& l = body_->getLink(link);
  *on_parent = from_bt(body_->localPosToWorld(l.m_parent, l.m_eVector));
  *on_child = from_bt(body_->localPosToWorld(link, -l.m_dVector));
}

}  // namespace

std::unique_ptr<Solver> make_multibody(const Model& model, const Environment& environment,
                                       const Settings& settings) {
  return std::make_unique<MultibodySolver>(model, environment, settings);
}

}  // namespace puppet::reference::detail
