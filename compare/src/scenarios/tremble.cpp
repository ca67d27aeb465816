// tremble: drag with the seed's tremble on (procedural only; the references ignore it).
#include "builders.h"

namespace puppet::compare {

ScenarioRow tremble_scenario() {
  return {"tremble", [](const Model& model, const ScenarioOptions& options) {
            Scenario s = held_figure(model, options, /*head=*/true, circling_hand(options));
            s.environment.air_drag = 0.1;
            s.tremble = true;
            return s;
          }};
}

}  // namespace puppet::compare
