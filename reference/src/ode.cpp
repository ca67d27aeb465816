// The model as an ODE ragdoll (reference/ode.h): one dBody per segment, ball, hinge and fixed
// joints between them, AMotors for the ball limits, ball joints to the world for hard pins.
//
// Each body's frame is its segment frame (COM, principal axes), so state needs no conversion.
// ODE measures a joint's angles as the first body's rotation relative to the second (measured:
// its hinge angle and Euler angles are minus the model's; Ode.AnEulerMotorStopsAtEachBoxFace
// holds it for each sign of the middle axis), so
//   dHingeJoint            stops [−upper, −lower] about the model's axis
//   AMotor, Euler mode     axis 0 the box's first axis on the parent, axis 2 its last on the
//                          child, axis 1 their cross product (a₂ × a₀, ± the middle axis): angle
//                          k is −θ_k about ODE's axis k, so stops [−upper, −lower] on the first
//                          and last, and on the middle the same when a₂ × a₀ is +a₁, the box's
//                          own range when it is −a₁
//   AMotor, user mode      axis 0 minus the swing axis, angle the swing angle, stop the ellipse's
//                          bound in that direction; axis 1 minus the twist axis, angle the twist,
//                          stops ±twist; axes and angles set before every step
#include "puppet/reference/ode.h"

#include <ode/ode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <numbers>
#include <stdexcept>

#include "ode_library.h"
#include "pin_springs.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"

namespace puppet::reference {
namespace {

constexpr double kPi = std::numbers::pi;
// a geom against the ground plane gives at most four points (a box's face, a cylinder's rim)
constexpr int kMaxContactsPerGeom = 4;
// ODE stops the process on a non-finite quaternion (an internal assertion, which no handler may
// return from), so no non-finite number may reach it: a state is diverged, and ODE left alone,
// when a number is not finite or a speed is past this (m/s or rad/s; the scenarios' fastest
// segment moves at a few tens), which a state must pass through on its way to overflowing
constexpr double kRunawaySpeed = 1e6;

bool runaway(std::span<const BodyState> bodies) {
  if (!all_finite(bodies)) return true;
  for (const BodyState& b : bodies) {
    if (b.v.cwiseAbs().maxCoeff() > kRunawaySpeed || b.w.cwiseAbs().maxCoeff() > kRunawaySpeed) {
      return true;
    }
  }
  return false;
}

Vector3d to_vector(const dReal* v) { return {v[0], v[1], v[2]}; }
Quaterniond to_quaternion(const dReal* q) { return {q[0], q[1], q[2], q[3]}; }
void to_ode(const Quaterniond& q, dQuaternion out) {
  out[0] = q.w();
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}

dGeomID make_geom(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return dCreateSphere(nullptr, shape.radius);
    case ShapeType::kCapsule:  // along z; ODE takes the cylinder part's full length
      return dCreateCapsule(nullptr, shape.radius, 2.0 * shape.half_length);
    case ShapeType::kCylinder:
      return dCreateCylinder(nullptr, shape.radius, 2.0 * shape.half_length);
    case ShapeType::kBox:
      return dCreateBox(nullptr, 2.0 * shape.half_extents.x(), 2.0 * shape.half_extents.y(),
                        2.0 * shape.half_extents.z());
    case ShapeType::kEllipsoid:  // refused by ode_model_problem
      break;
  }
  return nullptr;
}

bool box_axis_free(const Joint& joint, int k) {
  return joint.box_lower[k] <= -kPi && joint.box_upper[k] >= kPi;
}

bool box_limited(const Joint& joint) {
  return joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox &&
         !(box_axis_free(joint, 0) && box_axis_free(joint, 1) && box_axis_free(joint, 2));
}

bool is_swing_twist_limited(const Joint& joint) {
  return joint.type == JointType::kBall && joint.ball_limit == BallLimit::kSwingTwist &&
         std::min({joint.swing_x, joint.swing_y, joint.twist}) < kPi;
}

// the swing angle the ellipse allows about the unit swing axis (u_x, u_y) of the joint frame
double swing_bound(const Joint& joint, double ux, double uy) {
  const auto term = [](double u, double half_angle) {
    if (half_angle >= kPi) return 0.0;
    if (half_angle <= 0.0) return u == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
    return (u / half_angle) * (u / half_angle);
  };
  const double e = term(ux, joint.swing_x) + term(uy, joint.swing_y);
  return e > 0.0 ? 1.0 / std::sqrt(e) : dInfinity;
}

class OdeSolver final : public Solver {
 public:
  OdeSolver(const Model& model, const Environment& environment, const OdeSettings& settings);
  ~OdeSolver() override;
  OdeSolver(const OdeSolver&) = delete;
  OdeSolver& operator=(const OdeSolver&) = delete;

