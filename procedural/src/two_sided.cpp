// Two-sided corrections: a constraint's error shared by both of its bodies in proportion to their
// generalised inverse masses (Gauss–Seidel position projection, as position-based dynamics does).
// The sweeps of `relaxed` and of `xpbd` are made of these; the one-sided rules never use them.
//
// A point constraint C = c_p − c_c (or point − target for a pin) is closed by the impulse
//   Δλ = (K + α̃ E)⁻¹ (−C − α̃ λ),   K = K_c + R K_p Rᵀ,  α̃ = α / h²            (XPBD, eq. 18)
// with K each side's 3×3 point mass matrix E/m − [r]× I⁻¹ [r]× (the block form of XPBD's scalar
// w₁ + w₂, which it equals along the correction's direction), α the compliance and λ the
// multiplier accumulated over the substep's sweeps. α = 0 is a rigid constraint, and then the
// code takes exactly the arithmetic of the rigid form (relaxed's results stay bit for bit).
// A limit is the same with the angular effective mass I_p⁻¹ + I_c⁻¹ and the clamp's rotation
// as its error.
//
// The lever arms. A correction's impulse λ at a point turns a segment by W (r × λ). Position-based
// dynamics takes r and W = R I⁻¹ Rᵀ at the pose being corrected (the update's prediction, moved
// by the sweep so far). With `start` given they are taken at the substep's start instead, r at
// the start orientation and W from `start` (start_inverse_inertias), while the point that must
// meet is the current one: the constraint force keeps the direction it had at the start of the
// step, as SHAKE does for particles (Ryckaert, Ciccotti, Berendsen 1977), and K, now
//   K = E/m − [r]× W₀ [r₀]×  per side  (not symmetric),
// is the point's response to λ. Measured on a rod pinned at one end (no gravity, 5 rad/s,
// 1/120 s): the predicted pose's arms lose 13 % of the spin in a second, the start's 0.02 %;
// swinging under gravity its error against the exact pendulum falls 5.8× to the generalised
// semi-implicit Euler's (docs/solver.md, "The lever arms").
//
// Müller, Macklin, Chentanez, Jeschke, Kim 2020, "Detailed rigid body simulation with extended
// position based dynamics", §3.3–3.4; Macklin, Müller, Chentanez 2016 (XPBD).
#include <algorithm>

#include "puppet/model/euler_box.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

// K⁻¹ y restricted to the directions P projects on (a slide's held ones): P (P K P + E − P)⁻¹ P y
Vector3d held_solve(const Matrix3d& k, const Vector3d& y, const Matrix3d* held) {
  if (!held) return solve3(k, y);
  const Matrix3d& p = *held;
  return p * solve3(Matrix3d(p * k * p + (Matrix3d::Identity() - p)), Vector3d(p * y));
}

// Δλ = (K + α̃E)⁻¹ (y − α̃ λ) in a frame where K and y are given; λ (world) is carried into that
// frame by `to_frame` and the increment added back; α̃ = 0 solves K⁻¹ y alone. `held`: the
// projector (that frame) on the directions the constraint holds, null for all three
template <typename ToFrame, typename ToWorld>
Vector3d compliant_solve(Matrix3d k, Vector3d y, double alpha_tilde, Vector3d* lambda,
                         const ToFrame& to_frame, const ToWorld& to_world,
                         const Matrix3d* held = nullptr) {
  if (alpha_tilde == 0.0) return held_solve(k, y, held);
  k.diagonal().array() += alpha_tilde;
  y -= alpha_tilde * to_frame(*lambda);
  const Vector3d delta = held_solve(k, y, held);
  *lambda += to_world(delta);
  return delta;
}

// (K + α̃E)⁻¹ (gap − α̃ λ) in world, λ the world multiplier; α̃ = 0 solves K⁻¹ gap alone
Vector3d world_compliant_solve(Matrix3d k, Vector3d gap, double alpha_tilde, Vector3d* lambda,
                               const Matrix3d* held = nullptr) {
  if (alpha_tilde == 0.0) return held_solve(k, gap, held);
  k.diagonal().array() += alpha_tilde;
  gap -= alpha_tilde * *lambda;
  const Vector3d delta = held_solve(k, gap, held);
  *lambda += delta;
  return delta;
}

