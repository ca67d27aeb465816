#include "flags.h"

#include "cli.h"
#include "puppet/compare/engines.h"
#include "puppet/compare/number.h"
#include "puppet/compare/output.h"
#include "puppet/compare/robustness.h"
#include "puppet/model/text.h"
#include "puppet/procedural/rule.h"
#include "puppet/results_layout.h"

namespace puppet::testbed {

using compare::ScenarioOptions;
using compare::SolverConfig;
using compare::SolverOptions;

namespace {

std::vector<std::string> all_rules() {
  std::vector<std::string> out;
  for (auto rule : procedural::kAllRules) out.emplace_back(procedural::rule_name(rule));
  return out;
}

}  // namespace

void add_model_flag(CLI::App* command, Flags& f) {
  command->add_option("--model", f.model, "model file, pinocchio, or chain:N")
      ->capture_default_str();
  add_model_reading_flags(command, f.reading);
}

void add_model_reading_flags(CLI::App* command, ReadOptions& reading) {
  command->add_flag("--strict", reading.strict,
                    "refuse MJCF elements the testbed does not model (actuators, sensors, "
                    "cameras...) instead of skipping them with a note");
  command->add_flag("--include-outside", reading.include_outside,
                    "let an MJCF <include> read files outside the model's folder");
}

void add_solver_choice_flags(CLI::App* command, Flags& f) {
  command->add_option("--solver", f.solver, "solver name, comma list, or all")
      ->capture_default_str();
  command->add_option("--rule", f.rule, "adjust rule (procedural), comma list, or all")
      ->capture_default_str();
}

void add_scenario_choice_flag(CLI::App* command, Flags& f) {
  command->add_option("--scenario", f.scenario, "scenario name, comma list, or all")
      ->capture_default_str();
}

void add_output_flags(CLI::App* command, Flags& f, const char* jobs_help) {
  command->add_option("--out", f.out, "output folder")->capture_default_str();
  command->add_option("--jobs", f.jobs, jobs_help)
      ->check(compare::whole_number_check())
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
}

void add_engine_budget_flag(CLI::App* command, double& budget) {
  command
      ->add_option("--engine-budget", budget,
                   "CPU seconds an engine may take for one simulated second at dt 1/240 s, by "
                   "its estimate from the model; past it the engine refuses the model")
      ->check(compare::finite_number_check())
      ->check(CLI::Range(1e-3, 1e9))
      ->capture_default_str();
}

void add_engine_flags(CLI::App* command, Flags& f) {
  // every row's, built or not: a command line means the same in every build
  for (const compare::Engine& engine : compare::engines()) {
    if (engine.add_flags) engine.add_flags(*command, f.options);
  }
  add_engine_budget_flag(command, f.engine_budget);
}

void add_grab_flags(CLI::App* command, Flags& f) {
  command->add_option("--grab", f.grab, "dragged point SEGMENT[:x,y,z] (segment frame)");
  command->add_option("--gravity", f.gravity, "gravity X,Y,Z (m/s^2)");
  const compare::GrabSettings grab;
  command->add_option("--grab-hz", f.grab_hz,
                      "the grab of drag, shake, water and tremble: its spring's frequency f (Hz; "
                      "default " +
                          compare::csv_number(grab.hz) + ")");
  command->add_option(
      "--grab-ratio", f.grab_ratio,
      "the grab's damping ratio (default " + compare::csv_number(grab.damping_ratio) + ")");
  command->add_option("--grab-cap", f.grab_cap,
                      "the grab's force cap in the figure's weights M g (default " +
                          compare::csv_number(grab.cap_weights) + ")");
  command->add_option("--grab-compliance", f.grab_compliance,
                      "the hand pin of marionette and yank: its compliance C (m/N): 0 holds the "
                      "hand on its target (default), C > 0 pulls it with a spring of stiffness "
                      "1/C");
}

void add_solver_flags(CLI::App* command, Flags& f) {
  add_model_flag(command, f);
  add_solver_choice_flags(command, f);
  add_output_flags(command, f);
  add_engine_flags(command, f);
  add_grab_flags(command, f);
}

void add_sweep_flags(CLI::App* command, Flags& f) {
  add_scenario_choice_flag(command, f);
  command
      ->add_option("--dt", f.dt, "time steps in seconds, comma list (fractions such as 1/240 too)")
      ->capture_default_str();
  command->add_option("--duration", f.duration, "seconds to simulate (default: the scenario's)");
  command->add_option("--pin", f.pin, "hanging point SEGMENT[:x,y,z] (segment frame)");
  command->add_option("--air-drag", f.air_drag, "air drag k_air (1/s)");
  command->add_option("--ground", f.ground, "ground plane on|off")
      ->check(CLI::IsMember({"on", "off"}));
  command->add_flag("--position-tremble", f.position_tremble,
                    "procedural: the seed's tremble as position noise in the update, in any "
                    "scenario (the tremble scenario's is a force every engine feels)");
}

void add_starts_flags(CLI::App* command, Flags& f, const char* starts_help) {
  command->add_option("--starts", f.starts, starts_help)->capture_default_str();
  command->add_option("--seed", f.seed, "the starts' seed")->capture_default_str();
}

Flags robustness_defaults() {
  Flags f;
  f.dt = "1/240";
  f.out = std::string(kResultsRoot) + "/" + kResultsRobustness;
  f.solver = compare::kProceduralEngine;
  return f;
}

void add_robustness_flags(CLI::App* command, Flags& f) {
  f = robustness_defaults();
  add_solver_flags(command, f);
  add_sweep_flags(command, f);
  add_starts_flags(command, f, "random starts per scenario, solver, rule and dt");
  command->add_option("--shard", f.shard,
                      "run only shard I of N (jobs j with j mod N = I); merge the shards with "
                      "testbed merge");
}

std::string replay_flags(const Flags& f) {
  const Flags defaults = robustness_defaults();
  std::string out;
  auto add = [&](const char* flag, const std::string& value, const std::string& default_value) {
    if (value != default_value) out += std::string(" ") + flag + " " + compare::shell_word(value);
  };
  add("--duration", f.duration, defaults.duration);
  for (const compare::Engine& engine : compare::engines()) {
    if (engine.replay_flags) engine.replay_flags(f.options, out);
  }
  add("--grab-compliance", f.grab_compliance, defaults.grab_compliance);
  add("--grab-hz", f.grab_hz, defaults.grab_hz);
  add("--grab-ratio", f.grab_ratio, defaults.grab_ratio);
  add("--grab-cap", f.grab_cap, defaults.grab_cap);
  add("--pin", f.pin, defaults.pin);
  add("--grab", f.grab, defaults.grab);
  add("--gravity", f.gravity, defaults.gravity);
  add("--air-drag", f.air_drag, defaults.air_drag);
  add("--ground", f.ground, defaults.ground);
  if (f.position_tremble) out += " --position-tremble";
  return out;
}

ScenarioOptions parse_scenario_options(const Flags& f) {
  ScenarioOptions options;
  options.tilt_deg = parse_in("--tilt", f.tilt, -180.0, 180.0, " deg");
  options.hz = parse_in("--hz", f.hz, 1e-3, 50.0, " Hz");
  if (!f.pin.empty()) options.pin = parse_point("--pin", f.pin);
  if (!f.grab.empty()) options.grab = parse_point("--grab", f.grab);
  if (!f.grab_compliance.empty()) {
    options.grab_compliance = parse_in("--grab-compliance", f.grab_compliance, 0.0, 1e3, " m/N");
  }
  auto read = [](const char* flag, const std::string& text, double* value) {
    if (!text.empty() && !compare::parse_finite(text, value)) {
      throw UsageError(std::string(flag) + ": not a finite number: " + shown(text));
    }
  };
  read("--grab-hz", f.grab_hz, &options.grab_spring.hz);
  read("--grab-ratio", f.grab_ratio, &options.grab_spring.damping_ratio);
  read("--grab-cap", f.grab_cap, &options.grab_spring.cap_weights);
  if (const auto problem = compare::grab_settings_problem(options.grab_spring)) {
    throw UsageError(compare::with_flag(*problem));
  }
  // the model's own limit on gravity
  if (!f.gravity.empty()) options.gravity = parse_vector("--gravity", f.gravity, 1e3);
  // drag decays exactly over a step (step_drag_rate): any rate is stable
  if (!f.air_drag.empty()) options.air_drag = parse_in("--air-drag", f.air_drag, 0.0, 1e9, " 1/s");
  if (!f.ground.empty()) options.ground = f.ground == "on";  // CLI11 checked it
  return options;
}

std::vector<SolverConfig> parse_solver_configs(const Flags& f) {
  SolverOptions options = f.options;  // CLI11 checked the ranges
  options.procedural.tremble = f.position_tremble;
  std::vector<procedural::Rule> rules;
  for (const auto& rule : expand("--rule", f.rule, all_rules())) {
    rules.push_back(*procedural::parse_rule(rule));  // expand() accepted only rule names
  }
  std::vector<std::string> all_engines;
  for (const compare::Engine& engine : compare::engines()) all_engines.emplace_back(engine.name);
  if (f.solver != "all") {
    const std::string missing =
        compare::unbuilt_engine_problem(expand("--solver", f.solver, all_engines));
    if (!missing.empty()) throw UsageError("--solver: " + missing);
  }
  return compare::solver_configs(expand("--solver", f.solver, compare::solver_names()), rules,
                                 options);
}

void apply_engine_verdicts(std::vector<SolverConfig>& configs, const Model& model, const Flags& f) {
  std::vector<std::string> refused, noted;
  std::vector<std::pair<std::string, std::string>> notes;  // a note, and the engines it is of
  const auto among = [](const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  // a procedural configuration is refused per rule (xpbd and tree hold what the others do not)
  const auto label_of = [](const SolverConfig& config) {
    const std::string rule = compare::rule_of(config);
    return rule.empty() ? config.solver : config.solver + " rule " + rule;
  };
  for (const SolverConfig& config : configs) {
    const std::string rule = compare::rule_of(config);
    const std::string label = label_of(config);
    if (among(refused, label)) continue;
    const std::string problem =
        compare::engine_model_problem(config.solver, model, config.options, f.engine_budget);
    if (problem.empty()) {
      // what it approximates, once per engine
      const std::string note = compare::engine_model_note(config.solver, model);
      if (!note.empty() && !among(noted, config.solver)) {
        noted.push_back(config.solver);
        auto same = std::find_if(notes.begin(), notes.end(),
                                 [&](const auto& n) { return n.first == note; });
        if (same == notes.end()) {
          notes.emplace_back(note, config.solver);
        } else {
          same->second += ", " + config.solver;
        }
      }
      continue;
    }
    if (!rule.empty() && f.rule != "all") {
      throw UsageError("--rule: " + rule + " cannot run " + shown(f.model) + ": " + problem);
    }
    if (rule.empty() && f.solver != "all") {
      throw UsageError("--solver: " + config.solver + " cannot run " + shown(f.model) + ": " +
                       problem);
    }
    print_error("testbed: ",
                "note: " + label + " left out, it cannot run " + shown(f.model) + ": " + problem);
    refused.push_back(label);
  }
  for (const auto& [note, engines] : notes) {
    print_error("testbed: ", "note: " + engines + ": " + note);
  }
  std::erase_if(configs, [&](const SolverConfig& c) { return among(refused, label_of(c)); });
}

}  // namespace puppet::testbed
