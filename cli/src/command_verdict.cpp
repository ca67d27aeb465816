// testbed verdict: per solver and scenario, the cheapest configuration (dt, substeps, sweeps)
// within each error budget against the truth that survives N random starts; writes
// candidates.csv and verdict.csv.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "flags.h"
#include "progress.h"
#include "puppet/compare/output.h"
#include "puppet/compare/output_folder.h"
#include "puppet/compare/start.h"
#include "puppet/compare/verdict.h"
#include "puppet/model/text.h"
#include "puppet/results_layout.h"
#include "tables.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

// the truths' floors from a run's summary.csv: a regular file of a sweep's size (/dev/zero or a
// FIFO would never end)
void read_floors(const Flags& f, const Model& model, VerdictSpec& spec) {
  std::error_code error;
  const auto status = std::filesystem::status(f.floors_from, error);
  if (error || !std::filesystem::is_regular_file(status)) {
    throw UsageError("--floors-from: " + shown(f.floors_from) + ": not a readable file");
  }
  if (std::filesystem::file_size(f.floors_from, error) > (size_t{256} << 20) || error) {
    throw UsageError("--floors-from: " + shown(f.floors_from) + ": larger than 256 MiB");
  }
  std::ifstream in(f.floors_from, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in || in.bad()) {
    throw UsageError("--floors-from: " + shown(f.floors_from) + ": cannot read");
  }
  try {
    spec.floors = floors_from_summary(text.str(), f.floors_from, model, spec.scenarios,
                                      current_git_sha(), spec.engine_budget);
  } catch (const std::runtime_error& e) {
    throw UsageError(std::string("--floors-from: ") + e.what());
  }
}

int verdict(const Flags& f) {
  VerdictSpec spec;
  spec.scenarios = expand("--scenario", f.scenario, scenario_names());
  spec.scenario = parse_scenario_options(f);
  spec.solvers = parse_solver_configs(f);
  spec.dts = parse_dts(f.dt);
  for (double dt : spec.dts) {
    if (!divides_sample_interval(dt)) {
      throw UsageError("--dt: " + format_dt(dt) +
                       " s does not divide the error's sample "
                       "interval of 1/30 s");
    }
  }
  spec.budgets_m = parse_budgets(f.budget);
  spec.frame_hz = parse_in("--frame-hz", f.frame_hz, 1.0, 1000.0, " Hz");
  spec.starts = parse_starts(f.starts, 10000.0);
  spec.seed = parse_seed(f.seed);
  spec.jobs = f.jobs;
  spec.engine_budget = f.engine_budget;
  const Model model = parse_model(f.model, f.reading);
  spec.model = &model;
  apply_engine_verdicts(spec.solvers, model, f);
  if (truths_for(model, spec.engine_budget).empty()) {
    throw UsageError("--model: " + shown(f.model) +
                     ": no truth can run it (neither MuJoCo nor bullet-multibody)");
  }
  if (!f.floors_from.empty()) read_floors(f, model, spec);
  for (const std::string& name : spec.scenarios) {
    ScenarioOptions options = spec.scenario;
    make_scenario(name, model, options);  // a bad --grab or --pin fails here, before any run
    options.start = random_start(model, spec.seed, 0);
    make_scenario(name, model, options);
  }
  OutputFolder folder("--out", f.out, {"candidates.csv", "verdict.csv", "contact.csv"});
  Progress bar("verdict");
  std::string shown_phase;
  spec.on_progress = [&](const char* phase, size_t done, size_t total) {
    if (shown_phase != phase) {
      shown_phase = phase;
      bar = Progress(std::string("verdict: ") + phase);
    }
    bar(done, total);
  };
  const VerdictResult result = run_verdict(spec);
  const OutputContext context{model.name, current_git_sha(), machine_description()};
  write_file_atomically((folder.staging() / "candidates.csv").string(),
                        verdict_candidates_csv(result, context));
  write_file_atomically((folder.staging() / "verdict.csv").string(),
                        verdict_csv(result, spec, context));
  write_file_atomically((folder.staging() / "contact.csv").string(),
                        verdict_contact_csv(result, context));
  folder.commit();
  print_verdict_table(spec, result);
  std::printf("\nwrote %s: candidates.csv, verdict.csv, contact.csv\n", folder.path().c_str());
  return 0;
}

}  // namespace

Command add_verdict_command(CLI::App& app) {
  auto f = std::make_shared<Flags>();
  f->dt = compare::dt_flag();
  f->out = std::string(kResultsRoot) + "/" + kResultsVerdict;
  f->starts = "32";
  CLI::App* command = app.add_subcommand(
      "verdict",
      "per solver and scenario, the cheapest configuration (dt, substeps, sweeps) within each "
      "error budget against the truth that survives N random starts; write candidates.csv and "
      "verdict.csv");
  add_model_flag(command, *f);
  add_scenario_choice_flag(command, *f);
  add_solver_choice_flags(command, *f);
  command->add_option("--dt", f->dt, "time steps searched, comma list (each divides 1/30 s)")
      ->capture_default_str();
  command->add_option("--budget", f->budget, "error budgets, comma list (1mm, 1cm, 0.05m)")
      ->capture_default_str();
  add_starts_flags(command, *f,
                   "random starts a chosen configuration must survive without diverging");
  command
      ->add_option("--frame-hz", f->frame_hz,
                   "the frame rate of the per-frame view (a whole number of steps per frame)")
      ->capture_default_str();
  command->add_option("--floors-from", f->floors_from,
                      "the truths' floors from this summary.csv of testbed run (the same model "
                      "and commit, both truths at three dts) instead of measuring them");
  add_output_flags(command, *f, "worker threads (the timing runs alone)");
  return {command, [f] { return verdict(*f); }};
}

}  // namespace puppet::testbed
