// marionette: the paper's figure 4a as the paper does it: the figure hanging from its head, its
// right hand's tip held by a hard pin (a marionette's string) led round drag's circle, in air
// drag 0.1/s. A hard pin takes the hand where the path goes, whatever that asks of the figure: a
// random start can send it out of the reach the figure has between its two pins (the verdict
// says so beside its cells).
#include "builders.h"

namespace puppet::compare {

ScenarioRow marionette_scenario() {
  return {"marionette",
          "as drag, the hand on a hard pin led round the circle (the paper's figure 4a): the "
          "seed's own task, which a random start can put out of the figure's reach",
          [](const Model& model, const ScenarioOptions& options) {
            Scenario s =
                held_figure(model, options, /*head=*/true, circling_hand(options, /*grab=*/false));
            s.environment.air_drag = 0.1;
            return s;
          }};
}

}  // namespace puppet::compare
