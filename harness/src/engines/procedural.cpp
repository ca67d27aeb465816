// The engine `procedural`: the seed's solver and its rules (procedural/), behind the Simulator
// interface, with its flags (--iterations, --substeps, --no-velocities; --rule picks the rules a
// sweep runs, flags.cpp).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/compare/number.h"
#include "puppet/compare/output.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/joint_springs.h"
#include "puppet/model/text.h"
#include "puppet/procedural/solver.h"

namespace puppet::compare {
namespace {

class ProceduralSnapshot : public Snapshot {
 public:
  explicit ProceduralSnapshot(const procedural::State& s) : state(s) {}
  procedural::State state;
};

class ProceduralSimulator : public Simulator {
 public:
  explicit ProceduralSimulator(const procedural::Settings& settings) : settings_(settings) {}

  std::string name() const override { return "procedural"; }
  std::string rule() const override { return std::string(procedural::rule_name(settings_.rule)); }
  int substeps() const override { return settings_.substeps; }

  void reset(const Model& model, const Scenario& scenario) override {
    procedural::Settings settings = settings_;
    settings.time_stages = time_stages_;
    solver_.reset();  // before the model it holds
    solver_.emplace(armature_in_inertia(model, own_model_), settings, scenario.environment);
    solver_->reset(scenario.initial);
    solver_->set_pins(scenario.initial_pins());
  }
  void set_pins(std::span<const Pin> pins) override { solver_->set_pins(pins); }
  void set_pin_targets(std::span<const Vector3d> targets) override {
    solver_->set_pin_targets(targets);
  }
  void step(double dt) override { solver_->step(dt); }
  void set_time(double time) override { solver_->set_time(time); }
  std::span<const Wrench> user_wrenches() const override { return solver_->user_wrenches(); }
  void read_state(std::span<BodyState> out) const override {
    const auto& bodies = solver_->state().bodies;
    std::copy(bodies.begin(), bodies.end(), out.begin());
  }
  void set_state(std::span<const BodyState> bodies) override { solver_->place(bodies); }
  std::unique_ptr<Snapshot> snapshot() const override {
    return std::make_unique<ProceduralSnapshot>(solver_->state());
  }
  void restore(const Snapshot& snapshot) override {
    solver_->restore(static_cast<const ProceduralSnapshot&>(snapshot).state);
  }
  bool diverged() const override { return solver_->state().diverged; }

  std::vector<std::string_view> stage_names() const override {
    return {procedural::kStageNames.begin(), procedural::kStageNames.end()};
  }
  void set_stage_timing(bool on) override { time_stages_ = on; }
  std::vector<double> stage_seconds() const override {
    const auto& s = solver_->stage_seconds();
    return {s.begin(), s.end()};
  }

