// The procedural solver as Python holds it: its own, or one of a crowd's puppets.
#pragma once

#include <pybind11/numpy.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "puppet/procedural/solver.h"

namespace puppet::python {

/// Calls on a crowd and on its puppets while the crowd steps (with the GIL released) are refused:
/// a call holds its crowd's flag for its length, and a second one finds it held and raises
/// RuntimeError instead of running alongside (docs/python.md, "Threads and fork")
class Exclusive {
 public:
  Exclusive(std::atomic<bool>& busy, const char* what);
  ~Exclusive() { busy_.store(false, std::memory_order_release); }
  Exclusive(const Exclusive&) = delete;
  Exclusive& operator=(const Exclusive&) = delete;

 private:
  std::atomic<bool>& busy_;
};

/// a point of a segment held at a world target, its segment by index or name (resolved against
/// the solver's model when the pins are set)
struct PinSpec {
  py::object segment;
  Vector3d point{0, 0, 0};
  Vector3d target{0, 0, 0};
  double compliance = 0.0;
  GrabSpring grab{};  ///< hz 0: not a grab
};

/// the pins as the solvers take them, each segment resolved against the model (ValueError for
/// more than kMaxPins, an unknown name or an index out of range)
std::vector<Pin> to_pins(const Model& model, const std::vector<PinSpec>& specs);

/// a whole state from the four arrays as the package holds them (positions, rotations x, y, z,
/// w, velocities, angular velocities; one row per segment), copied after checking their shapes,
/// that every value is finite and that each rotation is a unit quaternion
std::vector<BodyState> bodies_from(const Model& model, const py::handle& positions,
                                   const py::handle& rotations, const py::handle& velocities,
                                   const py::handle& angular_velocities);

class Solver {
 public:
  /// a solver of its own
  Solver(ModelPtr model, const procedural::Settings& settings, const Environment& environment);
  /// puppet k of a crowd, which `owner` keeps alive; `busy` is the crowd's (Exclusive)
  Solver(ModelPtr model, procedural::Solver* puppet, py::object owner,
         std::shared_ptr<std::atomic<bool>> busy);

  void step(double dt);
  bool diverged() const {
    const Exclusive held = hold();
    return solver_->state().diverged;
  }
  double time() const {
    const Exclusive held = hold();
    return solver_->state().time;
  }
  void reset();
  void set_pins(const std::vector<PinSpec>& pins);
  void set_pin_targets(const py::handle& targets);
  // one pin's target, the others' kept
  void set_pin_target(const py::handle& pin, const py::handle& target);
  void set_state(const py::handle& x, const py::handle& q, const py::handle& v,
                 const py::handle& w);
  /// held for the length of any call that reads or changes the state (Exclusive)
  Exclusive hold() const { return Exclusive(*busy_, owner_ ? "Solver: its crowd" : "Solver"); }
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
  std::shared_ptr<std::atomic<bool>> busy_ = std::make_shared<std::atomic<bool>>(false);
};

/// the names of the solver's settings a Python caller may give as keywords, a comma list
/// (procedural/settings.h; position_tremble is Settings::tremble)
std::string setting_names();
/// the settings from keyword arguments (None: the rule's own), each checked, then by
/// procedural::validate; ValueError naming the argument
procedural::Settings make_settings(const std::string& rule, const py::kwargs& given);

}  // namespace puppet::python
