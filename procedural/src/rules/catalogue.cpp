// The rule catalogue (catalogue.h): one row per rule, in rule.h's order.
#include "catalogue.h"

#include <cassert>
#include <vector>

#include "rules.h"

namespace puppet::procedural {
namespace {

constexpr std::string_view kSweeps = "two-sided sweeps per substep";
constexpr std::string_view kNewton = "Newton iterations per substep";
constexpr std::string_view kNone = "";  // one pass: iterations are not read

// What a verdict searches besides dt (docs/verdict.md): the counts that trade cost for accuracy.
// xpbd's substeps from one to twice its default, tree's to its default (its error is the
// substep's, its joints closed at any count), relaxed's sweeps at its default and four times it.
constexpr int kXpbdSearch[] = {1, 2, 4, 8, 16};
constexpr int kTreeSearch[] = {1, 2, 4, 8};
constexpr int kRelaxedSearch[] = {4, 16};
constexpr RuleSearch kOnePass{};  // dt is all there is to choose

// The contact policies (contacts.cpp):
// - a one-sided rule's contact move may reopen joints, so it re-runs its pass from the segment
//   that hit deepest (kPushOutAndRepass);
// - relaxed has resolved contacts inside its sweeps; re-anchoring its final pass at a foot made
//   the whole body swing on the ankle's limit (measured: 100 m/s in `drop`), so what its
//   push-out leaves open is reported as joint gap instead (kPushOut);
// - xpbd and tree hold the ground as a constraint of their own solve (kInAdjust).
// The one-sided rules make one pass and read no iterations; their 4 is relaxed's, kept so that
// a configuration reads the same whichever rule it names.
// How the one-sided rules read the pass (OneSidedReading): the forced rotation, with literal's
// translation bound, weighted's constant gain, or subtree's walk over whole subtrees (a pin's
// segment alone closed by weighted's gain). The rules that solve at once read none of it.
constexpr OneSidedReading kForcedRotation{.constant_gain = false,
                                          .translation_bound = false,
                                          .lone_segment = std::nullopt,
                                          .walk = nullptr};
constexpr OneSidedReading kTranslationBound{.constant_gain = false,
                                            .translation_bound = true,
                                            .lone_segment = std::nullopt,
                                            .walk = nullptr};
constexpr OneSidedReading kConstantGain{.constant_gain = true,
                                        .translation_bound = false,
                                        .lone_segment = std::nullopt,
                                        .walk = nullptr};
constexpr OneSidedReading kSubtrees{.constant_gain = false,
                                    .translation_bound = false,
                                    .lone_segment = Rule::kWeighted,
                                    .walk = subtree_pass};

const RuleRow kRows[] = {
    {.rule = Rule::kLiteral,
     .info = {.name = "literal",
              .iterations = 4,
              .substeps = 1,
              .iterations_are = kNone,
              .search = kOnePass,
              .lanes = false,
              .grab_anchors = true,
              .seed = true},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = literal_forced_rotation,
     .prepare_joint = literal_prepare_joint,
     .limit_velocities = false,
     .one_sided = kTranslationBound,
     .closing_pass = std::nullopt},
    {.rule = Rule::kSmoothed,
     .info = {.name = "smoothed",
              .iterations = 4,
              .substeps = 1,
              .iterations_are = kNone,
              .search = kOnePass,
              .lanes = false,
              .grab_anchors = false,
              .seed = true},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = smoothed_forced_rotation,
     .prepare_joint = nullptr,
     .limit_velocities = false,
     .one_sided = kForcedRotation,
     .closing_pass = std::nullopt},
    {.rule = Rule::kWeighted,
     .info = {.name = "weighted",
              .iterations = 4,
              .substeps = 1,
              .iterations_are = kNone,
              .search = kOnePass,
              .lanes = false,
              .grab_anchors = false,
              .seed = true},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = weighted_prepare_joint,
     .limit_velocities = false,
     .one_sided = kConstantGain,
     .closing_pass = std::nullopt},
    // subtree: the weighted reading over whole subtrees; a pin's segment alone is weighted's
    {.rule = Rule::kSubtree,
     .info = {.name = "subtree",
              .iterations = 4,
              .substeps = 1,
              .iterations_are = kNone,
              .search = kOnePass,
              .lanes = false,
              .grab_anchors = false,
              .seed = true},
     .contacts = ContactPolicy::kPushOutAndRepass,
     .adjust = one_sided_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr,
     .limit_velocities = false,
     .one_sided = kSubtrees,
     .closing_pass = std::nullopt},
    // relaxed: the four sweeps of one step that the seed's pass (weighted's reading) then closes
    {.rule = Rule::kRelaxed,
     .info = {.name = "relaxed",
              .iterations = 4,
              .substeps = 1,
              .iterations_are = kSweeps,
              .search = {RuleKnob::kIterations, kRelaxedSearch, "sweep"},
              .lanes = false,
              .grab_anchors = false,
              .seed = true},
     .contacts = ContactPolicy::kPushOut,
     .adjust = relaxed_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr,
     .limit_velocities = false,
     .one_sided = kForcedRotation,
     .closing_pass = Rule::kWeighted},
    // xpbd: many short substeps of one sweep each (Müller et al. 2020), the count chosen by
    // measurement (docs/solver.md: the substep sweep)
    {.rule = Rule::kXpbd,
     .info = {.name = "xpbd",
              .iterations = 1,
              .substeps = kXpbdSubsteps,
              .iterations_are = kSweeps,
              .search = {RuleKnob::kSubsteps, kXpbdSearch, "substep"},
              .lanes = true,
              .grab_anchors = false},
     .contacts = ContactPolicy::kInAdjust,
     .adjust = xpbd_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr,
     .limit_velocities = true,
     .one_sided = kForcedRotation,
     .closing_pass = std::nullopt},
    // tree: a few substeps of a few Newton iterations of the exact projection
    {.rule = Rule::kTree,
     .info = {.name = "tree",
              .iterations = kTreeIterations,
              .substeps = kTreeSubsteps,
              .iterations_are = kNewton,
              .search = {RuleKnob::kSubsteps, kTreeSearch, "substep"},
              .lanes = false,
              .grab_anchors = false},
     .contacts = ContactPolicy::kInAdjust,
     .adjust = tree_adjust,
     .forced_rotation = weighted_forced_rotation,
     .prepare_joint = nullptr,
     .limit_velocities = true,
     .one_sided = kForcedRotation,
     .closing_pass = std::nullopt},
};
static_assert(std::size(kRows) == kAllRules.size(), "one row per rule");

}  // namespace

std::span<const RuleRow> rule_rows() { return kRows; }

std::span<const PrepareJointFn> joint_preparers() {
  // every rule's prepare_joint, in the rows' order (a rule with none keeps nothing per joint)
  static const std::vector<PrepareJointFn> prepare = [] {
    std::vector<PrepareJointFn> out;
    for (const RuleRow& row : kRows) {
      if (row.prepare_joint) out.push_back(row.prepare_joint);
    }
    return out;
  }();
  return prepare;
}

const RuleRow& rule_row(Rule rule) {
  const RuleRow& row = kRows[static_cast<int>(rule)];
  assert(row.rule == rule);  // rows in the enum's order (RuleCatalogue test)
  return row;
}

RuleInfo rule_info(Rule rule) { return rule_row(rule).info; }

std::string_view rule_name(Rule rule) { return rule_row(rule).info.name; }

}  // namespace puppet::procedural
