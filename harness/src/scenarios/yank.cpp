// yank: the figure held by its right hand alone, a hard pin led round drag's circle with no air
// drag (the frontier's scenario: at what frequency and dt each solver stays ok).
#include "builders.h"

namespace puppet::compare {

ScenarioRow yank_scenario() {
  return {"yank",
          "only the right hand held, a hard pin on drag's circle: stability, not accuracy (the "
          "frontier)",
          [](const Model& model, const ScenarioOptions& options) {
            return held_figure(model, options, /*head=*/false,
                               circling_hand(options, /*grab=*/false));
          }};
}

}  // namespace puppet::compare
