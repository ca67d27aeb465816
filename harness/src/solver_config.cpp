#include "puppet/compare/solver_config.h"

namespace puppet::compare {

std::string rule_of(const SolverConfig& config) {
  return has_rules(config.solver)
             ? std::string(procedural::rule_name(config.options.procedural.rule))
             : std::string();
}

std::string config_label(const SolverConfig& config) {
  return has_rules(config.solver) ? rule_of(config) : config.solver;
}

std::vector<SolverConfig> solver_configs(const std::vector<std::string>& solvers,
                                         std::span<const procedural::Rule> rules,
                                         const SolverOptions& options) {
  std::vector<SolverConfig> out;
  for (const std::string& solver : solvers) {
    if (!has_rules(solver)) {
      out.push_back({solver, options});
      continue;
    }
    for (const procedural::Rule rule : rules) {
      out.push_back({solver, options});
      out.back().options.procedural.rule = rule;
    }
  }
  return out;
}

}  // namespace puppet::compare
