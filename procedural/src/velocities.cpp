// Stage 4, velocities. The seed corrects poses only; without a velocity update the next update
// keeps accelerating what adjust pulls back. As position-based methods do, velocities are
// derived from the corrected pose and the one at the start of the step:
//   v = Δx/h,  ω = log(q·q_prev⁻¹)/h  (exact logarithm, shortest arc)
// seed: the small-angle form 2·vec(Δq)/h loses spin (−4 % per 10 s at 5 rad/s); not used.
// The tremble displacement is a pure offset: it is taken out of v so it does not pump momentum.
#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {

void derive_velocities(const Model& model, State& state, const std::vector<Vector3d>& tremble_delta,
                       double h) {
  const double inv_h = 1.0 / h;
  for (int i = 0; i < model.segment_count(); ++i) {
    BodyState& body = state.bodies[i];
    body.v = inv_h * (body.x - state.x_prev[i] - tremble_delta[i]);
    body.w = inv_h * quat_log(body.q * state.q_prev[i].conjugate());
  }
}

}  // namespace puppet::procedural
