// The seed's active response (§3.4, fig. 4b): a tremble that resists the pull, added to the
// segments' positions in the update,
//   center + noise(amplitude) · noise(frequency(time)),
// amplitude ∝ sin γ · exp(−x·h), period from cos(γ·t), x the pulling force, γ = x × speed.
//
// seed: taken literally exp(−x·h) is 0 (x ~ 100 N, h ~ 10⁵). This reading is unit-consistent:
//   x̂ = Σ pin forces / (M |g|)           the pull in body weights (pin force: 2 m |s|/dt², eq. 2)
//   γ = x̂ · |v| / (1 m/s)                per segment
//   amplitude = a_max · |sin γ| · exp(−x̂), a_max = 3 mm
//   frequency = f₀ (1 + ½ cos(γ t)), f₀ = 8 Hz (physiological tremor is 4–12 Hz)
// and the offset is deterministic 1-D gradient noise (Perlin) per segment and axis. Positions
// carry the offset; derive_velocities() removes it from v so the tremble pumps no momentum.
#include <cmath>
#include <cstdint>

#include "puppet/model/user_forces.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

constexpr double kMaxAmplitude = kTrembleAmplitude;  // m
constexpr double kBaseFrequency = kTrembleHz;        // Hz

}  // namespace

void tremble(const Model& model, const Settings& settings, State& state, double h,
             std::vector<Vector3d>& delta) {
  double pull = 0.0;
  for (int i = 0; i < state.pin_count; ++i) pull += state.pin_force[i];
  const double weight = model.total_mass * 9.81;
  const double pull_hat = pull / weight;

  // one shared clock: its rate follows the mean speed, so frequency(time) stays smooth
  double mean_speed = 0.0;
  for (const BodyState& body : state.bodies) mean_speed += body.v.norm();
  mean_speed /= model.segment_count();
  const double gamma_mean = pull_hat * mean_speed;
  state.tremble_phase += h * kBaseFrequency * (1.0 + 0.5 * std::cos(gamma_mean * state.time));

  for (int i = 0; i < model.segment_count(); ++i) {
    BodyState& body = state.bodies[i];
    const double gamma = pull_hat * body.v.norm();
    const double amplitude = kMaxAmplitude * std::abs(std::sin(gamma)) * std::exp(-pull_hat);
    Vector3d offset;
    for (int axis = 0; axis < 3; ++axis) {
      const uint64_t seed = mix_bits(settings.tremble_seed + 3 * static_cast<uint64_t>(i) + axis);
      offset[axis] = 2.0 * amplitude * gradient_noise(seed, state.tremble_phase);
    }
    delta[i] = offset - state.tremble_offset[i];
    state.tremble_offset[i] = offset;
    body.x += delta[i];
  }
}

}  // namespace puppet::procedural
