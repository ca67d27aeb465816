// Each rule's part of the adjust stage, one file per rule (rules/<rule>.cpp), with the same verbs
// (Box2D's one file per joint kind). Private to procedural/.
//
//   the one-sided rules choose the forced rotation R of a body whose point must meet a fixed
//   one (r from its centre to the point, s the gap); eq. 5 and the pass are shared
//   (forced_rotation.cpp, one_sided_pass.cpp):
//     literal, smoothed   <rule>_rotation(body, r, s, r × s, |r × s|)
//     weighted            weighted_rotation(composite, r, s), weighted_gain(segment, r)
//     subtree             subtree_pass(…): the one-sided pass, moving whole subtrees
//   the rules that solve for every constraint at once run their own adjust:
//     relaxed, xpbd, tree <rule>_adjust(…)
#pragma once

#include <span>

#include "../stages.h"

namespace puppet::procedural {

// |r × s| (m²) below which r ∥ s: there is no rotation axis, and R is the identity
constexpr double kParallel = 1e-12;

// the moment of inertia of `body` about the unit axis (world) of `cross`
inline double inertia_about(const MovingBody& body, const Vector3d& cross, double cross_norm) {
  return body.inertia_along(body.to_frame(cross / cross_norm));
}

// --- literal.cpp: eqs. 2–3 as written
Quaterniond literal_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                             const Vector3d& cross, double cross_norm);
// |r × s| (m²) below which the literal rule surely turns nothing, for a body whose largest
// principal moment is `largest_moment` (its θ = φ·exp(−1/(I_b |r × s|)) is exactly 0), never
// below the threshold under which r ∥ s
double literal_still_cross(double largest_moment);
// its row's forced rotation (the bound above first) and what it keeps per joint side
Quaterniond literal_forced_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                                    const Vector3d& cross, double cross_norm2);
void literal_prepare_joint(const Segment& segment, const Vector3d& r, int side, JointTerms& terms);

// --- smoothed.cpp: eq. 2 over one step, bounded by the angle that closes the gap
Quaterniond smoothed_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                              const Vector3d& cross, double cross_norm);
Quaterniond smoothed_forced_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                                     const Vector3d& cross, double cross_norm2);

// --- weighted.cpp: the minimum-kinetic-energy correction of a point
// for a composite body (rule subtree); a single segment takes close_segment_point() or its joint's
// constant gain
Quaterniond weighted_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s);
// a segment's rotation vector per unit gap of its point r (both in its frame): D⁻¹ [r]× K⁻¹
Matrix3d weighted_gain(const Segment& segment, const Vector3d& r, const Matrix3d& point_mass);
// its row's forced rotation (every two-sided rule's too, should one close a point one-sidedly)
// and the gain it keeps per joint side (after the side's point mass)
Quaterniond weighted_forced_rotation(const MovingBody& body, const Vector3d& r, const Vector3d& s,
                                     const Vector3d& cross, double cross_norm2);
void weighted_prepare_joint(const Segment& segment, const Vector3d& r, int side, JointTerms& terms);

// --- subtree.cpp: the one-sided pass of rule subtree after the secondary pins: the anchor's
// whole body to its pin when `pinned`, then every joint moving the subtree beyond it as one body
void subtree_pass(const Model& model, std::span<const JointTerms> joints, const AnchorOrder& order,
                  bool pinned, const PinTargets& targets, State& state, Workspace& ws);

// --- one_sided_pass.cpp: the adjust of literal, smoothed, weighted and subtree: compliant pins'
// targets softened, then one one-sided pass from the anchor
void one_sided_adjust(const Model& model, std::span<const JointTerms> joints,
                      const Settings& settings, const Environment& environment,
                      const AnchorOrder& order, const PinTargets& targets, State& state,
                      Workspace& ws, double h);

// --- relaxed.cpp, xpbd.cpp, tree.cpp: the whole adjust of the rule for one substep of length h
void relaxed_adjust(const Model& model, std::span<const JointTerms> joints,
                    const Settings& settings, const Environment& environment,
                    const AnchorOrder& order, const PinTargets& targets, State& state,
                    Workspace& ws, double h);
void xpbd_adjust(const Model& model, std::span<const JointTerms> joints, const Settings& settings,
                 const Environment& environment, const AnchorOrder& order,
                 const PinTargets& targets, State& state, Workspace& ws, double h);
void tree_adjust(const Model& model, std::span<const JointTerms> joints, const Settings& settings,
                 const Environment& environment, const AnchorOrder& order,
                 const PinTargets& targets, State& state, Workspace& ws, double h);

}  // namespace puppet::procedural
