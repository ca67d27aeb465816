// How the step scales with the model, and how many puppets a machine steps.
//
//   scaling/<solver or rule>/N   one step of chain:N (N capsules hanging from ball joints) in
//                                `hang`, N = 4 … 1024, with the complexity fitted over N;
//                                counter segment_s: seconds per segment and step
//   crowd/<rule>/K/threads:T     K independent Pinocchios in `drag` stepped once by a
//                                procedural::Crowd on T threads; items are puppet-steps
#include <memory>

#include "bench_support.h"

using namespace puppet;
using namespace puppet::bench;

namespace {

constexpr int kScalingBatchSteps = 8;  // steps per timed batch (chain:1024 in Bullet: ~10 ms)

void scaling_benchmark(benchmark::State& state, const SolverConfig& config) {
  const int n = static_cast<int>(state.range(0));
  const Workload workload = make_workload(chain(n), "hang", kScalingBatchSteps);
  const auto simulator = compare::make_simulator(config.solver, config.options);
  run_batches(state, *simulator, workload);
  state.SetComplexityN(n);
  state.counters["segment_s"] = benchmark::Counter(static_cast<double>(n) * kScalingBatchSteps,
                                                benchmark::Counter::kIsIterationInvariantRate |
                                                    benchmark::Counter::kInvert);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (const SolverConfig& config : solver_configs()) {
    benchmark::RegisterBenchmark(("scaling/" + config.label).c_str(),
                                 [config](benchmark::State& state) {
                                   scaling_benchmark(state, config);
                                 })
        ->RangeMultiplier(4)
        ->Range(4, 1024)
        ->Complexity()
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
