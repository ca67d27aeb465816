/// \file
/// The adjust rules: how a joint's gap is split between the moved segment's rotation and its
/// translation (docs/solver.md, "The rules"). The first five are the seed's readings; `xpbd` is
/// the position-based family's substepped two-sided solver and `tree` the same projection solved
/// exactly on the tree. Each has its own source file in procedural/src/rules/.
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace puppet::procedural {

enum class Rule { kLiteral, kSmoothed, kWeighted, kSubtree, kRelaxed, kXpbd, kTree };
inline constexpr std::array kAllRules = {Rule::kLiteral, Rule::kSmoothed, Rule::kWeighted,
                                         Rule::kSubtree, Rule::kRelaxed,  Rule::kXpbd,
                                         Rule::kTree};

/// the rule's name as the command lines and CSVs spell it ("literal", …, "tree")
std::string_view rule_name(Rule rule);
/// the rule of that name; nullopt for any other text
std::optional<Rule> parse_rule(std::string_view name);

}  // namespace puppet::procedural
