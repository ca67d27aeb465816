// Rule `weighted`: the minimum-kinetic-energy correction of a point constraint on a rigid body
// (the seed's "minimise b's angular momentum" made exact):
//   K = E/m − [r]× I⁻¹ [r]×, λ = K⁻¹ s, rotation vector I⁻¹ (r × λ)
// For a single segment both are constant in its own frame, so a joint's correction is a constant
// matrix of the gap (JointTerms::rotation_gain, weighted_gain()); a composite body (rule subtree)
// builds K from its tensor at each correction (weighted_rotation()). Relaxed's final pass and the
// ground's push-out use the same correction (docs/solver.md, "weighted").
#include <cassert>

#include "puppet/model/rotation.h"
#include "rules.h"

namespace puppet::procedural {

Quaterniond weighted_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s) {
  assert(!body.diagonal);
  // in the body's frame, where its tensor was built
  const Vector3d r_frame = body.to_frame(r);
  const Vector3d lambda =
      solve3(point_mass_matrix(body.inv_mass, body.inertia_inv, r_frame), body.to_frame(s));
  return quat_exp(body.to_world(body.inertia_inv * r_frame.cross(lambda)));
}

Matrix3d weighted_gain(const Segment& segment, const Vector3d& r, const Matrix3d& point_mass) {
  // the impulse λ = K⁻¹ s closes the gap s; it turns the segment by D⁻¹ (r × λ)
  return segment.inv_inertia.asDiagonal() * cross_matrix(r) * point_mass.inverse();
}

Quaterniond weighted_forced_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                                     const Vector3d& /*cross*/, double /*cross_norm2*/) {
  return weighted_rotation(body, r, s);
}

void weighted_prepare_joint(const Segment& segment, const Vector3d& r, int side,
                            JointTerms& terms) {
  terms.rotation_gain[side] = weighted_gain(segment, r, terms.point_mass[side]);
}

}  // namespace puppet::procedural
