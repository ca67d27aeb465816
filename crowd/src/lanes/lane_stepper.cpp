// The crowd's lane path (lane_stepper.h): a batch's states copied into the kernel's lanes and
// back, the kernel chosen by the processor's instruction set, and what the kernel cannot do in
// lanes (a limit's decomposition) answered by the scalar solver's own functions.
#include "lane_stepper.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <new>

#include "puppet/model/euler_box.h"

#include "joint_limits.h"
#include "model_tables.h"
#include "stages.h"
#include "workspace.h"

namespace puppet::procedural::lanes {
namespace {

constexpr std::align_val_t kAlignment{64};

bool lane_limit_error(const void* context, int joint, const double child_to_parent[4],
                      double error[3], double rows[kRowFields]) {
  const auto& tables = *static_cast<const std::pair<const Model*, const ModelTables*>*>(context);
  Vector3d lane_error;
  LimitRows limit_rows;
  const Quaterniond q(child_to_parent[0], child_to_parent[1], child_to_parent[2],
                      child_to_parent[3]);
  if (!limit_error(tables.first->joints[joint], tables.second->joints[joint], q, &lane_error,
                   &limit_rows)) {
    return false;
  }
  for (int k = 0; k < 3; ++k) error[k] = lane_error[k];
  rows[0] = limit_rows.count;
  for (int r = 0; r < limit_rows.count; ++r) {
    for (int k = 0; k < 3; ++k) rows[1 + 3 * r + k] = limit_rows.directions(r, k);
  }
  return true;
}

const std::pair<const Model*, const ModelTables*>& lane_tables(const void* context) {
  return *static_cast<const std::pair<const Model*, const ModelTables*>*>(context);
}

Quaterniond lane_quaternion(const double q[4]) { return Quaterniond(q[0], q[1], q[2], q[3]); }

void lane_hold_limit_rates(const void* context, int joint, const double rows[kRowFields],
                           double parent[10], double child[10]) {
  const auto& [model, tables] = lane_tables(context);
  const auto body = [](const double* in) {
    BodyState b;
    b.q = lane_quaternion(in);
    b.v = Vector3d(in[4], in[5], in[6]);
    b.w = Vector3d(in[7], in[8], in[9]);
    return b;
  };
  LimitRows limit_rows;
  limit_rows.count = static_cast<int>(rows[0]);
  for (int r = 0; r < limit_rows.count; ++r) {
    for (int k = 0; k < 3; ++k) limit_rows.directions(r, k) = rows[1 + 3 * r + k];
  }
  BodyState p = body(parent), c = body(child);
  hold_limit_rates(*model, tables->joints[joint], model->joints[joint], limit_rows, 0.0,
                   Vector3d::Zero(), p, c);
  for (int k = 0; k < 3; ++k) {
    parent[4 + k] = p.v[k];
    parent[7 + k] = p.w[k];
    child[4 + k] = c.v[k];
    child[7 + k] = c.w[k];
  }
}

// the widest lanes this processor has, up to `most`
int widest_lanes(int most) {
  __builtin_cpu_init();
  if (most >= 8 && __builtin_cpu_supports("avx512f")) return 8;
  if (most >= 4 && __builtin_cpu_supports("avx2")) return 4;
  return 2;
}

void put3(double* slots, int width, int slot, int lane, const Vector3d& v) {
  for (int k = 0; k < 3; ++k) slots[(slot + k) * width + lane] = v[k];
}
void put4(double* slots, int width, int slot, int lane, const Quaterniond& q) {
  slots[slot * width + lane] = q.w();
  slots[(slot + 1) * width + lane] = q.x();
  slots[(slot + 2) * width + lane] = q.y();
  slots[(slot + 3) * width + lane] = q.z();
}
Vector3d get3(const double* slots, int width, int slot, int lane) {
  return {slots[slot * width + lane], slots[(slot + 1) * width + lane],
          slots[(slot + 2) * width + lane]};
}
Quaterniond get4(const double* slots, int width, int slot, int lane) {
  return {slots[slot * width + lane], slots[(slot + 1) * width + lane],
          slots[(slot + 2) * width + lane], slots[(slot + 3) * width + lane]};
}

}  // namespace

std::unique_ptr<LaneStepper> LaneStepper::make(const Solver& puppet, int max_width) {
  if (max_width < 2) return nullptr;
  const Settings& settings = puppet.settings();
  const Environment& environment = puppet.environment();
  // the lanes' limit pass keeps no rate from before the adjust: restitution 0 only
  // and they do xpbd's default sweep alone (the limit functions, the limits first)
  if (!rule_info(settings.rule).lanes || settings.tremble || settings.time_stages ||
      !settings.limit_functions || !settings.limits_before_joints ||
      (puppet.limit_pass_ && settings.limit_restitution != 0.0) || environment.tremble ||
      environment.water || environment.ground || puppet.tables_->orders.empty() ||
      puppet.joint_springs_ || puppet.model_.root.hold != RootHold::kFree ||
      std::ranges::any_of(puppet.model_.joints, has_box_offsets) ||
      std::ranges::any_of(puppet.model_.joints,
                          [](const Joint& joint) { return joint.type == JointType::kSlide; })) {
    // joint springs, a root the world holds, hinges at different points, slides: the scalar step
    return nullptr;
  }
  const int width = widest_lanes(max_width);
  return std::unique_ptr<LaneStepper>(new LaneStepper(puppet, width));
}

LaneStepper::LaneStepper(const Solver& puppet, int width) : width_(width) {
  kernel_ = width == 8 ? step_xpbd_avx512 : width == 4 ? step_xpbd_avx2 : step_xpbd_sse2;
  const Model& model = puppet.model();
  const ModelTables& tables = *puppet.tables_;
  segments_ = model.segment_count();
  joints_ = model.joint_count();
  for (const Segment& segment : model.segments) {
    SegmentTerms terms{segment.mass, segment.inv_mass, {}, {}};
    for (int k = 0; k < 3; ++k) {
      terms.inertia[k] = segment.inertia[k];
      terms.inv_inertia[k] = segment.inv_inertia[k];
    }
    segment_terms_.push_back(terms);
  }
  for (int j = 0; j < joints_; ++j) {
    const Joint& joint = model.joints[j];
    const JointTerms& terms = tables.joints[j];
    JointPlan plan{};
    plan.parent = joint.parent;
    plan.child = joint.child;
    for (int k = 0; k < 3; ++k) {
      plan.anchor_parent[k] = joint.anchor_in_parent[k];
      plan.anchor_child[k] = joint.anchor_in_child[k];
      for (int c = 0; c < 3; ++c) {
        plan.mass_parent[3 * k + c] = terms.point_mass[0](k, c);
        plan.mass_child[3 * k + c] = terms.point_mass[1](k, c);
      }
    }
    plan.frame_shift[0] = terms.frame_shift.w();
    plan.frame_shift[1] = terms.frame_shift.x();
    plan.frame_shift[2] = terms.frame_shift.y();
    plan.frame_shift[3] = terms.frame_shift.z();
    plan.limit_free_w = terms.limit_free_w;
    const Vector3d hinge_row = joint.frame_in_child * joint.hinge_axis;
    for (int k = 0; k < 3; ++k) plan.hinge_row[k] = hinge_row[k];
    const auto put_quaternion = [](const Quaterniond& q, double* out) {
      out[0] = q.w();
      out[1] = q.x();
      out[2] = q.y();
      out[3] = q.z();
    };
    put_quaternion(joint.frame_in_parent, plan.frame_parent);
    put_quaternion(joint.frame_in_child, plan.frame_child);
    plan.limit = kAskEachLane;
    if (terms.box.enabled) {
      plan.limit = kBox;
      const BoxTest& box = terms.box;
      for (int k = 0; k < 3; ++k) {
        plan.box_axes[k] = box.axes[k];
        plan.box_lower_cos[k] = box.lower_cos[k];
        plan.box_lower_sin[k] = box.lower_sin[k];
        plan.box_upper_cos[k] = box.upper_cos[k];
        plan.box_upper_sin[k] = box.upper_sin[k];
        plan.box_wide[k] = box.wide[k];
      }
      plan.box_sign = box.sign;
      plan.box_margin = kBoxMargin;
    } else if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kSwingTwist &&
               joint.swing_x > 0.0 && joint.swing_y > 0.0 && joint.twist < M_PI) {
      plan.limit = kCone;
      plan.swing_x = joint.swing_x;
      plan.swing_y = joint.swing_y;
      plan.twist_half_tan = joint.twist_half_sin / joint.twist_half_cos;
    } else if (joint.type == JointType::kHinge) {
      plan.limit = kHinge;
      for (int k = 0; k < 3; ++k) plan.hinge_axis[k] = joint.hinge_axis[k];
      plan.lower_half_sin = joint.lower_half_sin;
      plan.lower_half_cos = joint.lower_half_cos;
      plan.upper_half_sin = joint.upper_half_sin;
      plan.upper_half_cos = joint.upper_half_cos;
    }
    joint_plans_.push_back(plan);
  }
  for (const AnchorOrder& order : tables.orders) {
    std::vector<int> joints;
    for (const AnchorOrder::Link& link : order.links) joints.push_back(link.joint);
    orders_.push_back(std::move(joints));
  }
  limit_context_ = {&model, &tables};
  const Settings& settings = puppet.settings();
  base_.segments = segments_;
  base_.joints = joints_;
  base_.segment = segment_terms_.data();
  base_.joint = joint_plans_.data();
  for (int k = 0; k < 3; ++k) base_.gravity[k] = puppet.environment().gravity[k];
  base_.substeps = settings.substeps;
  base_.iterations = settings.iterations;
  base_.joint_compliance = settings.joint_compliance;
  base_.limit_compliance = settings.limit_compliance;
  base_.derive_velocities = settings.derive_velocities;
  base_.start_lever_arms = settings.start_lever_arms;
  base_.limit_pass = puppet.limit_pass_;
  base_.limit_error = lane_limit_error;
  base_.hold_limit_rates = lane_hold_limit_rates;
  base_.limit_context = &limit_context_;
}

