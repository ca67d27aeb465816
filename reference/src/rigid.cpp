// The model as a classic ragdoll: one btRigidBody per segment (maximal coordinates) tied by
// joint constraints that Bullet's sequential-impulse solver enforces a few sweeps at a time.
//
// Each body's frame is its segment frame (COM, principal axes), so state needs no conversion.
// Joint constraint frames are the model's joint frame seen from each segment, re-labelled for
// each Bullet constraint's axis convention:
//   btConeTwistConstraint  twist about x, swing1 about z, swing2 about y
//                          → frame axes (x, y, z) = the joint frame's (z, x, y), so
//                            swing1 = swing_y, swing2 = swing_x, twist = twist
//   btHingeConstraint      hinge about z, getHingeAngle() is minus the right-handed angle
//                          (its reference sign is −1) → limits [−upper, −lower]
//   btFixedConstraint      the joint frame itself
//   btGeneric6DofSpring2Constraint (a box limit)  the joint frame itself; its RO_abc angles
//                          (α, β, γ) turn A⁻¹B by R_c(−γ)R_b(−β)R_a(−α), so the box's order
//                          reversed with each angle negated: limits [−upper, −lower] per axis
#include <algorithm>
#include <cmath>
#include <numbers>

#include <BulletDynamics/ConstraintSolver/btGeneric6DofSpring2Constraint.h>

#include "bullet_common.h"
#include "puppet/model/rotation.h"

namespace puppet::reference::detail {
namespace {

constexpr double kPi = std::numbers::pi;

// the cone-twist frame in the joint frame: columns are the joint frame's z, x, y
Quaterniond cone_twist_relabel() {
  Matrix3d r;
  r.col(0) = Vector3d::UnitZ();
  r.col(1) = Vector3d::UnitX();
  r.col(2) = Vector3d::UnitY();
  return Quaterniond(r);
}

class RigidSolver final : public Solver {
 public:
  RigidSolver(const Model& model, const Environment& environment, const Settings& settings);
  ~RigidSolver() override;

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

  double segment_mass(int segment) const override { return 1.0 / bodies_[segment]->getInvMass(); }
  Vector3d segment_inertia(int segment) const override {
    return from_bt(bodies_[segment]->getLocalInertia());
  }
  void joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const override;

 private:
  void build_bodies();
  void build_joints();
  void build_hold();
  static std::unique_ptr<btTypedConstraint> make_box(btRigidBody& parent, btRigidBody& child,
                                                     const Joint& joint, const btTransform& frame_a,
                                                     const btTransform& frame_b);
  void place(int segment, const BodyState& body);

  const Model& model_;
  Environment environment_;
  // each joint's constraint frame in its parent and its child (origin = the anchor)
  std::vector<btTransform> frame_in_parent_, frame_in_child_;

  // Bullet objects: the world is declared last so that it is destroyed first
  CollisionMachinery machinery_;
  btSequentialImpulseConstraintSolver constraint_solver_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  // The world, for pins: a static body of this solver's own at the origin. Bullet's one-body
  // constraints hold to btTypedConstraint::getFixedBody(), one static body for the whole
  // process, and adding or removing a constraint grows or shrinks its list of constraints:
  // two solvers on two threads corrupted the heap there (double free, found by ThreadSanitizer
  // in a --jobs 2 sweep; scripts/tsan_sweep.sh).
  btRigidBody anchor_{btRigidBody::btRigidBodyConstructionInfo(0.0, nullptr, nullptr)};
  std::vector<std::unique_ptr<btTypedConstraint>> joints_;
  std::vector<std::unique_ptr<btPoint2PointConstraint>> pins_;
  std::unique_ptr<btGeneric6DofSpring2Constraint> hold_;  // the world's on the root, if any
  PinSprings springs_;  // which pins are hard, and the compliant ones
  Ground ground_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;

