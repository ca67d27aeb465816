// drag: the figure hanging from its head, its right hand's tip grabbed as a user grabs it (the
// capped spring–damper of GrabSettings) and the grab led round a 0.3 m circle in the x–z plane
// at --hz (0.5 Hz), in air drag 0.1/s. The headline: a user dragging the puppet is what the
// testbed is for.
#include "builders.h"

namespace puppet::compare {

ScenarioRow drag_scenario() {
  return {"drag",
          "the head pinned, the right hand grabbed as a user grabs a ragdoll (a capped "
          "spring–damper, the same force in every engine) and the grab led round a 0.3 m circle at "
          "0.5 Hz: what a game does with a mouse",
          [](const Model& model, const ScenarioOptions& options) {
            Scenario s =
                held_figure(model, options, /*head=*/true, circling_hand(options, /*grab=*/true));
            s.environment.air_drag = 0.1;
            return s;
          },
          /*headline=*/true};
}

}  // namespace puppet::compare
