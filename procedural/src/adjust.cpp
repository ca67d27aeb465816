// Stage 2, adjust (seed §3.3): pins, joints and limits in one pass over the tree from the
// anchor (the first pinned segment, else the root).
//
// For each link the placed segment is a (fixed) and the moved one b: close_point() gives the
// forced rotation of the rule and the translation of eq. 5, then limited_orientation() clamps the
// joint (eq. 4) and rotates b about the joint point, which keeps the joint closed. A pin is a
// joint between the world (a) and a point of its segment. For a single segment the weighted
// rotation is a constant matrix of the gap in b's frame (JointTerms::rotation_gain).
//
// Rule `subtree` moves the whole subtree hanging from b as one rigid body: composite mass and
// inertia come from one backward pass, and each segment's accumulated motion is composed on the
// way down, so the pass stays O(n).
//
// Rule `relaxed` first runs `iterations` two-sided sweeps (Gauss–Seidel, as position-based
// dynamics does): pins, then every joint, then every limit, then the ground contacts. Every
// correction is shared by both sides through K_a + K_b (a joint's in the child's frame, where
// both sides' K are constants but for the parent's rotation into it); then the one-sided
// `weighted` pass closes every joint exactly.
//
// seed: with two pins the pass starts from the first; every other pin is closed on its own
// segment before the pass (world as a), so the pass leaves the joints closed and what is left
// of the other pins' gaps is reported as pin_gap_m.
#include "puppet/model/rotation.h"
#include "stages.h"

