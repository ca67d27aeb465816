// The scenarios of docs/design.md, defined once and used by the CLI, the tests, the benchmarks
// and any viewer. Each is deterministic and runs on any model.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "puppet/compare/start.h"
#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::compare {

// What is wrong with a scenario's or a solver's options, and which option: `option` names the
// ScenarioOptions or SolverOptions field ("pin", "grab", "scenario", "solver",
// "bullet_iterations"), empty when it is none of them. A command line adds its flag.
class ScenarioError : public std::runtime_error {
 public:
  explicit ScenarioError(const std::string& message, std::string option_name = {})
      : std::runtime_error(message), option(std::move(option_name)) {}
  std::string option;
};
// the message a command line prints: "--<option with - for _>: <message>", or the message alone
// when no option is named
std::string with_flag(const ScenarioError& error);

// a segment, and optionally a point on it (segment frame); without one the scenario picks the
// segment's highest point at rest (for a hanging pin) or its lowest (for a grab)
struct PointChoice {
  std::string segment;
  std::optional<Vector3d> local_point;
};

// The user's grab in drag, shake, water and tremble, and the viewer's mouse (docs/design.md, "The
// grab"): GrabSpring's law at Jolt's samples' f = 2 Hz and damping ratio 1, its force capped at
// one figure weight (M g₀): a hand can hold the figure up, not fling it. Applied explicitly, as
// an external force, it is stable in every engine at every dt the testbed runs (2π f h = 0.42 at
// 1/30 s); Box2D's 5 Hz at ratio 0.7 is not (docs/design.md, "The grab").
struct GrabSettings {
  double hz = 2.0;
  double damping_ratio = 1.0;
  double cap_weights = 1.0;  // F_max in the figure's weights M g₀ (user_forces.h: g₀)
};
// the law for a model: F_max = cap_weights · M g₀
GrabSpring grab_spring(const Model& model, const GrabSettings& settings);
// what is wrong with the settings (a frequency that is not positive, a ratio that is negative or
// not a number, a cap that is not positive), naming the field ("grab_hz", "grab_ratio",
// "grab_cap"); nullopt when they are valid
std::optional<ScenarioError> grab_settings_problem(const GrabSettings& settings);

// what a user may change from the command line; unset fields keep the scenario's values
struct ScenarioOptions {
  double tilt_deg = 30.0;  // initial tilt of hang and the scenarios built on it
  double hz = 0.5;         // circle frequency of drag and yank
  std::optional<PointChoice> pin;
  std::optional<PointChoice> grab;
  double grab_compliance = 0.0;  // m/N of the marionette's and yank's hand pin (Pin::compliance)
  GrabSettings grab_spring;      // the grab's law in drag, shake, water and tremble
  std::optional<Vector3d> gravity;
  std::optional<double> air_drag;
  std::optional<bool> ground;
  // a random start (start.h): the pose and joint velocities, and for the scenarios that use them
  // the tilt, the grab's point, frequency and phase (a point given by `grab` stays)
  std::optional<StartInputs> start;
};

enum class TargetPath {
  kFixed,   // stays at its initial point
  kCircle,  // circle in the x–z plane through its initial point (its lowest point)
  kShakeX,  // sinusoid along x about its initial point
};

struct PinPath {
  Pin pin;  // target = the initial world point
  TargetPath path = TargetPath::kFixed;
  double radius = 0.0;  // circle radius or shake amplitude (m)
  double hz = 0.0;
  double phase = 0.0;  // rad: where on its circle or shake the target starts (0: the lowest point)
};

struct Scenario {
  std::string name;
  double duration = 5.0;  // s
  Environment environment;
  std::vector<BodyState> initial;
  std::vector<PinPath> pins;
  // the model's root is joined to the world (RootJoint): the world's hold stands where the head's
  // pin would, and neither momentum is conserved
  bool root_held = false;

  // pin targets at time t (the end of the step being taken), ramped in with a smoothstep over
  // the first 0.5 s
  void targets_at(double t, std::vector<Vector3d>& out) const;
  std::vector<Pin> initial_pins() const;
  // nothing external does work: energy is conserved (hang, spin)
  bool conserves_energy() const;
  // no external force at all: momentum is conserved (spin)
  bool conserves_momentum() const;
};

// How much further apart a scenario's first two hard pins' targets ever are (sampled every
// 1/240 s) than the figure can span between the pinned points (m; ≤ 0: within reach; −∞ without
// two hard pins). The span is the chain of segments between them, point to joint to joint to
// point, each piece rigid: a hard pin led further asks for more than the figure has (marionette
// from some random starts), which no solver can give without pumping energy in.
double reach_shortfall(const Model& model, const Scenario& scenario);

// the names of the scenarios, in the catalogue's order (harness/src/scenarios/catalogue.cpp: one
// file per scenario)
const std::vector<std::string>& scenario_names();
// what a scenario asks of a solver, and why, in a sentence (empty for an unknown name)
std::string scenario_asks(const std::string& name);
// whether a scenario is a scene on the ground that the verdict judges by its violations, its
// first impact and its outcomes over random starts (contact_judge.h), not by its trajectory
bool judged_by_contact(const std::string& name);
// the scenario a table quotes when it quotes one (the README's and the verdict's per-frame
// figures): drag, a user dragging the puppet by its hand with the grab
const std::string& headline_scenario();
// builds a named scenario for a model, then applies the options' overrides of the environment
// (gravity, air drag, ground); throws ScenarioError
Scenario make_scenario(const std::string& name, const Model& model,
                       const ScenarioOptions& options = {});

// the built-in Pinocchio's model file, in the source tree unless a copy installed away from it
// (the Python package's) says where it is
std::string builtin_model_path();
void set_builtin_model_path(const std::string& path);
// "pinocchio" names the built-in figure; anything else is a model file or chain:N (load_model),
// read as `options` say (the command line's --strict and --include-outside: by default MJCF
// elements the testbed does not model are skipped with a note). What the reading skipped is
// printed to stderr as one line. Nothing of one call's options is kept for the next.
Model load_named_model(const std::string& name, const ReadOptions& options = {});

}  // namespace puppet::compare
