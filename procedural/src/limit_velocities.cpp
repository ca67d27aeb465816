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
  // Unknowns: the impulse P at the joint point (on the child, world) and one torque λₖ along each
  // row's world direction nₖ; the parent takes their opposites. Rows: the joint point's relative
  // velocity (to stay as it is) and each row's rate. With W each side's inverse inertia (world)
  // and r its arm, A = [[K, B], [Bᵀ, L]]:
  //   K = (1/m_c + 1/m_p) E − [r_c]× W_c [r_c]× − [r_p]× W_p [r_p]×,
  //   B eₖ = (W_c nₖ) × r_c + (W_p nₖ) × r_p,   Lₖₗ = nₖᵀ (W_c + W_p) nₗ,
  // solved through the Schur complement of K: (L − Bᵀ K⁻¹ B) λ = Δu, then P = −K⁻¹ B λ.
  const auto inverse_inertia = [](const Quaterniond& q, const Vector3d& inv) {
    const Matrix3d r = q.toRotationMatrix();
    return Matrix3d(r * inv.asDiagonal() * r.transpose());
  };
  const Matrix3d w_child = inverse_inertia(child.q, cs.inv_inertia);
  const Matrix3d w_parent = inverse_inertia(parent.q, ps.inv_inertia);
  const Vector3d r_child = child.q * joint.anchor_in_child;
  const Vector3d r_parent = parent.q * joint.anchor_in_parent;
  Matrix3d k = -cross_matrix(r_child) * w_child * cross_matrix(r_child) -
               cross_matrix(r_parent) * w_parent * cross_matrix(r_parent);
  k.diagonal().array() += cs.inv_mass + ps.inv_mass;
  const Vector3d w_rel = child.w - parent.w;
  const Vector3d came_in = child.q * rate_before;
  Matrix3d n = Matrix3d::Zero();       // columns: the rows' world directions
  Matrix3d k_inv_b = Matrix3d::Zero();  // K⁻¹ B
  Matrix3d schur = Matrix3d::Identity();  // unused rows padded (their λ is 0)
  Vector3d du = Vector3d::Zero();
  for (int i = 0; i < rows.count; ++i) {
    n.col(i) = child.q * Vector3d(rows.directions.row(i).transpose());
    k_inv_b.col(i) = solve3(k, (w_child * n.col(i)).cross(r_child) +
                                   (w_parent * n.col(i)).cross(r_parent));
    du(i) = -restitution * std::max(0.0, n.col(i).dot(came_in)) - n.col(i).dot(w_rel);
  }
  const Matrix3d w_sum = w_child + w_parent;
  for (int i = 0; i < rows.count; ++i) {
    const Vector3d b_i = (w_child * n.col(i)).cross(r_child) + (w_parent * n.col(i)).cross(r_parent);
    for (int l = 0; l < rows.count; ++l) {
      schur(i, l) = n.col(i).dot(w_sum * n.col(l)) - b_i.dot(k_inv_b.col(l));
    }
  }
  // a box's first and last faces at gimbal lock: nearly parallel rows (as limit_error)
  schur.diagonal().array() += 1e-12 * schur.trace();
  const Vector3d lambda = solve3(schur, du);
  Vector3d torque = Vector3d::Zero();
  for (int i = 0; i < rows.count; ++i) torque += lambda(i) * n.col(i);
  const Vector3d impulse = -(k_inv_b * lambda);
  child.v += cs.inv_mass * impulse;
  child.w += w_child * (r_child.cross(impulse) + torque);
  parent.v -= ps.inv_mass * impulse;
  parent.w -= w_parent * (r_parent.cross(impulse) + torque);
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
