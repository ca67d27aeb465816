// The crowd from Python: many puppets of one model stepped together on a fixed set of threads
// (crowd.h), each reachable as a Solver.
#include <pybind11/stl.h>

#include <unistd.h>

#include <memory>
#include <optional>
#include <string>

#include "puppet/procedural/crowd.h"
#include "solver.h"

namespace puppet::python {
namespace {

class Crowd {
 public:
  Crowd(ModelPtr model, int puppets, const procedural::Settings& settings,
        const Environment& environment, int threads, procedural::CrowdLanes lanes)
      : model_(std::move(model)), process_(getpid()) {
    try {
      crowd_ = std::make_unique<procedural::Crowd>(*model_, settings, environment, puppets, threads,
                                                   lanes);
    } catch (const std::invalid_argument& e) {
      throw py::value_error(bounded(e.what()));
    }
    const auto rest = rest_pose(*model_);
    for (int k = 0; k < crowd_->size(); ++k) crowd_->puppet(k).reset(rest);
  }

  ~Crowd() {
    // in a process forked after it was made, its worker threads do not exist: they are neither
    // joined nor woken, and the crowd is let go unfreed
    if (getpid() != process_) static_cast<void>(crowd_.release());
  }
  Crowd(const Crowd&) = delete;
  Crowd& operator=(const Crowd&) = delete;

  void step(double dt) {
    if (!(dt > 0.0 && dt <= 1.0)) refuse("dt", "must be in (0, 1] s");
    if (getpid() != process_ && crowd_->threads() > 1) {
      throw std::runtime_error(
          "Crowd: made with " + std::to_string(crowd_->threads()) +
          " threads before fork(), whose threads the child process lacks; make a new Crowd in "
          "the child");
    }
    const Exclusive held(*busy_, "Crowd: it");
    py::gil_scoped_release release;  // the workers need no Python
    crowd_->step(dt);
  }

  // every puppet's member at `offset` (width doubles), as one (puppets, n, width) copy
  py::array gather(size_t offset, ssize_t width) const {
    const Exclusive held(*busy_, "Crowd: it");
    const auto n = static_cast<ssize_t>(model_->segment_count());
    py::array_t<double> out({static_cast<ssize_t>(crowd_->size()), n, width});
    double* o = out.mutable_data();
    for (int k = 0; k < crowd_->size(); ++k) {
      for (const BodyState& b : crowd_->puppet(k).state().bodies) {
        const auto* member =
            reinterpret_cast<const double*>(reinterpret_cast<const char*>(&b) + offset);
        for (ssize_t c = 0; c < width; ++c) *o++ = member[c];
      }
    }
    return out;
  }

  procedural::Crowd& crowd() { return *crowd_; }
  const ModelPtr& model() const { return model_; }
  const std::shared_ptr<std::atomic<bool>>& busy() const { return busy_; }

 private:
  ModelPtr model_;
  std::unique_ptr<procedural::Crowd> crowd_;
  pid_t process_;  // the process that made it (its worker threads are that process's)
  std::shared_ptr<std::atomic<bool>> busy_ = std::make_shared<std::atomic<bool>>(false);
};

procedural::CrowdLanes parse_lanes(const std::string& lanes) {
  if (lanes == "widest") return procedural::CrowdLanes::kWidest;
  if (lanes == "four") return procedural::CrowdLanes::kFour;
  if (lanes == "two") return procedural::CrowdLanes::kTwo;
  if (lanes == "none") return procedural::CrowdLanes::kNone;
  refuse("lanes", "unknown value \"" + lanes + "\" (expected one of widest, four, two, none)");
}

}  // namespace

void bind_crowd(py::module_& m) {
  py::class_<Crowd>(m, "Crowd",
                    "many puppets of one model stepped together on `threads` threads; xpbd's in "
                    "SIMD lanes (docs/solver.md, \"a crowd in SIMD lanes\")")
      .def(py::init([](ModelPtr model, const py::object& puppets, const std::string& rule,
                       std::optional<Environment> environment, const py::object& threads,
                       const std::string& lanes, const py::kwargs& settings) {
             return std::make_unique<Crowd>(
                 std::move(model), static_cast<int>(whole("puppets", puppets, 1, 1'000'000)),
                 make_settings(rule, settings), environment.value_or(Environment{}),
                 static_cast<int>(whole("threads", threads, 1, 256)), parse_lanes(lanes));
           }),
           py::arg("model"), py::arg("puppets"), py::arg("rule") = "xpbd", py::kw_only(),
           py::arg("environment") = py::none(), py::arg("threads") = 1, py::arg("lanes") = "widest",
           (std::string("the solver's settings as keywords, as Solver's: ") + setting_names())
               .c_str())
      .def("step", &Crowd::step, py::arg("dt"), "every puppet one step of dt seconds")
      .def("__len__", [](Crowd& c) { return c.crowd().size(); })
      .def_property_readonly("threads", [](Crowd& c) { return c.crowd().threads(); })
      .def_property_readonly(
          "lanes", [](Crowd& c) { return c.crowd().lanes(); },
          "puppets stepped together: 8, 4, 2, or 1 (one by one)")
      .def(
          "puppet",
          [](py::object self, const py::object& k) {
            Crowd& c = self.cast<Crowd&>();
            const auto index = static_cast<int>(whole("k", k, 0, c.crowd().size() - 1));
            return Solver(c.model(), &c.crowd().puppet(index), self, c.busy());
          },
          py::arg("k"),
          "puppet k as a Solver (its pins, state and views), kept alive with the crowd")
      .def(
          "positions", [](const Crowd& c) { return c.gather(offsetof(BodyState, x), 3); },
          "(puppets, n, 3) COM positions, a copy")
      .def(
          "rotations", [](const Crowd& c) { return c.gather(offsetof(BodyState, q), 4); },
          "(puppets, n, 4) orientations (x, y, z, w), a copy")
      .def(
          "diverged",
          [](Crowd& c) {
            const Exclusive held(*c.busy(), "Crowd: it");
            std::vector<bool> out;
            for (int k = 0; k < c.crowd().size(); ++k) {
              out.push_back(c.crowd().puppet(k).state().diverged);
            }
            return out;
          },
          "per puppet, whether it diverged");
}

}  // namespace puppet::python
