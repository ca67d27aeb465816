// How the step scales with the model, and how many puppets a machine steps.
//
//   scaling/<solver or rule>/N   one step of chain:N (N capsules hanging from ball joints) in
//                                `hang`, N = 4 … 1024, with the complexity fitted over N;
//                                counter segment_s: seconds per segment and step
//   crowd/<rule>/puppets:K/threads:T/lanes:L   K Pinocchios in `marionette` stepped by a
//                                procedural::Crowd on T threads, L puppets per SIMD batch (xpbd:
//                                1, 2 (SSE2), 4 (AVX2) and 8 (AVX-512, skipped on a processor
//                                without it); the other rules: 1); items are puppet-steps
#include <memory>
#include <vector>

#include "bench_support.h"
#include "puppet/compare/engines.h"
#include "puppet/procedural/crowd.h"

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
  state.counters["segment_s"] = benchmark::Counter(
      static_cast<double>(n) * kScalingBatchSteps,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// K Pinocchios in `marionette`, all restored to the state one of them reached after the warm-up,
// then kCrowdBatchSteps steps timed (each puppet's pin target is set by the crowd's control, just
// before it steps), as a step/ benchmark does for one puppet; the restore (a copy of every
// puppet's state) is not timed
constexpr int kCrowdBatchSteps = 8;

procedural::CrowdLanes crowd_lanes(int64_t lanes) {
  switch (lanes) {
    case 8:
      return procedural::CrowdLanes::kWidest;
    case 4:
      return procedural::CrowdLanes::kFour;
    case 2:
      return procedural::CrowdLanes::kTwo;
    default:
      return procedural::CrowdLanes::kNone;
  }
}

void crowd_benchmark(benchmark::State& state, procedural::Rule rule) {
  const int puppets = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const int lanes = static_cast<int>(state.range(2));
  // marionette: the figure held by two pins (a grabbed puppet is stepped alone, outside the lanes)
  const Workload workload = make_workload(pinocchio(), "marionette", kCrowdBatchSteps);
  const compare::Scenario& scenario = workload.scenario;
  const auto lone = warmed_up_solver(state, workload, rule);
  procedural::Crowd crowd(pinocchio(), procedural_settings(rule), scenario.environment, puppets,
                          threads, crowd_lanes(lanes));
  if (crowd.lanes() != lanes) {
    state.SkipWithError("this processor has no such lanes");
    return;
  }
  for (int k = 0; k < puppets; ++k) crowd.puppet(k).set_pins(scenario.initial_pins());
  const std::vector<Vector3d>* step_targets = nullptr;
  const procedural::Crowd::Control follow = [&step_targets](int, procedural::Solver& puppet) {
    puppet.set_pin_targets(*step_targets);
  };
  for (auto _ : state) {
    for (int k = 0; k < puppets; ++k) crowd.puppet(k).restore(lone->state());
    state.SetIterationTime(seconds_of([&] {
      for (const std::vector<Vector3d>& targets : workload.batch_targets) {
        step_targets = &targets;
        crowd.step(kDt, follow);
      }
    }));
  }
  for (int k = 0; k < puppets; ++k) {
    if (crowd.puppet(k).state().diverged) {
      state.SkipWithError("a puppet diverged");
      break;
    }
  }
  state.SetItemsProcessed(state.iterations() * puppets * kCrowdBatchSteps);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (const SolverConfig& config : solver_configs()) {
    // the longest chain the engine takes (MuJoCo's XML parser nests at most 100 elements, its
    // tinyxml2's depth limit, so chain:256 cannot be MJCF): its catalogue row says
    int64_t longest = 4;
    while (longest < 1024 &&
           compare::engine_model_problem(config.solver, chain(static_cast<int>(4 * longest)))
               .empty()) {
      longest *= 4;
    }
    benchmark::RegisterBenchmark(
        ("scaling/" + compare::config_label(config)).c_str(),
        [config](benchmark::State& state) { scaling_benchmark(state, config); })
        ->RangeMultiplier(4)
        ->Range(4, longest)
        ->Complexity()
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
  }
  for (procedural::Rule rule : procedural::kAllRules) {
    const std::string name(procedural::rule_name(rule));
    // the substepped rules cost 10–100x a one-pass step (a 20,000-puppet tree crowd is 41 s per
    // step on one thread): their crowds stop at 1,000 puppets, where the one-pass rules' puppets
    // per second already equal their 20,000's (measured: relaxed 83 k/s and 82 k/s)
    const procedural::RuleInfo info = procedural::rule_info(rule);
    const bool substepped = info.substeps > 1;
    const std::vector<int64_t> puppets =
        substepped ? std::vector<int64_t>{1000} : std::vector<int64_t>{1000, 20000};
    const std::vector<int64_t> lanes =
        info.lanes ? std::vector<int64_t>{1, 2, 4, 8} : std::vector<int64_t>{1};
    benchmark::RegisterBenchmark(("crowd/" + name).c_str(),
                                 [rule](benchmark::State& state) { crowd_benchmark(state, rule); })
        ->ArgNames({"puppets", "threads", "lanes"})
        ->ArgsProduct({puppets, {1, 2}, lanes})
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
