// The procedural solver as Python holds it: its own, or one of a crowd's puppets.
#pragma once

#include <pybind11/numpy.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "puppet/procedural/solver.h"

namespace puppet::python {

/// a point of a segment held at a world target, its segment by index or name (resolved against
/// the solver's model when the pins are set)
struct PinSpec {
  py::object segment;
  Vector3d point{0, 0, 0};
  Vector3d target{0, 0, 0};
  double compliance = 0.0;
  GrabSpring grab{};  ///< hz 0: not a grab
};

class Solver {
 public:
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

  /// a solver of its own
  Solver(ModelPtr model, const procedural::Settings& settings, const Environment& environment);
  /// puppet k of a crowd, which `owner` keeps alive
  Solver(ModelPtr model, procedural::Solver* puppet, py::object owner);

  void step(double dt);
  bool diverged() const { return solver_->state().diverged; }
  double time() const { return solver_->state().time; }
  void reset();
  void set_pins(const std::vector<PinSpec>& pins);
  void set_pin_targets(const Array& targets);
  void set_state(const Array& x, const Array& q, const Array& v, const Array& w);
  /// a read-only view of one member of every body (offset in bytes, width in doubles)
  py::array view(py::handle owner, size_t offset, ssize_t width) const;
  py::array user_forces() const;

  const ModelPtr& model() const { return model_; }
  procedural::Solver& solver() { return *solver_; }
  const procedural::Solver& solver() const { return *solver_; }

 private:
  ModelPtr model_;
  std::unique_ptr<procedural::Solver> own_;
  procedural::Solver* solver_ = nullptr;
  py::object owner_;  ///< the crowd a puppet belongs to
};

/// the names of the solver's settings a Python caller may give as keywords, a comma list
/// (procedural/settings.h; position_tremble is Settings::tremble)
std::string setting_names();
/// the settings from keyword arguments (None: the rule's own), each checked, then by
/// procedural::validate; ValueError naming the argument
procedural::Settings make_settings(const std::string& rule, const py::kwargs& given);

}  // namespace puppet::python
