// hang: the marionette at rest, its head's top pinned, tilted by --tilt (30°) and let go; no air
// drag, so energy is conserved (docs/design.md, "Scenarios").
#include "builders.h"

namespace puppet::compare {

ScenarioRow hang_scenario() {
  return {"hang",
          "the figure hangs from its head, tilted 30° and let go: energy is conserved, so any "
          "drift is the solver's",
          [](const Model& model, const ScenarioOptions& options) {
            return held_figure(model, options, /*head=*/true, std::nullopt);
          }};
}

}  // namespace puppet::compare