  std::vector<BodyState> states_;  // scratch, sized once
  bool diverged_ = false;
};

RigidSolver::RigidSolver(const Model& model, const Environment& environment,
                         const Settings& settings)
    : model_(model), environment_(environment) {
  world_ =
      std::make_unique<btDiscreteDynamicsWorld>(&machinery_.dispatcher, &machinery_.broadphase,
                                                &constraint_solver_, &machinery_.configuration);
  // gravity comes with the other environment forces through environment_wrench
  world_->setGravity(btVector3(0, 0, 0));
  btContactSolverInfo& info = world_->getSolverInfo();
  // a game ragdoll's budget: Bullet's default 10 sweeps (an option)
  info.m_numIterations = settings.iterations;
  info.m_erp = settings.erp;
  build_bodies();
  build_joints();
  build_hold();
  if (environment.ground) {
    ground_ = make_ground();
    world_->addRigidBody(ground_.body.get(), kGroundGroup, kSegmentGroup);
  }
  states_ = rest_pose(model);
  set_state(states_);
}

RigidSolver::~RigidSolver() {
  for (auto& pin : pins_) world_->removeConstraint(pin.get());
  for (auto& joint : joints_) world_->removeConstraint(joint.get());
  if (hold_) world_->removeConstraint(hold_.get());
  for (auto& body : bodies_) world_->removeRigidBody(body.get());
  if (ground_.body) world_->removeRigidBody(ground_.body.get());
}

void RigidSolver::build_bodies() {
  const int mask = segment_mask(environment_);
  for (const Segment& segment : model_.segments) {
    btCollisionShape* shape = make_segment_shape(segment, shapes_);
    // the model's inertia, never Bullet's calculateLocalInertia
    btRigidBody::btRigidBodyConstructionInfo info(segment.mass, nullptr, shape,
                                                  to_bt(segment.inertia));
    info.m_startWorldTransform = to_bt(segment.rest_orientation, segment.rest_position);
    info.m_linearDamping = 0.0;  // nothing but the environment takes energy out
    info.m_angularDamping = 0.0;
    info.m_friction = environment_.friction;  // times the ground's 1
    info.m_restitution = 0.0;
    auto body = std::make_unique<btRigidBody>(info);
    // never deactivated: a sleeping body stops moving and stops costing time
    body->setActivationState(DISABLE_DEACTIVATION);
    // Bullet's default: the gyroscopic term, integrated implicitly in the body frame
    body->setFlags(BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
    world_->addRigidBody(body.get(), kSegmentGroup, mask);
    bodies_.push_back(std::move(body));
  }
}

void RigidSolver::build_joints() {
  const Quaterniond relabel = cone_twist_relabel();
  for (const Joint& joint : model_.joints) {
    btRigidBody& parent = *bodies_[joint.parent];
    btRigidBody& child = *bodies_[joint.child];
    Quaterniond in_parent = joint.frame_in_parent;
    Quaterniond in_child = joint.frame_in_child;
    const bool box = joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox;
    if (joint.type == JointType::kBall && !box) {
      in_parent = in_parent * relabel;
      in_child = in_child * relabel;
    } else if (joint.type == JointType::kHinge) {
      // the hinge axis becomes the frame's z
      const Quaterniond to_axis = Quaterniond::FromTwoVectors(Vector3d::UnitZ(), joint.hinge_axis);
      in_parent = in_parent * to_axis;
      in_child = in_child * to_axis;
    } else if (joint.type == JointType::kSlide) {
      // the slide's direction becomes the frame's x
      const Quaterniond to_axis = Quaterniond::FromTwoVectors(Vector3d::UnitX(), joint.hinge_axis);
      in_parent = in_parent * to_axis;
      in_child = in_child * to_axis;
    }
    const btTransform frame_a = to_bt(in_parent, joint.anchor_in_parent);
    const btTransform frame_b = to_bt(in_child, joint.anchor_in_child);
    frame_in_parent_.push_back(frame_a);
    frame_in_child_.push_back(frame_b);

    std::unique_ptr<btTypedConstraint> constraint;
    if (box) {
      constraint = make_box(parent, child, joint, frame_a, frame_b);
      world_->addConstraint(constraint.get(), true);
      joints_.push_back(std::move(constraint));
      continue;
    }
    switch (joint.type) {
      case JointType::kBall: {
        auto cone = std::make_unique<btConeTwistConstraint>(parent, child, frame_a, frame_b);
        // limits of half a turn or more never act; Bullet's cone is undefined past π
        const double swing_y = std::min(joint.swing_y, kPi);
        const double swing_x = std::min(joint.swing_x, kPi);
        const double twist = std::min(joint.twist, kPi);
        cone->setLimit(swing_y, swing_x, twist);  // Bullet's softness, bias and relaxation
        constraint = std::move(cone);
        break;
      }
      case JointType::kHinge: {
        auto hinge = std::make_unique<btHingeConstraint>(parent, child, frame_a, frame_b);
        // Bullet's softness and bias; its relaxation factor is the limit's restitution (the
        // default 1 gave back 0.30 of an impact's speed, LimitImpact): 0, near-inelastic as
        // every engine's limits
        if (joint.lower > -kPi || joint.upper < kPi) {
          hinge->setLimit(-joint.upper, -joint.lower, 0.9, 0.3, 0.0);
        }
        constraint = std::move(hinge);
        break;
      }
      case JointType::kFixed:
        constraint = std::make_unique<btFixedConstraint>(parent, child, frame_a, frame_b);
        break;
      case JointType::kSlide: {
        // Bullet's slider: along its frame's x, free (lower above upper, its default) or within
        // the range (B's origin from A's: +s); its turn about x locked (its angular range 0, its
        // default), its limits inelastic (damping 1, its default). Not a 6-dof joint: that one
        // pushes across the slide at each body's own point, which turns the pair as they part
        // (measured: a bead flying out along a spinning rod lost 10 % of the pair's angular
        // momentum in 0.6 s); the slider pushes both at one point
        auto slide = std::make_unique<btSliderConstraint>(parent, child, frame_a, frame_b, true);
        if (std::isfinite(joint.lower)) {
          slide->setLowerLinLimit(joint.lower);
          slide->setUpperLinLimit(joint.upper);
        }
        constraint = std::move(slide);
        break;
      }
    }
    // joined segments never collide (nor do any others: see the collision groups)
    world_->addConstraint(constraint.get(), true);
    joints_.push_back(std::move(constraint));
  }
}

// The world's hold on the root (RootJoint) as a 6-dof joint between the solver's static body and
// the root, its frame at the anchor with axes along the hold's: a slide's along x, a hinge's
// along z, a planar root's slides along x and y and its hinge along z (the third turned round if
// they are left-handed, with its range). What the hold leaves free is free (lower above upper),
// the rest locked; a slide's range is its translation's (B's origin from A's, in A's frame: +s),
// a hinge's its angle's (RO_xyz's angle about z is minus the right-handed one: [−upper, −lower])
void RigidSolver::build_hold() {
  const RootJoint& root = model_.root;
  if (root.hold == RootHold::kFree) return;
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  if (root.hold == RootHold::kSlide || root.hold == RootHold::kHinge) {
    const Vector3d& a = root.axes[0];
    const Vector3d u = any_orthogonal(a), v = a.cross(u);
    if (root.hold == RootHold::kSlide) {
      axes << a, u, v;
    } else {
      axes << u, v, a;
    }
  } else if (root.hold == RootHold::kPlanar) {
    axes << root.axes[0], root.axes[1], root.axes[2];
    if (axes.determinant() < 0.0) axes.col(1) = -axes.col(1);
  }
  const Quaterniond frame(axes);
  const Segment& segment = model_.segments[0];
  const btTransform frame_a = to_bt(frame, root.anchor_world);
  const btTransform frame_b =
      to_bt(segment.rest_orientation.conjugate() * frame, root.anchor_in_root);
  hold_ = std::make_unique<btGeneric6DofSpring2Constraint>(anchor_, *bodies_[0], frame_a, frame_b,
                                                           RO_XYZ);
  btVector3 linear_lower(0, 0, 0), linear_upper(0, 0, 0);
  btVector3 angular_lower(0, 0, 0), angular_upper(0, 0, 0);
  const bool planar = root.hold == RootHold::kPlanar;
  if (root.hold == RootHold::kSlide || planar) {
    // a free slide: lower above upper; a limited one its range
    linear_lower.setX(root.limited ? root.lower : 1.0);
    linear_upper.setX(root.limited ? root.upper : -1.0);
  }
  if (planar) {
    linear_lower.setY(1.0);
    linear_upper.setY(-1.0);
  }
  if (root.hold == RootHold::kHinge || planar) {
    angular_lower.setZ(root.limited ? -root.upper : 1.0);
    angular_upper.setZ(root.limited ? -root.lower : -1.0);
  }
  if (root.hold == RootHold::kBall) {
    linear_lower = linear_upper = btVector3(0, 0, 0);
    angular_lower = btVector3(1, 1, 1);
    angular_upper = btVector3(-1, -1, -1);
  }
  hold_->setLinearLowerLimit(linear_lower);
  hold_->setLinearUpperLimit(linear_upper);
  hold_->setAngularLowerLimit(angular_lower);
  hold_->setAngularUpperLimit(angular_upper);
  world_->addConstraint(hold_.get(), true);
}

// a box limit as a 6-dof joint: the three translations locked, each angle within its range
std::unique_ptr<btTypedConstraint> RigidSolver::make_box(btRigidBody& parent, btRigidBody& child,
                                                         const Joint& joint,
                                                         const btTransform& frame_a,
                                                         const btTransform& frame_b) {
  // RotateOrder lists the orders x y z, x z y, y x z, y z x, z x y, z y x: the reversed order's
  // index
  const auto& o = joint.box_order.axes;
  constexpr int kOrders[3][3] = {{-1, 0, 1}, {2, -1, 3}, {4, 5, -1}};
  const auto order = static_cast<RotateOrder>(kOrders[o[2]][o[1]]);
  auto six =
      std::make_unique<btGeneric6DofSpring2Constraint>(parent, child, frame_a, frame_b, order);
  six->setLinearLowerLimit(btVector3(0, 0, 0));
  six->setLinearUpperLimit(btVector3(0, 0, 0));
  btVector3 lower, upper;
  for (int k = 0; k < 3; ++k) {
    const bool free = joint.box_lower[k] <= -kPi && joint.box_upper[k] >= kPi;
    // lower above upper leaves an axis free
    lower[o[k]] = free ? 1.0 : -joint.box_upper[k];
    upper[o[k]] = free ? -1.0 : -joint.box_lower[k];
  }
  six->setAngularLowerLimit(lower);
  six->setAngularUpperLimit(upper);
  return six;
}

void RigidSolver::set_pins(std::span<const Pin> pins) {
  for (auto& pin : pins_) world_->removeConstraint(pin.get());
  pins_.clear();
  springs_.clear();
  for (const Pin& pin : pins) {
    if (!springs_.add(pin, static_cast<int>(pins_.size()))) continue;
    // the pin holds pivotInA at pivotInB, a point of the anchor at the origin: a world point
    auto p2p = std::make_unique<btPoint2PointConstraint>(*bodies_[pin.segment], anchor_,
                                                         to_bt(pin.local_point), to_bt(pin.target));
    world_->addConstraint(p2p.get(), true);
    pins_.push_back(std::move(p2p));
  }
}

void RigidSolver::set_pin_targets(std::span<const Vector3d> targets) {
  for (size_t k = 0; k < springs_.slots.size() && k < targets.size(); ++k) {
    const int hard = springs_.retarget(k, targets[k]);
    if (hard >= 0) pins_[hard]->setPivotB(to_bt(targets[k]));
  }
}

void RigidSolver::step(double dt) {
  if (diverged_) return;
  read_state(states_);
  const std::span<const Wrench> wrenches = springs_.wrenches(model_, environment_, states_, dt);
  for (int s = 0; s < model_.segment_count(); ++s) {
    bodies_[s]->applyCentralForce(to_bt(wrenches[s].force));
    bodies_[s]->applyTorque(to_bt(wrenches[s].torque));
  }
  // exactly one internal step of dt: maxSubSteps = 0 turns Bullet's fixed-step accumulator off
  world_->stepSimulation(dt, 0, dt);
  springs_.time += dt;
  read_state(states_);
  diverged_ = diverged_ || !all_finite(states_);
}

void RigidSolver::read_state(std::span<BodyState> out) const {
  for (size_t s = 0; s < bodies_.size(); ++s) {
    const btTransform& t = bodies_[s]->getCenterOfMassTransform();
    out[s].x = from_bt(t.getOrigin());
    out[s].q = from_bt(t.getRotation());
    out[s].v = from_bt(bodies_[s]->getLinearVelocity());
    out[s].w = from_bt(bodies_[s]->getAngularVelocity());
  }
}

void RigidSolver::place(int segment, const BodyState& body) {
  btRigidBody& b = *bodies_[segment];
  b.setCenterOfMassTransform(to_bt(body.q, body.x));
  b.setLinearVelocity(to_bt(body.v));
  b.setAngularVelocity(to_bt(body.w));
  b.setInterpolationLinearVelocity(to_bt(body.v));
  b.setInterpolationAngularVelocity(to_bt(body.w));
}

void RigidSolver::set_state(std::span<const BodyState> bodies) {
  for (int s = 0; s < model_.segment_count(); ++s) place(s, bodies[s]);
  clear_contact_caches(machinery_.dispatcher);
}

// the rotation is saved as Bullet's matrix, not a quaternion, so that a restore is bit-exact
std::vector<double> RigidSolver::save() const {
  std::vector<double> saved;
  for (const auto& body : bodies_) {
    const btTransform& t = body->getCenterOfMassTransform();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) saved.push_back(t.getBasis()[r][c]);
    for (const btVector3& v :
         {t.getOrigin(), body->getLinearVelocity(), body->getAngularVelocity()})
      saved.insert(saved.end(), {v.x(), v.y(), v.z()});
  }
  for (const auto& pin : pins_) {
    const btVector3& target = pin->getPivotInB();
    saved.insert(saved.end(), {target.x(), target.y(), target.z()});
  }
  for (const Pin& spring : springs_.springs) {
    saved.insert(saved.end(), {spring.target.x(), spring.target.y(), spring.target.z()});
  }
  saved.push_back(springs_.time);
  saved.push_back(diverged_ ? 1.0 : 0.0);
  return saved;
}

void RigidSolver::load(std::span<const double> saved) {
  const double* v = saved.data();
  for (auto& body : bodies_) {
    const btMatrix3x3 basis(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8]);
    body->setCenterOfMassTransform(btTransform(basis, btVector3(v[9], v[10], v[11])));
    body->setLinearVelocity(btVector3(v[12], v[13], v[14]));
    body->setAngularVelocity(btVector3(v[15], v[16], v[17]));
    v += 18;
  }
  for (auto& pin : pins_) {
    pin->setPivotB(btVector3(v[0], v[1], v[2]));
    v += 3;
  }
  for (Pin& spring : springs_.springs) {
    spring.target = Vector3d(v[0], v[1], v[2]);
    v += 3;
  }
  springs_.time = *v++;
  diverged_ = v[0] != 0.0;
  clear_contact_caches(machinery_.dispatcher);
}

void RigidSolver::joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const {
  const Joint& j = model_.joints[joint];
  const btTypedConstraint& c = *joints_[joint];
  // the frames Bullet holds, not the ones this file computed
  btTransform a = btTransform::getIdentity(), b = btTransform::getIdentity();
  switch (j.type) {
    case JointType::kBall:
      if (j.ball_limit == BallLimit::kEulerBox) {
        a = static_cast<const btGeneric6DofSpring2Constraint&>(c).getFrameOffsetA();
        b = static_cast<const btGeneric6DofSpring2Constraint&>(c).getFrameOffsetB();
        break;
      }
      a = static_cast<const btConeTwistConstraint&>(c).getAFrame();
      b = static_cast<const btConeTwistConstraint&>(c).getBFrame();
      break;
    case JointType::kHinge:
      a = static_cast<const btHingeConstraint&>(c).getAFrame();
      b = static_cast<const btHingeConstraint&>(c).getBFrame();
      break;
    case JointType::kFixed:
      a = static_cast<const btFixedConstraint&>(c).getFrameOffsetA();
      b = static_cast<const btFixedConstraint&>(c).getFrameOffsetB();
      break;
    case JointType::kSlide:
      a = static_cast<const btSliderConstraint&>(c).getFrameOffsetA();
      b = static_cast<const btSliderConstraint&>(c).getFrameOffsetB();
      break;
  }
  *on_parent = from_bt(bodies_[j.parent]->getCenterOfMassTransform() * a.getOrigin());
  *on_child = from_bt(bodies_[j.child]->getCenterOfMassTransform() * b.getOrigin());
}

}  // namespace

std::unique_ptr<Solver> make_rigid(const Model& model, const Environment& environment,
                                   const Settings& settings) {
  return std::make_unique<RigidSolver>(model, environment, settings);
}

}  // namespace puppet::reference::detail
