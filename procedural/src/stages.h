// The solver's stages and the geometry they share; private to procedural/.
#pragma once

#include <array>
#include <span>

#include "puppet/procedural/solver.h"

namespace puppet::procedural {

// a rigid motion p ↦ q·p + t, applied to a whole segment (or a subtree of them)
struct Motion {
  Quaterniond q = Quaterniond::Identity();
  Vector3d t{0, 0, 0};

  Vector3d apply(const Vector3d& p) const { return q * p + t; }
  void apply(BodyState& body) const {
    body.x = q * body.x + t;
    body.q = (q * body.q).normalized();
  }
  // (this ∘ inner)(p) = this(inner(p))
  Motion after(const Motion& inner) const { return {q * inner.q, q * inner.t + t}; }
  // rotation `rotation` about the point `centre`
  static Motion about(const Quaterniond& rotation, const Vector3d& centre) {
    return {rotation, centre - rotation * centre};
  }
};

// the side of a joint that a correction moves: one segment, or a composite subtree
struct MovingBody {
  double mass = 0.0;
  Vector3d centre{0, 0, 0};                 // centre of mass, world
  Matrix3d inertia = Matrix3d::Zero();      // world, about the centre
  Matrix3d inertia_inv = Matrix3d::Zero();  // its inverse
};

MovingBody single_body(const Segment& segment, const BodyState& body);

// the 3×3 effective mass of a point at offset r from the centre: K = E/m − [r]× I⁻¹ [r]×
Matrix3d point_mass_matrix(const MovingBody& body, const Vector3d& r);

// The correction that moves point c_b of `body` onto c_a: the rule's forced rotation R about
// the body's centre (eqs. 2–3 or their readings), then the forced translation of eq. 5,
// T = (I − R)·r + s, which closes the gap exactly.
Motion close_point(Rule rule, const MovingBody& body, const Vector3d& c_b, const Vector3d& c_a,
                   double h);

// The rotation of b about the joint point that brings the joint back inside its limits (eq. 4),
// evaluated on q_rel = (parent frame)⁻¹(child frame) whichever side b is; identity when inside.
Quaterniond limit_correction(const Joint& joint, bool b_is_child, const Quaterniond& q_a,
                             const Quaterniond& q_b);

// world position of a point given in a segment's frame
inline Vector3d world_point(const BodyState& body, const Vector3d& local) {
  return body.x + body.q * local;
}

// per-substep pin targets (already interpolated across substeps)
using PinTargets = std::array<Vector3d, kMaxPins>;

// stage 1: every segment alone under its forces
void update(const Model& model, const Environment& environment, State& state, double h);
// the seed's tremble (§3.4), added to positions at the end of update; delta per segment out
void tremble(const Model& model, const Settings& settings, State& state, double h,
             std::vector<Vector3d>& delta);
// stage 2: pins, joints and limits from the anchor
void adjust(const Model& model, const Settings& settings, const Environment& environment,
            std::span<const AnchorOrder> orders, int anchor, const PinTargets& targets,
            State& state, Workspace& workspace, double h);
// one-sided pass of `rule` over `order`; pins closed only when with_pins
void one_sided_pass(const Model& model, Rule rule, const AnchorOrder& order, bool with_pins,
                    const PinTargets& targets, State& state, Workspace& workspace, double h);
// stage 3: push shape points out of the ground with friction; returns the deepest-penetrating
// segment before correction, or -1 without contact
int resolve_contacts(const Model& model, const Environment& environment, State& state, double h);
// push one segment out of the ground (shared by resolve_contacts and relaxed sweeps); returns
// the deepest penetration (m) found before the correction
double push_out_of_ground(const Model& model, const Environment& environment, int segment,
                          State& state, double h);
// stage 4: velocities from the corrected poses and the previous ones
void derive_velocities(const Model& model, State& state, const std::vector<Vector3d>& tremble_delta,
                       double h);

}  // namespace puppet::procedural