namespace puppet::procedural {
namespace {

Matrix3d skew_square_term(const Vector3d& r, double mass) {
  // m (|r|² E − r rᵀ): the parallel-axis term
  return mass * (r.squaredNorm() * Matrix3d::Identity() - r * r.transpose());
}

// composite mass properties of every preorder subtree, from the current poses
void build_subtrees(const Model& model, const AnchorOrder& order, const State& state,
                    Workspace& ws) {
  const int n = static_cast<int>(order.preorder.size());
  for (int k = 0; k < n; ++k) {
    const int seg = order.preorder[k];
    const Segment& segment = model.segments[seg];
    const BodyState& body = state.bodies[seg];
    const Matrix3d rotation = body.q.toRotationMatrix();
    ws.subtree_mass[k] = segment.mass;
    ws.subtree_moment[k] = segment.mass * body.x;
    ws.subtree_second[k] = rotation * segment.inertia.asDiagonal() * rotation.transpose() +
                           skew_square_term(body.x, segment.mass);
  }
  for (int k = n - 1; k > 0; --k) {
    const int p = order.parent_position[k];
    ws.subtree_mass[p] += ws.subtree_mass[k];
    ws.subtree_moment[p] += ws.subtree_moment[k];
    ws.subtree_second[p] += ws.subtree_second[k];
  }
}

// the composite body of subtree k, moved by `motion` (the accumulated motion of its parent)
MovingBody composite_body(const Workspace& ws, int k, const Motion& motion) {
  MovingBody body;
  body.mass = ws.subtree_mass[k];
  body.inv_mass = 1.0 / body.mass;
  const Vector3d centre = ws.subtree_moment[k] / body.mass;
  body.centre = motion.apply(centre);
  // the tensor stays in the orientation of the pass's start, which the accumulated motion has
  // turned into the current one: no R I Rᵀ per link
  body.frame = motion.q;
  body.inertia = ws.subtree_second[k] - skew_square_term(centre, body.mass);
  body.inertia_inv = body.inertia.inverse();
  return body;
}

// the joint point in a's frame and in b's frame
struct LinkAnchors {
  const Vector3d& local_a;
  const Vector3d& local_b;
};
LinkAnchors link_anchors(const Joint& joint, const AnchorOrder::Link& link) {
  if (link.b_is_child) return {joint.anchor_in_parent, joint.anchor_in_child};
  return {joint.anchor_in_child, joint.anchor_in_parent};
}

// close the joint of link k and clamp its limits for a composite b (rule `subtree`); returns the
// motion applied to everything b carries
Motion close_link(const Model& model, const JointTerms& terms, Rule rule,
                  const AnchorOrder::Link& link, const MovingBody& body, const BodyState& a,
                  const BodyState& b_current) {
  const Joint& joint = model.joints[link.joint];
  const auto [local_a, local_b] = link_anchors(joint, link);
  const Vector3d c_a = world_point(a, local_a);
  const Motion closing =
      close_point(rule, body, world_point(b_current, local_b), c_a).motion(body.centre);

  // eq. 4: clamp to the limits, rotating b about the (now closed) joint point
  const Quaterniond b_closed = closing.rotates() ? closing.q * b_current.q : b_current.q;
  const Quaterniond clamp = limit_correction(joint, terms, link.b_is_child, a.q, b_closed);
  const Motion clamping = Motion::about(clamp, c_a);
  return clamping.rotates() ? clamping.after(closing) : closing;
}

// close_link for a single segment b, applied in place: b's joint point is known in its own
// frame, so the motion is never built: b is turned (the rule's rotation, then the clamp) and
// placed with its joint point on c_a, or only translated when neither turns it
void close_segment_link(const Model& model, const JointTerms& terms, Rule rule,
                        const AnchorOrder::Link& link, const BodyState& a, BodyState& b) {
  const Joint& joint = model.joints[link.joint];
  const auto [local_a, local_b] = link_anchors(joint, link);
  const Vector3d c_a = world_point(a, local_a);
  Quaterniond turned;
  if (rule == Rule::kWeighted) {
    // the gap in b's frame, where the weighted rotation is a constant matrix of it
    const Vector3d gap = b.q.conjugate() * (c_a - b.x) - local_b;
    turned = times_exp(b.q, terms.rotation_gain[link.b_is_child] * gap);
  } else {
    // nearly every literal link is a pure translation by s, decided as close_point() does but
    // from the side's constant bound
    const Vector3d c_b = world_point(b, local_b);
    const Vector3d s = c_a - c_b;
    Correction closing{Quaterniond::Identity(), s};
    if (rule != Rule::kLiteral ||
        (c_b - b.x).cross(s).squaredNorm() >= terms.literal_still_cross2[link.b_is_child]) {
      closing = close_point(rule, single_body(model.segments[link.b], b), c_b, c_a);
    }
    if (!closing.rotates()) {
      // a pure translation: the clamp, if any, turns b about c_a
      b.x += closing.translation;
      if (!limited_orientation(joint, terms, link.b_is_child, a.q, b.q, &b.q)) {
        return;
      }
      b.q = renormalized(b.q);
      b.x = c_a - b.q * local_b;
      return;
    }
    turned = closing.rotation * b.q;
  }
  // eq. 5 for the rotated b, then eq. 4: either way its joint point ends at c_a
  limited_orientation(joint, terms, link.b_is_child, a.q, turned, &turned);
  b.q = renormalized(turned);
  b.x = c_a - b.q * local_b;
}

// a pin closed by moving its own segment alone (the world is a): the weighted correction in place,
// or the rule's forced rotation and translation
void close_pin(const Model& model, Rule rule, const Pin& pin, const Vector3d& target,
               BodyState& body) {
  const Segment& segment = model.segments[pin.segment];
  if (rule == Rule::kWeighted) {
    close_segment_point(segment, pin.local_point, target, body);
    return;
  }
  close_point(rule, single_body(segment, body), world_point(body, pin.local_point), target)
      .apply(body);
}

// whether a pin is closed by this one-sided pass
bool closes(PinClosure closure, const Pin& pin) {
  return closure == PinClosure::kAll ||
         (closure == PinClosure::kRigidOnly && pin.compliance == 0.0);
}

void close_secondary_pins(const Model& model, Rule rule, PinClosure closure,
                          const PinTargets& targets, State& state) {
  const Rule single = rule == Rule::kSubtree ? Rule::kWeighted : rule;
  for (int i = 1; i < state.pin_count; ++i) {
    const Pin& pin = state.pins[i];
    if (!closes(closure, pin)) continue;
    close_pin(model, single, pin, targets[i], state.bodies[pin.segment]);
  }
}

// A compliant pin (C > 0) closed by one one-sided correction: its target moved back toward the
// point by what the compliance holds, t' = t − α̃ (K + α̃E)⁻¹ (t − p), α̃ = C/h², with K the
// pinned segment's own point mass (XPBD's first iteration, λ = 0). seed: the one-sided rules
// then carry the rest of the body along: a parent never feels its children, so the spring
// stretches as if only the pinned segment hung from it (measured in the tests).
void soften_compliant_targets(const Model& model, const State& state, double h,
                              PinTargets& targets) {
  for (int i = 0; i < state.pin_count; ++i) {
    const Pin& pin = state.pins[i];
    if (pin.compliance == 0.0) continue;
    const Segment& segment = model.segments[pin.segment];
    const BodyState& body = state.bodies[pin.segment];
    const double alpha_tilde = pin.compliance / (h * h);
    Matrix3d k = diagonal_point_mass_matrix(segment.inv_mass, segment.inv_inertia, pin.local_point);
    k.diagonal().array() += alpha_tilde;
    const Vector3d gap = body.q.conjugate() * (targets[i] - body.x) - pin.local_point;
    targets[i] -= alpha_tilde * (body.q * solve3(k, gap));
  }
}

void relaxed_sweeps(const Model& model, std::span<const JointTerms> joints,
                    const Settings& settings, const Environment& environment,
                    const AnchorOrder& order, const PinTargets& targets, State& state,
                    Workspace& ws, double h) {
  for (int i = 0; i < state.pin_count; ++i) ws.pin_lambda[i].setZero();
  for (int iteration = 0; iteration < settings.iterations; ++iteration) {
    for (int i = 0; i < state.pin_count; ++i) {
      const Pin& pin = state.pins[i];
      share_pin_correction(model, pin, targets[i], pin.compliance / (h * h), &ws.pin_lambda[i],
                           state);
    }
    // every joint, then every limit: a limit corrected right after its own joint is partly undone
    // by the next joint's correction, and what a sweep leaves past a limit the final one-sided
    // pass clamps at the cost of the pins (measured: twice as many runs diverged, see README)
    for (const AnchorOrder::Link& link : order.links) {
      share_joint_correction(model, joints[link.joint], model.joints[link.joint], 0.0, nullptr,
                             state);
    }
    for (const AnchorOrder::Link& link : order.links) {
      share_limit_correction(model, joints[link.joint], model.joints[link.joint], 0.0, nullptr,
                             state);
    }
    // the shared corrections compose unit quaternions and leave them unnormalised (off by a
    // few ulps): one renormalisation per segment and sweep instead of one per correction
    for (BodyState& body : state.bodies) body.q = renormalized(body.q);
    if (environment.ground) {
      for (int s = 0; s < model.segment_count(); ++s) {
        push_out_of_ground(model, environment, s, state);
      }
    }
  }
}

}  // namespace

void one_sided_pass(const Model& model, std::span<const JointTerms> joints, Rule rule,
                    const AnchorOrder& order, PinClosure closure, const PinTargets& targets,
                    State& state, Workspace& ws) {
  const bool pinned = state.pin_count > 0 && state.pins[0].segment == order.anchor &&
                      closes(closure, state.pins[0]);
  close_secondary_pins(model, rule, closure, targets, state);
  const bool subtree = rule == Rule::kSubtree;
  if (subtree) build_subtrees(model, order, state, ws);

  // the anchor: closed to its pin (a joint with the world), else left where update put it
  BodyState& anchor = state.bodies[order.anchor];
  Motion anchor_motion;
  if (pinned && subtree) {
    const MovingBody body = composite_body(ws, 0, Motion());
    anchor_motion =
        close_point(rule, body, world_point(anchor, state.pins[0].local_point), targets[0])
            .motion(body.centre);
    anchor_motion.apply(anchor);
  } else if (pinned) {
    close_pin(model, rule, state.pins[0], targets[0], anchor);
  }
  if (subtree) {
    ws.motion_q[0] = anchor_motion.q;
    ws.motion_t[0] = anchor_motion.t;
  }

  // every joint, parent-before-child from the anchor
  if (!subtree) {
    for (const AnchorOrder::Link& link : order.level_links) {
      close_segment_link(model, joints[link.joint], rule, link, state.bodies[link.a],
                         state.bodies[link.b]);
    }
    return;
  }
  const int links = static_cast<int>(order.links.size());
  for (int k = 0; k < links; ++k) {
    const AnchorOrder::Link& link = order.links[k];
    const int position = k + 1;
    BodyState& b = state.bodies[link.b];
    const int parent = order.parent_position[position];
    const Motion inherited{ws.motion_q[parent], ws.motion_t[parent]};
    BodyState current = b;
    inherited.apply(current);
    const Motion motion =
        close_link(model, joints[link.joint], rule, link, composite_body(ws, position, inherited),
                   state.bodies[link.a], current);
    const Motion total = motion.after(inherited);
    ws.motion_q[position] = total.q;
    ws.motion_t[position] = total.t;
    b = current;
    motion.apply(b);
  }
}

void adjust(const Model& model, const Settings& settings, const Environment& environment,
            const ModelTables& tables, int anchor, const PinTargets& targets, State& state,
            Workspace& ws, double h) {
  // the pins' pull, expressed as the force that would close them in one step (eq. 2's f)
  for (int i = 0; i < state.pin_count; ++i) {
    const Pin& pin = state.pins[i];
    const double gap =
        (targets[i] - world_point(state.bodies[pin.segment], pin.local_point)).norm();
    state.pin_force[i] = 2.0 * model.segments[pin.segment].mass * gap / (h * h);
  }
  const AnchorOrder& order = anchor_order(model, tables, ws, anchor);
  switch (settings.rule) {
    case Rule::kXpbd:
      // two-sided sweeps only: no one-sided closure
      xpbd_sweeps(model, tables.joints, settings, environment, order, targets, state, ws, h);
      return;
    case Rule::kTree:
      // the exact projection, Newton-iterated: no one-sided closure either
      tree_projection(model, tables.joints, settings, environment, order, targets, state, ws, h);
      return;
    case Rule::kRelaxed:
      // the sweeps share every correction, then the one-sided pass closes the joints exactly
      // from the anchor; a compliant pin was the sweeps' to pull, and the pass leaves it be
      relaxed_sweeps(model, tables.joints, settings, environment, order, targets, state, ws, h);
      one_sided_pass(model, tables.joints, Rule::kWeighted, order, PinClosure::kRigidOnly, targets,
                     state, ws);
      return;
    case Rule::kLiteral:
    case Rule::kSmoothed:
    case Rule::kWeighted:
    case Rule::kSubtree: {
      PinTargets closing = targets;
      soften_compliant_targets(model, state, h, closing);
      one_sided_pass(model, tables.joints, settings.rule, order, PinClosure::kAll, closing, state,
                     ws);
      return;
    }
  }
}

}  // namespace puppet::procedural
