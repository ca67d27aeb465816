// Joint limits (seed eq. 4). A joint's relative rotation q_rel = (parent frame)⁻¹(child frame)
// is clamped to its limits (clamp_to_limits, model/rotation.cpp: a ball's swing cone and twist, a
// hinge's angle); the moved side is then turned so that its relative rotation is the clamped one.
// A cheap test first: a rotation by less than the smallest limit angle is surely inside, and
// |w(q_rel)| tells it from the two orientations without forming q_rel (JointTerms::frame_shift).
#include <algorithm>
#include <cmath>

#include "joint_limits.h"
#include "puppet/model/rotation.h"

namespace puppet::procedural {

double limit_free_w(const Joint& joint) {
  if (joint.type != JointType::kBall) return 2.0;  // a hinge removes every other direction
  // a box's Euler angles are not bounded by the rotation's angle near gimbal lock: always test
  if (joint.ball_limit == BallLimit::kEulerBox) return 2.0;
  // a rotation by ρ has twist ≤ ρ and swing ≤ ρ: inside when ρ is below every half-angle
  const double free_angle = std::min({joint.twist, joint.swing_x, joint.swing_y});
  return free_angle > 0.0 ? std::cos(0.5 * free_angle) : 2.0;
}

bool limited_orientation(const Joint& joint, const JointTerms& terms, bool b_is_child,
                         const Quaterniond& q_a, const Quaterniond& q_b, Quaterniond* q_b_limited) {
  const Quaterniond& q_parent = b_is_child ? q_a : q_b;
  const Quaterniond& q_child = b_is_child ? q_b : q_a;
  // |w(q_rel)| = |q_p · (q_c ⊗ frame_shift)|: surely inside without forming q_rel
  if (terms.limit_free_w < 1.0 &&
      std::abs(q_parent.coeffs().dot(times_frame(q_child, terms.frame_shift).coeffs())) >
          terms.limit_free_w) {
    return false;
  }
  const Quaterniond q_rel = joint_relative_rotation(joint, q_parent, q_child);
  const Quaterniond clamped = clamp_to_limits(joint, q_rel);
  if (clamped.coeffs() == q_rel.coeffs()) return false;
  // rebuild b from a and the clamped q_rel (inverted when b is the parent), never from a
  // re-decomposed inverse
  *q_b_limited = b_is_child
                     ? times_frame(times_frame(q_a, joint.frame_in_parent) * clamped,
                                   joint.frame_in_child.conjugate())
                     : times_frame(times_frame(q_a, joint.frame_in_child) * clamped.conjugate(),
                                   joint.frame_in_parent.conjugate());
  return true;
}

bool limit_error(const Joint& joint, const JointTerms& terms, const Quaterniond& child_to_parent,
                 Vector3d* error) {
  // |w(q_rel)| = |w(frame_shift ⊗ (q_c⁻¹ q_p)⁻¹)| = |frame_shift · (q_c⁻¹ q_p)|
  if (std::abs(terms.frame_shift.coeffs().dot(child_to_parent.coeffs())) > terms.limit_free_w) {
    return false;
  }
  // q_rel = Fp⁻¹ q_p⁻¹ q_c Fc = (q_c⁻¹ q_p Fp)⁻¹ Fc
  const Quaterniond parent_frame = times_frame(child_to_parent, joint.frame_in_parent);
  const Quaterniond q_rel = times_frame(parent_frame.conjugate(), joint.frame_in_child);
  const Quaterniond clamped = clamp_to_limits(joint, q_rel);
  if (clamped.coeffs() == q_rel.coeffs()) return false;
  // the limited child is q_p Fp clamped Fc⁻¹, and q_c⁻¹ times it is q_c⁻¹ q_p Fp clamped Fc⁻¹
  *error = quat_log(times_frame(parent_frame * clamped, joint.frame_in_child.conjugate()));
  return true;
}

Quaterniond limit_correction(const Joint& joint, const JointTerms& terms, bool b_is_child,
                             const Quaterniond& q_a, const Quaterniond& q_b) {
  Quaterniond q_b_limited;
  if (!limited_orientation(joint, terms, b_is_child, q_a, q_b, &q_b_limited)) {
    return Quaterniond::Identity();
  }
  return (q_b_limited * q_b.conjugate()).normalized();
}

}  // namespace puppet::procedural
