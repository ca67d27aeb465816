// The model as one btMultiBody (Featherstone's articulated-body algorithm, reduced coordinates).
//
// Rooting. Where a hard pin holds its point on a target that does not move (a marionette's
// head), the tree hangs from it: the base is a fixed point at the target and the pinned segment
// is the first link, on a spherical joint there, so the pin holds exactly as MuJoCo's does
// (mujoco.cpp). Joints on the path from that segment to the model's root are then built from
// their child's side. Otherwise the base is the model's root segment, floating, and pins are
// PinRows (limit_rows.h). A pin whose target starts to move stops being the root: the tree is
// rebuilt from the model's root and the state carried over through world poses.
//
// Frames. Each link's frame is its segment's frame (the model keeps it principal, as Bullet's
// diagonal inertia needs), at the COM (Bullet's link origin). With q_L a link's world
// orientation and q_L0 its rest value (the identity for the fixed base),
//   zero rotation  z = q_L0(this)⁻¹ · q_L0(parent)            (Bullet's rotParentToThis)
//   spherical      q_L(this) = q_L(parent) · z⁻¹ · q_joint
//   revolute       q_joint = rotation by θ about the link's axis
// and a spherical joint's three velocities are ω_this − ω_parent in this link's frame. A hinge
// built from its child's side turns about minus its axis as the parent sees it, so that θ is the
// model's angle either way: the model's q_rel = R(a, θ) gives the parent, seen from the child,
// q_c⁻¹ q_p = F_c R(a, −θ) F_p⁻¹ = z⁻¹ R(−F_p a, θ).

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <BulletDynamics/Featherstone/btMultiBodySphericalJointLimit.h>

#include <cmath>
#include <numbers>

#include "bullet_common.h"
#include "limit_rows.h"
#include "world_poses.h"

namespace puppet::reference::detail {
namespace {

constexpr double kPi = std::numbers::pi;

// the pin the tree hangs from, if any
struct Hang {
  int pin = -1;  // its index among the pins, −1 when the base is the model's root, floating
  int segment = -1;
  Vector3d point{0, 0, 0};  // in the segment's frame
  Vector3d target{0, 0, 0};
};

class MultibodySolver final : public Solver {
 public:
  MultibodySolver(const Model& model, const Environment& environment, const Settings& settings);
  ~MultibodySolver() override;

  void set_pins(std::span<const Pin> pins) override;
  void set_pin_targets(std::span<const Vector3d> targets) override;
  void step(double dt) override;
  void set_time(double time) override { springs_.time = time; }
  std::span<const Wrench> user_wrenches() const override { return springs_.user; }
  void read_state(std::span<BodyState> out) const override;
  void set_state(std::span<const BodyState> bodies) override;
  std::vector<double> save() const override;
  void load(std::span<const double> saved) override;
  bool diverged() const override { return diverged_; }

  double segment_mass(int segment) const override {
    const int link = link_of_[segment];
    return link < 0 ? body_->getBaseMass() : body_->getLinkMass(link);
  }
  Vector3d segment_inertia(int segment) const override {
    const int link = link_of_[segment];
    return from_bt(link < 0 ? body_->getBaseInertia() : body_->getLinkInertia(link));
  }
  void joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const override;

 private:
  // (re)builds the articulation for hang_: the links, colliders, limits and pins
  void assemble();
  void tear_down();
  void lay_out();
  void build_links();
  void build_limits();
  void build_colliders();
  void build_pins();
  bool hang_holds(std::span<const BodyState> bodies) const;
  // after the coordinates changed from outside a step: colliders follow, contacts forget
  void coordinates_changed();
  bool state_finite() const;

  const Model& model_;
  Environment environment_;
  Settings settings_;
  std::vector<Pin> pins_;
  Hang hang_;
  long generation_ = 0;  // assemblies so far: a saved state names the one it was saved under

