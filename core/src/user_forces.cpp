#include "puppet/model/user_forces.h"

#include <cmath>

namespace puppet {
namespace {

// a gradient at an integer lattice point, in [−1, 1]
double gradient(uint64_t seed, int64_t lattice) {
  const uint64_t bits = mix_bits(seed ^ mix_bits(static_cast<uint64_t>(lattice)));
  return static_cast<double>(bits >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

}  // namespace

uint64_t mix_bits(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double gradient_noise(uint64_t seed, double t) {
  const double cell = std::floor(t);
  const double f = t - cell;
  const auto lattice = static_cast<int64_t>(cell);
  const double g0 = gradient(seed, lattice) * f;
  const double g1 = gradient(seed, lattice + 1) * (f - 1.0);
  const double fade = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
  return g0 + fade * (g1 - g0);
}

Vector3d grab_force(const Pin& grab, const Segment& segment, const BodyState& body) {
  const Vector3d arm = body.q * grab.local_point;
  const Vector3d point = body.x + arm;
  const Vector3d point_velocity = body.v + body.w.cross(arm);
  const double omega = 2.0 * M_PI * grab.grab.hz;
  // K = (1/m) E − [r]× I⁻¹ [r]×: the point's response to a force at it
  Matrix3d cross;
  cross << 0.0, -arm.z(), arm.y(), arm.z(), 0.0, -arm.x(), -arm.y(), arm.x(), 0.0;
  const Matrix3d response =
      segment.inv_mass * Matrix3d::Identity() - cross * world_inertia_inv(segment, body.q) * cross;
  const Vector3d acceleration = omega * omega * (grab.target - point) -
                                2.0 * grab.grab.damping_ratio * omega * point_velocity;
  Vector3d force = response.ldlt().solve(acceleration);
  const double length = force.norm();
  if (length > grab.grab.max_force) force *= grab.grab.max_force / length;
  return force;
}

Vector3d tremble_force(double mass, int segment, const BodyState& body, double time, double pull,
                       uint64_t seed) {
  constexpr double kOmega = 2.0 * M_PI * kTrembleHz;
  constexpr double kAcceleration = kOmega * kOmega * kTrembleAmplitude;
  const double gamma = pull * body.v.norm();
  const double size = mass * kAcceleration * std::abs(std::sin(gamma)) * std::exp(-pull);
  if (size == 0.0) return Vector3d::Zero();
  // the phase of f₀ (1 + ½ cos γt): f₀ (t + sin(γt) / 2γ), whose limit at γ → 0 is f₀ · 3t/2
  const double gt = gamma * time;
  const double sinc = std::abs(gt) > 1e-8 ? std::sin(gt) / gt : 1.0;
  const double phase = kTrembleHz * time * (1.0 + 0.5 * sinc);
  Vector3d force;
  for (int axis = 0; axis < 3; ++axis) {
    const uint64_t key = mix_bits(seed + 3 * static_cast<uint64_t>(segment) + axis);
    force[axis] = 2.0 * size * gradient_noise(key, phase);
  }
  return force;
}

double user_wrenches(const Model& model, const Environment& environment, std::span<const Pin> pins,
                     std::span<const BodyState> bodies, double time, std::span<Wrench> out) {
  for (Wrench& w : out) w = Wrench{};
  double pull = 0.0;
  for (const Pin& pin : pins) {
    if (!pin.is_grab()) continue;
    const Segment& segment = model.segments[pin.segment];
    const BodyState& body = bodies[pin.segment];
    const Vector3d force = grab_force(pin, segment, body);
    Wrench& w = out[pin.segment];
    w.force += force;
    w.torque += (body.q * pin.local_point).cross(force);
    pull += force.norm() / (segment.mass * kStandardGravity);
  }
  if (environment.tremble) {
    for (int i = 0; i < model.segment_count(); ++i) {
      out[i].force +=
          tremble_force(model.segments[i].mass, i, bodies[i], time, pull, environment.tremble_seed);
    }
  }
  return pull;
}

}  // namespace puppet
