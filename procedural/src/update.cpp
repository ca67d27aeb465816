// Stage 1, update (seed §3.2): every segment moves alone under its forces; joints are ignored.
//
//   v ← v + h·F/m,  x ← x + h·v                        (semi-implicit Euler)
//   ω: torque, then the gyroscopic term ω × Iω taken implicitly with one Newton step in the
//      body frame (as Bullet and Box2D do; explicit Euler gains angular momentum)
//   q ← exp(h·ω) ⊗ q, renormalised                      (exact exponential map)
//
// Forces: the environment's (gravity, air drag, buoyancy and water drag: the same formulas as
// every solver), the user's (state.user_force, and the grabs and tremble of user_forces.h), and the
// seed's ground repulsion: a spring on the deepest point below z = 0, the soft part of the contact
// that resolve_contacts() makes hard.
#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

constexpr double kGroundStiffness = 987.0;  // (2π·5 Hz)², per unit mass (1/s²)

// implicit gyroscopic step in the body frame: solve I(ω' − ω) + h ω' × Iω' = 0 by one Newton
// step from ω' = ω. With I = diag(I₁, I₂, I₃) and ω = (p, q, r) the Jacobian
// J = I + h([ω]× I − [Iω]×) has columns
//   c₀ = (I₁, h r (I₁ − I₃), h q (I₂ − I₁)), c₁ = (h r (I₃ − I₂), I₂, h p (I₂ − I₁)),
//   c₂ = (h q (I₃ − I₂), h p (I₁ − I₃), I₃),
// and J δ = h ω × Iω is solved by Cramer's rule (one division, no 3×3 inverse).
Vector3d gyroscopic_step(const Vector3d& inertia, const Vector3d& w_body, double h) {
  const double p = w_body.x(), q = w_body.y(), r = w_body.z();
  const double i1 = inertia.x(), i2 = inertia.y(), i3 = inertia.z();
  const Vector3d c0(i1, h * r * (i1 - i3), h * q * (i2 - i1));
  const Vector3d c1(h * r * (i3 - i2), i2, h * p * (i2 - i1));
  const Vector3d c2(h * q * (i3 - i2), h * p * (i1 - i3), i3);
  const Vector3d residual = h * w_body.cross(inertia.cwiseProduct(w_body));
  const Vector3d c12 = c1.cross(c2);
  const double inv_det = 1.0 / c0.dot(c12);
  const Vector3d delta(residual.dot(c12), c0.dot(residual.cross(c2)), c0.dot(c1.cross(residual)));
  return w_body - inv_det * delta;
}

}  // namespace

void update(const Model& model, const Environment& environment, std::span<const Wrench> user,
            State& state, double h) {
  // out of water every segment's drag rate is the air's: one expm1 per substep, not per segment
  const double air_rate = step_drag_rate(environment.air_drag, h);
  const bool pulled = !user.empty();  // a grab or the tremble: empty without either
  for (int i = 0; i < model.segment_count(); ++i) {
    const Segment& segment = model.segments[i];
    BodyState& body = state.bodies[i];
    state.x_prev[i] = body.x;
    state.q_prev[i] = body.q;

    const EnvironmentForce environment_part = environment.water
                                                  ? environment_force(segment, environment, body, h)
                                                  : air_force(segment, environment, body, air_rate);
    Vector3d force = environment_part.force + state.user_force[i];
    if (pulled) force += user[i].force;
    if (environment.ground) {
      double low = 0.0, high = 0.0;
      vertical_extent(segment, body.q, body.x, &low, &high);
      if (low < 0.0) force.z() -= segment.mass * kGroundStiffness * low;
    }

    // linear: semi-implicit Euler
    body.v += (h * segment.inv_mass) * force;
    body.x += h * body.v;

    // angular, in the body frame: the drag torque −c·I·ω is the angular acceleration −c·ω there
    // (no inertia, no rotation to world and back; 1 − h·rate is e^(−c·h), step_drag_rate), then
    // the user's torque impulse, then the implicit gyroscopic step
    Vector3d w_body = body.q.conjugate() * body.w;
    if (environment_part.drag != 0.0) w_body *= 1.0 - h * environment_part.drag;
    Vector3d torque = state.user_torque[i];
    if (pulled) torque += user[i].torque;
    if (!torque.isZero(0.0)) {
      w_body += h * (body.q.conjugate() * torque).cwiseProduct(segment.inv_inertia);
    }
    w_body = gyroscopic_step(segment.inertia, w_body, h);
    body.w = body.q * w_body;
    // exp(h ω) ⊗ q = q ⊗ exp(h ω_body)
    body.q = renormalized(times_exp(body.q, h * w_body));
  }
}

}  // namespace puppet::procedural
