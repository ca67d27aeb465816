// The procedural solver's stages one at a time, and the floor they are measured against.
//
//   stage/<scenario>/<rule>/<stage>  one stage (update, adjust, contacts, velocities) on the
//                                    state the stages before it left, restored each time
//   floor/<scenario>                 the same 14 segments integrated as free bodies: the update
//                                    stage alone, stepped kBatchSteps times per batch like a
//                                    step/ benchmark, so step ÷ floor compares like with like
//
// The solvers are built with compare::procedural_settings, exactly as the harness builds them.
#include <memory>

#include "bench_support.h"
#include "puppet/procedural/solver.h"

using namespace puppet;
using namespace puppet::bench;

namespace {

void stage_benchmark(benchmark::State& state, const std::string& scenario, procedural::Rule rule,
                     procedural::Stage stage) {
  const Workload workload = make_workload(pinocchio(), scenario, 1);
  const auto solver = warmed_up_solver(state, workload, rule);
  solver->set_pin_targets(workload.batch_targets[0]);
  // the state each stage starts from: the stages before it run once on the snapshot
  procedural::State start = solver->state();
  for (int s = 0; s < stage; ++s) solver->run_stage(static_cast<procedural::Stage>(s), kDt);
  start = solver->state();
  for (auto _ : state) {
    solver->restore(start);
    state.SetIterationTime(seconds_of([&] { solver->run_stage(stage, kDt); }));
  }
  state.SetItemsProcessed(state.iterations());
}

void floor_benchmark(benchmark::State& state, const std::string& scenario) {
  const Workload workload = make_workload(pinocchio(), scenario, kBatchSteps);
  const auto solver = warmed_up_solver(state, workload, procedural::Rule::kLiteral);
  const procedural::State start = solver->state();
  for (auto _ : state) {
    solver->restore(start);
    state.SetIterationTime(seconds_of([&] {
      for (int k = 0; k < kBatchSteps; ++k) solver->run_stage(procedural::kUpdate, kDt);
    }));
  }
  state.SetItemsProcessed(state.iterations() * kBatchSteps);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for (const std::string& scenario : kStepScenarios) {
    benchmark::RegisterBenchmark(
        ("floor/" + scenario).c_str(),
        [scenario](benchmark::State& state) { floor_benchmark(state, scenario); })
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
    for (procedural::Rule rule : procedural::kAllRules) {
      const std::string rule_name(procedural::rule_name(rule));
      for (int s = 0; s < procedural::kStageCount; ++s) {
        const auto stage = static_cast<procedural::Stage>(s);
        const std::string name =
            "stage/" + scenario + "/" + rule_name + "/" + std::string(procedural::kStageNames[s]);
        benchmark::RegisterBenchmark(name.c_str(),
                                     [scenario, rule, stage](benchmark::State& state) {
                                       stage_benchmark(state, scenario, rule, stage);
                                     })
            ->UseManualTime()
            ->Unit(benchmark::kNanosecond);
      }
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
