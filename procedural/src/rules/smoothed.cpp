// Rule `smoothed`: eq. 2 read as an angular acceleration over one step, bounded by the angle
// that closes the gap. θ_raw = ½ α dt² = m |r||s| sin φ / I_b, φ_max = ∠(r, r + s):
//   θ = φ_max (1 − exp(−θ_raw/φ_max))
// so a small gap turns b by θ_raw and a large one by at most φ_max (docs/solver.md, "smoothed").
#include <cmath>

#include "puppet/model/rotation.h"
#include "rules.h"

namespace puppet::procedural {

Quaterniond smoothed_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                              const Vector3d& cross, double cross_norm) {
  const double theta_raw = body.mass * cross_norm / inertia_about(body, cross, cross_norm);
  // φ_max = ∠(r, r + s); r × (r + s) = r × s
  const double phi_max = std::atan2(cross_norm, r.dot(r + s));
  if (phi_max <= 0.0) return Quaterniond::Identity();
  const double theta = phi_max * (1.0 - std::exp(-theta_raw / phi_max));
  return quat_exp((theta / cross_norm) * cross);
}

Quaterniond smoothed_forced_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                                     const Vector3d& cross, double cross_norm2) {
  return smoothed_rotation(body, r, s, cross, std::sqrt(cross_norm2));
}

}  // namespace puppet::procedural
