// The forced rotation R and forced translation T of the seed's adjust step (§3.3).
//
// Segment b, centre x, must bring its joint point c_b onto c_a (a is fixed):
//   r = c_b − x,  s = c_a − c_b                                                (§3.3)
//   r + s = R·r + T                                                             (1)
//   T = (I − R)·r + s                                                           (5)
// Eq. 5 closes the gap exactly for any R; a rule only chooses R, each in its own file:
//   literal   eqs. 2–3 as written (rules/literal.cpp)
//   smoothed  eq. 2 over one step, bounded by the closing angle (rules/smoothed.cpp)
//   weighted  the minimum-kinetic-energy correction (rules/weighted.cpp)
//   subtree   as weighted, for the composite body hanging from b (rules/subtree.cpp builds it)
//   relaxed   its final one-sided pass is weighted
//
// seed: when r ∥ s there is no rotation axis; R = identity and the joint closes by translation.
#include <cmath>

#include "rules/catalogue.h"
#include "rules/rules.h"

namespace puppet::procedural {

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
    rotation = rule_row(rule).forced_rotation(body, r, s, cross, cross_norm2);
  }
  // eq. 5: x ↦ x + T with T = (I − R) r + s
  Correction correction{rotation, s};
  if (correction.rotates()) correction.translation = r - rotation * r + s;
  return correction;
}

}  // namespace puppet::procedural
