// The rules' names and the settings' ranges and defaults.
#include <string>

#include "puppet/procedural/settings.h"

namespace puppet::procedural {

std::string_view rule_name(Rule rule) {
  switch (rule) {
    case Rule::kLiteral:
      return "literal";
    case Rule::kSmoothed:
      return "smoothed";
    case Rule::kWeighted:
      return "weighted";
    case Rule::kSubtree:
      return "subtree";
    case Rule::kRelaxed:
      return "relaxed";
    case Rule::kXpbd:
      return "xpbd";
    case Rule::kTree:
      return "tree";
  }
  return "?";
}

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
  return {};
}

Settings rule_defaults(Settings settings) {
  // xpbd: many short substeps of one sweep each (Müller et al. 2020), the count chosen by
  // measurement (docs: the substep sweep); relaxed: the four sweeps of one step the seed's pass
  // closes; the other rules make one pass and read no iterations
  // tree: a few substeps of a few Newton iterations of the exact projection
  int iterations = 4, substeps = 1;
  if (settings.rule == Rule::kXpbd) {
    iterations = 1;
    substeps = kXpbdSubsteps;
  } else if (settings.rule == Rule::kTree) {
    iterations = kTreeIterations;
    substeps = kTreeSubsteps;
  }
  if (settings.iterations == kRuleDefault) settings.iterations = iterations;
  if (settings.substeps == kRuleDefault) settings.substeps = substeps;
  return settings;
}

}  // namespace puppet::procedural
