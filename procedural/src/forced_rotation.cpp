// The forced rotation R and forced translation T of the seed's adjust step (§3.3).
//
// Segment b, centre x, must bring its joint point c_b onto c_a (a is fixed):
//   r = c_b − x,  s = c_a − c_b                                                (§3.3)
//   r + s = R·r + T                                                             (1)
//   T = (I − R)·r + s                                                           (5)
// Eq. 5 closes the gap exactly for any R; the rules below only choose R:
//
//   literal   A = r×s/|r×s|, φ = ∠(r, s), I_b = Aᵀ I A, f = 2 m s/dt²,
//             τ = |r × f|, h = 2 m/(I_b dt²), θ = φ·exp(−h/τ)                  (2), (3)
//             (h/τ = 1/(I_b |r×s|) is huge in SI units: θ ≈ 0, pure translation)
//   smoothed  θ_raw = ½ α dt² = m |r||s| sin φ / I_b (eq. 2 over one step), bounded by
//             φ_max = ∠(r, r + s): θ = φ_max (1 − exp(−θ_raw/φ_max))
//   weighted  the minimum-kinetic-energy correction of a point constraint on a rigid body
//             (the seed's "minimise b's angular momentum" made exact):
//             K = E/m − [r]× I⁻¹ [r]×, λ = K⁻¹ s, rotation vector I⁻¹ (r × λ)
//   subtree   as weighted, for the composite body hanging from b (the caller builds it)
//   relaxed   its final one-sided pass is weighted
//
// seed: when r ∥ s there is no rotation axis; R = identity and the joint closes by translation.
#include <algorithm>
#include <cassert>
#include <cmath>

#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

constexpr double kParallel = 1e-12;  // |r × s| (m²) below which r ∥ s
// exp(−x) is exactly 0 in double precision above this: the literal rotation is none at all
constexpr double kExpUnderflow = 746.0;
// literal: θ = 0 while 1/(I_b |r × s|) > kExpUnderflow, which holds for certain while
// I_max |r × s| < ½/kExpUnderflow (I_b ≤ I_max; the factor ½ is a margin for rounding)
constexpr double kSurelyUnderflows = 0.5 / kExpUnderflow;

// the moment of inertia about the unit axis (world) of `cross`
double inertia_about(const MovingBody& body, const Vector3d& cross, double cross_norm) {
  return body.inertia_along(body.to_frame(cross / cross_norm));
}

Quaterniond literal_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                             const Vector3d& cross, double cross_norm) {
  // h/τ = [2m/(I_b dt²)] / [|r × 2m s/dt²|] = 1/(I_b |r × s|): dt and m cancel
  const double decay_rate = 1.0 / (inertia_about(body, cross, cross_norm) * cross_norm);
  if (decay_rate > kExpUnderflow) return Quaterniond::Identity();  // θ = φ·0
  const double phi = std::atan2(cross_norm, r.dot(s));
  const double theta = phi * std::exp(-decay_rate);
  return quat_exp((theta / cross_norm) * cross);
}

Quaterniond smoothed_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                              const Vector3d& cross, double cross_norm) {
  const double theta_raw = body.mass * cross_norm / inertia_about(body, cross, cross_norm);
  // φ_max = ∠(r, r + s); r × (r + s) = r × s
  const double phi_max = std::atan2(cross_norm, r.dot(r + s));
  if (phi_max <= 0.0) return Quaterniond::Identity();
  const double theta = phi_max * (1.0 - std::exp(-theta_raw / phi_max));
  return quat_exp((theta / cross_norm) * cross);
}

// a composite body (rule subtree); a single segment takes close_segment_point() or its joint's
// constant gain instead
Quaterniond weighted_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s) {
  assert(!body.diagonal);
  // in the body's frame, where its tensor was built
  const Vector3d r_frame = body.to_frame(r);
  const Vector3d lambda =
      solve3(point_mass_matrix(body.inv_mass, body.inertia_inv, r_frame), body.to_frame(s));
  return quat_exp(body.to_world(body.inertia_inv * r_frame.cross(lambda)));
}

}  // namespace

double literal_still_cross(double largest_moment) {
  return std::max(kParallel, kSurelyUnderflows / largest_moment);
}

MovingBody single_body(const Segment& segment, const BodyState& body) {
  MovingBody out;
  out.mass = segment.mass;
  out.inv_mass = segment.inv_mass;
  out.centre = body.x;
  out.frame = body.q;
  out.diagonal = true;
  out.inertia_diag = segment.inertia;
  return out;
}

Correction close_point(Rule rule, const MovingBody& body, const Vector3d& c_b,
                       const Vector3d& c_a) {
  const Vector3d r = c_b - body.centre;
  const Vector3d s = c_a - c_b;
  const Vector3d cross = r.cross(s);
  const double cross_norm2 = cross.squaredNorm();
  Quaterniond rotation = Quaterniond::Identity();
  if (cross_norm2 >= kParallel * kParallel) {
    switch (rule) {
      case Rule::kLiteral: {
        // in SI units nearly every link: no axis, no sqrt
        const double bound = literal_still_cross(body.largest_moment());
        if (cross_norm2 < bound * bound) break;
        rotation = literal_rotation(body, r, s, cross, std::sqrt(cross_norm2));
        break;
      }
      case Rule::kSmoothed:
        rotation = smoothed_rotation(body, r, s, cross, std::sqrt(cross_norm2));
        break;
      case Rule::kWeighted:
      case Rule::kSubtree:
      case Rule::kRelaxed:
      case Rule::kXpbd:  // never close one-sidedly; the weighted reading if asked
      case Rule::kTree:
        rotation = weighted_rotation(body, r, s);
        break;
    }
  }
  // eq. 5: x ↦ x + T with T = (I − R) r + s
  Correction correction{rotation, s};
  if (correction.rotates()) correction.translation = r - rotation * r + s;
  return correction;
}

double limit_free_w(const Joint& joint) {
  if (joint.type != JointType::kBall) return 2.0;  // a hinge removes every other direction
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
