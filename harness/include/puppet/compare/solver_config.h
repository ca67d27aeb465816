// A solver and its options, as the studies sweep them, the CLI parses them and the benchmarks
// time them: one name for a configuration everywhere (docs/design.md, "Layout").
#pragma once

#include <span>
#include <string>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/procedural/rule.h"

namespace puppet::compare {

// a solver and its options (for procedural, the rule among them)
struct SolverConfig {
  std::string solver;
  SolverOptions options;
};
// the rule column of a configuration's rows: its rule's name for procedural, else empty
std::string rule_of(const SolverConfig& config);
// a configuration's one-word name: its rule's for procedural ("xpbd"), else its engine's
std::string config_label(const SolverConfig& config);
// the configurations of these solvers, in their order, all from `options`: an engine that runs
// the rules (has_rules) once per rule of `rules`, each other engine once
std::vector<SolverConfig> solver_configs(const std::vector<std::string>& solvers,
                                         std::span<const procedural::Rule> rules,
                                         const SolverOptions& options = {});

}  // namespace puppet::compare