// A slide's point on the parent's side: the parent's anchor moved along the slide by the
// coordinate s (clamped to its range), so that both sides' points are one point and the pair of
// impulses turns the two segments as one; `held`, in world, projects on the directions the point
// holds: across the slide, and along it too past an end of its range
struct SlideSide {
  Vector3d anchor;  // parent's frame
  Matrix3d held;    // world
};
SlideSide slide_side(const Joint& joint, const BodyState& parent, const BodyState& child) {
  const Vector3d in_parent = joint.frame_in_parent * joint.hinge_axis;
  const Vector3d a = parent.q * in_parent;
  const Vector3d d =
      (child.x + child.q * joint.anchor_in_child) - (parent.x + parent.q * joint.anchor_in_parent);
  const double s = a.dot(d);
  const double kept = std::clamp(s, joint.lower, joint.upper);
  SlideSide side;
  side.anchor = joint.anchor_in_parent + kept * in_parent;
  side.held = Matrix3d::Identity();
  if (kept == s) side.held -= a * a.transpose();
  return side;
}

// a segment's response to an impulse at its point r (world, current) with its lever arm r₀ and
// inverse inertia W₀ at the substep's start: −[r]× W₀ [r₀]×, the turn's part of K
Matrix3d start_arm_response(const Vector3d& r, const Matrix3d& w0, const Vector3d& r0) {
  // column j: −r × (W₀ (r₀ × eⱼ)) = (W₀ (r₀ × eⱼ)) × r
  Matrix3d k;
  k.col(0) = (w0 * Vector3d(0.0, r0.z(), -r0.y())).cross(r);
  k.col(1) = (w0 * Vector3d(-r0.z(), 0.0, r0.x())).cross(r);
  k.col(2) = (w0 * Vector3d(r0.y(), -r0.x(), 0.0)).cross(r);
  return k;
}

}  // namespace

void start_inverse_inertias(const Model& model, const State& state, std::span<Matrix3d> out) {
  for (int i = 0; i < model.segment_count(); ++i) {
    const Matrix3d rotation = state.q_prev[i].toRotationMatrix();
    out[i].noalias() = rotation * model.segments[i].inv_inertia.asDiagonal() * rotation.transpose();
  }
}

void share_pin_correction(const Model& model, const Pin& pin, const Vector3d& target,
                          double alpha_tilde, Vector3d* lambda, const Matrix3d* start,
                          State& state) {
  if (start) {
    BodyState& body = state.bodies[pin.segment];
    const Segment& segment = model.segments[pin.segment];
    const Matrix3d& w0 = start[pin.segment];
    const Vector3d r = body.q * pin.local_point;
    const Vector3d r0 = state.q_prev[pin.segment] * pin.local_point;
    Matrix3d k = start_arm_response(r, w0, r0);
    k.diagonal().array() += segment.inv_mass;
    const Vector3d impulse = world_compliant_solve(k, target - body.x - r, alpha_tilde, lambda);
    body.x += segment.inv_mass * impulse;
    body.q = quat_exp(w0 * r0.cross(impulse)) * body.q;
    return;
  }
  // the world does not move: the segment takes the whole correction, in its own frame, where its
  // inertia is diagonal
  BodyState& body = state.bodies[pin.segment];
  const Segment& segment = model.segments[pin.segment];
  const Vector3d& r = pin.local_point;
  const Vector3d gap = body.q.conjugate() * (target - body.x) - r;
  const Vector3d impulse = compliant_solve(
      diagonal_point_mass_matrix(segment.inv_mass, segment.inv_inertia, r), gap, alpha_tilde,
      lambda, [&](const Vector3d& w) { return Vector3d(body.q.conjugate() * w); },
      [&](const Vector3d& f) { return Vector3d(body.q * f); });
  body.x += segment.inv_mass * (body.q * impulse);
  body.q = times_exp(body.q, segment.inv_inertia.cwiseProduct(r.cross(impulse)));
}

