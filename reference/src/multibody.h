// The model as one btMultiBody (Featherstone's articulated-body algorithm, reduced coordinates).
//
// Rooting. Where a hard pin holds its point on a target that does not move (a marionette's
// head), the tree hangs from it: the base is a fixed point at the target and the pinned segment
// is the first link, on a spherical joint there, so the pin holds exactly as MuJoCo's does
// (mujoco.cpp). Joints on the path from that segment to the model's root are then built from
// their child's side. Otherwise the base is the model's root segment, floating, and pins are
// PinRows (limit_rows.h). A pin whose target starts to move stops being the root: the tree is
// rebuilt from the model's root and the state carried over through world poses. A root the world
// holds (RootJoint) is Bullet's fixed base: the base is a fixed point at the hold's anchor, the
// root the first link on the hold's own joint (a weld fixed, a hinge revolute, a slide prismatic,
// a ball spherical), a hinge's or slide's range Bullet's btMultiBodyJointLimitConstraint on that
// coordinate; pins are then always rows. A planar root is two massless prismatic links, then the
// root on a revolute joint at the anchor: the model's own coordinates (s₀, s₁, θ), as MuJoCo's.
// Bullet's planar joint, which turns the link about its centre and moves that in the turning
// link's frame, strays from a spinning projectile's path at first order in h (2.7 cm over 1 s at
// 1/480 s and 3 rad/s; a quarter of it at a quarter of the step), where the links do not.
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
//
// The solver's parts: multibody_build.cpp builds the tree (links, limits, colliders, pins),
// multibody.cpp steps it, sets and reads its state. Private to reference/.
#pragma once

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

inline constexpr double kPi = std::numbers::pi;

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
  // the root's joint to the world, when it holds the root: link 0's coordinates from a state
  void set_held_root(const BodyState& root);
  // after the coordinates changed from outside a step: colliders follow, contacts forget
  void coordinates_changed();
  bool state_finite() const;

  const Model& model_;
  const bool held_;  // the world holds the root (RootJoint): Bullet's fixed base
  Environment environment_;
  Settings settings_;
  std::vector<Pin> pins_;
  Hang hang_;
  long generation_ = 0;  // assemblies so far: a saved state names the one it was saved under

  // the tree as built, links parent first: per segment its link (−1: the floating base), per
  // link its segment (−1: a planar hold's massless slide), the link it hangs from (−1: the base),
  // the model joint between them (−1: the hanging pin's or the hold's), whether the link is that
  // joint's child, and its rest orientation; the root segment's link under a held root
  std::vector<int> link_of_;
  std::vector<int> segment_of_;
  std::vector<int> parent_link_;
  std::vector<int> joint_of_;
  std::vector<char> forward_;
  std::vector<Quaterniond> zero_;  // z above, per link
  std::vector<Vector3d> axis_;     // a revolute or prismatic link's axis in its frame
  int root_link_ = 0;

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

}  // namespace puppet::reference::detail
