// The rule catalogue: one row per rule (rule.h's enum), holding everything the stages ask of a
// rule, so that no stage switches on the rule (Box2D's joint function tables). Private to
// procedural/; rule_info() gives its public part.
//
// A rule is its file (rules/<rule>.cpp, declared in rules.h), its row here (catalogue.cpp), its
// enum value in rule.h, its CMake line and its test.
#pragma once

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
};

const RuleRow& rule_row(Rule rule);
// every row, in rule.h's order
std::span<const RuleRow> rule_rows();
// the rows' prepare_joint (those that have one), in their order: what make_model_tables fills
// each joint's terms with
std::span<const PrepareJointFn> joint_preparers();

}  // namespace puppet::procedural