LaneStepper::~LaneStepper() = default;

LaneStepper::Scratch::Scratch(const LaneStepper& stepper)
    : slots_(static_cast<double*>(
          ::operator new[](sizeof(double) * stepper.width() *
                               slot_count(stepper.segments_, stepper.joints_, kMaxPins),
                           kAlignment))) {}

void LaneStepper::Scratch::Free::operator()(double* p) const { ::operator delete[](p, kAlignment); }

namespace {

bool same_pins(const State& a, const State& b) {
  if (a.pin_count != b.pin_count) return false;
  for (int i = 0; i < a.pin_count; ++i) {
    if (a.pins[i].segment != b.pins[i].segment) return false;
  }
  return true;
}

}  // namespace

void LaneStepper::step(std::span<Solver* const> puppets, double dt, Scratch& scratch) const {
  // every puppet goes through lanes (whatever its neighbours, so that its bits do not depend on
  // its batch), in batches of the first waiting puppet and the next ones with its pins; a
  // diverged one (or any, for dt ≤ 0) is left to Solver::step, which leaves it as it is, and so
  // is one held by a grab (a force the lanes do not compute)
  constexpr size_t kWindow = 64;  // puppets sorted into batches at a time: one bit each
  for (size_t start = 0; start < puppets.size(); start += kWindow) {
    const size_t count = std::min(kWindow, puppets.size() - start);
    uint64_t waiting = 0;
    for (size_t i = 0; i < count; ++i) {
      Solver& puppet = *puppets[start + i];
      if (dt > 0.0 && !puppet.state_.diverged && puppet.state_.grab_count == 0) {
        waiting |= uint64_t{1} << i;
      } else {
        puppet.step(dt);
      }
    }
    while (waiting != 0) {
      std::array<Solver*, kMostLanes> batch{};
      int lanes = 0;
      const State* leader = nullptr;
      for (size_t i = 0; i < count && lanes < width_; ++i) {
        if (!(waiting & (uint64_t{1} << i))) continue;
        Solver* puppet = puppets[start + i];
        if (leader && !same_pins(puppet->state_, *leader)) continue;
        if (!leader) leader = &puppet->state_;
        batch[lanes++] = puppet;
        waiting &= ~(uint64_t{1} << i);
      }
      step_batch(std::span(batch.data(), lanes), dt, scratch);
    }
  }
}

