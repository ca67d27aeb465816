// Stage 1, update (seed §3.2): every segment moves alone under its forces; joints are ignored.
//
//   v ← v + h·F/m,  x ← x + h·v                        (semi-implicit Euler)
//   ω: torque, then the gyroscopic term ω × Iω taken implicitly with one Newton step in the
//      body frame (as Bullet and Box2D do; explicit Euler gains angular momentum)
//   q ← exp(h·ω) ⊗ q, normalised                        (exact exponential map)
//
// Forces: the environment's (gravity, air drag, buoyancy and water drag: the same formulas as
// every solver), the user's, and the seed's ground repulsion: a spring on the deepest point
// below z = 0, the soft part of the contact that resolve_contacts() makes hard.
#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

constexpr double kGroundStiffness = 987.0;  // (2π·5 Hz)², per unit mass (1/s²)

// implicit gyroscopic step in the body frame: solve I(ω' − ω) + h ω' × Iω' = 0 by one Newton
// step from ω' = ω
Vector3d gyroscopic_step(const Vector3d& inertia, const Vector3d& w_body, double h) {
  const Vector3d iw = inertia.cwiseProduct(w_body);
  const Vector3d residual = h * w_body.cross(iw);
  Matrix3d skew_w, skew_iw;
  skew_w << 0, -w_body.z(), w_body.y(), w_body.z(), 0, -w_body.x(), -w_body.y(), w_body.x(), 0;
  skew_iw << 0, -iw.z(), iw.y(), iw.z(), 0, -iw.x(), -iw.y(), iw.x(), 0;
  const Matrix3d jacobian =
      Matrix3d(inertia.asDiagonal()) + h * (skew_w * inertia.asDiagonal() - skew_iw);
  return w_body - jacobian.inverse() * residual;
}

}  // namespace

void update(const Model& model, const Environment& environment, State& state, double h) {
  for (int i = 0; i < model.segment_count(); ++i) {
    const Segment& segment = model.segments[i];
    BodyState& body = state.bodies[i];
    state.x_prev[i] = body.x;
    state.q_prev[i] = body.q;

    Wrench wrench = environment_wrench(segment, environment, body);
    wrench.force += state.user_force[i];
    wrench.torque += state.user_torque[i];
    if (environment.ground) {
      double low = 0.0, high = 0.0;
      vertical_extent(segment, body.q, body.x, &low, &high);
      if (low < 0.0) wrench.force.z() -= segment.mass * kGroundStiffness * low;
    }

    // linear: semi-implicit Euler
    body.v += h / segment.mass * wrench.force;
    body.x += h * body.v;

    // angular: torque impulse, then the implicit gyroscopic step, in the body frame
    Vector3d w_body = body.q.conjugate() * body.w;
    if (!wrench.torque.isZero(0.0)) {
      w_body += h * (body.q.conjugate() * wrench.torque).cwiseQuotient(segment.inertia);
    }
    w_body = gyroscopic_step(segment.inertia, w_body, h);
    body.w = body.q * w_body;
    // exp(h ω) ⊗ q = q ⊗ exp(h ω_body)
    body.q = (body.q * quat_exp(h * w_body)).normalized();
  }
}

}  // namespace puppet::procedural