  void set_pins(std::span<const Pin> pins) override;
  void set_pin_targets(std::span<const Vector3d> targets) override;
  void step(double dt) override;
  void set_time(double time) override { springs_.time = time; }
  std::span<const Wrench> user_wrenches() const override { return springs_.user; }
  void read_state(std::span<BodyState> out) const override;
  void set_state(std::span<const BodyState> bodies) override;
  std::vector<double> save() const override;
  void load(std::span<const double> saved) override;
  bool diverged() const override { return diverged_ || engine_error_; }
  bool engine_error() const override { return engine_error_; }

  double segment_mass(int segment) const override;
  Vector3d segment_inertia(int segment) const override;
  void joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const override;

 private:
  void build_bodies(std::span<const BodyState> rest);
  void build_joints(std::span<const BodyState> rest);
  void add_box_motor(const Joint& joint, const Quaterniond& frame_world, dBodyID parent,
                     dBodyID child);
  void aim_swing_twist_motors();
  void collide_with_ground();

  const Model& model_;
  Environment environment_;
  OdeSettings settings_;
  dWorldID world_ = nullptr;
  dThreadingImplementationID threading_ = nullptr;
  std::vector<dBodyID> bodies_;
  std::vector<dGeomID> geoms_;
  dGeomID ground_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  std::vector<dJointID> joints_;  // per model joint
  // the swing–twist limits' user-mode motors, with their joints
  std::vector<std::pair<int, dJointID>> swing_twist_motors_;
  std::vector<dJointID> pins_;  // the hard pins
  detail::PinSprings springs_;
  unsigned long random_state_ = 0;  // dWorldQuickStep's generator, this world's own
  std::vector<dContactGeom> contact_scratch_;
  std::vector<BodyState> states_;  // scratch, sized once
  bool diverged_ = false;
  bool engine_error_ = false;  // ODE stopped a step with its error: not stepped again
};

OdeSolver::OdeSolver(const Model& model, const Environment& environment,
                     const OdeSettings& settings)
    : model_(model), environment_(environment), settings_(settings) {
  detail::ensure_ode_thread();
  world_ = dWorldCreate();
  // ODE steps a world through a threading implementation, by default one shared by every world
  // in the process, whose job list two worlds stepped on two threads corrupted (an internal
  // assertion, found by RunsAgreeBitwiseAloneBesideAnotherAndFromASnapshot): each world has its
  // own, self-threaded (the step on the caller's thread)
  threading_ = dThreadingAllocateSelfThreadedImplementation();
  dWorldSetStepThreadingImplementation(world_, dThreadingImplementationGetFunctions(threading_),
                                       threading_);
  // gravity comes with the other environment forces through environment_wrench
  dWorldSetGravity(world_, 0, 0, 0);
  dWorldSetERP(world_, settings.erp);
  dWorldSetCFM(world_, settings.cfm);
  dWorldSetQuickStepNumIterations(world_, settings.iterations);
  // ODE's defaults, stated: nothing but the environment takes energy out, no body sleeps, no
  // speed is clamped
  dWorldSetLinearDamping(world_, 0.0);
  dWorldSetAngularDamping(world_, 0.0);
  dWorldSetAutoDisableFlag(world_, 0);
  dWorldSetMaxAngularSpeed(world_, dInfinity);
  dWorldSetContactMaxCorrectingVel(world_, dInfinity);
  dWorldSetContactSurfaceLayer(world_, 0.0);
  states_ = rest_pose(model);
  build_bodies(states_);
  build_joints(states_);
  detail::make_hold(world_, bodies_[0], model_.root);  // the world owns it
  if (environment.ground) {
    ground_ = dCreatePlane(nullptr, 0, 0, 1, 0);
    contacts_ = dJointGroupCreate(0);
    contact_scratch_.resize(kMaxContactsPerGeom);
  }
  set_state(states_);
}

OdeSolver::~OdeSolver() {
  if (engine_error_) {
    // a step ODE stopped with its error leaves the world's threading mid-step, and freeing it
    // asserts again (in a destructor, where nothing may throw): the world and everything of it
    // are kept, reachable, for the life of the process
    detail::keep_after_failure({world_, threading_, ground_, contacts_});
    for (dGeomID geom : geoms_) detail::keep_after_failure({geom});
    return;
  }
  for (dGeomID geom : geoms_) dGeomDestroy(geom);
  if (ground_) dGeomDestroy(ground_);
  if (contacts_) dJointGroupDestroy(contacts_);
  dWorldSetStepThreadingImplementation(world_, nullptr, nullptr);
  dWorldDestroy(world_);  // its bodies and joints with it
  dThreadingFreeImplementation(threading_);
}

void OdeSolver::build_bodies(std::span<const BodyState> rest) {
  for (int s = 0; s < model_.segment_count(); ++s) {
    const Segment& segment = model_.segments[s];
    dBodyID body = dBodyCreate(world_);
    dMass mass;
    // the model's inertia about the COM, the body's origin, in its principal frame
    dMassSetParameters(&mass, segment.mass, 0, 0, 0, segment.inertia.x(), segment.inertia.y(),
                       segment.inertia.z(), 0, 0, 0);
    dBodySetMass(body, &mass);
    // ODE's default, stated: the gyroscopic term, integrated implicitly
    dBodySetGyroscopicMode(body, 1);
    dBodySetPosition(body, rest[s].x.x(), rest[s].x.y(), rest[s].x.z());
    dQuaternion q;
    to_ode(rest[s].q, q);
    dBodySetQuaternion(body, q);
    bodies_.push_back(body);
    if (!environment_.ground) continue;  // segments collide with the ground only
    for (const Shape& shape : segment.shapes) {
      dGeomID geom = make_geom(shape);
      dGeomSetBody(geom, body);
      if (!lone_shape(segment)) {
        dGeomSetOffsetPosition(geom, shape.position.x(), shape.position.y(), shape.position.z());
        dQuaternion offset;
        to_ode(shape.orientation, offset);
        dGeomSetOffsetQuaternion(geom, offset);
      }
      geoms_.push_back(geom);
    }
  }
}

// joints are built at the rest pose: ODE takes a hinge's and a fixed joint's zero from the
// bodies' orientations when its axis is set, and an Euler motor's from its axes
void OdeSolver::build_joints(std::span<const BodyState> rest) {
  for (int k = 0; k < static_cast<int>(model_.joints.size()); ++k) {
    const Joint& joint = model_.joints[k];
    dBodyID parent = bodies_[joint.parent];
    dBodyID child = bodies_[joint.child];
    const BodyState& p = rest[joint.parent];
    const Vector3d anchor = p.x + p.q * joint.anchor_in_parent;
    const Quaterniond frame_world = times_frame(p.q, joint.frame_in_parent);
    dJointID made = nullptr;
    switch (joint.type) {
      case JointType::kBall:
        made = dJointCreateBall(world_, nullptr);
        dJointAttach(made, parent, child);
        dJointSetBallAnchor(made, anchor.x(), anchor.y(), anchor.z());
        if (box_limited(joint)) {
          add_box_motor(joint, frame_world, parent, child);
        } else if (is_swing_twist_limited(joint)) {
          dJointID motor = dJointCreateAMotor(world_, nullptr);
          dJointAttach(motor, parent, child);
          dJointSetAMotorMode(motor, dAMotorUser);
          dJointSetAMotorNumAxes(motor, 2);
          swing_twist_motors_.emplace_back(k, motor);
        }
        break;
      case JointType::kHinge:
      case JointType::kFixed:
      case JointType::kSlide:
        made = detail::make_pair_joint(world_, joint, parent, child, anchor, frame_world);
        break;
    }
    joints_.push_back(made);
  }
}

void OdeSolver::add_box_motor(const Joint& joint, const Quaterniond& frame_world, dBodyID parent,
                              dBodyID child) {
  const auto& o = joint.box_order.axes;
  dJointID motor = dJointCreateAMotor(world_, nullptr);
  dJointAttach(motor, parent, child);
  dJointSetAMotorMode(motor, dAMotorEuler);
  const Vector3d first = frame_world * Vector3d::Unit(o[0]);
  const Vector3d last = frame_world * Vector3d::Unit(o[2]);
  dJointSetAMotorAxis(motor, 0, 1, first.x(), first.y(), first.z());
  dJointSetAMotorAxis(motor, 2, 2, last.x(), last.y(), last.z());
  // ODE's middle axis is a₂ × a₀: its angle is −θ₁ when that is +a₁, θ₁ when it is −a₁
  const double middle_sign = Vector3d::Unit(o[2]).cross(Vector3d::Unit(o[0]))[o[1]];
  constexpr std::array<int, 3> kLo = {dParamLoStop, dParamLoStop2, dParamLoStop3};
  constexpr std::array<int, 3> kHi = {dParamHiStop, dParamHiStop2, dParamHiStop3};
  for (int k = 0; k < 3; ++k) {
    if (box_axis_free(joint, k)) continue;
    const bool negated = k != 1 || middle_sign > 0.0;
    const double lo = negated ? -joint.box_upper[k] : joint.box_lower[k];
    const double hi = negated ? -joint.box_lower[k] : joint.box_upper[k];
    dJointSetAMotorParam(motor, kHi[k], hi);
    dJointSetAMotorParam(motor, kLo[k], lo);
  }
}

// each swing–twist motor's axes, angles and swing bound for the coming step, from the pose
void OdeSolver::aim_swing_twist_motors() {
  for (const auto& [k, motor] : swing_twist_motors_) {
    const Joint& joint = model_.joints[k];
    const BodyState& p = states_[joint.parent];
    const BodyState& c = states_[joint.child];
    const Quaterniond parent_frame = times_frame(p.q, joint.frame_in_parent);
    const Quaterniond child_frame = times_frame(c.q, joint.frame_in_child);
    const SwingTwist st =
        decompose_swing_twist(parent_frame.conjugate() * child_frame, Vector3d::UnitZ());
    const Vector3d s = quat_log(st.swing);  // in the parent's joint frame, z = 0
    const double angle = s.norm();
    const Vector3d u = angle > 0.0 ? Vector3d(s / angle) : Vector3d::UnitX();
    // ODE's rate of a user angle is (ω_parent − ω_child)·axis: the axes are negated
    const Vector3d swing_axis = -(parent_frame * u);
    const Vector3d twist_axis = -(child_frame * Vector3d::UnitZ());
    dJointSetAMotorAxis(motor, 0, 0, swing_axis.x(), swing_axis.y(), swing_axis.z());
    dJointSetAMotorAxis(motor, 1, 0, twist_axis.x(), twist_axis.y(), twist_axis.z());
    dJointSetAMotorAngle(motor, 0, angle);
    dJointSetAMotorAngle(motor, 1, st.twist_angle);
    dJointSetAMotorParam(motor, dParamHiStop, swing_bound(joint, u.x(), u.y()));
    dJointSetAMotorParam(motor, dParamLoStop, -dInfinity);
    const double twist = joint.twist < kPi ? joint.twist : dInfinity;
    dJointSetAMotorParam(motor, dParamHiStop2, twist);
    dJointSetAMotorParam(motor, dParamLoStop2, -twist);
  }
}

void OdeSolver::set_pins(std::span<const Pin> pins) {
  for (dJointID pin : pins_) dJointDestroy(pin);
  pins_.clear();
  springs_.clear();
  for (const Pin& pin : pins) {
    if (!springs_.add(pin, static_cast<int>(pins_.size()))) continue;
    dJointID joint = dJointCreateBall(world_, nullptr);
    dJointAttach(joint, bodies_[pin.segment], nullptr);
    // the body's point where it is now, then the world's end at the target
    const dReal* x = dBodyGetPosition(bodies_[pin.segment]);
    const Quaterniond q = to_quaternion(dBodyGetQuaternion(bodies_[pin.segment]));
    const Vector3d point = to_vector(x) + q * pin.local_point;
    dJointSetBallAnchor(joint, point.x(), point.y(), point.z());
    dJointSetBallAnchor2(joint, pin.target.x(), pin.target.y(), pin.target.z());
    pins_.push_back(joint);
  }
}

void OdeSolver::set_pin_targets(std::span<const Vector3d> targets) {
  for (size_t k = 0; k < springs_.slots.size() && k < targets.size(); ++k) {
    if (!targets[k].allFinite()) {  // ODE is never given it
      read_state(states_);
      diverged_ = true;
      return;
    }
    const int hard = springs_.retarget(k, targets[k]);
    if (hard >= 0)
      dJointSetBallAnchor2(pins_[hard], targets[k].x(), targets[k].y(), targets[k].z());
  }
}

void OdeSolver::collide_with_ground() {
  dJointGroupEmpty(contacts_);
  for (dGeomID geom : geoms_) {
    const int n =
        dCollide(geom, ground_, kMaxContactsPerGeom, contact_scratch_.data(), sizeof(dContactGeom));
    for (int i = 0; i < n; ++i) {
      dContact contact{};
      // Coulomb's pyramid with the bound μ·(normal force): without dContactApprox1, ODE reads μ
      // as a bound in newtons
      contact.surface.mode = dContactApprox1;
      contact.surface.mu = environment_.friction;
      contact.geom = contact_scratch_[i];
      dJointID joint = dJointCreateContact(world_, contacts_, &contact);
      dJointAttach(joint, dGeomGetBody(geom), nullptr);
    }
  }
}

void OdeSolver::step(double dt) {
  if (diverged_ || engine_error_) return;
  detail::ensure_ode_thread();
  read_state(states_);
  const std::span<const Wrench> wrenches = springs_.wrenches(model_, environment_, states_, dt);
  for (const Wrench& w : wrenches) {
    if (!w.force.allFinite() || !w.torque.allFinite()) {
      diverged_ = true;  // states_ holds the state it came from
      return;
    }
  }
  for (int s = 0; s < model_.segment_count(); ++s) {
    const Wrench& w = wrenches[s];
    dBodyAddForce(bodies_[s], w.force.x(), w.force.y(), w.force.z());
    dBodyAddTorque(bodies_[s], w.torque.x(), w.torque.y(), w.torque.z());
  }
  try {
    aim_swing_twist_motors();
    if (ground_) collide_with_ground();
    if (settings_.stepper == OdeStepper::kQuick) {
      const std::lock_guard<std::mutex> hold(detail::quick_step_lock());
      dRandSetSeed(random_state_);
      dWorldQuickStep(world_, dt);
      random_state_ = dRandGetSeed();
    } else {
      dWorldStep(world_, dt);
    }
  } catch (const detail::OdeFailure& failure) {
    // states_ holds the state the step came from; ODE's world is not stepped again
    diverged_ = true;
    engine_error_ = true;
    std::fprintf(stderr,
                 "ode: ODE stopped a step with its error \"%s\"; the run reads as "
                 "diverged\n",
                 failure.what());
    return;
  }
  springs_.time += dt;
  read_state(states_);
  diverged_ = runaway(states_);
}

void OdeSolver::read_state(std::span<BodyState> out) const {
  if (diverged_) {  // the state that diverged, which ODE was never given
    std::copy(states_.begin(), states_.end(), out.begin());
    return;
  }
  for (size_t s = 0; s < bodies_.size(); ++s) {
    out[s].x = to_vector(dBodyGetPosition(bodies_[s]));
    out[s].q = to_quaternion(dBodyGetQuaternion(bodies_[s]));
    out[s].v = to_vector(dBodyGetLinearVel(bodies_[s]));
    out[s].w = to_vector(dBodyGetAngularVel(bodies_[s]));
  }
}

void OdeSolver::set_state(std::span<const BodyState> bodies) {
  if (runaway(bodies)) {
    std::copy(bodies.begin(), bodies.end(), states_.begin());
    diverged_ = true;
    return;
  }
  diverged_ = false;
  for (size_t s = 0; s < bodies_.size(); ++s) {
    const BodyState& b = bodies[s];
    dBodySetPosition(bodies_[s], b.x.x(), b.x.y(), b.x.z());
    dQuaternion q;
    to_ode(b.q, q);
    dBodySetQuaternion(bodies_[s], q);
    dBodySetLinearVel(bodies_[s], b.v.x(), b.v.y(), b.v.z());
    dBodySetAngularVel(bodies_[s], b.w.x(), b.w.y(), b.w.z());
  }
}

// ODE keeps a body's rotation as its quaternion and derives the matrix from it, so 13 numbers a
// body restore it exactly (load)
std::vector<double> OdeSolver::save() const {
  std::vector<double> saved;
  for (dBodyID body : bodies_) {
    for (const dReal* v :
         {dBodyGetPosition(body), dBodyGetLinearVel(body), dBodyGetAngularVel(body)})
      saved.insert(saved.end(), v, v + 3);
    const dReal* q = dBodyGetQuaternion(body);
    saved.insert(saved.end(), q, q + 4);
  }
  for (dJointID pin : pins_) {
    dVector3 target;
    dJointGetBallAnchor2(pin, target);
    saved.insert(saved.end(), target, target + 3);
  }
  for (const Pin& spring : springs_.springs) {
    saved.insert(saved.end(), {spring.target.x(), spring.target.y(), spring.target.z()});
  }
  saved.push_back(springs_.time);
  saved.push_back(static_cast<double>(random_state_));
  saved.push_back(diverged_ ? 1.0 : 0.0);
  return saved;
}

void OdeSolver::load(std::span<const double> saved) {
  const double* v = saved.data();
  for (dBodyID body : bodies_) {
    dBodySetPosition(body, v[0], v[1], v[2]);
    dBodySetLinearVel(body, v[3], v[4], v[5]);
    dBodySetAngularVel(body, v[6], v[7], v[8]);
    // dBodySetQuaternion normalises the quaternion, which moves its last bits: it places the
    // body (and marks its geoms moved), then the saved quaternion goes into ODE's own copy and
    // the rotation matrix is derived from it as ODE's step derives it
    const dQuaternion q = {v[9], v[10], v[11], v[12]};
    dBodySetQuaternion(body, q);
    dReal* own_q = const_cast<dReal*>(dBodyGetQuaternion(body));
    std::copy(q, q + 4, own_q);
    dQtoR(own_q, const_cast<dReal*>(dBodyGetRotation(body)));
    v += 13;
  }
  for (dJointID pin : pins_) {
    dJointSetBallAnchor2(pin, v[0], v[1], v[2]);
    v += 3;
  }
  for (Pin& spring : springs_.springs) {
    spring.target = Vector3d(v[0], v[1], v[2]);
    v += 3;
  }
  springs_.time = *v++;
  random_state_ = static_cast<unsigned long>(*v++);
  diverged_ = v[0] != 0.0;
}

double OdeSolver::segment_mass(int segment) const {
  dMass mass;
  dBodyGetMass(bodies_[segment], &mass);
  return mass.mass;
}

Vector3d OdeSolver::segment_inertia(int segment) const {
  dMass mass;
  dBodyGetMass(bodies_[segment], &mass);
  return {mass.I[0], mass.I[5], mass.I[10]};  // ODE's 3×4 row-major matrix
}

void OdeSolver::joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const {
  dJointID j = joints_[joint];
  dVector3 a, b;
  switch (model_.joints[joint].type) {
    case JointType::kBall:
      dJointGetBallAnchor(j, a);
      dJointGetBallAnchor2(j, b);
      break;
    case JointType::kHinge:
      dJointGetHingeAnchor(j, a);
      dJointGetHingeAnchor2(j, b);
      break;
    case JointType::kFixed:
    case JointType::kSlide: {
      // a fixed joint and a slider have no anchor in ODE: the point is the model's, carried by
      // each body
      const Joint& m = model_.joints[joint];
      const auto carried = [this](int s, const Vector3d& local) {
        const Quaterniond q = to_quaternion(dBodyGetQuaternion(bodies_[s]));
        return Vector3d(to_vector(dBodyGetPosition(bodies_[s])) + q * local);
      };
      *on_parent = carried(m.parent, m.anchor_in_parent);
      *on_child = carried(m.child, m.anchor_in_child);
      return;
    }
  }
  *on_parent = to_vector(a);
  *on_child = to_vector(b);
}

}  // namespace

