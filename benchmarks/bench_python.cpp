// step() called from Python against the same step called from C++ (issue 52's target: at most
// 10 % more), in one process and one run: the interpreter is embedded here and imports the built
// package (python/). Both sides step the xpbd rule on Pinocchio hanging from its head, pinned
// 0.2 m aside so that it swings. The sides are paired: each iteration restores both solvers to
// their state after a 0.5 s warm-up and times kBatchSteps steps of each in turn (which goes first
// alternates), the Python side as a user writes the loop (`for _ in range(n): solver.step(dt)`),
// so that a machine slowed for a while slows both alike; timed as two benchmarks, they once read
// 1.44 apart in a CI run where the same build reads 0.95–1.07 here. Each side's seconds per step
// is a counter, s_per_item/cpp and s_per_item/python, which the gate reads as the benchmarks
// python/step/xpbd/cpp and python/step/xpbd/python (results/gate.json).
#include <pybind11/embed.h>

#include <memory>

#include "bench_support.h"
#include "puppet/compare/scenario.h"

namespace py = pybind11;
using namespace puppet;

namespace {

constexpr int kWarmUpSteps = 120;
constexpr double kStepDt = 1.0 / 240.0;

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

void step_paired(benchmark::State& state) {
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

  py::dict scope;
  scope["warm_up_steps"] = kWarmUpSteps;
  scope["dt"] = kStepDt;
  py::exec(kPythonSide, scope);
  const py::object python_solver = scope["solver"], python_start = scope["start"];
  const py::object batch = scope["batch"], restore = python_solver.attr("restore");

  double cxx_seconds = 0.0, python_seconds = 0.0;
  bool cxx_first = true;
  for (auto _ : state) {
    solver.restore(start);
    restore(python_start);
    auto cxx = [&] {
      cxx_seconds += bench::seconds_of([&] {
        for (int k = 0; k < bench::kBatchSteps; ++k) solver.step(kStepDt);
      });
    };
    auto python = [&] { python_seconds += bench::seconds_of([&] { batch(bench::kBatchSteps); }); };
    const double before = cxx_seconds + python_seconds;
    if (cxx_first) {
      cxx();
      python();
    } else {
      python();
      cxx();
    }
    cxx_first = !cxx_first;
    state.SetIterationTime(cxx_seconds + python_seconds - before);
  }
  if (solver.state().diverged || python_solver.attr("diverged").cast<bool>()) {
    state.SkipWithError("diverged in a timed batch");
  }
  const double steps = static_cast<double>(state.iterations()) * bench::kBatchSteps;
  state.SetItemsProcessed(2 * static_cast<int64_t>(steps));  // a step of each side
  state.counters["s_per_item/cpp"] = cxx_seconds / steps;
  state.counters["s_per_item/python"] = python_seconds / steps;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  py::scoped_interpreter interpreter;
  py::module_::import("sys").attr("path").attr("insert")(0, PUPPET_PYTHON_DIR);
  benchmark::RegisterBenchmark("python/step/xpbd", step_paired)
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
