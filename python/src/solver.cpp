// The procedural solver from Python: stepping, pins and grabs, and the state as NumPy arrays that
// view the solver's own memory (read-only: a state is written through set_state, which checks it).
#include "solver.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

#include "puppet/procedural/rule.h"

namespace puppet::python {

namespace {

using procedural::Settings;

// the settings a caller may give, by kind: each name once, read by make_settings and listed by
// setting_names
struct WholeSetting {
  const char* name;
  int Settings::*field;
  int lo, hi;
};
constexpr WholeSetting kWholes[] = {
    {"iterations", &Settings::iterations, 0, procedural::kMaxIterations},
    {"substeps", &Settings::substeps, 1, procedural::kMaxSubsteps}};
struct NumberSetting {
  const char* name;
  double Settings::*field;
};
constexpr NumberSetting kNumbers[] = {{"joint_compliance", &Settings::joint_compliance},
                                      {"limit_compliance", &Settings::limit_compliance},
                                      {"limit_restitution", &Settings::limit_restitution}};
struct FlagSetting {
  const char* name;
  bool Settings::*field;
};
// position_tremble is Settings::tremble, the seed's tremble of the poses (the environment's
// tremble is the force every engine applies)
constexpr FlagSetting kFlags[] = {{"derive_velocities", &Settings::derive_velocities},
                                  {"start_lever_arms", &Settings::start_lever_arms},
                                  {"limit_functions", &Settings::limit_functions},
                                  {"limits_before_joints", &Settings::limits_before_joints},
                                  {"limit_velocity_pass", &Settings::limit_velocity_pass},
                                  {"position_tremble", &Settings::tremble}};
constexpr const char* kSeedSetting = "tremble_seed";

}  // namespace

std::string setting_names() {
  std::string names;
  const auto add = [&names](const char* name) {
    names += (names.empty() ? "" : ", ") + std::string(name);
  };
  for (const auto& s : kWholes) add(s.name);
  for (const auto& s : kNumbers) add(s.name);
  for (const auto& s : kFlags) add(s.name);
  add(kSeedSetting);
  return names;
}

procedural::Settings make_settings(const std::string& rule, const py::kwargs& given) {
  const auto parsed = procedural::parse_rule(rule);
  if (!parsed) {
    std::string known;
    for (auto r : procedural::kAllRules) {
      known += (known.empty() ? "" : ", ") + std::string(procedural::rule_name(r));
    }
    refuse("rule", "unknown value \"" + rule + "\" (expected one of " + known + ")");
  }
  Settings settings;
  settings.rule = *parsed;
  for (const auto& [key, value] : given) {
    const auto name = key.cast<std::string>();
    if (value.is_none()) continue;  // the rule's own
    const auto is = [&name](const auto& s) { return name == s.name; };
    if (const auto* s = std::find_if(std::begin(kWholes), std::end(kWholes), is);
        s != std::end(kWholes)) {
      settings.*s->field = static_cast<int>(whole(s->name, value, s->lo, s->hi));
    } else if (const auto* n = std::find_if(std::begin(kNumbers), std::end(kNumbers), is);
               n != std::end(kNumbers)) {
      if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value)) {
        refuse(name, "expected a number");
      }
      settings.*n->field = finite(n->name, value.cast<double>());
    } else if (const auto* f = std::find_if(std::begin(kFlags), std::end(kFlags), is);
               f != std::end(kFlags)) {
      if (!py::isinstance<py::bool_>(value)) refuse(name, "expected True or False");
      settings.*f->field = value.cast<bool>();
    } else if (name == kSeedSetting) {
      // the command line's seeds have at most 18 digits
      settings.tremble_seed =
          static_cast<uint64_t>(whole(kSeedSetting, value, 0, 999'999'999'999'999'999LL));
    } else {
      refuse(name, "not a setting (expected one of " + setting_names() + ")");
    }
  }
  const std::string problem = procedural::validate(settings);
  if (!problem.empty()) throw py::value_error(bounded(problem));
  return settings;
}

Solver::Solver(ModelPtr model, const procedural::Settings& settings, const Environment& environment)
    : model_(std::move(model)) {
  try {
    own_ = std::make_unique<procedural::Solver>(*model_, settings, environment);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(bounded(e.what()));
  }
  solver_ = own_.get();
  solver_->reset(rest_pose(*model_));
}

Solver::Solver(ModelPtr model, procedural::Solver* puppet, py::object owner,
               std::shared_ptr<std::atomic<bool>> busy)
    : model_(std::move(model)), solver_(puppet), owner_(std::move(owner)), busy_(std::move(busy)) {}

Exclusive::Exclusive(std::atomic<bool>& busy, const char* what) : busy_(busy) {
  if (busy_.exchange(true, std::memory_order_acq_rel)) {
    throw std::runtime_error(std::string(what) +
                             " is stepping on another thread; a crowd and its puppets take one "
                             "call at a time");
  }
}

void Solver::step(double dt) {
  if (!(dt > 0.0 && dt <= 1.0)) refuse("dt", "must be in (0, 1] s");
  const Exclusive held = hold();
  solver_->step(dt);
}

void Solver::reset() {
  const Exclusive held = hold();
  solver_->reset(rest_pose(*model_));
}

std::vector<Pin> to_pins(const Model& model, const std::vector<PinSpec>& specs) {
  if (specs.size() > static_cast<size_t>(procedural::kMaxPins)) {
    refuse("pins", std::to_string(specs.size()) + " given, at most " +
                       std::to_string(procedural::kMaxPins));
  }
  std::vector<Pin> pins;
  for (const PinSpec& spec : specs) {
    Pin pin;
    if (py::isinstance<py::str>(spec.segment)) {
      const auto name = spec.segment.cast<std::string>();
      pin.segment = model.find_segment(name);
      if (pin.segment < 0) refuse("pin", "no segment \"" + name + "\" in " + model.name);
    } else {
      pin.segment =
          static_cast<int>(whole("pin: segment", spec.segment, 0, model.segment_count() - 1));
    }
    pin.local_point = spec.point;
    pin.target = spec.target;
    pin.compliance = spec.compliance;
    pin.grab = spec.grab;
    pins.push_back(pin);
  }
  return pins;
}

void Solver::set_pins(const std::vector<PinSpec>& specs) {
  const std::vector<Pin> pins = to_pins(*model_, specs);
  const Exclusive held = hold();
  solver_->set_pins(pins);
}

void Solver::set_pin_targets(const py::handle& given) {
  // the solver's own count: a crowd's puppet is reached through a new Solver each time
  const int pins = solver_->state().slot_count;
  const auto targets = real_array("targets", given, pins, 3);
  std::array<Vector3d, procedural::kMaxPins> moved;
  for (int k = 0; k < pins; ++k) {
    moved[k] = Vector3d(targets.at(k, 0), targets.at(k, 1), targets.at(k, 2));
  }
  const Exclusive held = hold();
  solver_->set_pin_targets(std::span(moved.data(), static_cast<size_t>(pins)));
}

void Solver::set_pin_target(const py::handle& pin, const py::handle& target) {
  const int pins = solver_->state().slot_count;
  if (pins == 0) refuse("pin", "the solver has no pins (set_pins first)");
  const auto k = static_cast<int>(whole("pin", pin, 0, pins - 1));
  const Vector3d moved = vector3("target", target);
  std::array<Vector3d, procedural::kMaxPins> targets;
  // set_pins' order: a pin's slot is in pins, a grab's in grabs (State::slots)
  const procedural::State& state = solver_->state();
  for (int i = 0; i < pins; ++i) {
    const int slot = state.slots[i];
    targets[i] = slot >= 0 ? state.pins[slot].target : state.grabs[-1 - slot].target;
  }
  targets[k] = moved;
  const Exclusive held = hold();
  solver_->set_pin_targets(std::span(targets.data(), static_cast<size_t>(pins)));
}

std::vector<BodyState> bodies_from(const Model& model, const py::handle& x_given,
                                   const py::handle& q_given, const py::handle& v_given,
                                   const py::handle& w_given) {
  const auto n = static_cast<ssize_t>(model.segment_count());
  const auto x = real_array("positions", x_given, n, 3);
  const auto q = real_array("rotations", q_given, n, 4);
  const auto v = real_array("velocities", v_given, n, 3);
  const auto w = real_array("angular_velocities", w_given, n, 3);
  std::vector<BodyState> bodies(static_cast<size_t>(n));
  for (ssize_t i = 0; i < n; ++i) {
    BodyState& b = bodies[static_cast<size_t>(i)];
    b.x = Vector3d(x.at(i, 0), x.at(i, 1), x.at(i, 2));
    b.q = Quaterniond(q.at(i, 3), q.at(i, 0), q.at(i, 1), q.at(i, 2));
    if (std::abs(b.q.norm() - 1.0) > 1e-6) {
      refuse("rotations", "row " + std::to_string(i) + " is not a unit quaternion (x, y, z, w)");
    }
    b.v = Vector3d(v.at(i, 0), v.at(i, 1), v.at(i, 2));
    b.w = Vector3d(w.at(i, 0), w.at(i, 1), w.at(i, 2));
  }
  return bodies;
}

void Solver::set_state(const py::handle& x_given, const py::handle& q_given,
                       const py::handle& v_given, const py::handle& w_given) {
  const std::vector<BodyState> bodies = bodies_from(*model_, x_given, q_given, v_given, w_given);
  const Exclusive held = hold();
  solver_->place(bodies);
}

py::array Solver::view(py::handle owner, size_t offset, ssize_t width) const {
  const Exclusive held = hold();
  const std::vector<BodyState>& bodies = solver_->state().bodies;
  const auto* base = reinterpret_cast<const char*>(bodies.data()) + offset;
  py::array out(py::dtype::of<double>(), {static_cast<ssize_t>(bodies.size()), width},
                {static_cast<ssize_t>(sizeof(BodyState)), static_cast<ssize_t>(sizeof(double))},
                reinterpret_cast<const double*>(base), owner);
  py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return out;
}

py::array Solver::user_forces() const {
  const Exclusive held = hold();
  const auto wrenches = solver_->user_wrenches();
  py::array_t<double> out({static_cast<ssize_t>(wrenches.size()), ssize_t{6}});
  auto o = out.mutable_unchecked<2>();
  for (size_t i = 0; i < wrenches.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      o(i, k) = wrenches[i].force[k];
      o(i, 3 + k) = wrenches[i].torque[k];
    }
  }
  return out;
}