void hold_root(const Model& model, const Matrix3d* start, State& state) {
  const RootJoint& root = model.root;
  if (root.hold == RootHold::kFree) return;
  BodyState& body = state.bodies[0];
  const Segment& segment = model.segments[0];
  const int slides = root_slide_count(root.hold);
  const int hinge = root_hinge_index(root.hold);
  // the anchor: the gap to where the hold lets it be, and the projector on the held directions
  const Vector3d r = body.q * root.anchor_in_root;
  Vector3d gap = root.anchor_world - (body.x + r);
  Matrix3d held = Matrix3d::Identity();
  for (int k = 0; k < slides; ++k) {
    const Vector3d& a = root.axes[static_cast<size_t>(k)];
    const double along = -a.dot(gap);  // the slide's coordinate
    held -= a * a.transpose();
    gap -= a.dot(gap) * a;
    // a slide's range: past an end, the direction is held back to it
    if (root.limited && (along > root.upper || along < root.lower)) {
      gap += (std::clamp(along, root.lower, root.upper) - along) * a;
      held += a * a.transpose();
    }
  }
  if (gap.squaredNorm() > 0.0) {
    // the lever arms at the substep's start or at the current pose (Settings::start_lever_arms);
    // the root turns only as its hold lets it (W restricted to its free rotations: none under a
    // weld or a slide, the hinge's axis, a ball's all), so the anchor's correction moves it along
    // no free direction
    const Quaterniond& arms = start ? state.q_prev[0] : body.q;
    const Vector3d r0 = arms * root.anchor_in_root;
    const Matrix3d rotation = arms.toRotationMatrix();
    Matrix3d w0 = Matrix3d::Zero();
    if (root.hold == RootHold::kBall) {
      w0 = start ? start[0]
                 : Matrix3d(rotation * segment.inv_inertia.asDiagonal() * rotation.transpose());
    } else if (hinge >= 0) {
      const Vector3d& a = root.axes[static_cast<size_t>(hinge)];
      const Vector3d local = rotation.transpose() * a;
      w0 = a * a.transpose() / local.dot(segment.inertia.cwiseProduct(local));
    }
    Matrix3d k = start_arm_response(r, w0, r0);
    k.diagonal().array() += segment.inv_mass;
    // K restricted to the held directions; the free ones take no impulse
    const Matrix3d restricted = held * k * held + (Matrix3d::Identity() - held);
    const Vector3d impulse = held * solve3(restricted, gap);
    body.x += segment.inv_mass * impulse;
    body.q = renormalized(quat_exp(w0 * r0.cross(impulse)) * body.q);
  }
  // the orientation, turned about the anchor: back by the held turn, and a hinge's range
  Vector3d turn = -root_held_turn(model, body.q);  // the rotation (world) the root needs
  if (root.limited && root.hold == RootHold::kHinge) {
    const double angle = root_coordinates(model, body).value[0];
    turn += (std::clamp(angle, root.lower, root.upper) - angle) * root.axes[0];
  }
  if (turn.squaredNorm() > 0.0) {
    const Vector3d anchor = body.x + body.q * root.anchor_in_root;
    const Quaterniond rotation = quat_exp(turn);
    body.x = anchor + rotation * (body.x - anchor);
    body.q = renormalized(rotation * body.q);
  }
}

