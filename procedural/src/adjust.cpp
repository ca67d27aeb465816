// Stage 2, adjust (seed §3.3): pins, joints and limits from the anchor (the first pinned
// segment, else the root), as the settings' rule does it (its row's adjust, rules/catalogue.cpp;
// its code in rules/<rule>.cpp):
//
//   literal, smoothed, weighted, subtree   one one-sided pass (one_sided_pass.cpp); a compliant
//                                          pin's target is first softened by its compliance
//   relaxed                                two-sided sweeps, then a one-sided weighted pass
//   xpbd                                   two-sided sweeps only (compliant, substepped)
//   tree                                   the exact projection, Newton-iterated
#include "rules/catalogue.h"

namespace puppet::procedural {

void adjust(const Model& model, const Settings& settings, const Environment& environment,
            const ModelTables& tables, int anchor, const PinTargets& targets, State& state,
            Workspace& ws, double h) {
  // the pins' pull, expressed as the force that would close them in one step (eq. 2's f)
  for (int i = 0; i < state.pin_count; ++i) {
    const Pin& pin = state.pins[i];
    const double gap =
        (targets[i] - world_point(state.bodies[pin.segment], pin.local_point)).norm();
    state.pin_force[i] = 2.0 * model.segments[pin.segment].mass * gap / (h * h);
  }
  const AnchorOrder& order = anchor_order(model, tables, ws, anchor);
  rule_row(settings.rule)
      .adjust(model, tables.joints, settings, environment, order, targets, state, ws, h);
}

}  // namespace puppet::procedural
