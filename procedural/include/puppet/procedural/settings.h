/// \file
/// What a procedural solver is told once, at construction (Jolt's settings structs): the rule and
/// its iteration counts, compliances and switches.
#pragma once

#include <cstdint>
#include <string>

#include "puppet/procedural/rule.h"

namespace puppet::procedural {

/// iterations or substeps left at this value take the rule's own (rule_defaults())
constexpr int kRuleDefault = -1;
/// xpbd's substeps per step unless told (chosen by measurement: docs/solver.md, the substep sweep)
constexpr int kXpbdSubsteps = 8;
/// tree's substeps and Newton iterations per substep unless told (chosen by measurement)
constexpr int kTreeSubsteps = 8;
constexpr int kTreeIterations = 1;
/// the ranges validate() accepts
constexpr int kMaxIterations = 1000;
constexpr int kMaxSubsteps = 1000;
constexpr double kMaxCompliance = 1e6;

struct Settings {
  Rule rule = Rule::kXpbd;  ///< the verdict's pick (docs/verdict.md); the seed's own: relaxed
  /// two-sided sweeps per substep (relaxed: 4, xpbd: 1); tree: Newton iterations per substep
  int iterations = kRuleDefault;
  int substeps = kRuleDefault;  ///< each step(dt) runs this many stages of dt/substeps (xpbd: 8)
  /// xpbd and tree: compliance of the joints' point constraints (m/N) and of their limits
  /// (rad/(N·m)); 0 is rigid, as every model joint is. A pin's compliance is the pin's own
  /// (Pin::compliance).
  double joint_compliance = 0.0;
  double limit_compliance = 0.0;
  bool derive_velocities = true;  ///< v, ω from the corrected poses (the seed is silent)
  /// xpbd: a pin's or joint's correction turns each segment through its lever arm and
  /// inverse inertia at the substep's start (SHAKE's constraint direction), not at the pose being
  /// corrected (docs/solver.md, "The lever arms")
  bool start_lever_arms = true;
  /// xpbd: a ball's limits corrected as its limit functions, together along their gradients
  /// (false: the clamp's rotation, a box's per-angle clamp; docs/solver.md, "the limits")
  bool limit_functions = true;
  /// xpbd: in a sweep every limit before every joint's point (false: the joints first)
  bool limits_before_joints = true;
  /// xpbd, tree: after the velocities are derived, every limit the step ran into gets
  /// the rate its restitution asks (docs/solver.md, "The limits' velocity pass")
  bool limit_velocity_pass = true;
  /// the limits' restitution e in [0, 1]: the rate a limit gives back, over the one it came in
  /// with (0, as both truths nearly are: they give back 1–2 %). Above 0 a crowd steps its
  /// puppets one by one (the lanes keep no rate from before the position pass)
  double limit_restitution = 0.0;
  bool tremble = false;      ///< the seed's active response (§3.4)
  bool time_stages = false;  ///< measure each stage's wall time (costs a few clock reads)
  uint64_t tremble_seed = 2001;
};

/// empty when valid, else what is wrong ("iterations must be in [0, 1000]")
std::string validate(const Settings& settings);
/// the settings with every kRuleDefault replaced by the rule's own value
Settings rule_defaults(Settings settings);

}  // namespace puppet::procedural
