// Load a model, hang it by its root, grab its right hand (else its last segment) and pull it up
// and aside for a second, then let go and let it swing for another.
//   embed MODEL.json    (models/pinocchio.json, or chain:N)
#include <cstdio>
#include <exception>

#include "puppet/model/model.h"
#include "puppet/procedural/solver.h"

int main(int argc, char** argv) {
  using namespace puppet;
  try {
    const Model model = load_model(argc > 1 ? argv[1] : "chain:8");
    procedural::Settings settings;
    settings.rule = procedural::Rule::kXpbd;
    procedural::Solver solver(model, settings, Environment{.gravity = model.gravity});
    const int hand = model.find_segment("r_hand") >= 0 ? model.find_segment("r_hand")
                                                       : model.segment_count() - 1;
    const Pin root{.segment = 0, .target = solver.state().bodies[0].x};
    const Pin grab{.segment = hand, .target = solver.state().bodies[hand].x};
    const Pin pins[] = {root, grab};
    solver.set_pins(pins);
    for (int k = 1; k <= 240; ++k) {  // 1 s at 240 Hz, the hand's target moving 0.3 m
      const Vector3d targets[] = {root.target, grab.target + Vector3d(0.3, 0.0, 0.3) * (k / 240.0)};
      solver.set_pin_targets(targets);
      solver.step(1.0 / 240.0);
    }
    solver.set_pins({&root, 1});
    for (int k = 0; k < 240; ++k) solver.step(1.0 / 240.0);
    const Vector3d x = solver.state().bodies[hand].x;
    std::printf("%s: hand at (%.3f, %.3f, %.3f) m after 2 s%s\n", model.name.c_str(), x.x(), x.y(),
                x.z(), solver.state().diverged ? ", diverged" : "");
    return solver.state().diverged ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embed: %s\n", e.what());
    return 2;
  }
}