void share_joint_correction(const Model& model, const JointTerms& terms, const Joint& joint,
                            double alpha_tilde, Vector3d* lambda, const Matrix3d* start,
                            State& state) {
  if (start) {
    BodyState& parent = state.bodies[joint.parent];
    BodyState& child = state.bodies[joint.child];
    const double inv_mass_parent = model.segments[joint.parent].inv_mass;
    const double inv_mass_child = model.segments[joint.child].inv_mass;
    const Matrix3d& w0_parent = start[joint.parent];
    const Matrix3d& w0_child = start[joint.child];
    // a box of hinges at different points carries the parent's point along its angles, a slide
    // along its direction
    const bool slide = joint.type == JointType::kSlide;
    const SlideSide along = slide ? slide_side(joint, parent, child) : SlideSide{};
    const Vector3d anchor_parent = slide ? along.anchor : parent_anchor(joint, parent.q, child.q);
    const Vector3d r_parent = parent.q * anchor_parent;
    const Vector3d r_child = child.q * joint.anchor_in_child;
    const Vector3d r0_parent = state.q_prev[joint.parent] * anchor_parent;
    const Vector3d r0_child = state.q_prev[joint.child] * joint.anchor_in_child;
    Matrix3d k = start_arm_response(r_child, w0_child, r0_child) +
                 start_arm_response(r_parent, w0_parent, r0_parent);
    k.diagonal().array() += inv_mass_parent + inv_mass_child;
    // the impulse on the child (world); the parent takes its opposite
    const Vector3d impulse =
        world_compliant_solve(k, (parent.x + r_parent) - (child.x + r_child), alpha_tilde, lambda,
                              slide ? &along.held : nullptr);
    child.x += inv_mass_child * impulse;
    child.q = quat_exp(w0_child * r0_child.cross(impulse)) * child.q;
    parent.x -= inv_mass_parent * impulse;
    parent.q = quat_exp(-(w0_parent * r0_parent.cross(impulse))) * parent.q;
    return;
  }
  // everything in the child's frame: each side's K is constant in its own frame
  // (JointTerms::point_mass), and R, the parent's frame seen from the child's, carries K_p over
  BodyState& parent = state.bodies[joint.parent];
  BodyState& child = state.bodies[joint.child];
  const Segment& parent_segment = model.segments[joint.parent];
  const Segment& child_segment = model.segments[joint.child];
  const Matrix3d rotation = (child.q.conjugate() * parent.q).toRotationMatrix();
  const bool slide = joint.type == JointType::kSlide;
  ParentSide side;
  Matrix3d held;  // a slide's, in the child's frame
  if (slide) {
    const SlideSide along = slide_side(joint, parent, child);
    const Matrix3d to_child = child.q.conjugate().toRotationMatrix();
    side = {along.anchor, diagonal_point_mass_matrix(parent_segment.inv_mass,
                                                     parent_segment.inv_inertia, along.anchor)};
    held = to_child * along.held * to_child.transpose();
  } else {
    side = parent_side(model, terms, joint, parent.q, child.q);
  }
  const Vector3d& anchor_parent = side.anchor;
  const Matrix3d k = terms.point_mass[1] + rotation * side.point_mass * rotation.transpose();
  const Vector3d gap =
      child.q.conjugate() * (parent.x - child.x) + rotation * anchor_parent - joint.anchor_in_child;
  // the impulse on the child, in its frame
  const Vector3d impulse = compliant_solve(
      k, gap, alpha_tilde, lambda,
      [&](const Vector3d& w) { return Vector3d(child.q.conjugate() * w); },
      [&](const Vector3d& f) { return Vector3d(child.q * f); }, slide ? &held : nullptr);
  const Vector3d impulse_parent = rotation.transpose() * impulse;
  const Vector3d impulse_world = child.q * impulse;
  child.x += child_segment.inv_mass * impulse_world;
  child.q = times_exp(child.q,
                      child_segment.inv_inertia.cwiseProduct(joint.anchor_in_child.cross(impulse)));
  parent.x -= parent_segment.inv_mass * impulse_world;
  parent.q = times_exp(
      parent.q, -parent_segment.inv_inertia.cwiseProduct(anchor_parent.cross(impulse_parent)));
}

bool share_limit_correction(const Model& model, const JointTerms& terms, const Joint& joint,
                            double alpha_tilde, Vector3d* lambda, LimitRows* rows, bool functions,
                            State& state) {
  BodyState& parent = state.bodies[joint.parent];
  BodyState& child = state.bodies[joint.child];
  const Quaterniond child_to_parent = child.q.conjugate() * parent.q;
  Vector3d error;  // the rotation the child needs, parent fixed, in the child's frame
  rows->count = 0;
  if (!limit_error(joint, terms, child_to_parent, &error, rows, functions)) return false;
  // a hinge's error also removes its swing, which is no limit the velocity pass holds: its row is
  // its angle's, when past an end
  if (joint.type == JointType::kHinge) {
    *rows = limit_rows(joint, joint_relative_rotation(joint, parent.q, child.q), 0.0);
  }
  const bool past = rows->count > 0;
  const Vector3d& inv_parent = model.segments[joint.parent].inv_inertia;
  const Vector3d& inv_child = model.segments[joint.child].inv_inertia;
  const Matrix3d rotation = child_to_parent.toRotationMatrix();
  Matrix3d inv_sum = rotation * inv_parent.asDiagonal() * rotation.transpose();
  inv_sum.diagonal() += inv_child;
  const Vector3d impulse = compliant_solve(
      inv_sum, error, alpha_tilde, lambda,
      [&](const Vector3d& w) { return Vector3d(child.q.conjugate() * w); },
      [&](const Vector3d& f) { return Vector3d(child.q * f); });
  child.q = times_exp(child.q, inv_child.cwiseProduct(impulse));
  parent.q = times_exp(parent.q, -inv_parent.cwiseProduct(rotation.transpose() * impulse));
  return past;
}

}  // namespace puppet::procedural