 private:
  procedural::Settings settings_;
  bool time_stages_ = false;
  std::optional<Model> own_model_;  // the model with armature as inertia (joint_springs.h)
  std::optional<procedural::Solver> solver_;
};

procedural::Settings settings_from(const SolverOptions& options) {
  const procedural::Settings& settings = options.procedural;
  const std::string problem = procedural::validate(settings);
  if (!problem.empty()) throw ScenarioError(problem);
  return procedural::rule_defaults(settings);
}

std::unique_ptr<Simulator> make(const SolverOptions& options) {
  return std::make_unique<ProceduralSimulator>(settings_from(options));
}

// every valid model, as far as the engine goes: what a rule cannot step, it says itself
// (procedural::rule_model_problem, asked by engine_model_problem with the rule)
std::string model_problem(const Model&) { return {}; }

// what --iterations and --substeps mean to each rule, from the rule catalogue (rule_info):
// "relaxed, xpbd: two-sided sweeps per substep; tree: Newton iterations per substep (default:
// the rule's: relaxed 4, xpbd 1, tree 1)"
std::string iterations_help() {
  // the rules that read their iterations, grouped by what the iterations count
  std::vector<std::pair<std::string_view, std::string>> groups;  // meaning, rule names
  std::string defaults;
  for (const procedural::Rule rule : procedural::kAllRules) {
    const procedural::RuleInfo info = procedural::rule_info(rule);
    if (info.iterations_are.empty()) continue;
    defaults += (defaults.empty() ? "" : ", ") + std::string(info.name) + " " +
                std::to_string(info.iterations);
    auto group = std::find_if(groups.begin(), groups.end(),
                              [&](const auto& g) { return g.first == info.iterations_are; });
    if (group == groups.end()) group = groups.insert(groups.end(), {info.iterations_are, ""});
    group->second += (group->second.empty() ? "" : ", ") + std::string(info.name);
  }
  std::string meanings;
  for (const auto& [meaning, names] : groups) {
    meanings += (meanings.empty() ? "" : "; ") + names + ": " + std::string(meaning);
  }
  return meanings + "; the others make one pass (default: the rule's: " + defaults + ")";
}

void add_flags(CLI::App& command, SolverOptions& options) {
  command.add_option("--iterations", options.procedural.iterations, iterations_help())
      ->check(whole_number_check())
      ->check(CLI::Range(0, procedural::kMaxIterations));
  command.add_option("--substeps", options.procedural.substeps, procedural_substeps_help())
      ->check(whole_number_check())
      ->check(CLI::Range(1, procedural::kMaxSubsteps));
  command.add_flag_callback(
      "--no-velocities", [&options] { options.procedural.derive_velocities = false; },
      "procedural: do not derive velocities from poses");
  command.add_flag_callback(
      "--current-lever-arms", [&options] { options.procedural.start_lever_arms = false; },
      "xpbd: turn a correction through the lever arms of the pose being corrected "
      "(position-based dynamics' own), not the substep's start");
  command.add_flag_callback(
      "--limit-clamp", [&options] { options.procedural.limit_functions = false; },
      "xpbd: correct a ball's limits by the clamp's rotation (a box's per-angle clamp), not by "
      "its limit functions");
  command.add_flag_callback(
      "--joints-before-limits", [&options] { options.procedural.limits_before_joints = false; },
      "xpbd: correct every joint's point before every limit in a sweep");
  command.add_flag_callback(
      "--no-limit-pass", [&options] { options.procedural.limit_velocity_pass = false; },
      "xpbd, tree: leave out the limits' velocity pass (the rate a limit's correction "
      "leaves is kept)");
  command
      .add_option("--limit-restitution", options.procedural.limit_restitution,
                  "xpbd, tree: the rate a limit gives back over the one it came in "
                  "with (default 0)")
      ->check(finite_number_check())
      ->check(CLI::Range(0.0, 1.0));
}

void replay_flags(const SolverOptions& options, std::string& out) {
  const SolverOptions defaults;
  if (options.procedural.iterations != defaults.procedural.iterations) {
    out += " --iterations " + std::to_string(options.procedural.iterations);
  }
  if (options.procedural.substeps != defaults.procedural.substeps) {
    out += " --substeps " + std::to_string(options.procedural.substeps);
  }
  if (!options.procedural.derive_velocities) out += " --no-velocities";
  if (!options.procedural.start_lever_arms) out += " --current-lever-arms";
  if (!options.procedural.limit_functions) out += " --limit-clamp";
  if (!options.procedural.limits_before_joints) out += " --joints-before-limits";
  if (!options.procedural.limit_velocity_pass) out += " --no-limit-pass";
  if (options.procedural.limit_restitution != defaults.procedural.limit_restitution) {
    out += " --limit-restitution " + csv_number(options.procedural.limit_restitution);
  }
}

// the rule's own search (its row in the rule catalogue): its substeps or its sweeps
void search(const SolverOptions& base, std::vector<Setting>& out) {
  const procedural::RuleSearch grid = procedural::rule_info(base.procedural.rule).search;
  if (grid.knob == procedural::RuleKnob::kNone) return;
  const bool substeps = grid.knob == procedural::RuleKnob::kSubsteps;
  for (const int n : grid.values) {
    Setting s{(substeps ? "--substeps " : "--iterations ") + std::to_string(n),
              std::to_string(n) + " " + std::string(grid.noun) + (n == 1 ? "" : "s"), base};
    (substeps ? s.options.procedural.substeps : s.options.procedural.iterations) = n;
    out.push_back(std::move(s));
  }
}

// Every rule is linear in the segments per sweep and substep (1,600 limited links: about 10 ms a
// step for xpbd's eight substeps), and in the points where its shapes meet the ground. Figures
// folded onto the ground (bench_budget: chains of capsules, boxes and box-limited boxes, four rods
// of many boxes, Pinocchio and humanoid.xml, each let go curled and timed 1.5 s later;
// scripts/budget_table.py results/bench/budget.json --fit gives the terms, docs/reliability.md
// the ratios): at
// their own substeps and sweeps, xpbd takes 3.5 µs a segment and 1.6 µs a contact point, tree
// 6.6 µs, 1.3 µs and 0.25 µs a limit row (within 0.8–1.35×); the one-pass rules are estimated as
// xpbd's eight substeps, the most any rule's defaults make. Substeps given scale it.
double cost(const Model& model, const SolverOptions& options) {
  const ModelSize n = model_size(model);
  const procedural::RuleInfo info = procedural::rule_info(options.procedural.rule);
  const bool tree = options.procedural.rule == procedural::Rule::kTree;
  const double step = tree
                          ? 6.6e-6 * n.segments + 1.3e-6 * n.contact_points + 0.25e-6 * n.limit_rows
                          : 3.5e-6 * n.segments + 1.6e-6 * n.contact_points;
  const int substeps =
      options.procedural.substeps > 0 ? options.procedural.substeps : std::max(info.substeps, 8);
  return step * substeps / std::max(info.substeps, 8) / kBudgetDt;
}

}  // namespace

std::string procedural_substeps_help() {
  std::string defaults;
  for (const procedural::Rule rule : procedural::kAllRules) {
    const procedural::RuleInfo info = procedural::rule_info(rule);
    if (info.substeps == 1) continue;
    defaults += std::string(info.name) + " " + std::to_string(info.substeps) + ", ";
  }
  return "procedural substeps per step (default: the rule's: " + defaults + "the others 1)";
}

procedural::Settings procedural_settings(const SolverOptions& options) {
  return settings_from(options);
}

Engine procedural_engine() {
  return {.name = kProceduralEngine,
          .summary = "the seed's update/adjust solver and its rules (--rule)",
          .constraints =
              "its rule's adjust pass moves the segments so the joints meet; limits "
              "are projected hard, contacts pushed out (docs/solver.md)",
          .has_rules = true,
          .model_problem = model_problem,
          .second_cost = cost,
          .make = make,
          .add_flags = add_flags,
          .replay_flags = replay_flags,
          .search = search};
}

}  // namespace puppet::compare
