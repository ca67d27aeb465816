// tremble: drag with the seed's tremble (§3.4) on, as a force on every segment that every engine
// applies alike (user_forces.h: tremble_force).
#include "builders.h"

namespace puppet::compare {

ScenarioRow tremble_scenario() {
  return {"tremble",
          "drag with the seed's tremble as a force on every segment, in every engine: a solver's "
          "error on a trembling figure",
          [](const Model& model, const ScenarioOptions& options) {
            Scenario s =
                held_figure(model, options, /*head=*/true, circling_hand(options, /*grab=*/true));
            s.environment.air_drag = 0.1;
            s.environment.tremble = true;
            return s;
          }};
}

}  // namespace puppet::compare
