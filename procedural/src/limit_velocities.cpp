// The limits' velocity pass (stage 4, after the velocities are derived from the poses), for the
// rules whose velocities come from their positions (relaxed, xpbd, tree).
//
// Why: the position pass puts a joint that went past its limit back on it, and v = Δx/h then
// holds whatever the pass did. A limit closed in one correction leaves the joint's rate at about
// zero, but a correction undone in part by the next joint's, or closed over two substeps, leaves
// a rate away from the limit: measured, a hinge driven into its end at 3 rad/s came back at 0.20
// (relaxed, tree) and 0.31 (xpbd) of that speed, where both truths give back 1–2 %.
//
// What: as the XPBD rigid-body paper does for contacts (Müller et al. 2020, §3.6), every limit
// the update's predicted pose had violated gets, after the derivation, the rate its restitution
// asks along each limit function still at its bound: u·ω_rel = −e · (the rate it came in with),
// 0 by default. The rows of one joint are solved together (a box's corner, two or three faces at
// once), by angular impulses equal and opposite on its two segments through their inverse
// inertias; joints one after another from the anchor order's first (Gauss–Seidel, one sweep).
//
// Energy: with e = 0 each joint's impulse takes out exactly the kinetic energy of the rates it
// stops, ½ Δuᵀ A⁻¹ Δu ≥ 0 with A the rows' inverse inertia, so the pass never adds energy; with
// e > 0 it gives back at most e² of what came in. Joint gaps: the impulses are pure torque pairs,
// so the pass moves no segment's centre and no pose; the joint point's velocities it leaves
// apart are closed by the next substep's position pass as any other.
#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {

void mark_violated_limits(const Model& model, const ModelTables& tables, const State& state,
                          Workspace& ws) {
  for (int j = 0; j < model.joint_count(); ++j) {
    const Joint& joint = model.joints[j];
    const JointTerms& terms = tables.joints[j];
    const BodyState& parent = state.bodies[joint.parent];
    const BodyState& child = state.bodies[joint.child];
    ws.limit_violated[j] = 0;
    if (!may_reach_limit(terms, child.q.conjugate() * parent.q)) continue;
    const Quaterniond q_rel = joint_relative_rotation(joint, parent.q, child.q);
    if (terms.box.enabled && surely_inside_box(terms.box, q_rel)) continue;
    if (limit_rows(joint, q_rel, 0.0).count == 0) continue;
    ws.limit_violated[j] = 1;
    ws.limit_rate_before[j] = child.q.conjugate() * (child.w - parent.w);
  }
}

void limit_velocity_pass(const Model& model, double restitution, const Workspace& ws,
                         State& state) {
  for (int j = 0; j < model.joint_count(); ++j) {
    if (!ws.limit_violated[j]) continue;
    const Joint& joint = model.joints[j];
    BodyState& parent = state.bodies[joint.parent];
    BodyState& child = state.bodies[joint.child];
    const LimitRows rows =
        limit_rows(joint, joint_relative_rotation(joint, parent.q, child.q), -kAtLimit);
    if (rows.count == 0) continue;  // the pass left it inside: nothing holds it there
    const Vector3d& inv_parent = model.segments[joint.parent].inv_inertia;
    const Vector3d& inv_child = model.segments[joint.child].inv_inertia;
    const Matrix3d rotation = (child.q.conjugate() * parent.q).toRotationMatrix();
    Matrix3d inv_sum = rotation * inv_parent.asDiagonal() * rotation.transpose();
    inv_sum.diagonal() += inv_child;
    const Vector3d w_rel = child.q.conjugate() * (child.w - parent.w);
    // A λ = Δu over the active rows; unused rows padded as λ = 0
    Matrix3d a = Matrix3d::Identity();
    Vector3d du = Vector3d::Zero();
    for (int k = 0; k < rows.count; ++k) {
      const Vector3d u = rows.directions.row(k).transpose();
      for (int l = 0; l < rows.count; ++l) {
        a(k, l) = u.dot(inv_sum * rows.directions.row(l).transpose());
      }
      const double came_in = std::max(0.0, u.dot(ws.limit_rate_before[j]));
      du(k) = -restitution * came_in - u.dot(w_rel);
    }
    const Vector3d lambda = solve3(a, du);
    Vector3d impulse = Vector3d::Zero();  // Σ λₖ uₖ, the child's (its frame)
    for (int k = 0; k < rows.count; ++k) impulse += lambda(k) * rows.directions.row(k).transpose();
    child.w += child.q * inv_child.cwiseProduct(impulse);
    parent.w -= parent.q * inv_parent.cwiseProduct(rotation.transpose() * impulse);
  }
}

}  // namespace puppet::procedural
