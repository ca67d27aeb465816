/// \file
/// The forces a user exerts, with the same formulas in every engine (docs/design.md, "The grab"
/// and "The tremble"): a grab's capped spring–damper and the seed's tremble. Each engine
/// computes them from its own state at the start of each of its steps (or substeps) and applies
/// them as external forces, as it does the environment's.
#pragma once

#include <cstdint>
#include <span>

#include "puppet/model/environment.h"

namespace puppet {

/// A grab's pull at its point (world), from the state: F = M (ω² (t − p) − 2 ζ ω ṗ), ω = 2π f,
/// scaled back to F_max when longer (GrabSpring). M = K⁻¹ is the grabbed segment's effective mass
/// at the point, K = 1/m − [r]× I⁻¹ [r]× (r the arm from the COM, I the world inertia): the point
/// of the segment alone then moves as a damped oscillator of frequency f and ratio ζ, what Jolt's
/// and Box2D's soft constraints mean by their frequency. Joints only add mass at the point, so the
/// grab is slower in the figure than alone, and an explicit step of it is stable for 2π f h ≲ 1.
Vector3d grab_force(const Pin& grab, const Segment& segment, const BodyState& body);

/// The tremble's clock and size (the procedural rules' position tremble, tremble.cpp, reads the
/// seed the same way): f₀ = 8 Hz (physiological tremor is 4–12 Hz) and the acceleration of a
/// 3 mm displacement at f₀, (2π f₀)² · 3 mm ≈ 7.6 m/s².
inline constexpr double kTrembleHz = 8.0;
inline constexpr double kTrembleAmplitude = 0.003;  // m
/// the weight the pull is measured in (m/s²): the standard gravity, so that a figure without
/// gravity (spin) trembles as one with it
inline constexpr double kStandardGravity = 9.81;

/// The seed's tremble (§3.4, fig. 4b) as a force on segment i, per axis a:
///   F = m_i · A · |sin γ_i| · e^(−x̂) · 2 n_ia(τ_i),  A = (2π f₀)² · 3 mm,
///   γ_i = x̂ · |v_i| / (1 m/s),  τ_i = f₀ (t + sin(γ_i t) / (2 γ_i)),
/// where x̂ is the pull in the grabbed segments' weights (Σ_k |F_k| / (m_k g₀)), τ_i the phase of
/// the frequency f₀ (1 + ½ cos(γ_i t)) (the seed's "period from cos(γ t)"), and n_ia 1-D gradient
/// noise in about [−½, ½] seeded by the segment and axis. Deterministic: a function of the state,
/// the time and the seed alone.
Vector3d tremble_force(double mass, int segment, const BodyState& body, double time, double pull,
                       uint64_t seed);

/// The user's forces on every segment at one state, as wrenches at the COMs (world), written over
/// `out` (one per segment): each grab among `pins` (Pin::is_grab; the others are skipped) pulling
/// at its point, and with environment.tremble the tremble. Returns the pull x̂. No allocation.
double user_wrenches(const Model& model, const Environment& environment, std::span<const Pin> pins,
                     std::span<const BodyState> bodies, double time, std::span<Wrench> out);

/// splitmix64's finaliser: a well-mixed 64-bit value from any seed
uint64_t mix_bits(uint64_t x);
/// 1-D gradient noise (Perlin) in about [−½, ½]: smooth (a quintic fade), 0 at integer t
double gradient_noise(uint64_t seed, double t);

}  // namespace puppet
