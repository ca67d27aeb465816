// The rule catalogue (catalogue.h): one row per rule, in rule.h's order.
#include "catalogue.h"

#include <cassert>

#include "rules.h"

namespace puppet::procedural {
namespace {

constexpr std::string_view kSweeps = "two-sided sweeps per substep";
constexpr std::string_view kNewton = "Newton iterations per substep";
constexpr std::string_view kNone = "";  // one pass: iterations are not read

// The contact policies (contacts.cpp):
// - a one-sided rule's contact move may reopen joints, so it re-runs its pass from the segment
//   that hit deepest (kPushOutAndRepass);
// - relaxed has resolved contacts inside its sweeps; re-anchoring its final pass at a foot made
//   the whole body swing on the ankle's limit (measured: 100 m/s in `drop`), so what its
//   push-out leaves open is reported as joint gap instead (kPushOut);
// - xpbd and tree hold the ground as a constraint of their own solve (kInAdjust).
// The one-sided rules make one pass and read no iterations; their 4 is relaxed's, kept so that
// a configuration reads the same whichever rule it names.
const RuleRow kRows[] = {
    {.rule = Rule::kLiteral,
     .info = {.name = "literal", .iterations = 4, .substeps = 1, .iterations_are = kNone},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = literal_forced_rotation,
     .prepare_joint = literal_prepare_joint},
    {.rule = Rule::kSmoothed,
     .info = {.name = "smoothed", .iterations = 4, .substeps = 1, .iterations_are = kNone},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = smoothed_forced_rotation,
     .prepare_joint = nullptr},
    {.rule = Rule::kWeighted,
     .info = {.name = "weighted", .iterations = 4, .substeps = 1, .iterations_are = kNone},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = weighted_prepare_joint},
    {.rule = Rule::kSubtree,
     .info = {.name = "subtree", .iterations = 4, .substeps = 1, .iterations_are = kNone},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr},
    // relaxed: the four sweeps of one step that the seed's pass then closes
    {.rule = Rule::kRelaxed,
     .info = {.name = "relaxed", .iterations = 4, .substeps = 1, .iterations_are = kSweeps},
     .contacts = ContactPolicy::kPushOut,
     .adjust = relaxed_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr},
    // xpbd: many short substeps of one sweep each (Müller et al. 2020), the count chosen by
    // measurement (docs/solver.md: the substep sweep)
    {.rule = Rule::kXpbd,
     .info =
         {.name = "xpbd", .iterations = 1, .substeps = kXpbdSubsteps, .iterations_are = kSweeps},
     .contacts = ContactPolicy::kInAdjust,
     .adjust = xpbd_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr},
    // tree: a few substeps of a few Newton iterations of the exact projection
    {.rule = Rule::kTree,
     .info = {.name = "tree",
              .iterations = kTreeIterations,
              .substeps = kTreeSubsteps,
              .iterations_are = kNewton},
     .contacts = ContactPolicy::kInAdjust,
     .adjust = tree_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr},
};
static_assert(std::size(kRows) == kAllRules.size(), "one row per rule");

}  // namespace

std::span<const RuleRow> rule_rows() { return kRows; }

const RuleRow& rule_row(Rule rule) {
  const RuleRow& row = kRows[static_cast<int>(rule)];
  assert(row.rule == rule);  // rows in the enum's order (RuleCatalogue test)
  return row;
}

RuleInfo rule_info(Rule rule) { return rule_row(rule).info; }

std::string_view rule_name(Rule rule) { return rule_row(rule).info.name; }

}  // namespace puppet::procedural
