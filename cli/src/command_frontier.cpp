// testbed frontier: per solver and rule, the largest circle frequency and dt at which yank stays
// ok, by bisection; writes frontier.csv.
#include <cstdio>
#include <memory>

#include "cli.h"
#include "commands.h"
#include "flags.h"
#include "progress.h"
#include "puppet/compare/frontier.h"
#include "puppet/compare/output.h"
#include "puppet/compare/output_folder.h"
#include "tables.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

int frontier(const Flags& f) {
  FrontierSpec spec;
  spec.scenario = parse_scenario_options(f);
  spec.configs = parse_solver_configs(f);
  spec.jobs = f.jobs;
  const Model model = parse_model(f.model, f.reading);
  spec.model = &model;
  apply_engine_verdicts(spec.configs, model, f);
  make_scenario("yank", model, spec.scenario);  // a bad --grab fails here, before any run
  OutputFolder folder("--out", f.out, {"frontier.csv"});
  spec.on_progress = Progress("frontier");
  const std::vector<FrontierRow> rows = find_frontier(spec);

  const OutputContext context{model.name, current_git_sha(), machine_description()};
  write_file_atomically((folder.staging() / "frontier.csv").string(), frontier_csv(rows, context));
  folder.commit();
  print_frontier_table(spec, rows);
  std::printf("\nwrote %s/frontier.csv\n", folder.path().c_str());
  return 0;
}

}  // namespace

Command add_frontier_command(CLI::App& app) {
  auto f = std::make_shared<Flags>();
  CLI::App* command = app.add_subcommand(
      "frontier",
      "bisect, per solver and rule, the largest circle frequency and dt at which yank stays ok; "
      "write frontier.csv");
  add_solver_flags(command, *f);
  command->add_option("--hz", f->hz, "circle frequency held during the dt search (Hz)")
      ->capture_default_str();
  return {command, [f] { return frontier(*f); }};
}

}  // namespace puppet::testbed