  // the tree as built, links parent first: per segment its link (−1: the floating base), per
  // link its segment, the link it hangs from (−1: the base), the model joint between them (−1:
  // the hanging pin's), whether the link is that joint's child, and its rest orientation
  std::vector<int> link_of_;
  std::vector<int> segment_of_;
  std::vector<int> parent_link_;
  std::vector<int> joint_of_;
  std::vector<char> forward_;
  std::vector<Quaterniond> zero_;  // z above, per link
  std::vector<Vector3d> axis_;     // a revolute link's axis in its frame

  // Bullet objects: the world is declared last so that it is destroyed first
  CollisionMachinery machinery_;
  btMultiBodyConstraintSolver constraint_solver_;
  std::unique_ptr<btMultiBody> body_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders_;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> limits_;
  std::vector<std::unique_ptr<PinRows>>
      hard_;            // per hard pin; null for the one the tree hangs from
  PinSprings springs_;  // which pins are hard, and the compliant ones
  Ground ground_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_;

  // scratch, sized once per assembly
  mutable std::vector<BodyState> bodies_;
  mutable std::vector<Quaterniond> link_q_;
  mutable std::vector<Vector3d> link_x_;
  mutable btAlignedObjectArray<btVector3> link_omega_, link_velocity_;
  btAlignedObjectArray<btQuaternion> world_to_local_;
  btAlignedObjectArray<btVector3> local_origin_;
  bool diverged_ = false;
};

MultibodySolver::MultibodySolver(const Model& model, const Environment& environment,
                                 const Settings& settings)
    : model_(model), environment_(environment), settings_(settings) {
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
  if (environment.ground) {
    ground_ = make_ground();
    world_->addRigidBody(ground_.body.get(), kGroundGroup, kSegmentGroup);
  }
  bodies_.resize(model.segment_count());
  assemble();
  set_state(rest_pose(model));
}

MultibodySolver::~MultibodySolver() {
  tear_down();
  if (ground_.body) world_->removeRigidBody(ground_.body.get());
}

void MultibodySolver::tear_down() {
  if (!body_) return;
  for (auto& pin : hard_) {
    if (pin) world_->removeMultiBodyConstraint(pin.get());
  }
  for (auto& limit : limits_) world_->removeMultiBodyConstraint(limit.get());
  for (auto& collider : colliders_) world_->removeCollisionObject(collider.get());
  world_->removeMultiBody(body_.get());
  hard_.clear();
  limits_.clear();
  colliders_.clear();
  shapes_.clear();
  body_.reset();
}

void MultibodySolver::assemble() {
  tear_down();
  ++generation_;
  lay_out();
  const bool hung = hang_.segment >= 0;
  const int links = static_cast<int>(segment_of_.size());
  // the base: a fixed point, or the model's root segment floating (fixedBase = false).
  // canSleep = false: a sleeping body stops moving and stops costing time, which would
  // falsify both motion and timings
  const Segment& root = model_.segments[0];
  body_ = std::make_unique<btMultiBody>(
      links, hung ? 0.0 : root.mass, hung ? btVector3(0, 0, 0) : to_bt(root.inertia), hung, false);
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
  if (hung) {
    body_->setBasePos(to_bt(hang_.target));
    body_->setWorldToBaseRot(btQuaternion::getIdentity());
  }
  world_->addMultiBody(body_.get());
  build_colliders();
  build_limits();
  build_pins();

  link_q_.resize(links);
  link_x_.resize(links);
  link_omega_.resize(links + 1);
  link_velocity_.resize(links + 1);
  world_to_local_.resize(links + 1);
  local_origin_.resize(links + 1);
}

// the links in the order Bullet needs (parent first), walking the model's joints out from the
// hanging segment or the model's root
void MultibodySolver::lay_out() {
  const int n = model_.segment_count();
  std::vector<std::vector<int>> joints_of(n);
  for (int j = 0; j < model_.joint_count(); ++j) {
    joints_of[model_.joints[j].parent].push_back(j);
    joints_of[model_.joints[j].child].push_back(j);
  }
  link_of_.assign(n, -1);
  segment_of_.clear();
  parent_link_.clear();
  joint_of_.clear();
  forward_.clear();
  zero_.clear();
  axis_.clear();
  const bool hung = hang_.segment >= 0;
  const int first = hung ? hang_.segment : 0;
  std::vector<char> placed(n, 0);
  placed[first] = 1;
  std::vector<int> queue = {first};
  if (hung) {
    link_of_[first] = 0;
    segment_of_.push_back(first);
    parent_link_.push_back(-1);
    joint_of_.push_back(-1);
    forward_.push_back(1);
    zero_.push_back(model_.segments[first].rest_orientation.conjugate());
    axis_.push_back(Vector3d::Zero());
  }
  for (size_t k = 0; k < queue.size(); ++k) {
    const int s = queue[k];
    for (int j : joints_of[s]) {
      const Joint& joint = model_.joints[j];
      const int next = joint.parent == s ? joint.child : joint.parent;
      if (placed[next]) continue;
      placed[next] = 1;
      queue.push_back(next);
      link_of_[next] = static_cast<int>(segment_of_.size());
      segment_of_.push_back(next);
      parent_link_.push_back(link_of_[s]);
      joint_of_.push_back(j);
      const bool forward = joint.child == next;
      forward_.push_back(forward);
      zero_.push_back(model_.segments[next].rest_orientation.conjugate() *
                      model_.segments[s].rest_orientation);
      axis_.push_back(forward ? Vector3d(joint.frame_in_child * joint.hinge_axis)
                              : Vector3d(-(joint.frame_in_parent * joint.hinge_axis)));
    }
  }
}

void MultibodySolver::build_links() {
  for (int link = 0; link < static_cast<int>(segment_of_.size()); ++link) {
    const Segment& segment = model_.segments[segment_of_[link]];
    const btQuaternion zero = to_bt(zero_[link]);
    const btVector3 inertia = to_bt(segment.inertia);
    if (joint_of_[link] < 0) {
      // hanging from the fixed base: the pinned point on the base's origin
      body_->setupSpherical(link, segment.mass, inertia, -1, zero, btVector3(0, 0, 0),
                            to_bt(-hang_.point), true);
      continue;
    }
    const Joint& joint = model_.joints[joint_of_[link]];
    // the joint point from the parent link's COM (its frame), and to this link's COM (this frame)
    const Vector3d e = forward_[link] ? joint.anchor_in_parent : joint.anchor_in_child;
    const Vector3d d = -(forward_[link] ? joint.anchor_in_child : joint.anchor_in_parent);
    const int parent = parent_link_[link];
    switch (joint.type) {
      case JointType::kBall:
        body_->setupSpherical(link, segment.mass, inertia, parent, zero, to_bt(e), to_bt(d), true);
        break;
      case JointType::kHinge:
        body_->setupRevolute(link, segment.mass, inertia, parent, zero, to_bt(axis_[link]),
                             to_bt(e), to_bt(d), true);
        break;
      case JointType::kFixed:
        body_->setupFixed(link, segment.mass, inertia, parent, zero, to_bt(e), to_bt(d), true);
        break;
    }
  }
}

// Limits are the model's (limit_rows.cpp: a hinge's range, a swing ellipse and twist, or a box)
// unless Bullet's own Euler-angle box is asked for a swing–twist joint (then the tree is never
// hung from a pin: that limit reads a link's own coordinates). Limits of half a turn or more
// never act and are not built.
void MultibodySolver::build_limits() {
  for (int link = 0; link < static_cast<int>(segment_of_.size()); ++link) {
    const int j = joint_of_[link];
    if (j < 0) continue;
    const Joint& joint = model_.joints[j];
    const JointLinks links{link_of_[joint.child], link_of_[joint.parent], link};
    std::unique_ptr<btMultiBodyConstraint> limit;
    if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox) {
      limit = make_limit(body_.get(), links, joint);
    } else if (joint.type == JointType::kBall) {
      if (joint.swing_x >= kPi && joint.swing_y >= kPi && joint.twist >= kPi) continue;
      if (!settings_.euler_ball_limits) {
        limit = make_limit(body_.get(), links, joint);
      } else {
        // a box of Euler angles about the link frame's axes, agreeing with the model's ellipse
        // only along the axes (and only where the segment frame is the joint frame)
        auto spherical = std::make_unique<btMultiBodySphericalJointLimit>(
            body_.get(), link, joint.swing_x, joint.swing_y, joint.twist, kMaxImpulse);
        // its position gain kp multiplies m_erp; Bullet's default 0.2 would make the ball
        // limits five times softer than the hinge limits and the pins: 1 makes them all alike
        spherical->setPositionTarget(btQuaternion::getIdentity(), 1.0);
        limit = std::move(spherical);
      }
    } else if (joint.type == JointType::kHinge) {
      if (joint.lower <= -kPi && joint.upper >= kPi) continue;
      limit = make_limit(body_.get(), links, joint);
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
    btCollisionShape* shape = make_segment_shape(model_.segments[s], shapes_);
    const int link = link_of_[s];
    auto collider = std::make_unique<btMultiBodyLinkCollider>(body_.get(), link);
    collider->setCollisionShape(shape);
    // Bullet multiplies the two frictions; the ground's is 1
    collider->setFriction(environment_.friction);
    collider->setRestitution(0.0);
    world_->addCollisionObject(collider.get(), kSegmentGroup, mask);
    if (link < 0) {
      body_->setBaseCollider(collider.get());
    } else {
      body_->getLink(link).m_collider = collider.get();
    }
    colliders_.push_back(std::move(collider));
  }
}

// the pins as rows, but for the one the tree hangs from, which is its first joint
void MultibodySolver::build_pins() {
  for (auto& pin : hard_) {
    if (pin) world_->removeMultiBodyConstraint(pin.get());
  }
  hard_.clear();
  springs_.clear();
  for (int k = 0; k < static_cast<int>(pins_.size()); ++k) {
    const Pin& pin = pins_[k];
    if (!springs_.add(pin, static_cast<int>(hard_.size()))) continue;
    if (k == hang_.pin) {
      hard_.emplace_back();
      continue;
    }
    auto rows =
        std::make_unique<PinRows>(body_.get(), link_of_[pin.segment], pin.local_point, pin.target);
    rows->finalizeMultiDof();
    world_->addMultiBodyConstraint(rows.get());
    hard_.push_back(std::move(rows));
  }
}

// The tree hangs from a hard pin whose point is on its target, and stays hung from it while it
// is among the pins with the same target. Not from a segment that other hard pins also hold (a
// weld, not a string): hung from one of three pins on a rod, with rows for the other two,
// Bullet's sequential impulses let a limit on the next joint overshoot and give back 11% of an
// impact's speed, at 200 sweeps as at 2000; from the floating rod, 2%. Never with Bullet's own
// ball limits (build_limits).
void MultibodySolver::set_pins(std::span<const Pin> pins) {
  read_state(bodies_);
  auto alone = [&pins](int k) {
    for (int i = 0; i < static_cast<int>(pins.size()); ++i) {
      if (i != k && pins[i].segment == pins[k].segment && pins[i].is_hard()) return false;
    }
    return pins[k].is_hard();
  };
  Hang hang;
  for (int k = 0; hang_.pin >= 0 && k < static_cast<int>(pins.size()); ++k) {
    const Pin& pin = pins[k];
    if (alone(k) && pin.segment == hang_.segment && pin.local_point == hang_.point &&
        pin.target == hang_.target) {
      hang = hang_;
      hang.pin = k;
    }
  }
  for (int k = 0; hang.pin < 0 && !settings_.euler_ball_limits && k < static_cast<int>(pins.size());
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
  for (int link = 0; link < static_cast<int>(segment_of_.size()); ++link) {
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
      case JointType::kFixed:
        break;
    }
  }
  coordinates_changed();
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

}  // namespace

std::unique_ptr<Solver> make_multibody(const Model& model, const Environment& environment,
                                       const Settings& settings) {
  return std::make_unique<MultibodySolver>(model, environment, settings);
}

}  // namespace puppet::reference::detail
