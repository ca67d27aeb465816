// Metrics that need one solver (docs/design.md, "Metrics"); their definitions are part of the
// contract. All take per-segment states in the model's segment frames, so they need no
// solver-specific code.
#pragma once

#include <cmath>

#include <span>
#include <string>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::compare {

// |c_a − c_b| of every joint (m)
void joint_gaps(const Model& model, std::span<const BodyState> bodies, std::span<double> out);
// |point − target| of every pin (m); 0 for a grab, whose stretch is its law's, not a violation
void pin_gaps(std::span<const Pin> pins, std::span<const Vector3d> targets,
              std::span<const BodyState> bodies, std::span<double> out);
// how far each joint is outside its limits (deg, 0 inside)
void limit_violations_deg(const Model& model, std::span<const BodyState> bodies,
                          std::span<double> out);
// kinetic + potential energy, potential −m g·x (J)
double mechanical_energy(const Model& model, const Environment& environment,
                         std::span<const BodyState> bodies);
double kinetic_energy(const Model& model, std::span<const BodyState> bodies);
Vector3d centre_of_mass(const Model& model, std::span<const BodyState> bodies);
Vector3d linear_momentum(const Model& model, std::span<const BodyState> bodies);
// about the centre of mass
Vector3d angular_momentum(const Model& model, std::span<const BodyState> bodies);
// deepest penetration of any shape below the ground z = 0 (m, 0 when none)
double ground_penetration(const Model& model, std::span<const BodyState> bodies);
// fastest segment's COM speed (m/s)
double peak_speed(std::span<const BodyState> bodies);

// the scale energy drift is measured against, from the model's own mass M and rest height H:
// E_ref = M·max(|g|, g₀)·H + KE(0), g₀ = 9.81 m/s², so that it is never zero (weightless, at
// rest) and does not depend on where the model is
inline constexpr double kStandardGravity = 9.81;
double energy_reference(const Model& model, const Environment& environment,
                        std::span<const BodyState> initial);

// Accuracy: a state against the truth's state at the same time (docs/design.md, "Metrics").
// pose_err_m: RMS over segments of the COM distance (m)
double pose_error(std::span<const BodyState> bodies, std::span<const BodyState> truth);
// joint_angle_err_deg: RMS over joints of the geodesic angle between the two relative
// rotations (deg); blind to where the body is, sees only how it is bent
double joint_angle_error_deg(const Model& model, std::span<const BodyState> bodies,
                             std::span<const BodyState> truth);

// the quantities recorded after every step
struct StepMetrics {
  double t = 0.0;
  double joint_gap_max = 0.0, joint_gap_rms = 0.0;  // over joints
  double pin_gap_max = 0.0;
  double limit_violation_max_deg = 0.0;
  double energy_drift = 0.0;            // (E − E(0)) / E_ref
  double linear_momentum_drift = 0.0;   // |P − P(0)| / (M v_rms(0))
  double angular_momentum_drift = 0.0;  // |L − L(0)| / |L(0)|
  double penetration = 0.0;
  double peak_speed = 0.0;
  bool finite = true;
};

// the divergence criteria of docs/design.md ("status")
constexpr double kDivergedJointGap = 0.5;    // m
constexpr double kDivergedEnergyDrift = 10;  // × E_ref
// why a state counts as diverged, or nullptr when it does not
inline const char* divergence_reason(const StepMetrics& m) {
  if (!m.finite) return "non-finite";
  // a metric that is not a number (an overflow, 0/0) is never a state that is ok
  const double sum = m.joint_gap_max + m.joint_gap_rms + m.pin_gap_max + m.limit_violation_max_deg +
                     m.energy_drift + m.linear_momentum_drift + m.angular_momentum_drift +
                     m.penetration + m.peak_speed;
  if (!std::isfinite(sum)) return "non-finite metric";
  if (m.joint_gap_max > kDivergedJointGap) return "joint gap";
  if (m.energy_drift > kDivergedEnergyDrift) return "energy";
  return nullptr;
}

// one observation of summary.csv (docs/design.md, "Outputs"); reference is "truth", "pairwise" or
// empty
struct SummaryRow {
  std::string metric, stat;
  double value = 0.0;
  std::string unit;
  std::string reference;
};

// evaluates StepMetrics along a run; buffers sized once
class MetricsProbe {
 public:
  MetricsProbe(const Model& model, const Environment& environment, std::span<const Pin> pins,
               std::span<const BodyState> initial);
  StepMetrics measure(double t, std::span<const BodyState> bodies,
                      std::span<const Vector3d> targets);

 private:
  const Model& model_;
  Environment environment_;
  std::vector<Pin> pins_;
  // energy drift as ΔKE + ΔPE from the initial state, so that no offset of the model costs
  // precision: ΔPE = −Σ m g·(x − x(0))
  // and the joints' springs' energy (joint_springs.h): ΔE_spring
  double kinetic0_, spring0_, energy_ref_;
  std::vector<Vector3d> initial_x_;
  Vector3d momentum0_, angular0_;
  double momentum_scale_;
  std::vector<double> joint_buffer_, pin_buffer_;
};

}  // namespace puppet::compare
