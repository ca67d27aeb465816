// Load a model (by default `pinocchio`, the built-in figure, read from where the package was
// installed), hang it by its root, grab the end of its right forearm (else of its last segment)
// and pull it up and aside for a second, then let go and let it swing for another.
//   embed [MODEL]    (pinocchio, a model file, or chain:N)
#include <cstdio>
#include <exception>
#include <string>

#include "puppet/model/model.h"
#include "puppet/procedural/solver.h"

int main(int argc, char** argv) {
  using namespace puppet;
  try {
    const std::string name = argc > 1 ? argv[1] : "pinocchio";
    const Model model = load_model(name);
    procedural::Settings settings;  // rule xpbd, the default
    procedural::Solver solver(model, settings, Environment{.gravity = model.gravity});
    // Pinocchio's arms end at the forearms; any other model is grabbed by its last segment
    const int arm = model.find_segment("r_forearm") >= 0 ? model.find_segment("r_forearm")
                                                         : model.segment_count() - 1;
    const Segment& segment = model.segments[arm];
    // the arm's end: its shape's furthest point away from the joint to its parent
    const Vector3d from_joint = -model.joints[segment.parent_joint].anchor_in_child;
    const Vector3d end = support_point(segment, from_joint);
    const BodyState& body = solver.state().bodies[arm];
    const Pin root{.segment = 0, .target = solver.state().bodies[0].x};
    const Pin grab{.segment = arm, .local_point = end, .target = body.x + body.q * end};
    const Pin pins[] = {root, grab};
    solver.set_pins(pins);
    for (int k = 1; k <= 240; ++k) {  // 1 s at 240 Hz, the end's target moving 0.3 m
      const Vector3d targets[] = {root.target, grab.target + Vector3d(0.3, 0.0, 0.3) * (k / 240.0)};
      solver.set_pin_targets(targets);
      solver.step(1.0 / 240.0);
    }
    solver.set_pins({&root, 1});
    for (int k = 0; k < 240; ++k) solver.step(1.0 / 240.0);
    const BodyState& after = solver.state().bodies[arm];
    const Vector3d x = after.x + after.q * end;
    std::printf("%s (%s): the end of %s at (%.3f, %.3f, %.3f) m after 2 s, rule %s%s\n",
                model.name.c_str(), name == "pinocchio" ? pinocchio_path().c_str() : name.c_str(),
                segment.name.c_str(), x.x(), x.y(), x.z(),
                std::string(procedural::rule_name(solver.settings().rule)).c_str(),
                solver.state().diverged ? ", diverged" : "");
    return solver.state().diverged ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "embed: %s\n", e.what());
    return 2;
  }
}