std::string validate(const OdeSettings& settings) {
  if (settings.iterations < 1 || settings.iterations > 10000)
    return "iterations must be in [1, 10000], got " + std::to_string(settings.iterations);
  if (!(settings.erp > 0.0 && settings.erp <= 1.0))
    return "erp must be in (0, 1], got " + std::to_string(settings.erp);
  if (!(settings.cfm >= 0.0 && settings.cfm <= 1.0))
    return "cfm must be in [0, 1], got " + std::to_string(settings.cfm);
  return {};
}

bool have_ode() { return true; }

std::string ode_model_problem(const Model& model) {
  if (model.root.hold == RootHold::kPlanar) {
    return "its root is joined to the world by a planar joint (slide, slide, hinge), which ODE "
           "0.16 has no joint for (its Plane2D holds a body to the plane z = 0 only)";
  }
  for (const Segment& segment : model.segments) {
    for (const Shape& shape : segment.shapes) {
      if (shape.type == ShapeType::kEllipsoid) {
        return "segment \"" + segment.name + "\" has an ellipsoid, for which ODE has no geom";
      }
    }
  }
  if (std::string problem = slide_armature_problem(model); !problem.empty()) return problem;
  return box_offsets_problem(model);
}

std::unique_ptr<Solver> make_ode(const Model& model, const Environment& environment,
                                 const OdeSettings& settings) {
  if (std::string p = validate(settings); !p.empty()) throw std::invalid_argument("ode: " + p);
  if (std::string p = ode_model_problem(model); !p.empty()) throw ModelError("ode: " + p);
  return std::make_unique<OdeSolver>(model, environment, settings);
}

}  // namespace puppet::reference
