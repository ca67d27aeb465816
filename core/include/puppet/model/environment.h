/// \file
/// The world a model moves in, and the forces it exerts, with the same formulas in every solver
/// (docs/design.md, "Environment"), so that differences between solvers are the solvers'.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "puppet/model/model.h"

namespace puppet {

struct Environment {
  Vector3d gravity{0.0, 0.0, -9.81};
  /// the seed's tremble (§3.4) as a force on every segment (user_forces.h: tremble_force),
  /// applied alike by every engine
  bool tremble = false;
  uint64_t tremble_seed = 2001;
  double air_drag = 0.0;  ///< k_air (1/s): F = −k·m·v, τ = −k·I·ω
  bool water = false;
  double water_level = 0.0;       ///< z of the surface (m)
  double water_density = 1000.0;  ///< ρ_w (kg/m³)
  double water_drag = 0.0;        ///< k_water (1/s), scaled by the submerged fraction
  bool ground = false;            ///< plane z = 0
  double friction = 0.8;          ///< μ
};

/// pose and velocity of one segment: COM position, orientation of the segment frame, linear and
/// angular velocity, all in world
struct BodyState {
  Vector3d x{0, 0, 0};
  Quaterniond q = Quaterniond::Identity();
  Vector3d v{0, 0, 0};
  Vector3d w{0, 0, 0};
};

/// every component of every body is a finite number (solvers flag a state that is not as
/// diverged), in one pass without a branch per value: 0·x is NaN exactly when x is ±inf or NaN,
/// and NaN survives any sum. Values so large (≳ 1e307) that their sum overflows are reported as
/// well, which is what a solver calls diverged anyway.
inline bool all_finite(std::span<const BodyState> bodies) {
  double zero = 0.0;
  for (const BodyState& b : bodies) {
    zero += 0.0 * ((b.x.sum() + b.q.coeffs().sum()) + (b.v.sum() + b.w.sum()));
  }
  return zero == 0.0;
}

/// A user's grab as every engine's picking tool makes it (docs/design.md, "The grab"): the point
/// pulled toward its target by a spring–damper normalised by the effective mass M of the grabbed
/// segment at the point (as a soft constraint's frequency is), its force capped,
///   F = M (ω² (t − p) − 2 ζ ω ṗ),  ω = 2π f,  |F| ≤ F_max,
/// applied as an external force at the point (user_forces.h: grab_force).
struct GrabSpring {
  double hz = 0.0;             ///< f (Hz); 0: the pin is a constraint (hard or compliant)
  double damping_ratio = 1.0;  ///< ζ
  double max_force = 0.0;      ///< F_max (N)
};

/// a point of a segment held at a world target (a user's drag, a marionette string)
struct Pin {
  int segment = -1;
  Vector3d local_point{0, 0, 0};  ///< segment frame
  Vector3d target{0, 0, 0};       ///< world
  /// m/N: 0 holds the point on its target (the seed's hard pin); C > 0 pulls it with the force
  /// (target − point)/C, a zero-length spring of stiffness 1/C, as a user's grab does in an engine
  double compliance = 0.0;
  /// hz > 0: not a constraint but a grab, a capped spring–damper force (GrabSpring)
  GrabSpring grab{};
  bool is_grab() const { return grab.hz > 0.0; }
  /// held on its target by a constraint (the seed's hard pin): not compliant, not a grab
  bool is_hard() const { return compliance <= 0.0 && !is_grab(); }
};

/// every segment at its rest pose, at rest
std::vector<BodyState> rest_pose(const Model& model);

struct Wrench {
  Vector3d force{0, 0, 0};   ///< at the COM
  Vector3d torque{0, 0, 0};  ///< world
};

/// the world's up (+z) seen in a body's frame: the third row of its rotation matrix
inline Vector3d up_in_frame(const Quaterniond& q) {
  return {2.0 * (q.x() * q.z() - q.w() * q.y()), 2.0 * (q.y() * q.z() + q.w() * q.x()),
          1.0 - 2.0 * (q.x() * q.x() + q.y() * q.y())};
}
/// a shape's half height along a unit direction of its frame (its support distance)
double half_height(const Shape& shape, const Vector3d& up);
/// how far a shape placed in its segment reaches below and above the segment's origin along
/// `up` (a unit direction of the segment frame)
void shape_reach(const Shape& shape, const Vector3d& up, double* below, double* above);
/// world z-extent of a segment's shapes
void vertical_extent(const Segment& segment, const Quaterniond& q, const Vector3d& x, double* low,
                     double* high);
/// fraction of the segment below the water surface: linear in depth across its vertical extent
/// (smooth, unlike a switch at the centre, which makes results depend on dt)
double submerged_fraction(const Segment& segment, const Environment& environment,
                          const BodyState& body);
/// The rate that, applied as the force −rate·m·v over a step of length h, decays v by exactly
/// e^(−c·h), as the drag dv/dt = −c·v does: (1 − e^(−c·h))/h, which is c as h → 0 and at most 1/h.
/// An explicit −c·m·v would overshoot zero for c·h > 1 and grow without bound for c·h > 2.
inline double step_drag_rate(double c, double h) {
  return h > 0.0 && c != 0.0 ? -std::expm1(-c * h) / h : c;
}
/// the environment's force on one segment over a step of length h, and the drag rate of its
/// torque −rate·I·ω (both step_drag_rate of c)
struct EnvironmentForce {
  Vector3d force{0, 0, 0};  ///< at the COM: gravity, buoyancy, drag −rate·m·v
  double drag = 0.0;        ///< step_drag_rate of c: air drag plus water drag × submerged fraction
};
EnvironmentForce environment_force(const Segment& segment, const Environment& environment,
                                   const BodyState& body, double h);
/// the same for a segment out of water, with the air's rate given: step_drag_rate(air_drag, h) is
/// the same for every such segment, so a stage that steps them all takes it once
inline EnvironmentForce air_force(const Segment& segment, const Environment& environment,
                                  const BodyState& body, double air_rate) {
  return {segment.mass * environment.gravity - air_rate * segment.mass * body.v, air_rate};
}
/// gravity, air drag, buoyancy and water drag on one segment over a step of length h (no contact
/// forces)
Wrench environment_wrench(const Segment& segment, const Environment& environment,
                          const BodyState& body, double h);

/// A compliant pin (C > 0) as a zero-length spring of stiffness 1/C between its point and its
/// target: the force (target − p)/C at the point, as a wrench at the COM (world). The Bullet
/// references apply it as an external force, evaluated at the start of the step.
Wrench pin_spring_wrench(const Pin& pin, const BodyState& body);

/// world inertia tensor of a segment in a given orientation
inline Matrix3d world_inertia(const Segment& segment, const Quaterniond& q) {
  const Matrix3d r = q.toRotationMatrix();
  return r * segment.inertia.asDiagonal() * r.transpose();
}
/// its inverse, R I⁻¹ Rᵀ, from the loader's 1/I; a segment symmetric about its z axis (a capsule,
/// a sphere) needs only that axis in world
Matrix3d world_inertia_inv(const Segment& segment, const Quaterniond& q);

}  // namespace puppet
