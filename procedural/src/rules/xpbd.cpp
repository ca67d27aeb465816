// Rule `xpbd`: extended position-based dynamics for rigid bodies (Müller, Macklin, Chentanez,
// Jeschke, Kim 2020, "Detailed rigid body simulation with extended position based dynamics";
// Macklin, Müller, Chentanez 2016, "XPBD"), the best of the update/adjust family the seed belongs
// to. Per substep of h = dt / substeps:
//
//   update            every segment alone under its forces (the same stage as every rule; the
//                     joints' springs and dampers among them, joint_springs.h)
//   adjust            `iterations` Gauss–Seidel sweeps (default 1): pins and the world's hold on
//                     the root, then every limit, then every joint's point (the joints first
//                     with Settings::limits_before_joints off), then the ground, each re-evaluated
//                     from the current poses and closed by both of its bodies in proportion to
//                     their generalised inverse masses, with compliance α (two_sided.cpp)
//   velocities        v = Δx/h, ω = log(q q_prev⁻¹)/h, then the velocity passes: each limit
//                     its adjust met loses its rate into the limit (limit_velocities.cpp), and
//                     the ground's normal velocity is removed (no restitution) with Coulomb
//                     friction on the impulse that takes (contacts.cpp, ground_velocity_pass)
//
// seed: unlike every seed rule there is no one-sided closure: joints close only to the
// residual the sweeps leave (joint_gap_m reports it); with many short substeps that residual
// shrinks as h², and nothing moves a child as if its parent were infinitely heavy. Joint
// dampers act in the update, implicit per joint, not in the velocity passes.
#include "rules.h"

namespace puppet::procedural {
namespace {

// every joint's point, parent before child from the anchor
void joint_sweep(const Model& model, std::span<const JointTerms> joints, const AnchorOrder& order,
                 double joint_alpha, const Matrix3d* start, State& state, Workspace& ws) {
  for (const AnchorOrder::Link& link : order.links) {
    share_joint_correction(model, joints[link.joint], model.joints[link.joint], joint_alpha,
                           &ws.joint_lambda[link.joint], start, state);
  }
}

}  // namespace

void xpbd_adjust(const Model& model, std::span<const JointTerms> joints, const Settings& settings,
                 const Environment& environment, const AnchorOrder& order,
                 const PinTargets& targets, State& state, Workspace& ws, double h) {
  const double inv_h2 = 1.0 / (h * h);
  const double joint_alpha = settings.joint_compliance * inv_h2;
  const double limit_alpha = settings.limit_compliance * inv_h2;
  // the multipliers the compliance terms read start from zero at every substep
  for (int i = 0; i < state.pin_count; ++i) ws.pin_lambda[i].setZero();
  if (joint_alpha != 0.0) {
    for (Vector3d& lambda : ws.joint_lambda) lambda.setZero();
  }
  if (limit_alpha != 0.0) {
    for (Vector3d& lambda : ws.limit_lambda) lambda.setZero();
  }
  const Matrix3d* start = nullptr;
  if (settings.start_lever_arms) {
    start_inverse_inertias(model, state, ws.start_inverse_inertia);
    start = ws.start_inverse_inertia.data();
  }
  for (int iteration = 0; iteration < settings.iterations; ++iteration) {
    for (int i = 0; i < state.pin_count; ++i) {
      share_pin_correction(model, state.pins[i], targets[i], state.pins[i].compliance * inv_h2,
                           &ws.pin_lambda[i], start, state);
    }
    hold_root(model, start, state);
    // every limit, then every joint's point parent before child from the anchor (a limit's turn
    // about its sides' centres opens the joint, which the joints' pass then closes); or the
    // joints first (Settings::limits_before_joints)
    if (!settings.limits_before_joints)
      joint_sweep(model, joints, order, joint_alpha, start, state, ws);
    for (const AnchorOrder::Link& link : order.links) {
      LimitRows rows;
      if (share_limit_correction(model, joints[link.joint], model.joints[link.joint], limit_alpha,
                                 &ws.limit_lambda[link.joint], &rows, settings.limit_functions,
                                 state)) {
        mark_limit(ws, link.joint, rows);
      }
    }
    if (settings.limits_before_joints)
      joint_sweep(model, joints, order, joint_alpha, start, state, ws);
    for (BodyState& body : state.bodies) body.q = renormalized(body.q);
    // the ground is static (infinite mass): its correction is the segment's alone
    if (environment.ground) {
      for (int s = 0; s < model.segment_count(); ++s) {
        push_out_of_ground(model, environment, s, state);
      }
    }
  }
}

}  // namespace puppet::procedural
