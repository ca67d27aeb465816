#include "puppet/procedural/solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "stages.h"

namespace puppet::procedural {

std::string_view rule_name(Rule rule) {
  switch (rule) {
    case Rule::kLiteral:
      return "literal";
    case Rule::kSmoothed:
      return "smoothed";
    case Rule::kWeighted:
      return "weighted";
    case Rule::kSubtree:
      return "subtree";
    case Rule::kRelaxed:
      return "relaxed";
    case Rule::kXpbd:
      return "xpbd";
    case Rule::kTree:
      return "tree";
  }
  return "?";
}

std::optional<Rule> parse_rule(std::string_view name) {
  for (Rule rule : kAllRules) {
    if (rule_name(rule) == name) return rule;
  }
  return std::nullopt;
}

std::string validate(const Settings& settings) {
  if (settings.iterations != kRuleDefault &&
      (settings.iterations < 0 || settings.iterations > 1000))
    return "iterations must be in [0, 1000]";
  if (settings.substeps != kRuleDefault && (settings.substeps < 1 || settings.substeps > 1000))
    return "substeps must be in [1, 1000]";
  if (!(settings.joint_compliance >= 0.0 && settings.joint_compliance <= 1e6))
    return "joint compliance must be in [0, 1e6] m/N";
  if (!(settings.limit_compliance >= 0.0 && settings.limit_compliance <= 1e6))
    return "limit compliance must be in [0, 1e6] rad/(N m)";
  return {};
}

Settings rule_defaults(Settings settings) {
  // xpbd: many short substeps of one sweep each (Müller et al. 2020), the count chosen by
  // measurement (docs: the substep sweep); relaxed: the four sweeps of one step the seed's pass
  // closes; the other rules make one pass and read no iterations
  // tree: a few substeps of a few Newton iterations of the exact projection
  int iterations = 4, substeps = 1;
  if (settings.rule == Rule::kXpbd) {
    iterations = 1;
    substeps = kXpbdSubsteps;
  } else if (settings.rule == Rule::kTree) {
    iterations = kTreeIterations;
    substeps = kTreeSubsteps;
  }
  if (settings.iterations == kRuleDefault) settings.iterations = iterations;
  if (settings.substeps == kRuleDefault) settings.substeps = substeps;
  return settings;
}

Incidence make_incidence(const Model& model) {
  const int n = model.segment_count();
  Incidence incidence;
  incidence.offsets.assign(n + 1, 0);
  for (const Joint& joint : model.joints) {
    ++incidence.offsets[joint.parent + 1];
    ++incidence.offsets[joint.child + 1];
  }
  for (int s = 0; s < n; ++s) incidence.offsets[s + 1] += incidence.offsets[s];
  incidence.joints.resize(incidence.offsets[n]);
  std::vector<int> filled(incidence.offsets.begin(), incidence.offsets.end() - 1);
  for (int j = 0; j < model.joint_count(); ++j) {
    incidence.joints[filled[model.joints[j].parent]++] = j;
    incidence.joints[filled[model.joints[j].child]++] = j;
  }
  return incidence;
}

void AnchorOrderScratch::reserve(int segments) {
  position.resize(segments);
  depth.resize(segments);
  depth_start.resize(segments + 1);
  stack.reserve(segments);
}

void fill_anchor_order(const Model& model, const Incidence& incidence, int anchor,
                       AnchorOrder& order, AnchorOrderScratch& scratch) {
  const int n = model.segment_count();
  order.anchor = anchor;
  order.links.clear();
  order.preorder.clear();
  order.parent_position.assign(n, -1);
  std::vector<int>& position = scratch.position;
  std::fill(position.begin(), position.end(), -1);
  // depth-first preorder: parents before children, and every subtree a contiguous range
  auto& stack = scratch.stack;
  stack.clear();
  stack.push_back({anchor, -1, -1});
  while (!stack.empty()) {
    const AnchorOrderScratch::Frame frame = stack.back();
    stack.pop_back();
    const int k = static_cast<int>(order.preorder.size());
    position[frame.segment] = k;
    order.preorder.push_back(frame.segment);
    order.parent_position[k] = frame.from_position;
    if (frame.via_joint >= 0) {
      const Joint& joint = model.joints[frame.via_joint];
      const bool b_is_child = joint.child == frame.segment;
      order.links.push_back(
          {frame.via_joint, b_is_child ? joint.parent : joint.child, frame.segment, b_is_child});
    }
    // the segment's joints in reverse, so that the first one is walked first
    for (int e = incidence.offsets[frame.segment + 1] - 1; e >= incidence.offsets[frame.segment];
         --e) {
      const Joint& joint = model.joints[incidence.joints[e]];
      const int other = joint.parent == frame.segment ? joint.child : joint.parent;
      if (position[other] < 0) stack.push_back({other, incidence.joints[e], k});
    }
  }
  // breadth-first: depth by depth, in preorder within a depth (a counting sort, O(n))
  std::vector<int>& depth = scratch.depth;
  std::vector<int>& start = scratch.depth_start;
  std::fill(start.begin(), start.end(), 0);
  if (n > 0) depth[0] = 0;
  for (int k = 1; k < n; ++k) {
    depth[k] = depth[order.parent_position[k]] + 1;
    ++start[depth[k]];
  }
  for (int d = 1; d <= n; ++d) start[d] += start[d - 1];  // start[d]: links of depth ≤ d
  order.level_links.resize(order.links.size());
  for (int k = n - 1; k > 0; --k) order.level_links[--start[depth[k]]] = order.links[k - 1];
  // subtree ends, from the back: a subtree ends where its last descendant's does
  order.subtree_end.resize(n);
  for (int k = 0; k < n; ++k) order.subtree_end[k] = k + 1;
  for (int k = n - 1; k > 0; --k) {
    const int p = order.parent_position[k];
    order.subtree_end[p] = std::max(order.subtree_end[p], order.subtree_end[k]);
  }
}

AnchorOrder make_anchor_order(const Model& model, int anchor) {
  AnchorOrder order;
  AnchorOrderScratch scratch;
  scratch.reserve(model.segment_count());
  fill_anchor_order(model, make_incidence(model), anchor, order, scratch);
  return order;
}

const AnchorOrder& anchor_order(const Model& model, const ModelTables& tables, Workspace& ws,
                                int anchor) {
  if (!tables.orders.empty()) return tables.orders[anchor];
  for (int slot = 0; slot < 2; ++slot) {
    if (ws.order_anchor[slot] == anchor) return ws.orders[slot];
  }
  const int slot = ws.order_next;
  ws.order_next = 1 - slot;
  fill_anchor_order(model, tables.incidence, anchor, ws.orders[slot], ws.order_scratch);
  ws.order_anchor[slot] = anchor;
  return ws.orders[slot];
}

namespace {

JointTerms make_joint_terms(const Model& model, const Joint& joint) {
  JointTerms terms;
  terms.limit_free_w = limit_free_w(joint);
  terms.frame_shift = joint.frame_in_child * joint.frame_in_parent.conjugate();
  const std::array<const Segment*, 2> segments = {&model.segments[joint.parent],
                                                  &model.segments[joint.child]};
  const std::array<const Vector3d*, 2> anchors = {&joint.anchor_in_parent, &joint.anchor_in_child};
  for (int side = 0; side < 2; ++side) {
    const Segment& segment = *segments[side];
    const Vector3d& r = *anchors[side];
    terms.point_mass[side] = diagonal_point_mass_matrix(segment.inv_mass, segment.inv_inertia, r);
    // the impulse λ = K⁻¹ s closes the gap s; it turns the segment by D⁻¹ (r × λ)
    terms.rotation_gain[side] =
        segment.inv_inertia.asDiagonal() * cross_matrix(r) * terms.point_mass[side].inverse();
    const double still = literal_still_cross(segment.inertia.maxCoeff());
    terms.literal_still_cross2[side] = still * still;
  }
  return terms;
}

}  // namespace

std::shared_ptr<const ModelTables> make_model_tables(const Model& model) {
  auto tables = std::make_shared<ModelTables>();
  tables->incidence = make_incidence(model);
  if (model.segment_count() <= kKeptOrderSegments) {
    AnchorOrderScratch scratch;
    scratch.reserve(model.segment_count());
    tables->orders.resize(model.segment_count());
    for (int anchor = 0; anchor < model.segment_count(); ++anchor) {
      fill_anchor_order(model, tables->incidence, anchor, tables->orders[anchor], scratch);
    }
  }
  tables->joints.reserve(model.joint_count());
  for (const Joint& joint : model.joints) tables->joints.push_back(make_joint_terms(model, joint));
  return tables;
}

Solver::Solver(const Model& model, const Settings& settings, const Environment& environment,
               std::shared_ptr<const ModelTables> tables)
    : model_(model),
      settings_(rule_defaults(settings)),
      environment_(environment),
      tables_(std::move(tables)) {
  const std::string problem = validate(settings);
  if (!problem.empty()) throw std::invalid_argument(problem);
  const int n = model.segment_count();
  state_.bodies.resize(n);
  state_.x_prev.resize(n);
  state_.q_prev.resize(n);
  state_.user_force.assign(n, Vector3d::Zero());
  state_.user_torque.assign(n, Vector3d::Zero());
  state_.tremble_offset.assign(n, Vector3d::Zero());
  workspace_.subtree_mass.resize(n);
  workspace_.subtree_moment.resize(n);
  workspace_.subtree_second.resize(n);
  workspace_.motion_q.resize(n);
  workspace_.motion_t.resize(n);
  workspace_.tremble_delta.assign(n, Vector3d::Zero());
  workspace_.joint_lambda.assign(model.joint_count(), Vector3d::Zero());
  workspace_.limit_lambda.assign(model.joint_count(), Vector3d::Zero());
  workspace_.tree_nodes.resize(n + model.joint_count() + 1);
  workspace_.tree_solution.resize(workspace_.tree_nodes.size());
  workspace_.tree_columns.resize(kMaxLoopRows * workspace_.tree_nodes.size());
  workspace_.tree_loop_factor = Eigen::PartialPivLU<LoopMatrix>(kMaxLoopRows);
  // a pin or a contact may anchor the pass at any segment: every order is there before step()
  if (!tables_) tables_ = make_model_tables(model);
  const bool kept = !tables_->orders.empty();
  if ((kept && static_cast<int>(tables_->orders.size()) != n) ||
      static_cast<int>(tables_->joints.size()) != model.joint_count() ||
      static_cast<int>(tables_->incidence.offsets.size()) != n + 1) {
    throw std::invalid_argument("model tables of another model");
  }
  if (!kept) {
    // the workspace's orders hold any anchor's without allocating in a step
    workspace_.order_scratch.reserve(n);
    for (int slot = 0; slot < 2; ++slot) {
      fill_anchor_order(model, tables_->incidence, 0, workspace_.orders[slot],
                        workspace_.order_scratch);
      workspace_.order_anchor[slot] = 0;
    }
  }
  reset(rest_pose(model));
}

void Solver::reset(std::span<const BodyState> bodies) {
  if (static_cast<int>(bodies.size()) != model_.segment_count()) {
    throw std::invalid_argument("reset: one body state per segment expected");
  }
  for (int i = 0; i < model_.segment_count(); ++i) {
    state_.bodies[i] = bodies[i];
    state_.bodies[i].q.normalize();
    state_.x_prev[i] = bodies[i].x;
    state_.q_prev[i] = state_.bodies[i].q;
    state_.user_force[i].setZero();
    state_.user_torque[i].setZero();
    state_.tremble_offset[i].setZero();
  }
  state_.pin_count = 0;
  state_.pin_force.fill(0.0);
  state_.tremble_phase = 0.0;
  state_.time = 0.0;
  state_.diverged = false;
  state_.diverged_time = 0.0;
}

void Solver::set_pins(std::span<const Pin> pins) {
  if (pins.size() > kMaxPins) throw std::invalid_argument("too many pins");
  for (const Pin& pin : pins) {
    if (pin.segment < 0 || pin.segment >= model_.segment_count()) {
      throw std::invalid_argument("pin on a segment that does not exist");
    }
  }
  state_.pin_count = static_cast<int>(pins.size());
  for (size_t i = 0; i < pins.size(); ++i) {
    state_.pins[i] = pins[i];
    state_.pin_previous_target[i] = pins[i].target;
    state_.pin_force[i] = 0.0;
  }
}

void Solver::set_pin_targets(std::span<const Vector3d> targets) {
  const int count = std::min(static_cast<int>(targets.size()), state_.pin_count);
  for (int i = 0; i < count; ++i) state_.pins[i].target = targets[i];
}

void Solver::step(double dt) {
  stage_seconds_.fill(0.0);
  if (state_.diverged || !(dt > 0.0)) return;
  const int substeps = settings_.substeps;
  for (int k = 0; k < substeps; ++k) {
    substep(dt / substeps, static_cast<double>(k + 1) / substeps);
    if (state_.diverged) break;
  }
  for (int i = 0; i < state_.pin_count; ++i) state_.pin_previous_target[i] = state_.pins[i].target;
}

void Solver::substep(double h, double target_fraction) {
  // the pins' targets at the end of this substep
  for (int i = 0; i < state_.pin_count; ++i) {
    substep_targets_[i] = state_.pin_previous_target[i] +
                          target_fraction * (state_.pins[i].target - state_.pin_previous_target[i]);
  }
  if (!settings_.time_stages) {
    for (int stage = 0; stage < kStageCount; ++stage) run_stage(static_cast<Stage>(stage), h);
  } else {
    using Clock = std::chrono::steady_clock;
    Clock::time_point mark = Clock::now();
    for (int stage = 0; stage < kStageCount; ++stage) {
      run_stage(static_cast<Stage>(stage), h);
      const Clock::time_point now = Clock::now();
      stage_seconds_[stage] += std::chrono::duration<double>(now - mark).count();
      mark = now;
    }
  }
  state_.time += h;
  check_finite();
}

void Solver::run_stage(Stage stage, double h) {
  const int anchor = state_.pin_count > 0 ? state_.pins[0].segment : 0;
  switch (stage) {
    case kUpdate:
      update(model_, environment_, state_, h);
      if (settings_.tremble) tremble(model_, settings_, state_, h, workspace_.tremble_delta);
      break;
    case kAdjust:
      adjust(model_, settings_, environment_, *tables_, anchor, substep_targets_, state_,
             workspace_, h);
      break;
    case kContacts:
      if (environment_.ground)
        contacts_after_adjust(model_, settings_, environment_, *tables_, substep_targets_, state_,
                              workspace_);
      break;
    case kVelocities:
      if (settings_.derive_velocities) {
        derive_velocities(model_, state_, workspace_.tremble_delta, h);
        // xpbd's velocity pass: what the poses cannot say about the ground (no restitution)
        if ((settings_.rule == Rule::kXpbd || settings_.rule == Rule::kTree) &&
            environment_.ground) {
          ground_velocity_pass(model_, environment_, state_);
        }
      }
      break;
    case kStageCount:
      break;
  }
}

namespace {

template <typename T>
void prefetch_range(const std::vector<T>& values) {
  const char* begin = reinterpret_cast<const char*>(values.data());
  const char* end = begin + values.size() * sizeof(T);
  for (const char* p = begin; p < end; p += 64) __builtin_prefetch(p);
}

}  // namespace

void Solver::prefetch() const {
  const char* self = reinterpret_cast<const char*>(this);
  for (size_t offset = 0; offset < sizeof(*this); offset += 64) __builtin_prefetch(self + offset);
  prefetch_range(state_.bodies);
  prefetch_range(state_.x_prev);
  prefetch_range(state_.q_prev);
  prefetch_range(state_.user_force);
  prefetch_range(state_.user_torque);
  prefetch_range(workspace_.tremble_delta);
  const int anchor = state_.pin_count > 0 ? state_.pins[0].segment : 0;
  if (!tables_->orders.empty()) {
    prefetch_range(tables_->orders[anchor].links);
    prefetch_range(tables_->orders[anchor].level_links);
  }
}

void Solver::check_finite() {
  // numerical health: flag, never throw
  if (!all_finite(state_.bodies)) {
    state_.diverged = true;
    state_.diverged_time = state_.time;
  }
}

}  // namespace puppet::procedural
