/// \file
/// The adjust rules: how a joint's gap is split between the moved segment's rotation and its
/// translation (docs/solver.md, "The rules"). The first five are the seed's readings; `xpbd` is
/// the position-based family's substepped two-sided solver and `tree` the same projection solved
/// exactly on the tree. Each has its own source file in procedural/src/rules/.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string_view>

namespace puppet::procedural {

enum class Rule { kLiteral, kSmoothed, kWeighted, kSubtree, kRelaxed, kXpbd, kTree };
inline constexpr std::array kAllRules = {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted,
                                         Rule::kSubtree, Rule::kRelaxed,  Rule::kXpbd,
                                         Rule::kTree};

/// what a verdict (`testbed verdict`) searches for a rule besides dt: one of its counts over
/// `values`, each a noun's worth ("8 substeps"); nothing for a rule that makes one pass
enum class RuleKnob { kNone, kSubsteps, kIterations };
struct RuleSearch {
  RuleKnob knob = RuleKnob::kNone;
  std::span<const int> values;
  std::string_view noun;  ///< one of what the values count ("substep", "sweep")
};

/// what a rule is, as its row in the rule catalogue says (procedural/src/rules/catalogue.cpp)
struct RuleInfo {
  std::string_view name;  ///< as the command lines and CSVs spell it ("literal", …, "tree")
  int iterations = 1;     ///< its iterations per substep unless told
  int substeps = 1;       ///< its substeps per step unless told
  /// what its iterations count ("two-sided sweeps per substep"); empty when it reads none
  std::string_view iterations_are;
  RuleSearch search;   ///< what a verdict searches for it besides dt
  bool lanes = false;  ///< a Crowd steps it in SIMD lanes (CrowdLanes); else one by one
  /// a user's grab anchors its pass (the viewer's `auto` anchor): the seed's way, which only a
  /// rule that closes a joint by translating alone survives (docs/viewer.md)
  bool grab_anchors = false;
  /// one of the seed's readings of its adjust (literal, smoothed, weighted, subtree, relaxed);
  /// xpbd and tree are the best of the family it belongs to
  bool seed = false;
};
RuleInfo rule_info(Rule rule);

/// the rule's name as the command lines and CSVs spell it ("literal", …, "tree")
std::string_view rule_name(Rule rule);
/// the rule of that name; nullopt for any other text
std::optional<Rule> parse_rule(std::string_view name);

}  // namespace puppet::procedural
