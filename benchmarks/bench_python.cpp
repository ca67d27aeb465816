// step() called from Python against the same step called from C++ (issue 52's target: at most
// 10 % more), in one process and one run: the interpreter is embedded here and imports the built
// package (python/). Both sides step the xpbd rule on Pinocchio hanging from its head, pinned
// 0.2 m aside so that it swings; each iteration restores the state after a 0.5 s warm-up and times
// kBatchSteps steps, the Python side as a user writes the loop (`for _ in range(n):
// solver.step(dt)`). Names: python/step/xpbd/cpp and python/step/xpbd/python (results/gate.json).
#include <pybind11/embed.h>

#include <memory>

#include "bench_support.h"
#include "puppet/compare/scenario.h"

namespace py = pybind11;
using namespace puppet;

namespace {

constexpr int kWarmUpSteps = 120;
constexpr double kStepDt = 1.0 / 240.0;

void step_from_cxx(benchmark::State& state) {
  const Model model = compare::load_named_model("pinocchio");
  procedural::Settings settings;
  settings.rule = procedural::Rule::kXpbd;
  procedural::Solver solver(model, settings, Environment{});
  solver.reset(rest_pose(model));
  Pin pin;
  pin.segment = model.find_segment("head");
  pin.target = solver.state().bodies[pin.segment].x + Vector3d(0.2, 0.0, 0.0);
  solver.set_pins(std::span(&pin, 1));
  for (int k = 0; k < kWarmUpSteps; ++k) solver.step(kStepDt);
  const procedural::State start = solver.state();
  for (auto _ : state) {
    solver.restore(start);
    state.SetIterationTime(bench::seconds_of([&] {
      for (int k = 0; k < bench::kBatchSteps; ++k) solver.step(kStepDt);
    }));
  }
  if (solver.state().diverged) state.SkipWithError("diverged in a timed batch");
  state.SetItemsProcessed(state.iterations() * bench::kBatchSteps);
}

// the Python side, defined once in the interpreter
constexpr const char* kPythonSide = R"(
import puppet

model = puppet.load_model("pinocchio")
solver = puppet.Solver(model, "xpbd")
head = model.segment_index("head")
solver.set_pins([puppet.Pin(head, target=solver.positions[head] + [0.2, 0.0, 0.0])])
for _ in range(warm_up_steps):
    solver.step(dt)
start = solver.snapshot()

def batch(n):
    for _ in range(n):
        solver.step(dt)
)";

void step_from_python(benchmark::State& state) {
  py::dict scope;
  scope["warm_up_steps"] = kWarmUpSteps;
  scope["dt"] = kStepDt;
  py::exec(kPythonSide, scope);
  const py::object solver = scope["solver"], start = scope["start"], batch = scope["batch"];
  const py::object restore = solver.attr("restore");
  for (auto _ : state) {
    restore(start);
    state.SetIterationTime(bench::seconds_of([&] { batch(bench::kBatchSteps); }));
  }
  if (solver.attr("diverged").cast<bool>()) state.SkipWithError("diverged in a timed batch");
  state.SetItemsProcessed(state.iterations() * bench::kBatchSteps);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  py::scoped_interpreter interpreter;
  py::module_::import("sys").attr("path").attr("insert")(0, PUPPET_PYTHON_DIR);
  benchmark::RegisterBenchmark("python/step/xpbd/cpp", step_from_cxx)
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("python/step/xpbd/python", step_from_python)
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
