// A joint's constant terms (the model tables' per-joint part): what its limits' tests, the
// shared corrections and each rule read of a joint without recomputing it. Private to
// procedural/.
#pragma once

#include <array>

#include "puppet/model/model.h"

namespace puppet::procedural {

// A ball's Euler box as a test that needs no trigonometry (joint_limits.cpp, surely_inside_box):
// each angle's range as the cosines and sines of its ends
struct BoxTest {
  bool enabled = false;  // an Euler box whose ranges contain 0, the middle one within ±85°
  std::array<int, 3> axes{0, 1, 2};
  double sign = 1.0;  // +1 for a cyclic order (xyz, yzx, zxy), −1 for the others
  std::array<double, 3> lower_cos{}, lower_sin{}, upper_cos{}, upper_sin{};
  std::array<bool, 3> wide{};  // the range is wider than a half turn
};

// What the corrections read of one joint. A segment's inertia is diagonal and constant in its own
// frame, and so is its joint point, so everything here is too: [0] is the parent's side, [1] the
// child's (index by b_is_child).
struct JointTerms {
  // cos(ρ/2) for the largest angle ρ that no limit of the joint can reach (limit_free_w())
  double limit_free_w = 2.0;
  // an Euler box's ranges, to tell a rotation surely inside without its angles (make_box_test())
  BoxTest box;
  // Fc ⊗ Fp⁻¹, the joint's frame in the child carried into the parent's: w is unchanged by
  // conjugation, so w(q_rel) = w(Fp⁻¹ q_p⁻¹ q_c Fc) = q_p · (q_c ⊗ frame_shift), a 4-D dot product
  // that tells a joint surely inside its limits without forming q_rel
  Quaterniond frame_shift = Quaterniond::Identity();
  // K = E/m − [r]× D⁻¹ [r]× of the joint point, r its offset from the segment's centre:
  // relaxed's shared corrections add the two sides' K in one frame
  std::array<Matrix3d, 2> point_mass;
  // each side's inverse inertia (diagonal, its frame): the metric a limit's shared correction is
  // the smallest in (limit_error)
  std::array<Vector3d, 2> inv_inertia;
  // the weighted rule's rotation vector of that side per unit gap, both in its frame:
  // D⁻¹ [r]× K⁻¹ (the minimum-energy correction of the gap, made a constant matrix)
  std::array<Matrix3d, 2> rotation_gain;
  // the literal rule: |r × s|² below which moving that side closes the joint by translation alone
  // (literal_still_cross(), squared; at least the parallel threshold)
  std::array<double, 2> literal_still_cross2{0.0, 0.0};
};

// Everything the solver reads that depends on the model alone, built once. Solvers of one model
// (a crowd's puppets) share one table instead of each holding a copy.
// Every anchor's order is kept for models of up to kKeptOrderSegments segments (O(n²) memory:
// 0.9 MB for 128); a larger model keeps none, and each solver fills the orders it needs into its
// workspace when its anchor changes (O(n) each, see anchor_order()).

// what a rule keeps in the model tables for one side of a joint (the segment, its anchor r in
// its frame), written into terms at `side` (the rule catalogue's rows hold one each)
using PrepareJointFn = void (*)(const Segment& segment, const Vector3d& r, int side,
                                JointTerms& terms);

}  // namespace puppet::procedural
