// The Python module `puppet` (docs/python.md): load a model, step the procedural solver with any
// rule, and read its state as NumPy arrays that view the solver's own memory (read-only: a state
// is written through set_state, which the solver checks). Errors are Python exceptions with the
// command line's one-line messages.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/model/model.h"
#include "puppet/procedural/rule.h"
#include "puppet/procedural/solver.h"

namespace py = pybind11;

namespace puppet::python {
namespace {

// a model the solvers made from it keep alive (a solver holds a reference to its model)
using ModelPtr = std::shared_ptr<Model>;

ModelPtr load(const std::string& name) {
  try {
    return std::make_shared<Model>(compare::load_named_model(name));
  } catch (const std::exception& e) {
    throw py::value_error(e.what());
  }
}

// the procedural solver with the model it was made from
class Solver {
 public:
  Solver(ModelPtr model, const std::string& rule, int iterations, int substeps)
      : model_(std::move(model)) {
    const auto parsed = procedural::parse_rule(rule);
    if (!parsed) throw py::value_error("rule: unknown value \"" + rule + "\"");
    procedural::Settings settings;
    settings.rule = *parsed;
    if (iterations > 0) settings.iterations = iterations;
    if (substeps > 0) settings.substeps = substeps;
    solver_ = std::make_unique<procedural::Solver>(*model_, settings, Environment{});
    solver_->reset(rest_pose(*model_));
  }

  void step(double dt) {
    if (!(dt > 0.0 && dt <= 1.0)) throw py::value_error("dt: must be in (0, 1] s");
    solver_->step(dt);
  }
  bool diverged() const { return solver_->state().diverged; }

  // a read-only view of one member of every body (offset in bytes, width in doubles)
  py::array view(py::handle owner, size_t offset, ssize_t width) const {
    const std::vector<BodyState>& bodies = solver_->state().bodies;
    const auto* base = reinterpret_cast<const char*>(bodies.data()) + offset;
    py::array out(py::dtype::of<double>(), {static_cast<ssize_t>(bodies.size()), width},
                  {static_cast<ssize_t>(sizeof(BodyState)), static_cast<ssize_t>(sizeof(double))},
                  reinterpret_cast<const double*>(base), owner);
    py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return out;
  }

  // places every segment from (n, 3), (n, 4) (x, y, z, w), (n, 3) and (n, 3) arrays; a wrong
  // shape or a non-finite value is refused before anything changes
  void set_state(const py::array_t<double, py::array::c_style | py::array::forcecast>& x,
                 const py::array_t<double, py::array::c_style | py::array::forcecast>& q,
                 const py::array_t<double, py::array::c_style | py::array::forcecast>& v,
                 const py::array_t<double, py::array::c_style | py::array::forcecast>& w) {
    const auto n = static_cast<ssize_t>(model_->segment_count());
    const auto check = [n](const auto& a, const char* name, ssize_t width) {
      if (a.ndim() != 2 || a.shape(0) != n || a.shape(1) != width) {
        throw py::value_error(std::string(name) + ": expected shape (" + std::to_string(n) + ", " +
                              std::to_string(width) + ")");
      }
      for (ssize_t k = 0; k < a.size(); ++k) {
        if (!std::isfinite(a.data()[k])) {
          throw py::value_error(std::string(name) + ": a value is not finite");
        }
      }
    };
    check(x, "positions", 3);
    check(q, "rotations", 4);
    check(v, "velocities", 3);
    check(w, "angular_velocities", 3);
    std::vector<BodyState> bodies(static_cast<size_t>(n));
    for (ssize_t i = 0; i < n; ++i) {
      BodyState& b = bodies[static_cast<size_t>(i)];
      b.x = Vector3d(x.at(i, 0), x.at(i, 1), x.at(i, 2));
      b.q = Quaterniond(q.at(i, 3), q.at(i, 0), q.at(i, 1), q.at(i, 2));
      if (std::abs(b.q.norm() - 1.0) > 1e-6) {
        throw py::value_error("rotations: row " + std::to_string(i) + " is not a unit quaternion");
      }
      b.v = Vector3d(v.at(i, 0), v.at(i, 1), v.at(i, 2));
      b.w = Vector3d(w.at(i, 0), w.at(i, 1), w.at(i, 2));
    }
    solver_->place(bodies);
  }

  const Model& model() const { return *model_; }
  procedural::Solver& solver() { return *solver_; }

 private:
  ModelPtr model_;
  std::unique_ptr<procedural::Solver> solver_;
};

}  // namespace
}  // namespace puppet::python

PYBIND11_MODULE(puppet, m) {
  using namespace puppet;
  using namespace puppet::python;
  m.doc() = "The procedural articulated-body solver (Bae et al. 2001) and its family";

  py::class_<Model, ModelPtr>(m, "Model")
      .def_property_readonly("name", [](const Model& model) { return model.name; })
      .def_property_readonly("segment_count", &Model::segment_count)
      .def_property_readonly("segments", [](const Model& model) {
        std::vector<std::string> names;
        for (const Segment& s : model.segments) names.push_back(s.name);
        return names;
      });
  m.def("load_model", &load, py::arg("name"), "pinocchio, chain:N, or a model file (JSON or MJCF)");

  py::class_<Solver>(m, "Solver")
      .def(py::init<ModelPtr, const std::string&, int, int>(), py::arg("model"),
           py::arg("rule") = "relaxed", py::arg("iterations") = 0, py::arg("substeps") = 0,
           py::keep_alive<1, 2>())
      .def("step", &Solver::step, py::arg("dt"))
      .def_property_readonly("diverged", &Solver::diverged)
      .def("set_state", &Solver::set_state, py::arg("positions"), py::arg("rotations"),
           py::arg("velocities"), py::arg("angular_velocities"),
           "places every segment (copies the arrays; checks shapes, finiteness, unit rotations)")
      .def_property_readonly(
          "positions",
          [](py::object self) {
            return self.cast<Solver&>().view(self, offsetof(BodyState, x), 3);
          },
          "(n, 3) COM positions (m), a read-only view of the solver's state")
      .def_property_readonly(
          "rotations",
          [](py::object self) {
            return self.cast<Solver&>().view(self, offsetof(BodyState, q), 4);
          },
          "(n, 4) segment orientations as quaternions (x, y, z, w), a read-only view")
      .def_property_readonly(
          "velocities",
          [](py::object self) {
            return self.cast<Solver&>().view(self, offsetof(BodyState, v), 3);
          },
          "(n, 3) COM velocities (m/s), a read-only view")
      .def_property_readonly(
          "angular_velocities",
          [](py::object self) {
            return self.cast<Solver&>().view(self, offsetof(BodyState, w), 3);
          },
          "(n, 3) angular velocities (rad/s, world), a read-only view");
}
