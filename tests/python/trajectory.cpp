// The C++ side of tests/python/test_trajectory.py: Pinocchio in air with drag and a slanted
// gravity, its left forearm pulled by the testbed's grab along a straight line and, when argv[3]
// is "held", its head held by a hard pin; stepped at 1/240 s with the rule named by argv[1] for
// argv[2] steps; prints every segment's position and rotation (x, y, z,
// w) after each tenth step as hexadecimal floats, which the Python side must match bit for bit.
#include <cstdio>
#include <string>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/procedural/solver.h"

int main(int argc, char** argv) {
  using namespace puppet;
  if (argc != 4) {
    std::fprintf(stderr, "usage: python_trajectory RULE STEPS held|free\n");
    return 2;
  }
  const auto rule = procedural::parse_rule(argv[1]);
  const int steps = std::stoi(argv[2]);
  if (!rule || steps < 1) {
    std::fprintf(stderr, "python_trajectory: bad rule or step count\n");
    return 2;
  }
  const Model model = compare::load_named_model("pinocchio");
  Environment environment;
  environment.air_drag = 0.3;
  environment.gravity = Vector3d(1.5, 0.5, -9.81);  // off the vertical: the hanging figure swings
  procedural::Settings settings;
  settings.rule = *rule;
  procedural::Solver solver(model, settings, environment);
  solver.reset(rest_pose(model));
  const int head = model.find_segment("head");
  const int forearm = model.find_segment("l_forearm");
  const Vector3d held = solver.state().bodies[head].x;
  const Vector3d pulled = solver.state().bodies[forearm].x;
  Pin pin;
  pin.segment = head;
  pin.target = held;
  Pin grab;
  grab.segment = forearm;
  grab.target = pulled;
  grab.grab = compare::grab_spring(model, compare::GrabSettings{});
  const bool held_by_head = std::string(argv[3]) == "held";
  const std::vector<Pin> pins = held_by_head ? std::vector<Pin>{pin, grab} : std::vector<Pin>{grab};
  solver.set_pins(pins);
  for (int k = 1; k <= steps; ++k) {
    const Vector3d moved = pulled + k * Vector3d(0.001, 0.0, 0.0005);
    const std::vector<Vector3d> targets =
        held_by_head ? std::vector<Vector3d>{held, moved} : std::vector<Vector3d>{moved};
    solver.set_pin_targets(targets);
    solver.step(1.0 / 240.0);
    if (k % 10 != 0) continue;
    for (const BodyState& b : solver.state().bodies) {
      std::printf("%a %a %a %a %a %a %a\n", b.x.x(), b.x.y(), b.x.z(), b.q.x(), b.q.y(), b.q.z(),
                  b.q.w());
    }
  }
  return 0;
}
