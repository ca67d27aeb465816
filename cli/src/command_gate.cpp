// testbed gate: speed ratios from Google Benchmark JSON against the thresholds (gate.h); exit 0
// when every gate passes, 1 when one fails, 2 on bad input.
#include <iostream>
#include <memory>

#include "cli.h"
#include "commands.h"
#include "puppet/compare/gate.h"
#include "puppet/compare/output.h"
#include "puppet/model/text.h"
#include "puppet/results_layout.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

int gate(const std::vector<std::string>& bench_files, const std::string& thresholds,
         const std::string& csv) {
  if (!csv.empty()) {
    if (std::string problem = output_file_problem(csv); !problem.empty()) {
      throw UsageError("--csv: " + shown(csv) + " " + problem);
    }
  }
  const std::vector<GateSpec> specs = read_gate_specs(thresholds);
  std::vector<BenchTime> times;
  for (const std::string& file : bench_files) {
    for (const BenchTime& time : read_bench_times(file)) times.push_back(time);
  }
  const std::vector<GateResult> results = evaluate_gates(specs, times);
  std::cout << gate_table(results);
  if (!csv.empty()) {
    write_file_atomically(csv, bench_csv(times));
    std::cout << "wrote " << csv << '\n';
  }
  const bool passed = gate_passed(results);
  std::cout << (passed ? "gate: pass\n" : "gate: FAIL\n");
  return passed ? 0 : 1;
}

}  // namespace

Command add_gate_command(CLI::App& app) {
  struct Args {
    std::vector<std::string> files;
    std::string thresholds = std::string(kResultsRoot) + "/" + kResultsGateThresholds, csv;
  };
  auto args = std::make_shared<Args>();
  CLI::App* command = app.add_subcommand(
      "gate",
      "check speed ratios from Google Benchmark JSON (>= 9 repetitions, medians) against "
      "thresholds; exit 1 when one fails");
  command->add_option("BENCH.json", args->files, "Google Benchmark JSON output(s)")->required();
  command->add_option("--thresholds", args->thresholds, "the gates (JSON)")->capture_default_str();
  command->add_option("--csv", args->csv, "also write every benchmark's median to this CSV");
  return {command, [args] { return gate(args->files, args->thresholds, args->csv); }};
}

}  // namespace puppet::testbed
