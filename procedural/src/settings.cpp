// The settings' ranges and defaults (each rule's own are its row in rules/catalogue.cpp).
#include <string>

#include "puppet/procedural/settings.h"

namespace puppet::procedural {

std::optional<Rule> parse_rule(std::string_view name) {
  for (Rule rule : kAllRules) {
    if (rule_name(rule) == name) return rule;
  }
  return std::nullopt;
}

std::string validate(const Settings& settings) {
  if (settings.iterations != kRuleDefault &&
      (settings.iterations < 0 || settings.iterations > kMaxIterations))
    return "iterations must be in [0, 1000]";
  if (settings.substeps != kRuleDefault &&
      (settings.substeps < 1 || settings.substeps > kMaxSubsteps))
    return "substeps must be in [1, 1000]";
  if (!(settings.joint_compliance >= 0.0 && settings.joint_compliance <= kMaxCompliance))
    return "joint compliance must be in [0, 1e6] m/N";
  if (!(settings.limit_compliance >= 0.0 && settings.limit_compliance <= kMaxCompliance))
    return "limit compliance must be in [0, 1e6] rad/(N m)";
  if (!(settings.limit_restitution >= 0.0 && settings.limit_restitution <= 1.0))
    return "limit restitution must be in [0, 1]";
  return {};
}

Settings rule_defaults(Settings settings) {
  const RuleInfo rule = rule_info(settings.rule);
  if (settings.iterations == kRuleDefault) settings.iterations = rule.iterations;
  if (settings.substeps == kRuleDefault) settings.substeps = rule.substeps;
  return settings;
}

}  // namespace puppet::procedural
