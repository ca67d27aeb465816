// drop: the free figure tilted 20° about x through its centre of mass, its lowest point 1 m above
// the ground (friction 0.8), in air drag 0.05/s, for 3 s.
#include "builders.h"

namespace puppet::compare {

ScenarioRow drop_scenario() {
  return {"drop",
          "the free figure falls 1 m onto the ground (μ = 0.8): contact, judged by its violations, "
          "its first impact and its outcomes",
          [](const Model& model, const ScenarioOptions& options) {
            return figure_on_ground(model, options, /*tilt_deg=*/20.0, /*height=*/1.0);
          },
          /*headline=*/false, /*contact=*/true};
}

}  // namespace puppet::compare
