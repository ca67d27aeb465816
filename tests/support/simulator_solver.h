// An engine behind the testbed's Simulator (jolt, which is driven through a Node.js process) seen
// as a reference::Solver, so that the checks every reference is put through (reference_runs.h,
// limit_test.cpp) put it through the same ones.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "puppet/compare/simulator.h"
#include "puppet/reference/solver.h"

namespace puppet::test {

class SimulatorSolver : public reference::Solver {
 public:
  SimulatorSolver(const std::string& engine, const Model& model, const Environment& environment,
                  const compare::SolverOptions& options = {})
      : simulator_(compare::make_simulator(engine, options)) {
    scenario_.name = "test";
    scenario_.environment = environment;
    scenario_.initial = rest_pose(model);
    simulator_->reset(model, scenario_);
  }
  void set_pins(std::span<const Pin> pins) override { simulator_->set_pins(pins); }
  void set_pin_targets(std::span<const Vector3d> targets) override {
    simulator_->set_pin_targets(targets);
  }
  void step(double dt) override { simulator_->step(dt); }
  void set_time(double time) override { simulator_->set_time(time); }
  std::span<const Wrench> user_wrenches() const override { return simulator_->user_wrenches(); }
  void read_state(std::span<BodyState> out) const override { simulator_->read_state(out); }
  void set_state(std::span<const BodyState> bodies) override { simulator_->set_state(bodies); }
  std::vector<double> save() const override { return {}; }
  void load(std::span<const double>) override {}
  bool diverged() const override { return simulator_->diverged(); }
  // what the engine holds is not readable through a Simulator
  double segment_mass(int) const override { return std::numeric_limits<double>::quiet_NaN(); }
  Vector3d segment_inertia(int) const override { return Vector3d::Constant(segment_mass(0)); }
  void joint_anchors(int, Vector3d* on_parent, Vector3d* on_child) const override {
    *on_parent = *on_child = segment_inertia(0);
  }

 private:
  compare::Scenario scenario_;
  std::unique_ptr<compare::Simulator> simulator_;
};

}  // namespace puppet::test
