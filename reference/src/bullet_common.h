// What both Bullet worlds share: conversions between Eigen and Bullet, the model's shapes as
// Bullet shapes, the ground, and the collision groups.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <span>
#include <vector>

#include "pin_springs.h"
#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/reference/bullet.h"

namespace puppet::reference::detail {

inline btVector3 to_bt(const Vector3d& v) { return {v.x(), v.y(), v.z()}; }
inline btQuaternion to_bt(const Quaterniond& q) { return {q.x(), q.y(), q.z(), q.w()}; }
inline Vector3d from_bt(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
inline Quaterniond from_bt(const btQuaternion& q) { return {q.w(), q.x(), q.y(), q.z()}; }
inline btTransform to_bt(const Quaterniond& q, const Vector3d& x) {
  return btTransform(to_bt(q), to_bt(x));
}

// segments collide with the ground only, never with each other (docs/design.md: self-collision
// off); a group of our own, beyond Bullet's predefined filter bits
constexpr int kSegmentGroup = 1 << 8;
constexpr int kGroundGroup = btBroadphaseProxy::StaticFilter;
inline int segment_mask(const Environment& environment) {
  return environment.ground ? kGroundGroup : 0;
}

// Pins and limits stand for a hand and for bone and ligament: they must never give way. The
// impulse that holds 70 kg for one 1/30 s step is 23 N·s; this cap is 40,000 times that, so
// it is never reached and the constraints act as hard (Baumgarte) constraints.
constexpr double kMaxImpulse = 1e6;

// the model's shape, centred on the segment's COM in its segment frame (a capsule's axis is z
// in both conventions; half_length is half the cylinder part in both)
std::unique_ptr<btCollisionShape> make_shape(const Shape& shape);
// a segment's collider: its one shape, or a compound of its shapes each at its place in the
// segment frame; what it creates is kept in `owned` (children before their compound)
btCollisionShape* make_segment_shape(const Segment& segment,
                                     std::vector<std::unique_ptr<btCollisionShape>>& owned);

// the plane z = 0, friction 1 so that Bullet's product of frictions is the segment's μ
struct Ground {
  std::unique_ptr<btCollisionShape> shape;
  std::unique_ptr<btRigidBody> body;
};
Ground make_ground();

// the collision world's machinery, in the order it must be built and torn down
struct CollisionMachinery {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
};

// contact points carry warm-start impulses from step to step: a state set from outside must
// start without them, or the same state would step differently depending on its history
void clear_contact_caches(btCollisionDispatcher& dispatcher);

std::unique_ptr<Solver> make_multibody(const Model& model, const Environment& environment,
                                       const Settings& settings);
std::unique_ptr<Solver> make_rigid(const Model& model, const Environment& environment,
                                   const Settings& settings);

}  // namespace puppet::reference::detail
