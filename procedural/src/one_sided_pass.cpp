// The one-sided pass of the seed's adjust step (§3.3): one walk over the tree from the anchor
// (the first pinned segment, else the root), parents before children. For each link the placed
// segment is a (fixed) and the moved one b: the rule's forced rotation and the translation of
// eq. 5 close the joint (forced_rotation.cpp), then the limit clamp (eq. 4, joint_limits.cpp) turns
// b about the joint point, which keeps the joint closed. A pin is a joint between the world (a) and
// a point of its segment. For a single segment the weighted rotation is a constant matrix of the
// gap in b's frame (JointTerms::rotation_gain). Rule subtree moves whole subtrees instead
// (rules/subtree.cpp).
//
// seed: with two pins the pass starts from the first; every other pin is closed on its own
// segment before the pass (world as a), so the pass leaves the joints closed and what is left
// of the other pins' gaps is reported as pin_gap_m.
#include "puppet/model/rotation.h"
#include "rules/catalogue.h"

namespace puppet::procedural {
namespace {

// close_link for a single segment b, applied in place: b's joint point is known in its own
// frame, so the motion is never built: b is turned (the rule's rotation, then the clamp) and
// placed with its joint point on c_a, or only translated when neither turns it
void close_segment_link(const Model& model, const JointTerms& terms, const RuleRow& row,
                        const AnchorOrder::Link& link, const BodyState& a, BodyState& b) {
  const Joint& joint = model.joints[link.joint];
  const auto [local_a, local_b] = link_anchors(joint, link);
  const Vector3d c_a = world_point(a, local_a);
  Quaterniond turned;
  if (row.one_sided.constant_gain) {
    // the gap in b's frame, where the weighted rotation is a constant matrix of it
    const Vector3d gap = b.q.conjugate() * (c_a - b.x) - local_b;
    turned = times_exp(b.q, terms.rotation_gain[link.b_is_child] * gap);
  } else {
    // with a translation bound (literal) nearly every link is a pure translation by s, decided
    // as close_point() does but from the side's constant bound
    const Vector3d c_b = world_point(b, local_b);
    const Vector3d s = c_a - c_b;
    Correction closing{Quaterniond::Identity(), s};
    if (!row.one_sided.translation_bound ||
        (c_b - b.x).cross(s).squaredNorm() >= terms.literal_still_cross2[link.b_is_child]) {
      closing = close_point(row.rule, single_body(model.segments[link.b], b), c_b, c_a);
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
void close_pin(const Model& model, const RuleRow& row, const Pin& pin, const Vector3d& target,
               BodyState& body) {
  const Segment& segment = model.segments[pin.segment];
  if (row.one_sided.constant_gain) {
    close_segment_point(segment, pin.local_point, target, body);
    return;
  }
  close_point(row.rule, single_body(segment, body), world_point(body, pin.local_point), target)
      .apply(body);
}

// whether a pin is closed by this one-sided pass
bool closes(PinClosure closure, const Pin& pin) {
  return closure == PinClosure::kAll ||
         (closure == PinClosure::kRigidOnly && pin.compliance == 0.0);
}

void close_secondary_pins(const Model& model, const RuleRow& row, PinClosure closure,
                          const PinTargets& targets, State& state) {
  const RuleRow& single = rule_row(row.one_sided.lone_segment.value_or(row.rule));
  for (int i = 1; i < state.pin_count; ++i) {
    const Pin& pin = state.pins[i];
    if (!closes(closure, pin)) continue;
    close_pin(model, single, pin, targets[i], state.bodies[pin.segment]);
  }
}

}  // namespace

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

void one_sided_pass(const Model& model, std::span<const JointTerms> joints, Rule rule,
                    const AnchorOrder& order, PinClosure closure, const PinTargets& targets,
                    State& state, Workspace& ws) {
  const bool pinned = state.pin_count > 0 && state.pins[0].segment == order.anchor &&
                      closes(closure, state.pins[0]);
  const RuleRow& row = rule_row(rule);
  close_secondary_pins(model, row, closure, targets, state);
  if (row.one_sided.walk) {
    row.one_sided.walk(model, joints, order, pinned, targets, state, ws);
    return;
  }
  // the anchor: closed to its pin (a joint with the world), else left where update put it
  if (pinned) close_pin(model, row, state.pins[0], targets[0], state.bodies[order.anchor]);
  // every joint, parent-before-child from the anchor
  for (const AnchorOrder::Link& link : order.level_links) {
    close_segment_link(model, joints[link.joint], row, link, state.bodies[link.a],
                       state.bodies[link.b]);
  }
}

void one_sided_adjust(const Model& model, std::span<const JointTerms> joints,
                      const Settings& settings, const Environment& /*environment*/,
                      const AnchorOrder& order, const PinTargets& targets, State& state,
                      Workspace& ws, double h) {
  PinTargets closing = targets;
  soften_compliant_targets(model, state, h, closing);
  one_sided_pass(model, joints, settings.rule, order, PinClosure::kAll, closing, state, ws);
}

}  // namespace puppet::procedural
