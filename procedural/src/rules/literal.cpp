// Rule `literal`: the seed's eqs. 2–3 as written. The forced rotation of b about its centre is
//   A = r×s/|r×s|, φ = ∠(r, s), I_b = Aᵀ I A, f = 2 m s/dt²,
//   τ = |r × f|, h = 2 m/(I_b dt²), θ = φ·exp(−h/τ)                              (2), (3)
// and h/τ = 1/(I_b |r×s|): dt and m cancel. In SI units that exponent is huge for every joint
// of a puppet (θ ≈ 0), so the rule closes joints by translation alone: it never rotates
// (docs/solver.md, "literal").
#include <algorithm>
#include <cmath>

#include "puppet/model/rotation.h"
#include "rules.h"

namespace puppet::procedural {
namespace {

// exp(−x) is exactly 0 in double precision above this: the literal rotation is none at all
constexpr double kExpUnderflow = 746.0;
// literal: θ = 0 while 1/(I_b |r × s|) > kExpUnderflow, which holds for certain while
// I_max |r × s| < ½/kExpUnderflow (I_b ≤ I_max; the factor ½ is a margin for rounding)
constexpr double kSurelyUnderflows = 0.5 / kExpUnderflow;

}  // namespace

Quaterniond literal_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                             const Vector3d& cross, double cross_norm) {
  // h/τ = [2m/(I_b dt²)] / [|r × 2m s/dt²|] = 1/(I_b |r × s|): dt and m cancel
  const double decay_rate = 1.0 / (inertia_about(body, cross, cross_norm) * cross_norm);
  if (decay_rate > kExpUnderflow) return Quaterniond::Identity();  // θ = φ·0
  const double phi = std::atan2(cross_norm, r.dot(s));
  const double theta = phi * std::exp(-decay_rate);
  return quat_exp((theta / cross_norm) * cross);
}

double literal_still_cross(double largest_moment) {
  return std::max(kParallel, kSurelyUnderflows / largest_moment);
}

Quaterniond literal_forced_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                                    const Vector3d& cross, double cross_norm2) {
  // in SI units nearly every link: no axis, no sqrt
  const double bound = literal_still_cross(body.largest_moment());
  if (cross_norm2 < bound * bound) return Quaterniond::Identity();
  return literal_rotation(body, r, s, cross, std::sqrt(cross_norm2));
}

void literal_prepare_joint(const Segment& segment, const Vector3d& /*r*/, int side,
                           JointTerms& terms) {
  const double still = literal_still_cross(segment.inertia.maxCoeff());
  terms.literal_still_cross2[side] = still * still;
}

}  // namespace puppet::procedural
