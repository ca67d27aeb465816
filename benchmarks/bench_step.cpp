// One Pinocchio step in every solver configuration, in hang, drag and drop.
// Names: step/<scenario>/<solver or rule>, so --benchmark_filter=hang selects every solver's run
// of hang. Each is configured exactly as the harness runs it (compare::make_simulator).
#include <memory>

#include "bench_support.h"

using namespace puppet;
using namespace puppet::bench;

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (const std::string& scenario : kStepScenarios) {
    for (const SolverConfig& config : solver_configs()) {
      benchmark::RegisterBenchmark(
          ("step/" + scenario + "/" + compare::config_label(config)).c_str(),
          [scenario, config](benchmark::State& state) {
            const Workload workload = make_workload(pinocchio(), scenario, kBatchSteps);
            const auto simulator = compare::make_simulator(config.solver, config.options);
            run_batches(state, *simulator, workload);
          })
          ->UseManualTime()
          ->Unit(benchmark::kMicrosecond);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