namespace {

// a read-only view of member `offset` of the state, `width` doubles wide
template <size_t kOffset, ssize_t kWidth>
py::array member(py::object self) {
  return self.cast<Solver&>().view(self, kOffset, kWidth);
}

}  // namespace

void bind_solver(py::module_& m) {
  py::class_<PinSpec>(m, "Pin",
                      "a point of a segment held at a world target: a hard pin (compliance 0), "
                      "a zero-length spring (compliance C > 0, m/N), or a grab (a GrabSpring)")
      .def(py::init([](py::object segment, const py::object& point, const py::object& target,
                       double compliance, const std::optional<GrabSpring>& grab) {
             if (!py::isinstance<py::str>(segment) &&
                 (!py::isinstance<py::int_>(segment) || py::isinstance<py::bool_>(segment))) {
               refuse("segment", "expected a segment's name or index");
             }
             if (!(finite("compliance", compliance) >= 0.0)) {
               refuse("compliance", "must not be negative");
             }
             return PinSpec{std::move(segment), vector3("point", point), vector3("target", target),
                            compliance, grab.value_or(GrabSpring{})};
           }),
           py::arg("segment"), py::arg("point") = py::make_tuple(0.0, 0.0, 0.0), py::arg("target"),
           py::arg("compliance") = 0.0, py::arg("grab") = py::none())
      .def_readonly("segment", &PinSpec::segment)
      .def_property_readonly(
          "point",
          [](const PinSpec& p) { return py::make_tuple(p.point.x(), p.point.y(), p.point.z()); })
      .def_property_readonly(
          "target",
          [](const PinSpec& p) { return py::make_tuple(p.target.x(), p.target.y(), p.target.z()); })
      .def_readonly("compliance", &PinSpec::compliance);

  py::class_<procedural::State>(m, "Snapshot",
                                "a solver's whole state (Solver.snapshot), to restore bit for bit");

  py::class_<Solver>(m, "Solver", "the procedural solver: update, then adjust (docs/solver.md)")
      .def(py::init([](ModelPtr model, const std::string& rule,
                       std::optional<Environment> environment, const py::kwargs& settings) {
             return Solver(std::move(model), make_settings(rule, settings),
                           environment.value_or(Environment{}));
           }),
           py::arg("model"), py::arg("rule") = "xpbd", py::kw_only(),
           py::arg("environment") = py::none(),
           (std::string("settings as keywords (None: the rule's own): ") + setting_names()).c_str())
      .def("step", &Solver::step, py::arg("dt"), "one step of dt seconds, in (0, 1]")
      .def_property_readonly("diverged", &Solver::diverged)
      .def_property_readonly("time", &Solver::time, "simulated seconds since the last reset")
      .def_property_readonly("model", &Solver::model)
      .def_property_readonly(
          "rule", [](const Solver& s) { return procedural::rule_name(s.solver().settings().rule); })
      .def_property_readonly(
          "iterations",
          [](const Solver& s) { return rule_defaults(s.solver().settings()).iterations; },
          "sweeps per substep (tree: Newton iterations), the rule's own unless given")
      .def_property_readonly(
          "substeps", [](const Solver& s) { return rule_defaults(s.solver().settings()).substeps; },
          "substeps per step, the rule's own unless given")
      .def("reset", &Solver::reset, "every segment at its rest pose, at rest; no pins")
      .def("set_pins", &Solver::set_pins, py::arg("pins"),
           "replaces the pins and grabs (at most 4); the first hard pin anchors the adjust pass")
      .def("set_pin_targets", &Solver::set_pin_targets, py::arg("targets"),
           "(k, 3): the targets of the k pins for the end of the next step")
      .def("set_pin_target", &Solver::set_pin_target, py::arg("pin"), py::arg("target"),
           "one pin's target (its index in set_pins' order) for the end of the next step, the "
           "others' kept")
      .def("set_state", &Solver::set_state, py::arg("positions"), py::arg("rotations"),
           py::arg("velocities"), py::arg("angular_velocities"),
           "places every segment (copies the arrays; checks shapes, finiteness, unit rotations)")
      .def("snapshot",
           [](const Solver& s) {
             const Exclusive held = s.hold();
             return s.solver().state();
           })
      .def(
          "restore",
          [](Solver& s, const procedural::State& state) {
            const Exclusive held = s.hold();
            try {
              s.solver().restore(state);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(bounded(e.what()));
            }
          },
          py::arg("snapshot"), "puts back a snapshot of a solver of the same model")
      .def_property_readonly("positions", &member<offsetof(BodyState, x), 3>,
                             "(n, 3) COM positions (m), a read-only view of the solver's state")
      .def_property_readonly("rotations", &member<offsetof(BodyState, q), 4>,
                             "(n, 4) orientations as quaternions (x, y, z, w), a read-only view")
      .def_property_readonly("velocities", &member<offsetof(BodyState, v), 3>,
                             "(n, 3) COM velocities (m/s), a read-only view")
      .def_property_readonly("angular_velocities", &member<offsetof(BodyState, w), 3>,
                             "(n, 3) angular velocities (rad/s, world), a read-only view")
      .def_property_readonly("user_forces", &Solver::user_forces,
                             "(n, 6): force (N) and torque (N m) the grabs and tremble applied "
                             "in the last substep, per segment (a copy)");
}

}  // namespace puppet::python
