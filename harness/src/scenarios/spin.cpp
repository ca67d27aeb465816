// spin: the free figure spun rigidly at ω = (0.3, 0, 2) rad/s about its centre of mass, without
// gravity: energy and momentum are conserved. A figure whose root the world holds spins as far as
// the hold lets it (held_turns), and only its energy is conserved.
#include "builders.h"

namespace puppet::compare {

ScenarioRow spin_scenario() {
  return {"spin", "the free figure spun without gravity: energy and momentum are conserved",
          [](const Model& model, const ScenarioOptions& options) {
            Scenario s = held_figure(model, options, /*head=*/false, std::nullopt);
            s.environment.gravity.setZero();
            const Vector3d com = centre_of_mass(model, s.initial);
            const Vector3d omega(0.3, 0.0, 2.0);
            if (s.root_held) {
              // a held figure spins as far as its hold lets it: at |ω| about a hinge's axis
              for (const HeldTurn& turn : held_turns(model)) {
                const Vector3d w = turn.axis ? Vector3d(omega.norm() * *turn.axis) : omega;
                spin_subtree(model, turn.top, w, turn.centre, s.initial);
              }
              return s;
            }
            for (BodyState& body : s.initial) {
              body.w += omega;
              body.v += omega.cross(body.x - com);
            }
            return s;
          }};
}

}  // namespace puppet::compare
