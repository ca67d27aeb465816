// The procedural solver behind the Simulator interface.
#include <optional>

#include "puppet/compare/simulator.h"
#include "puppet/model/text.h"
#include "puppet/procedural/solver.h"
#include "puppet/reference/mujoco.h"

namespace puppet::compare {
namespace {

class ProceduralSnapshot : public Snapshot {
 public:
  explicit ProceduralSnapshot(const procedural::State& s) : state(s) {}
  procedural::State state;
};

class ProceduralSimulator : public Simulator {
 public:
  explicit ProceduralSimulator(const SolverOptions& options, const procedural::Settings& settings)
      : options_(options), settings_(settings) {}

  std::string name() const override { return "procedural"; }
  std::string rule() const override { return std::string(procedural::rule_name(settings_.rule)); }
  int substeps() const override { return settings_.substeps; }

  void reset(const Model& model, const Scenario& scenario) override {
    procedural::Settings settings = procedural_settings(options_, scenario);
    settings.time_stages = time_stages_;
    solver_.emplace(model, settings, scenario.environment);
    solver_->reset(scenario.initial);
    solver_->set_pins(scenario.initial_pins());
  }
  void set_pins(std::span<const Pin> pins) override { solver_->set_pins(pins); }
  void set_pin_targets(std::span<const Vector3d> targets) override {
    solver_->set_pin_targets(targets);
  }
  void step(double dt) override { solver_->step(dt); }
  void read_state(std::span<BodyState> out) const override {
    const auto& bodies = solver_->state().bodies;
    std::copy(bodies.begin(), bodies.end(), out.begin());
  }
  void set_state(std::span<const BodyState> bodies) override { solver_->place(bodies); }
  std::unique_ptr<Snapshot> snapshot() const override {
    return std::make_unique<ProceduralSnapshot>(solver_->state());
  }
  void restore(const Snapshot& snapshot) override {
    solver_->restore(static_cast<const ProceduralSnapshot&>(snapshot).state);
  }
  bool diverged() const override { return solver_->state().diverged; }

  std::vector<std::string_view> stage_names() const override {
    return {procedural::kStageNames.begin(), procedural::kStageNames.end()};
  }
  void set_stage_timing(bool on) override { time_stages_ = on; }
  std::vector<double> stage_seconds() const override {
    const auto& s = solver_->stage_seconds();
    return {s.begin(), s.end()};
  }

 private:
  SolverOptions options_;
  procedural::Settings settings_;  // without the scenario's
  bool time_stages_ = false;
  std::optional<procedural::Solver> solver_;
};

procedural::Settings settings_without_scenario(const SolverOptions& options) {
  procedural::Settings settings;
  settings.rule = options.rule;
  settings.iterations = options.iterations;
  settings.substeps = options.substeps;
  settings.derive_velocities = options.derive_velocities;
  const std::string problem = procedural::validate(settings);
  if (!problem.empty()) throw ScenarioError(problem);
  return procedural::rule_defaults(settings);
}

std::unique_ptr<Simulator> make_procedural_simulator(const SolverOptions& options) {
  return std::make_unique<ProceduralSimulator>(options, settings_without_scenario(options));
}

}  // namespace

procedural::Settings procedural_settings(const SolverOptions& options, const Scenario& scenario) {
  procedural::Settings settings = settings_without_scenario(options);
  settings.tremble = options.tremble && scenario.tremble;
  return settings;
}

// reference_simulator.cpp
std::unique_ptr<Simulator> make_reference_simulator(const std::string& solver,
                                                    const SolverOptions& options);

const std::vector<std::string>& solver_names() {
  // mujoco only where the build has MuJoCo
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out = {"procedural", "bullet-multibody", "bullet-rigid"};
    if (reference::have_mujoco()) out.push_back("mujoco");
    return out;
  }();
  return names;
}

std::unique_ptr<Simulator> make_simulator(const std::string& solver, const SolverOptions& options) {
  if (solver == "procedural") return make_procedural_simulator(options);
  if (solver == "bullet-multibody" || solver == "bullet-rigid" ||
      (solver == "mujoco" && reference::have_mujoco()))
    return make_reference_simulator(solver, options);
  throw ScenarioError("unknown solver " + shown(solver), "solver");
}

}  // namespace puppet::compare
