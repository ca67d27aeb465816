// drop: the free figure tilted 20° about x through its centre of mass, its lowest point 1 m above
// the ground (friction 0.8), in air drag 0.05/s, for 3 s.
#include <algorithm>
#include <cmath>

#include "builders.h"

namespace puppet::compare {

ScenarioRow drop_scenario() {
  return {"drop", "the free figure falls 1 m onto the ground (μ = 0.8): contact",
          [](const Model& model, const ScenarioOptions& options) {
            Scenario s = held_figure(model, options, /*head=*/false, std::nullopt);
            s.duration = 3.0;
            s.environment.air_drag = 0.05;
            s.environment.ground = true;
            s.environment.friction = 0.8;
            rotate_about(s.initial,
                         Quaterniond(Eigen::AngleAxisd(20.0 * M_PI / 180.0, Vector3d::UnitX())),
                         centre_of_mass(model, s.initial));
            double lowest = INFINITY;
            for (int i = 0; i < model.segment_count(); ++i) {
              double low = 0.0, high = 0.0;
              vertical_extent(model.segments[i], s.initial[i].q, s.initial[i].x, &low, &high);
              lowest = std::min(lowest, low);
            }
            for (BodyState& body : s.initial) body.x.z() += 1.0 - lowest;
            return s;
          }};
}

}  // namespace puppet::compare
