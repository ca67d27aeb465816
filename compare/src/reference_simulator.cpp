// The Bullet references behind the Simulator interface.
#include "puppet/compare/simulator.h"
#include "puppet/reference/bullet.h"
#include "puppet/reference/mujoco.h"

namespace puppet::compare {
namespace {

class ReferenceSnapshot : public Snapshot {
 public:
  explicit ReferenceSnapshot(std::vector<double> s) : saved(std::move(s)) {}
  std::vector<double> saved;
};

class ReferenceSimulator : public Simulator {
 public:
  ReferenceSimulator(reference::Kind kind, const reference::Settings& settings,
                     const reference::MujocoSettings& mujoco)
      : kind_(kind), settings_(settings), mujoco_(mujoco) {}

  std::string name() const override {
    switch (kind_) {
      case reference::Kind::kMultibody:
        return "bullet-multibody";
      case reference::Kind::kRigid:
        return "bullet-rigid";
      case reference::Kind::kMujoco:
        return "mujoco";
    }
    return {};
  }
  void reset(const Model& model, const Scenario& scenario) override {
    const std::vector<Pin> pins = scenario.initial_pins();
    solver_ = kind_ == reference::Kind::kMujoco
                  ? reference::make_mujoco(model, scenario.environment, mujoco_)
                  : reference::make_solver(kind_, model, scenario.environment, settings_);
    solver_->set_state(scenario.initial);
    solver_->set_pins(pins);
  }
  void set_pins(std::span<const Pin> pins) override { solver_->set_pins(pins); }
  void set_pin_targets(std::span<const Vector3d> targets) override {
    solver_->set_pin_targets(targets);
  }
  void step(double dt) override { solver_->step(dt); }
  void read_state(std::span<BodyState> out) const override { solver_->read_state(out); }
  void set_state(std::span<const BodyState> bodies) override { solver_->set_state(bodies); }
  std::unique_ptr<Snapshot> snapshot() const override {
    return std::make_unique<ReferenceSnapshot>(solver_->save());
  }
  void restore(const Snapshot& snapshot) override {
    solver_->load(static_cast<const ReferenceSnapshot&>(snapshot).saved);
  }
  bool diverged() const override { return solver_->diverged(); }

 private:
  reference::Kind kind_;
  reference::Settings settings_;
  reference::MujocoSettings mujoco_;
  std::unique_ptr<reference::Solver> solver_;
};

}  // namespace

std::unique_ptr<Simulator> make_reference_simulator(const std::string& solver,
                                                    const SolverOptions& options) {
  reference::Settings settings;
  settings.iterations = options.bullet_iterations;
  settings.euler_ball_limits = options.bullet_euler_limits;
  const std::string problem = reference::validate(settings);
  if (!problem.empty()) throw ScenarioError(problem, "bullet_iterations");
  reference::MujocoSettings mujoco;
  mujoco.integrator = options.mujoco_integrator;
  mujoco.constraint_time_constant = options.mujoco_time_constant;
  const auto kind = solver == "bullet-multibody" ? reference::Kind::kMultibody
                    : solver == "mujoco"         ? reference::Kind::kMujoco
                                                 : reference::Kind::kRigid;
  return std::make_unique<ReferenceSimulator>(kind, settings, mujoco);
}

}  // namespace puppet::compare
