#include "reference_adapter.h"

#include <optional>

#include "puppet/model/joint_springs.h"

namespace puppet::compare {
namespace {

class ReferenceSnapshot : public Snapshot {
 public:
  explicit ReferenceSnapshot(std::vector<double> s) : saved(std::move(s)) {}
  std::vector<double> saved;
};

class ReferenceSimulator : public Simulator {
 public:
  ReferenceSimulator(std::string name, ReferenceFactory factory, bool exact_armature)
      : name_(std::move(name)), factory_(std::move(factory)), exact_armature_(exact_armature) {}

  std::string name() const override { return name_; }
  void reset(const Model& model, const Scenario& scenario) override {
    const std::vector<Pin> pins = scenario.initial_pins();
    solver_.reset();  // before the model it holds
    solver_ = factory_(exact_armature_ ? model : armature_in_inertia(model, own_model_),
                       scenario.environment);
    solver_->set_state(scenario.initial);
    solver_->set_pins(pins);
  }
  void set_pins(std::span<const Pin> pins) override { solver_->set_pins(pins); }
  void set_pin_targets(std::span<const Vector3d> targets) override {
    solver_->set_pin_targets(targets);
  }
  void step(double dt) override { solver_->step(dt); }
  void set_time(double time) override { solver_->set_time(time); }
  std::span<const Wrench> user_wrenches() const override { return solver_->user_wrenches(); }
  void read_state(std::span<BodyState> out) const override { solver_->read_state(out); }
  void set_state(std::span<const BodyState> bodies) override { solver_->set_state(bodies); }
  std::unique_ptr<Snapshot> snapshot() const override {
    return std::make_unique<ReferenceSnapshot>(solver_->save());
  }
  void restore(const Snapshot& snapshot) override {
    solver_->load(static_cast<const ReferenceSnapshot&>(snapshot).saved);
  }
  bool diverged() const override { return solver_->diverged(); }
  bool engine_error() const override { return solver_->engine_error(); }

 private:
  std::string name_;
  ReferenceFactory factory_;
  bool exact_armature_;
  std::optional<Model> own_model_;  // the model with armature as inertia, when it has armature
  std::unique_ptr<reference::Solver> solver_;
};

}  // namespace

std::unique_ptr<Simulator> make_reference_simulator(std::string name, ReferenceFactory factory,
                                                    bool exact_armature) {
  return std::make_unique<ReferenceSimulator>(std::move(name), std::move(factory), exact_armature);
}

}  // namespace puppet::compare
