// The limits' velocity pass (stage 4, after the velocities are derived from the poses), for the
// rules whose velocities come from positions their last correction of a limit leaves (xpbd,
// tree; relaxed's final one-sided pass clamps, and gives nothing back).
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
#include <algorithm>
#include "puppet/model/rotation.h"

#include "stages.h"

namespace puppet::procedural {

void begin_limit_marks(const State& state, Workspace& ws) {
  std::fill(ws.limit_violated.begin(), ws.limit_violated.end(), 0);
  for (size_t i = 0; i < state.bodies.size(); ++i) ws.w_before[i] = state.bodies[i].w;
}

void hold_limit_rates(const Model& model, const JointTerms& terms, const Joint& joint,
                      const LimitRows& marked, double restitution, const Vector3d& rate_before,
                      BodyState& parent, BodyState& child) {
  const LimitRows rows =
      marked.count == kRowsAtPose
          ? limit_rows(joint, joint_relative_rotation(joint, parent.q, child.q), -kAtLimit)
          : marked;
  if (rows.count == 0) return;
  const Quaterniond child_to_parent = child.q.conjugate() * parent.q;
  const Segment& ps = model.segments[joint.parent];
  const Segment& cs = model.segments[joint.child];
  // Everything in the child's frame, where its inertia is diagonal, R the parent's frame seen
  // from it. Unknowns: the impulse P at the joint point (on the child) and a torque λₖ along each
  // row uₖ; the parent takes their opposites. Rows: the joint point's relative velocity (to stay
  // as it is) and each row's rate. With W each side's inverse inertia and a its arm,
  // A = [[K, B], [Bᵀ, L]]:
  //   K = K_c + R K_p Rᵀ (each side's point mass matrix, JointTerms::point_mass),
  //   B eₖ = (W_c uₖ) × a_c + (W_p uₖ) × a_p,   Lₖₗ = uₖᵀ (W_c + W_p) uₗ,
  // solved through the Schur complement of K: (L − Bᵀ K⁻¹ B) λ = Δu, then P = −K⁻¹ B λ.
  const Matrix3d rotation = child_to_parent.toRotationMatrix();
  const ParentSide side = parent_side(model, terms, joint, parent.q, child.q);
  const Matrix3d k = terms.point_mass[1] + rotation * side.point_mass * rotation.transpose();
  const Matrix3d w_parent = rotation * ps.inv_inertia.asDiagonal() * rotation.transpose();
  const Vector3d& a_child = joint.anchor_in_child;
  const Vector3d a_parent = rotation * side.anchor;
  const Vector3d w_rel = child.q.conjugate() * (child.w - parent.w);
  Matrix3d b = Matrix3d::Zero();          // columns: B eₖ
  Matrix3d k_inv_b = Matrix3d::Zero();    // K⁻¹ B
  Matrix3d schur = Matrix3d::Identity();  // unused rows padded (their λ is 0)
  Vector3d du = Vector3d::Zero();
  for (int i = 0; i < rows.count; ++i) {
    const Vector3d u = rows.directions.row(i).transpose();
    b.col(i) = cs.inv_inertia.cwiseProduct(u).cross(a_child) + (w_parent * u).cross(a_parent);
    k_inv_b.col(i) = solve3(k, b.col(i));
    du(i) = -restitution * std::max(0.0, u.dot(rate_before)) - u.dot(w_rel);
  }
  for (int i = 0; i < rows.count; ++i) {
    const Vector3d u = rows.directions.row(i).transpose();
    const Vector3d w_sum_u = cs.inv_inertia.cwiseProduct(u) + w_parent * u;
    for (int l = 0; l < rows.count; ++l) {
      schur(l, i) = rows.directions.row(l).dot(w_sum_u) - b.col(l).dot(k_inv_b.col(i));
    }
  }
  // a box's first and last faces at gimbal lock: nearly parallel rows (as limit_error)
  schur.diagonal().array() += 1e-12 * schur.trace();
  const Vector3d lambda = solve3(schur, du);
  Vector3d torque = Vector3d::Zero();
  for (int i = 0; i < rows.count; ++i) torque += lambda(i) * rows.directions.row(i).transpose();
  const Vector3d impulse = -(k_inv_b * lambda);  // on the child, its frame
  const Vector3d impulse_world = child.q * impulse;
  child.v += cs.inv_mass * impulse_world;
  child.w += child.q * cs.inv_inertia.cwiseProduct(a_child.cross(impulse) + torque);
  parent.v -= ps.inv_mass * impulse_world;
  // the parent's angular impulse a_p × P + τ, carried into its frame by Rᵀ
  parent.w -= parent.q * ps.inv_inertia.cwiseProduct(rotation.transpose() *
                                                     (a_parent.cross(impulse) + torque));
}

void limit_velocity_pass(const Model& model, const ModelTables& tables, double restitution,
                         const Workspace& ws, State& state) {
  for (int j = 0; j < model.joint_count(); ++j) {
    if (!ws.limit_violated[j]) continue;
    const Joint& joint = model.joints[j];
    BodyState& parent = state.bodies[joint.parent];
    BodyState& child = state.bodies[joint.child];
    const Vector3d rate_before =
        child.q.conjugate() * (ws.w_before[joint.child] - ws.w_before[joint.parent]);
    hold_limit_rates(model, tables.joints[j], joint, ws.limit_rows[j], restitution, rate_before,
                     parent, child);
  }
}

}  // namespace puppet::procedural
