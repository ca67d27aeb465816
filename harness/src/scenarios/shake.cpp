// shake: the figure hanging from its head, its left hand's tip grabbed (drag's grab) and the
// grab shaken ±0.1 m along x at 3 Hz, in air drag 0.1/s.
#include "builders.h"

namespace puppet::compare {

ScenarioRow shake_scenario() {
  return {"shake",
          "the head pinned, the left hand grabbed and the grab shaken ±0.1 m at 3 Hz: an input "
          "faster than the grab itself",
          [](const Model& model, const ScenarioOptions& options) {
            constexpr double kShakeHz = 3.0, kShakeAmplitude = 0.1;  // Hz, m
            // a start's frequency scaled from the circle's default (0.5 Hz) to the shake's
            const double hz = options.start ? kShakeHz * options.start->hz / 0.5 : kShakeHz;
            const HandPath hand{.segment = "l_forearm",
                                .path = TargetPath::kShakeX,
                                .radius = kShakeAmplitude,
                                .hz = hz,
                                .grab = true};
            Scenario s = held_figure(model, options, /*head=*/true, hand);
            s.environment.air_drag = 0.1;
            return s;
          }};
}

}  // namespace puppet::compare
