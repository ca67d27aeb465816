// The flags of the commands that run solvers (run, frontier, robustness, verdict), each defined
// once: a command adds the groups it takes, and reads them back through the parsers below, which
// check every value before anything runs.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <thread>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/compare/sweep.h"
#include "puppet/model/model.h"
#include "puppet/results_layout.h"

namespace puppet::testbed {

// the values as typed; numbers that may be fractions (1/240) are kept as text and read by
// parse_finite (CLI11 reads no fractions, and its doubles take hex and leading blanks); counts
// and choices are CLI11's, typed and checked
struct Flags {
  std::string model = "pinocchio", scenario = "all", solver = "all", rule = "all";
  std::string dt = compare::dt_flag(compare::kSweepStepRates), duration, out = kResultsRoot, pin,
              grab, gravity, air_drag, ground;
  std::string tilt = "30", hz = "0.5", sample_hz = "30", grab_compliance;
  // the grab's law (compare::GrabSettings); empty: its defaults
  std::string grab_hz, grab_ratio, grab_cap;
  // every engine's own settings, bound by its row's flags (engines.h); the rule is --rule's
  compare::SolverOptions options;
  int jobs = default_jobs();
  double engine_budget = compare::kDefaultEngineBudget;  // --engine-budget (engines.h)
  ReadOptions reading;  // --strict, --include-outside: how the model file is read
  bool position_tremble = false, no_timing = false;
  bool no_accuracy = false;
  bool first_truth_only = false;
  std::string truth_cache;  // run: a folder of truth trajectories (truth_cache.h)
  std::string start;        // run: SEED:INDEX, a random start (start.h)
  // robustness
  std::string starts = "100", seed = "1", shard;
  // verdict
  std::string budget = "1mm,1cm,5cm", frame_hz = "60", floors_from;

  static int default_jobs() {
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  }
};

// --engine-budget (engines.h: engine_model_problem): finite, from 1e-3 to 1e9 s
void add_engine_budget_flag(CLI::App* command, double& budget);
// --model, and how a model file is read: --strict, --include-outside
void add_model_flag(CLI::App* command, Flags& f);
void add_model_reading_flags(CLI::App* command, ReadOptions& reading);
// --solver and --rule
void add_solver_choice_flags(CLI::App* command, Flags& f);
// --scenario
void add_scenario_choice_flag(CLI::App* command, Flags& f);
// --out and --jobs
void add_output_flags(CLI::App* command, Flags& f, const char* jobs_help = "worker threads");
// every engine's own flags (its row in engines.h), bound to f.options
void add_engine_flags(CLI::App* command, Flags& f);
// the scenario's pieces a user may change: the dragged point, gravity, the grab's law and the
// marionette's pin compliance
void add_grab_flags(CLI::App* command, Flags& f);
// what a sweep of runs takes (run, robustness): scenarios, dts, duration, pin, air, ground and
// the tremble
void add_sweep_flags(CLI::App* command, Flags& f);
// the whole of model, solver, output, engine and grab flags: what run and frontier share
void add_solver_flags(CLI::App* command, Flags& f);

// --starts (what they are for: `starts_help`) and --seed, the random starts of robustness and
// verdict
void add_starts_flags(CLI::App* command, Flags& f, const char* starts_help);

// robustness's flags and their defaults: the command line's, and merge's reading of a shard's
// replay flags
Flags robustness_defaults();
void add_robustness_flags(CLI::App* command, Flags& f);
// the flags a replay of one robustness run repeats: every one that differs from robustness's
// defaults and changes the run, in a fixed order
std::string replay_flags(const Flags& f);

compare::ScenarioOptions parse_scenario_options(const Flags& f);
// every solver of --solver, and for procedural every rule of --rule
std::vector<compare::SolverConfig> parse_solver_configs(const Flags& f);
// One verdict per model, before anything runs: an engine that cannot build the model is refused
// when --solver names it, and left out with a note when --solver is all
void apply_engine_verdicts(std::vector<compare::SolverConfig>& configs, const Model& model,
                           const Flags& f);

}  // namespace puppet::testbed
