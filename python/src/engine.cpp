// Any engine of the testbed from Python (docs/python.md, "Any engine"): the harness's Simulator,
// which the testbed steps, behind the procedural Solver's calls (reset, step, the state, pins),
// so that a notebook compares engines directly. The state comes as copies: an engine's state
// lives in its own objects, not in an array of the package's.
#include <pybind11/stl.h>

#include <array>
#include <string>
#include <vector>

#include "bindings.h"
#include "puppet/compare/engines.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/text.h"
#include "solver.h"

namespace puppet::python {
namespace {

class Engine {
 public:
  Engine(ModelPtr model, const std::string& solver, const std::optional<std::string>& rule,
         const Environment& environment)
      : model_(std::move(model)) {
    compare::SolverOptions options;
    if (rule) {
      if (!compare::has_rules(solver)) {
        refuse("rule", "only an engine with rules takes one (procedural), not " + solver);
      }
      const auto parsed = procedural::parse_rule(*rule);
      if (!parsed) refuse("rule", "unknown rule \"" + one_line(*rule, 64) + "\"");
      options.procedural.rule = *parsed;
    }
    try {
      simulator_ = compare::make_simulator(solver, options);
    } catch (const std::exception& error) {
      refuse("solver", error.what());
    }
    if (std::string problem = compare::engine_model_problem(solver, *model_, options);
        !problem.empty()) {
      refuse("model", solver + " cannot run " + model_->name + ": " + problem);
    }
    scenario_.name = "python";
    scenario_.environment = environment;
    scenario_.initial = rest_pose(*model_);
    scenario_.root_held = root_held(*model_);
    reset();
  }

  void reset() {
    simulator_->reset(*model_, scenario_);
    pins_.clear();
    time_ = 0.0;
    read();
  }
  void step(double dt) {
    if (!(dt > 0.0 && dt <= 1.0)) refuse("dt", "must be in (0, 1] s");
    simulator_->step(dt);
    time_ += dt;
    read();
  }
  void set_pins(const std::vector<PinSpec>& specs) {
    pins_ = to_pins(*model_, specs);
    simulator_->set_pins(pins_);
  }
  void set_pin_targets(const py::handle& given) {
    const auto n = static_cast<ssize_t>(pins_.size());
    const auto targets = real_array("targets", given, n, 3);
    for (ssize_t k = 0; k < n; ++k) {
      pins_[static_cast<size_t>(k)].target =
          Vector3d(targets.at(k, 0), targets.at(k, 1), targets.at(k, 2));
    }
    move_pins();
  }
  void set_pin_target(const py::handle& pin, const py::handle& target) {
    if (pins_.empty()) refuse("pin", "the engine has no pins (set_pins first)");
    const auto k = whole("pin", pin, 0, static_cast<long long>(pins_.size()) - 1);
    pins_[static_cast<size_t>(k)].target = vector3("target", target);
    move_pins();
  }
  void set_state(const py::handle& x_given, const py::handle& q_given, const py::handle& v_given,
                 const py::handle& w_given) {
    const std::vector<BodyState> bodies = bodies_from(*model_, x_given, q_given, v_given, w_given);
    simulator_->set_state(bodies);
    read();
  }

  // (n, 3) or (n, 4) copies of the state: positions, rotations (x, y, z, w), velocities,
  // angular velocities
  py::array_t<double> column(int which) const {
    const auto n = static_cast<ssize_t>(bodies_.size());
    const ssize_t width = which == 1 ? 4 : 3;
    py::array_t<double> out({n, width});
    auto a = out.mutable_unchecked<2>();
    for (ssize_t i = 0; i < n; ++i) {
      const BodyState& b = bodies_[static_cast<size_t>(i)];
      const Vector3d& v = which == 0 ? b.x : which == 2 ? b.v : b.w;
      if (which == 1) {
        a(i, 0) = b.q.x(), a(i, 1) = b.q.y(), a(i, 2) = b.q.z(), a(i, 3) = b.q.w();
      } else {
        for (int k = 0; k < 3; ++k) a(i, k) = v[k];
      }
    }
    return out;
  }

  std::string name() const { return simulator_->name(); }
  std::string rule() const { return simulator_->rule(); }
  bool diverged() const { return simulator_->diverged(); }
  double time() const { return time_; }
  const ModelPtr& model() const { return model_; }

 private:
  void move_pins() {
    std::vector<Vector3d> targets;
    for (const Pin& pin : pins_) targets.push_back(pin.target);
    simulator_->set_pin_targets(targets);
  }
  void read() {
    bodies_.resize(static_cast<size_t>(model_->segment_count()));
    simulator_->read_state(bodies_);
  }

  ModelPtr model_;
  compare::Scenario scenario_;
  std::unique_ptr<compare::Simulator> simulator_;
  std::vector<Pin> pins_;
  std::vector<BodyState> bodies_;
  double time_ = 0.0;
};

}  // namespace

void bind_engine(py::module_& m) {
  py::class_<Engine>(m, "Engine",
                     "any engine of the testbed (procedural with its rule, bullet-multibody, "
                     "bullet-rigid, mujoco, ode, jolt) stepped as the testbed steps it, with the "
                     "procedural Solver's calls; the state as copies")
      .def(py::init([](ModelPtr model, const std::string& solver,
                       const std::optional<std::string>& rule,
                       const std::optional<Environment>& environment) {
             return Engine(std::move(model), solver, rule, environment.value_or(Environment{}));
           }),
           py::arg("model"), py::arg("solver"), py::kw_only(), py::arg("rule") = py::none(),
           py::arg("environment") = py::none())
      .def("step", &Engine::step, py::arg("dt"), "one step of dt seconds, in (0, 1]")
      .def("reset", &Engine::reset, "the rest pose, at rest, without pins")
      .def("set_pins", &Engine::set_pins, py::arg("pins"), "replaces the pins and grabs")
      .def("set_pin_targets", &Engine::set_pin_targets, py::arg("targets"),
           "(k, 3): the targets of the k pins for the end of the next step")
      .def("set_pin_target", &Engine::set_pin_target, py::arg("pin"), py::arg("target"),
           "one pin's target, the others' kept")
      .def("set_state", &Engine::set_state, py::arg("positions"), py::arg("rotations"),
           py::arg("velocities"), py::arg("angular_velocities"),
           "places every segment (a joint-consistent state; rotations x, y, z, w)")
      .def_property_readonly(
          "positions", [](const Engine& e) { return e.column(0); },
          "(n, 3) copy: each segment's centre of mass")
      .def_property_readonly(
          "rotations", [](const Engine& e) { return e.column(1); },
          "(n, 4) copy: each segment's orientation, x, y, z, w")
      .def_property_readonly("velocities", [](const Engine& e) { return e.column(2); })
      .def_property_readonly("angular_velocities", [](const Engine& e) { return e.column(3); })
      .def_property_readonly("solver", &Engine::name)
      .def_property_readonly("rule", &Engine::rule)
      .def_property_readonly("diverged", &Engine::diverged)
      .def_property_readonly("time", &Engine::time, "simulated seconds since the last reset")
      .def_property_readonly("model", &Engine::model)
      .def("__repr__", [](const Engine& e) {
        return "<puppet.Engine " + e.name() + (e.rule().empty() ? "" : " " + e.rule()) + " on " +
               e.model()->name + ", t = " + std::to_string(e.time()) + " s>";
      });
}

}  // namespace puppet::python
