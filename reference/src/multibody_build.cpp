// btMultiBody's tree built from the model (multibody.h): the rooting, the links in the order
// Bullet wants them, their limits, colliders and pins
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>

#include "multibody.h"
#include "puppet/model/root_joint.h"

namespace puppet::reference::detail {

MultibodySolver::MultibodySolver(const Model& model, const Environment& environment,
                                 const Settings& settings)
    : model_(model), held_(root_held(model)), environment_(environment), settings_(settings) {
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
  const bool fixed = hang_.segment >= 0 || held_;
  const int links = static_cast<int>(segment_of_.size());
  // the base: a fixed point, or the model's root segment floating (fixedBase = false).
  // canSleep = false: a sleeping body stops moving and stops costing time, which would
  // falsify both motion and timings
  const Segment& root = model_.segments[0];
  body_ =
      std::make_unique<btMultiBody>(links, fixed ? 0.0 : root.mass,
                                    fixed ? btVector3(0, 0, 0) : to_bt(root.inertia), fixed, false);
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
  if (fixed) {
    body_->setBasePos(to_bt(held_ ? model_.root.anchor_world : hang_.target));
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
  root_link_ = 0;
  if (hung || held_) {
    // the first link, on the fixed base: its joint is the hanging pin's or the world's hold; a
    // planar hold's two slides before it, massless links unturned at the anchor
    const Quaterniond rest = model_.segments[first].rest_orientation;
    const RootJoint& hold = model_.root;
    const bool planar = held_ && hold.hold == RootHold::kPlanar;
    for (int k = 0; planar && k < root_slide_count(hold.hold); ++k) {
      segment_of_.push_back(-1);
      parent_link_.push_back(k - 1);
      joint_of_.push_back(-1);
      forward_.push_back(1);
      zero_.push_back(Quaterniond::Identity());
      axis_.push_back(hold.axes[k]);
    }
    root_link_ = static_cast<int>(segment_of_.size());
    link_of_[first] = root_link_;
    segment_of_.push_back(first);
    parent_link_.push_back(root_link_ - 1);
    joint_of_.push_back(-1);
    forward_.push_back(1);
    zero_.push_back(rest.conjugate());
    const int axis = planar ? root_hinge_index(hold.hold) : 0;
    axis_.push_back(held_ ? Vector3d(rest.conjugate() * hold.axes[axis]) : Vector3d::Zero());
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
    const btQuaternion zero = to_bt(zero_[link]);
    const btVector3 origin(0, 0, 0);
    const btVector3 axis = to_bt(axis_[link]);
    const int parent = parent_link_[link];
    if (segment_of_[link] < 0) {  // a planar hold's slide
      body_->setupPrismatic(link, 0.0, origin, parent, zero, axis, origin, origin, true);
      continue;
    }
    const Segment& segment = model_.segments[segment_of_[link]];
    const btVector3 inertia = to_bt(segment.inertia);
    if (joint_of_[link] < 0) {
      // on the fixed base (or a planar hold's slides): the hold's anchor, or the pinned point
      // on the base's origin
      const btVector3 to_com = to_bt(held_ ? Vector3d(-model_.root.anchor_in_root) : -hang_.point);
      switch (held_ ? model_.root.hold : RootHold::kBall) {
        case RootHold::kWeld:
          body_->setupFixed(link, segment.mass, inertia, parent, zero, origin, to_com, true);
          break;
        case RootHold::kHinge:
        case RootHold::kPlanar:
          body_->setupRevolute(link, segment.mass, inertia, parent, zero, axis, origin, to_com,
                               true);
          break;
        case RootHold::kSlide:
          body_->setupPrismatic(link, segment.mass, inertia, parent, zero, axis, origin, to_com,
                                true);
          break;
        case RootHold::kFree:
        case RootHold::kBall:
          body_->setupSpherical(link, segment.mass, inertia, parent, zero, origin, to_com, true);
          break;
      }
      continue;
    }
    const Joint& joint = model_.joints[joint_of_[link]];
    // the joint point from the parent link's COM (its frame), and to this link's COM (this frame)
    const Vector3d e = forward_[link] ? joint.anchor_in_parent : joint.anchor_in_child;
    const Vector3d d = -(forward_[link] ? joint.anchor_in_child : joint.anchor_in_parent);
    switch (joint.type) {
      case JointType::kBall:
        body_->setupSpherical(link, segment.mass, inertia, parent, zero, to_bt(e), to_bt(d), true);
        break;
      case JointType::kHinge:
        body_->setupRevolute(link, segment.mass, inertia, parent, zero, to_bt(axis_[link]),
                             to_bt(e), to_bt(d), true);
        break;
      case JointType::kSlide:
        body_->setupPrismatic(link, segment.mass, inertia, parent, zero, to_bt(axis_[link]),
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
  const RootJoint& hold = model_.root;
  const bool ranged = hold.hold == RootHold::kSlide ||
                      (hold.hold == RootHold::kHinge && (hold.lower > -kPi || hold.upper < kPi));
  if (held_ && hold.limited && ranged) {
    // the hold's range on its own coordinate, which with the base fixed at the anchor is the
    // model's (a hinge's angle, a slide's distance)
    auto limit = std::make_unique<btMultiBodyJointLimitConstraint>(body_.get(), root_link_,
                                                                   hold.lower, hold.upper);
    limit->setMaxAppliedImpulse(kMaxImpulse);
    limit->finalizeMultiDof();
    world_->addMultiBodyConstraint(limit.get());
    limits_.push_back(std::move(limit));
  }
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
    } else if (joint.type == JointType::kSlide) {
      if (!std::isfinite(joint.lower)) continue;
      // its range on the link's own coordinate, the model's whichever way the link runs
      auto range = std::make_unique<btMultiBodyJointLimitConstraint>(body_.get(), link, joint.lower,
                                                                     joint.upper);
      range->setMaxAppliedImpulse(kMaxImpulse);
      limit = std::move(range);
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

}  // namespace puppet::reference::detail
