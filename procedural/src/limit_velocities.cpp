// The limits' velocity pass (stage 4, after the velocities are derived from the poses), for the
// rules whose velocities come from their positions (relaxed, xpbd, tree).
//
// Why: the position pass puts a joint that went past its limit back on it, and v = Δx/h then
// holds whatever the pass did. A limit closed in one correction leaves the joint's rate at about
// zero, but a correction undone in part by the next joint's, or closed over two substeps, leaves
// a rate away from the limit: measured, a hinge driven into its end at 3 rad/s came back at 0.20
// (relaxed, tree) and 0.31 (xpbd) of that speed, where both truths give back 1–2 %.
//
// What: as the XPBD rigid-body paper does for contacts (Müller et al. 2020, §3.6), every joint
// whose limit the substep's position pass corrected gets, after the derivation, the rate its
// restitution asks along each limit function still at its bound: u·ω_rel = −e · (the rate it came
// in with), 0 by default. The rows of one joint are solved together (a box's corner, two or three
// faces at once) with the joint point's three, whose relative velocity the impulses leave as it
// was: stopping a rate by torques alone would set the child's centre moving against its own turn,
// and the next position pass would close that into a rate back (measured: a hinge against a
// still parent came back at 0.37 of its speed with torques alone, 0 with the point's rows).
// Joints one after another by index (Gauss–Seidel, one sweep).
//
// Energy: with the joint point's relative velocity at zero (the joint held), the impulses do no
// work on it, and the rows' part takes out ½ (u² − u'²) in the metric of A = J M⁻¹ Jᵀ: at e = 0
// (the default) or on a single row with e ≤ 1 the pass never adds kinetic energy
// (limit_velocities_test.cpp); at a corner with e > 0 it can (one row sent back, another
// stopped: measured up to 3%). Joint gaps: the pass moves no pose, and leaves each joint point's
// relative velocity as the positions gave it.
#include "puppet/model/rotation.h"
#include <algorithm>

#include "stages.h"

namespace puppet::procedural {

void begin_limit_marks(const State& state, Workspace& ws) {
  std::fill(ws.limit_violated.begin(), ws.limit_violated.end(), 0);
  for (size_t i = 0; i < state.bodies.size(); ++i) ws.w_before[i] = state.bodies[i].w;
}

void hold_limit_rates(const Model& model, const Joint& joint, double restitution,
                      const Vector3d& rate_before, BodyState& parent, BodyState& child) {
  const LimitRows rows =
      limit_rows(joint, joint_relative_rotation(joint, parent.q, child.q), -kAtLimit);
  if (rows.count == 0) return;  // the pass left it inside: nothing holds it there
  const Segment& ps = model.segments[joint.parent];
  const Segment& cs = model.segments[joint.child];
  // generalised velocities (v_c, ω_c, v_p, ω_p), world; rows: the joint point's relative
  // velocity (3), then each limit row's rate
  using Matrix6x12 = Eigen::Matrix<double, 6, 12>;
  using Vector12d = Eigen::Matrix<double, 12, 1>;
  const Vector3d r_child = child.q * joint.anchor_in_child;
  const Vector3d r_parent = parent.q * joint.anchor_in_parent;
  Matrix6x12 jacobian = Matrix6x12::Zero();
  jacobian.block<3, 3>(0, 0).setIdentity();
  jacobian.block<3, 3>(0, 3) = -cross_matrix(r_child);
  jacobian.block<3, 3>(0, 6) = -Matrix3d::Identity();
  jacobian.block<3, 3>(0, 9) = cross_matrix(r_parent);
  Vector6d target = Vector6d::Zero();  // the point's relative velocity left as it is
  const Vector3d w_rel = child.w - parent.w;
  const Vector3d came_in = child.q * rate_before;
  for (int k = 0; k < rows.count; ++k) {
    const Vector3d n = child.q * Vector3d(rows.directions.row(k).transpose());
    jacobian.block<1, 3>(3 + k, 3) = n.transpose();
    jacobian.block<1, 3>(3 + k, 9) = -n.transpose();
    target(3 + k) = -restitution * std::max(0.0, n.dot(came_in)) - n.dot(w_rel);
  }
  // M⁻¹ Jᵀ, block by block (the inverse inertias in world at the current orientations)
  const auto inverse_inertia = [](const Quaterniond& q, const Vector3d& inv) {
    const Matrix3d r = q.toRotationMatrix();
    return Matrix3d(r * inv.asDiagonal() * r.transpose());
  };
  Eigen::Matrix<double, 12, 6> scaled = jacobian.transpose();
  scaled.middleRows<3>(0) *= cs.inv_mass;
  scaled.middleRows<3>(3) = inverse_inertia(child.q, cs.inv_inertia) * scaled.middleRows<3>(3);
  scaled.middleRows<3>(6) *= ps.inv_mass;
  scaled.middleRows<3>(9) = inverse_inertia(parent.q, ps.inv_inertia) * scaled.middleRows<3>(9);
  Matrix6d a = jacobian * scaled;
  for (int i = 3 + rows.count; i < 6; ++i) a(i, i) = 1.0;  // unused rows: their impulse is 0
  // a box's first and last faces at gimbal lock: nearly parallel rows (as limit_error)
  a.diagonal().array() += 1e-12 * a.trace();
  const Vector12d change = scaled * a.ldlt().solve(target);
  child.v += change.segment<3>(0);
  child.w += change.segment<3>(3);
  parent.v += change.segment<3>(6);
  parent.w += change.segment<3>(9);
}

void limit_velocity_pass(const Model& model, double restitution, const Workspace& ws,
                         State& state) {
  for (int j = 0; j < model.joint_count(); ++j) {
    if (!ws.limit_violated[j]) continue;
    const Joint& joint = model.joints[j];
    BodyState& parent = state.bodies[joint.parent];
    BodyState& child = state.bodies[joint.child];
    const Vector3d rate_before = child.q.conjugate() * (ws.w_before[joint.child] - ws.w_before[joint.parent]);
    hold_limit_rates(model, joint, restitution, rate_before, parent, child);
  }
}

}  // namespace puppet::procedural
