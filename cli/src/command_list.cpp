// testbed list: the names every other command accepts; with --json, every catalogue the scripts
// that read the testbed's CSVs need (scenarios, engines, rules, stages, truths, metrics, the
// summary's columns and how a trace's file is named), so that no script keeps a copy.
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "puppet/compare/engines.h"
#include "puppet/compare/frontier.h"
#include "puppet/compare/output.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/summary_metrics.h"
#include "puppet/compare/sweep.h"
#include "puppet/compare/verdict.h"
#include "puppet/procedural/rule.h"
#include "puppet/procedural/solver.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

int list_text() {
  std::cout << "scenarios:";
  for (const auto& s : scenario_names()) std::cout << ' ' << s;
  std::cout << "\nsolvers:  ";
  for (const auto& s : solver_names()) std::cout << ' ' << s;
  for (const Engine& engine : engines()) {
    if (!engine.built) {
      std::cout << "\n           not built: " << engine.name << " ("
                << (engine.missing ? engine.missing() : std::string()) << ")";
    }
  }
  std::cout << "\nrules:    ";
  for (auto rule : procedural::kAllRules) std::cout << ' ' << procedural::rule_name(rule);
  std::cout << " (procedural only; default "
            << procedural::rule_name(SolverOptions{}.procedural.rule) << ")\nmodels:    pinocchio ("
            << builtin_model_path() << "), chain:N, or any model file\n";
  return 0;
}

int list_json() {
  nlohmann::ordered_json out;
  out["scenarios"] = scenario_names();
  out["headline_scenario"] = headline_scenario();
  for (const std::string& name : scenario_names()) out["scenario_asks"][name] = scenario_asks(name);
  // the scenes the verdict judges by their violations, first impact and outcomes (contact.csv)
  out["contact_scenarios"] = nlohmann::ordered_json::array();
  for (const std::string& name : scenario_names()) {
    if (judged_by_contact(name)) out["contact_scenarios"].push_back(name);
  }
  out["frontier_scenario"] = kFrontierScenario;
  auto& engines_out = out["engines"] = nlohmann::ordered_json::array();
  for (const Engine& engine : engines()) {
    engines_out.push_back({{"name", engine.name},
                           {"summary", engine.summary},
                           {"constraints", engine.constraints},
                           {"built", engine.built},
                           {"missing", engine.built || !engine.missing ? "" : engine.missing()},
                           {"native", engine.native},
                           {"rules", engine.has_rules}});
  }
  auto& rules = out["rules"] = nlohmann::ordered_json::array();
  for (const procedural::Rule rule : procedural::kAllRules) {
    const procedural::RuleInfo info = procedural::rule_info(rule);
    rules.push_back({{"name", info.name},
                     {"iterations", info.iterations},
                     {"substeps", info.substeps},
                     {"iterations_are", info.iterations_are},
                     {"lanes", info.lanes},
                     {"seed", info.seed}});
  }
  out["default_rule"] = procedural::rule_name(SolverOptions{}.procedural.rule);
  // what a verdict searches for each configuration besides dt: the flags candidates.csv names a
  // setting by, and the words tables show for it
  auto& search = out["verdict_search"] = nlohmann::ordered_json::array();
  for (const SolverConfig& config : solver_configs(solver_names(), procedural::kAllRules)) {
    nlohmann::ordered_json settings = nlohmann::ordered_json::array();
    for (const Setting& s : settings_searched(config.solver, config.options)) {
      settings.push_back({{"flags", s.flags}, {"label", s.label}});
    }
    search.push_back(
        {{"solver", config.solver}, {"rule", rule_of(config)}, {"settings", settings}});
  }
  out["stages"] = procedural::kStageNames;
  // the references an accuracy row may name: the truths in the order a model gets them when
  // both can run it (sweep.h's truths_for), then the pairwise comparison
  out["truths"] = {{{"reference", kTruthReference},
                    {"solver", kMujocoTruthSolver},
                    {"text", kMujocoTruthText},
                    {"refined", kMujocoTruthRefined},
                    {"dt", kMujocoTruthDt}},
                   {{"reference", kSecondTruthReference},
                    {"solver", kBulletTruthSolver},
                    {"text", kBulletTruthText},
                    {"refined", kBulletTruthRefined},
                    {"dt", kBulletTruthDt}}};
  out["pairwise"] = {{"reference", kPairwiseReference}, {"solver", kPairwiseSolver}};
  auto& metrics = out["metrics"] = nlohmann::ordered_json::array();
  for (const MetricInfo& m : summary_metrics()) {
    metrics.push_back({{"name", m.name}, {"unit", m.unit}, {"meaning", m.meaning}});
  }
  auto& stats = out["stats"] = nlohmann::ordered_json::array();
  for (const StatInfo& s : summary_stats()) {
    stats.push_back({{"name", s.name}, {"meaning", s.meaning}});
  }
  out["summary_header"] = kSummaryHeader;
  // every other CSV the commands write, by file name: its header
  // the values a column may hold, by file and column
  std::vector<std::string> verdicts;
  for (const Verdict v : kAllVerdicts) {
    verdicts.emplace_back(verdict_name(v));
  }
  verdicts.emplace_back(kRefused);
  out["values"] = {
      {"summary.csv", {{"status", {kStatusOk, kStatusDiverged}}}},
      {"candidates.csv", {{"status", {kCandidateOk, kCandidateDiverged, kCandidateNotTimed}}}},
      {"verdict.csv", {{"verdict", verdicts}, {"view", {kViewSecond, kViewFrame}}}},
      {"frontier.csv", {{"quantity", {kQuantityHz, kQuantityDt}}}}};
  out["tables"] = {{"frontier.csv", kFrontierHeader},
                   {"candidates.csv", kCandidatesHeader},
                   {"verdict.csv", kVerdictHeader},
                   {"contact.csv", kContactHeader},
                   {"robustness.csv", kRobustnessHeader},
                   {"robustness_summary.csv", kRobustnessSummaryHeader},
                   {"worst.csv", kWorstHeader},
                   {"trace", kTraceHeader},
                   {"poses", kPosesHeader}};
  // traces/<stem>.csv and <stem>__poses.csv: each name's characters outside the safe set become
  // the replacement, a run without a rule has the no-rule mark, dt as summary.csv writes it
  out["trace"] = {{"stem", "{model}__{scenario}__{solver}__{rule}__{dt}"},
                  {"no_rule", "-"},
                  {"safe_characters", "A-Za-z0-9._-"},
                  {"replacement", "-"},
                  {"poses_suffix", "__poses"}};
  std::cout << out.dump(1) << '\n';
  return 0;
}

}  // namespace

Command add_list_command(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* command = app.add_subcommand("list", "list scenarios, solvers, rules and models");
  command->add_flag("--json", *json,
                    "every catalogue as JSON: scenarios, engines, rules, stages, truths, metrics, "
                    "the summary's columns and the traces' file names (the scripts read it)");
  return {command, [json] { return *json ? list_json() : list_text(); }};
}

}  // namespace puppet::testbed
