// Rule `subtree`: the one-sided pass, moving the whole subtree hanging from b as one rigid body
// (the seed's "the segments beyond b follow it"). Composite mass and inertia come from one
// backward pass over the anchor order, and each segment's accumulated motion is composed on the
// way down, so the pass stays O(n). Each composite is closed by the weighted correction of its
// tensor (weighted_rotation), then clamped about the joint point (docs/solver.md, "subtree").
#include "puppet/model/rotation.h"
#include "rules.h"

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

}  // namespace

void subtree_pass(const Model& model, std::span<const JointTerms> joints, const AnchorOrder& order,
                  bool pinned, const PinTargets& targets, State& state, Workspace& ws) {
  const Rule rule = Rule::kSubtree;
  build_subtrees(model, order, state, ws);
  // the anchor: its whole body closed to its pin (a joint with the world), else left where
  // update put it
  BodyState& anchor = state.bodies[order.anchor];
  Motion anchor_motion;
  if (pinned) {
    const MovingBody body = composite_body(ws, 0, Motion());
    anchor_motion =
        close_point(rule, body, world_point(anchor, state.pins[0].local_point), targets[0])
            .motion(body.centre);
    anchor_motion.apply(anchor);
  }
  ws.motion_q[0] = anchor_motion.q;
  ws.motion_t[0] = anchor_motion.t;
  // every joint, parent-before-child from the anchor
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

}  // namespace puppet::procedural