void LaneStepper::step_batch(std::span<Solver* const> batch, double dt, Scratch& scratch) const {
  const int lanes = static_cast<int>(batch.size());
  const State* leader = &batch[0]->state_;
  Plan plan = base_;
  plan.h = dt / plan.substeps;
  plan.air_rate = step_drag_rate(batch[0]->environment().air_drag, plan.h);
  const int anchor = leader->pin_count > 0 ? leader->pins[0].segment : 0;
  plan.order = orders_[anchor].data();
  plan.links = static_cast<int>(orders_[anchor].size());
  plan.pins = leader->pin_count;
  std::array<int, kMaxPins> pin_segment{};
  for (int i = 0; i < plan.pins; ++i) pin_segment[i] = leader->pins[i].segment;
  plan.pin_segment = pin_segment.data();
  plan.pin_offset = segments_ * kBodyFields;
  plan.lambda_offset = plan.pin_offset + plan.pins * kPinFields;
  plan.mark_offset = plan.lambda_offset + 6 * joints_ + 3 * plan.pins;

  // into lanes; a batch short of the width repeats its first puppet in the rest (not read back)
  double* slots = scratch.slots();
  const int width = width_;
  for (int lane = 0; lane < width; ++lane) {
    const State& state = batch[lane < lanes ? lane : 0]->state_;
    for (int b = 0; b < segments_; ++b) {
      const BodyState& body = state.bodies[b];
      const int base = b * kBodyFields;
      put3(slots, width, base + kX, lane, body.x);
      put4(slots, width, base + kQ, lane, body.q);
      put3(slots, width, base + kV, lane, body.v);
      put3(slots, width, base + kW, lane, body.w);
      put3(slots, width, base + kForce, lane, state.user_force[b]);
      put3(slots, width, base + kTorque, lane, state.user_torque[b]);
    }
    for (int i = 0; i < plan.pins; ++i) {
      const int base = plan.pin_offset + i * kPinFields;
      put3(slots, width, base + kPinPoint, lane, state.pins[i].local_point);
      slots[(base + kPinCompliance) * width + lane] = state.pins[i].compliance;
      put3(slots, width, base + kPinFrom, lane, state.pin_previous_target[i]);
      put3(slots, width, base + kPinTo, lane, state.pins[i].target);
    }
  }

  const unsigned non_finite = kernel_(plan, slots);

  // back, as Solver::step leaves a state; a lane that met a non-finite value steps alone
  for (int lane = 0; lane < lanes; ++lane) {
    Solver& puppet = *batch[lane];
    if (non_finite & (1u << lane)) {
      puppet.step(dt);
      continue;
    }
    State& state = puppet.state_;
    for (int b = 0; b < segments_; ++b) {
      BodyState& body = state.bodies[b];
      const int base = b * kBodyFields;
      body.x = get3(slots, width, base + kX, lane);
      body.q = get4(slots, width, base + kQ, lane);
      body.v = get3(slots, width, base + kV, lane);
      body.w = get3(slots, width, base + kW, lane);
      state.x_prev[b] = get3(slots, width, base + kXPrev, lane);
      state.q_prev[b] = get4(slots, width, base + kQPrev, lane);
    }
    for (int i = 0; i < plan.pins; ++i) {
      state.pin_force[i] = slots[(plan.pin_offset + i * kPinFields + kPinForce) * width + lane];
      state.pin_previous_target[i] = state.pins[i].target;
    }
    for (int k = 0; k < plan.substeps; ++k) state.time += plan.h;
    puppet.stage_seconds_.fill(0.0);
  }
}

}  // namespace puppet::procedural::lanes
