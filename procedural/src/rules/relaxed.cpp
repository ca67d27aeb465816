// Rule `relaxed`: `iterations` two-sided sweeps (Gauss–Seidel, as position-based dynamics
// does): pins, then every joint, then every limit, then the ground contacts. Every correction is
// shared by both sides through K_a + K_b (two_sided.cpp: a joint's in the child's frame, where
// both sides' K are constants but for the parent's rotation into it); then the one-sided
// `weighted` pass closes every joint exactly from the anchor (one_sided_pass.cpp). A compliant
// pin is the sweeps' to pull, and the final pass leaves it be (docs/solver.md, "relaxed").
#include "catalogue.h"
#include "puppet/model/rotation.h"
#include "rules.h"

namespace puppet::procedural {
namespace {

void relaxed_sweeps(const Model& model, std::span<const JointTerms> joints,
                    const Settings& settings, const Environment& environment,
                    const AnchorOrder& order, const PinTargets& targets, State& state,
                    Workspace& ws, double h) {
  for (int i = 0; i < state.pin_count; ++i) ws.pin_lambda[i].setZero();
  // the pose's own lever arms: with the substep's start's, the final one-sided pass (which turns
  // about the pose it closes) undoes what the sweeps moved, and a hand let go hung in the air
  // (measured: 3.6 cm of drop in 0.3 s against 55 cm)
  const Matrix3d* start = nullptr;
  for (int iteration = 0; iteration < settings.iterations; ++iteration) {
    for (int i = 0; i < state.pin_count; ++i) {
      const Pin& pin = state.pins[i];
      share_pin_correction(model, pin, targets[i], pin.compliance / (h * h), &ws.pin_lambda[i],
                           start, state);
    }
    // every joint, then every limit: a limit corrected right after its own joint is partly undone
    // by the next joint's correction, and what a sweep leaves past a limit the final one-sided
    // pass clamps at the cost of the pins (measured: twice as many runs diverged, docs/solver.md)
    for (const AnchorOrder::Link& link : order.links) {
      share_joint_correction(model, joints[link.joint], model.joints[link.joint], 0.0, nullptr,
                             start, state);
    }
    for (const AnchorOrder::Link& link : order.links) {
      LimitRows rows;
      if (share_limit_correction(model, joints[link.joint], model.joints[link.joint], 0.0, nullptr,
                                 &rows, false, state)) {
        mark_limit(ws, link.joint, rows);
      }
    }
    // the shared corrections compose unit quaternions and leave them unnormalised (off by a
    // few ulps): one renormalisation per segment and sweep instead of one per correction
    for (BodyState& body : state.bodies) body.q = renormalized(body.q);
    if (environment.ground) {
      for (int s = 0; s < model.segment_count(); ++s) {
        push_out_of_ground(model, environment, s, state);
      }
    }
  }
}

}  // namespace

void relaxed_adjust(const Model& model, std::span<const JointTerms> joints,
                    const Settings& settings, const Environment& environment,
                    const AnchorOrder& order, const PinTargets& targets, State& state,
                    Workspace& ws, double h) {
  relaxed_sweeps(model, joints, settings, environment, order, targets, state, ws, h);
  // the closing pass its row names (the seed's pass, weighted's reading)
  one_sided_pass(model, joints, *rule_row(settings.rule).closing_pass, order,
                 PinClosure::kRigidOnly, targets, state, ws);
}

}  // namespace puppet::procedural
