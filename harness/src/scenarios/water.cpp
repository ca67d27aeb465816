// water: drag's grabbed figure under a water surface 3 m up: buoyancy and water drag 2/s.
#include "builders.h"

namespace puppet::compare {

ScenarioRow water_scenario() {
  return {"water", "drag under water: buoyancy and water drag, the seed's third medium",
          [](const Model& model, const ScenarioOptions& options) {
            Scenario s =
                held_figure(model, options, /*head=*/true, circling_hand(options, /*grab=*/true));
            s.environment.air_drag = 0.1;
            s.environment.water = true;
            s.environment.water_level = 3.0;
            s.environment.water_density = 1000.0;
            s.environment.water_drag = 2.0;
            return s;
          }};
}

}  // namespace puppet::compare
