// The rule catalogue: one row per rule (rule.h's enum), holding everything the stages ask of a
// rule, so that no stage switches on the rule (Box2D's joint function tables). Private to
// procedural/; rule_info() gives its public part.
//
// A rule is its file (rules/<rule>.cpp, declared in rules.h), its row here (catalogue.cpp), its
// enum value in rule.h, its CMake line and its test.
#pragma once

#include <optional>
#include <span>

#include "../stages.h"

namespace puppet::procedural {

// the rule's position pass over one substep of length h, from the anchor's order
using AdjustFn = void (*)(const Model& model, std::span<const JointTerms> joints,
                          const Settings& settings, const Environment& environment,
                          const AnchorOrder& order, const PinTargets& targets, State& state,
                          Workspace& ws, double h);
// the rotation R that a one-sided closure of point r (from the body's centre) by the gap s
// turns the body by, given r × s and |r × s|² ≥ kParallel² (eq. 5 then closes the gap)
using ForcedRotationFn = Quaterniond (*)(const MovingBody& body, const Vector3d& r,
                                         const Vector3d& s, const Vector3d& cross,
                                         double cross_norm2);

// a walk from the anchor that replaces the one-sided pass's own walk over single segments (rule
// subtree's, which moves whole subtrees)
using OneSidedWalkFn = void (*)(const Model& model, std::span<const JointTerms> joints,
                                const AnchorOrder& order, bool pinned, const PinTargets& targets,
                                State& state, Workspace& ws);

// How a rule made of the one-sided pass reads it (one_sided_pass.cpp): the pass asks these, never
// the rule's name
struct OneSidedReading {
  // a single segment (a link's far side, a pinned segment) is closed by the constant gain of its
  // point (JointTerms::rotation_gain, close_segment_point) instead of the forced rotation
  bool constant_gain = false;
  // a link whose closing turn would fall below its side's bound (JointTerms::literal_still_cross2)
  // is a pure translation, decided without the rotation
  bool translation_bound = false;
  // the rule whose reading closes a segment alone (the pins after the first): the rule itself
  // when empty
  std::optional<Rule> lone_segment;
  // replaces the walk over single segments; null: the pass's own
  OneSidedWalkFn walk = nullptr;
};

struct RuleRow {
  Rule rule;
  RuleInfo info;
  ContactPolicy contacts;
  AdjustFn adjust;
  ForcedRotationFn forced_rotation;
  PrepareJointFn prepare_joint = nullptr;  // null: the rule keeps nothing per joint
  // its velocities come from its positions, so a limit's correction leaves a rate that the
  // limits' velocity pass must set (limit_velocities.cpp); the one-sided rules' clamp leaves none
  bool limit_velocities = false;
  OneSidedReading one_sided;
  // a rule whose own adjust ends with a one-sided pass (relaxed's sweeps, then a closing pass):
  // the rule whose reading that pass takes; empty: none
  std::optional<Rule> closing_pass;
};

const RuleRow& rule_row(Rule rule);
// every row, in rule.h's order
std::span<const RuleRow> rule_rows();
// the rows' prepare_joint (those that have one), in their order: what make_model_tables fills
// each joint's terms with
std::span<const PrepareJointFn> joint_preparers();

}  // namespace puppet::procedural
