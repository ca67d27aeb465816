// The verdict's choices side by side (results/verdict/verdict.csv, written by testbed verdict):
// per scenario and budget, the cheapest procedural rule and the cheapest reference engine, each
// in the configuration the verdict chose for it, on the model it was chosen on.
// Names: verdict/<scenario>/<budget>/procedural and verdict/<scenario>/<budget>/reference, the
// label says which solver and configuration. Items are simulated milliseconds, so the ratio of
// two medians is the ratio of their costs per simulated second: the gate holds the procedural
// family's speedup over the cheapest reference at equal accuracy and robustness.
//   bench_verdict [--verdict FILE] [Google Benchmark flags]
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "bench_support.h"
#include "puppet/compare/engines.h"
#include "puppet/compare/output.h"
#include "puppet/compare/verdict.h"
#include "puppet/results_layout.h"

using namespace puppet;
using namespace puppet::bench;

namespace {

// the simulated time of one timed batch: a whole number of steps at every dt the verdict
// searches (1/30 … 1/960 s)
constexpr double kBatchSeconds = 0.5;

struct Choice {
  std::string scenario, solver, rule, setting;
  double budget_m = 0.0, dt = 0.0, cost = 0.0;
};

std::vector<Choice> read_choices(const std::string& path, std::string* model) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open (run testbed verdict first)");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = compare::split_commas(line);
  auto column = [&](const char* name) {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return i;
    }
    throw std::runtime_error(path + ": no column " + name);
  };
  const size_t scenario = column("scenario"), solver = column("solver"), rule = column("rule"),
               view = column("view"), budget = column("budget_m"), verdict = column("verdict"),
               setting = column("setting"), dt = column("dt"), cost = column("cost_us_per_s"),
               model_column = column("model");
  std::vector<Choice> out;
  while (std::getline(in, line)) {
    // the fields read come before the free text (why), which may be quoted
    const std::vector<std::string> f = compare::split_commas(line);
    if (f.size() <= model_column || f[view] != "second" || f[verdict] != "met") continue;
    *model = f[model_column];
    out.push_back({f[scenario], f[solver], f[rule], f[setting], std::stod(f[budget]),
                   std::stod(f[dt]), std::stod(f[cost])});
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path =
      (std::filesystem::path(compare::builtin_model_path()).parent_path().parent_path() /
       kResultsRoot / kResultsVerdict / "verdict.csv")
          .string();
  std::vector<char*> args{argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--verdict") == 0 && i + 1 < argc) {
      path = argv[++i];
    } else {
      args.push_back(argv[i]);
    }
  }
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  std::string model_name;
  std::vector<Choice> choices;
  try {
    choices = read_choices(path, &model_name);
  } catch (const std::exception& e) {
    std::cerr << "bench_verdict: " << e.what() << '\n';
    return 2;
  }
  if (model_name != "pinocchio") {
    std::cerr << "bench_verdict: " << path << ": the verdict is of " << model_name
              << ", the benchmark times Pinocchio\n";
    return 2;
  }
  static const Model model = compare::load_named_model("pinocchio");
  // per scenario and budget, the cheapest of each family
  std::map<std::pair<std::string, double>, std::map<std::string, Choice>> best;
  for (const Choice& c : choices) {
    // a WebAssembly engine's cost is never ranked against native code's
    const compare::Engine* engine = compare::find_engine(c.solver);
    if (engine == nullptr || !engine->native) continue;
    const std::string family =
        compare::has_rules(c.solver) ? std::string(compare::kProceduralEngine) : "reference";
    auto& slot = best[{c.scenario, c.budget_m}];
    auto it = slot.find(family);
    if (it == slot.end() || c.cost < it->second.cost) slot[family] = c;
  }
  for (const auto& [key, families] : best) {
    if (families.size() < 2) continue;  // a ratio needs both
    for (const auto& entry : families) {
      // a copy, not a structured binding: clang 14 cannot capture those in a lambda
      const std::string family = entry.first;
      const Choice c = entry.second;
      const std::string name =
          "verdict/" + c.scenario + "/" + compare::budget_text(c.budget_m) + "/" + family;
      const compare::SolverOptions options =
          compare::candidate_options(c.solver, c.rule, c.setting);
      const std::string label = (c.rule.empty() ? c.solver : c.rule) + " 1/" +
                                std::to_string(std::lround(1.0 / c.dt)) + " s" +
                                (c.setting.empty() ? "" : " " + c.setting);
      benchmark::RegisterBenchmark(
          name.c_str(),
          [c, options, label](benchmark::State& state) {
            const int steps = static_cast<int>(std::lround(kBatchSeconds / c.dt));
            const Workload workload = make_workload(model, c.scenario, steps, c.dt);
            const auto simulator = compare::make_simulator(c.solver, options);
            state.SetLabel(label);
            run_batches(state, *simulator, workload, std::lround(kBatchSeconds * 1000));
          })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
