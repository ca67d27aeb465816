// collapse: the free figure let go standing, tilted 5° about x through its centre of mass with its
// lowest point on the ground (friction 0.8), in air drag 0.05/s, for 3 s: a character's death in
// a game, the ragdoll folding onto the floor from its feet.
#include "builders.h"

namespace puppet::compare {

ScenarioRow collapse_scenario() {
  return {"collapse",
          "the free figure, let go standing on the ground (μ = 0.8), folds onto it: contact from "
          "rest, judged by its violations and outcomes",
          [](const Model& model, const ScenarioOptions& options) {
            return figure_on_ground(model, options, /*tilt_deg=*/5.0, /*height=*/0.0);
          },
          /*headline=*/false, /*contact=*/true};
}

}  // namespace puppet::compare
