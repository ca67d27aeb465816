// The solver: its state, and step(dt) as the table of contents of the method.
//
//   step(dt)      for each of the rule's substeps of h = dt/substeps: substep(h)
//   substep(h)    the pins' targets moved along their path to this substep's end, then
//     update      every segment alone under its forces, plus the seed's tremble (update.cpp)
//     adjust      the rule's position pass: pins, joints and limits (adjust.cpp, rules/)
//     contacts    the ground, as the rule's contact policy says (contacts.cpp)
//     velocities  v, ω from the corrected poses; the ground's velocity pass (velocities.cpp)
//   and a non-finite pose flags the run as diverged: it is never advanced again.
#include "puppet/procedural/solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "puppet/model/euler_box.h"
#include "puppet/model/joint_springs.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/user_forces.h"
#include "rules/catalogue.h"
#include "stages.h"

namespace puppet::procedural {

std::shared_ptr<const ModelTables> make_model_tables(const Model& model) {
  return make_model_tables(model, joint_preparers());
}

std::string rule_model_problem(const Model& model, Rule rule) {
  if (rule != Rule::kXpbd && rule != Rule::kTree) {
    if (std::string problem = box_offsets_problem(model); !problem.empty()) return problem;
    for (const Joint& joint : model.joints) {
      if (joint.type == JointType::kSlide) {
        return "joint \"" + joint.name +
               "\" is a slide, which only rules xpbd and tree hold (rule " +
               std::string(rule_name(rule)) + " does not)";
      }
    }
  }
  if (!root_held(model)) return {};
  if (rule != Rule::kXpbd && rule != Rule::kTree) {
    return std::string("its root is joined to the world (a ") + root_hold_name(model.root.hold) +
           " root), which only rules xpbd and tree hold (rule " + std::string(rule_name(rule)) +
           " does not)";
  }
  return slide_armature_problem(model);
}

Solver::Solver(const Model& model, const Settings& settings, const Environment& environment,
               std::shared_ptr<const ModelTables> tables)
    : model_(model),
      settings_(rule_defaults(settings)),
      environment_(environment),
      tables_(std::move(tables)) {
  const std::string problem = validate(settings);
  if (!problem.empty()) throw std::invalid_argument(problem);
  if (std::string held = rule_model_problem(model, settings_.rule); !held.empty()) {
    throw ModelError("procedural: " + held);
  }
  joint_springs_ = has_joint_springs(model_);
  state_.root_held = root_held(model_);
  limit_pass_ = settings_.limit_velocity_pass && settings_.derive_velocities &&
                rule_row(settings_.rule).limit_velocities;
  const int n = model.segment_count();
  state_.bodies.resize(n);
  state_.x_prev.resize(n);
  state_.q_prev.resize(n);
  state_.user_force.assign(n, Vector3d::Zero());
  state_.user_torque.assign(n, Vector3d::Zero());
  state_.tremble_offset.assign(n, Vector3d::Zero());
  // a pin or a contact may anchor the pass at any segment: every order is there before step()
  if (!tables_) tables_ = make_model_tables(model);
  const bool kept = !tables_->orders.empty();
  if ((kept && static_cast<int>(tables_->orders.size()) != n) ||
      static_cast<int>(tables_->joints.size()) != model.joint_count() ||
      static_cast<int>(tables_->incidence.offsets.size()) != n + 1) {
    throw std::invalid_argument("model tables of another model");
  }
  workspace_ = std::make_unique<Workspace>(model, *tables_);
  reset(rest_pose(model));
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;

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
  state_.grab_count = 0;
  state_.slot_count = 0;
  state_.pin_force.fill(0.0);
  state_.tremble_phase = 0.0;
  state_.time = 0.0;
  state_.diverged = false;
  state_.diverged_time = 0.0;
}

void Solver::place(std::span<const BodyState> bodies) {
  if (static_cast<int>(bodies.size()) != model_.segment_count()) {
    throw std::invalid_argument("place: one body state per segment expected");
  }
  for (size_t i = 0; i < bodies.size(); ++i) {
    state_.bodies[i] = bodies[i];
    state_.x_prev[i] = bodies[i].x;
    state_.q_prev[i] = bodies[i].q;
  }
  // substeps interpolate from the previous targets: a placed state starts at the current ones
  for (int i = 0; i < state_.pin_count; ++i) state_.pin_previous_target[i] = state_.pins[i].target;
  for (int i = 0; i < state_.grab_count; ++i) {
    state_.grab_previous_target[i] = state_.grabs[i].target;
  }
  state_.diverged = false;
}

void Solver::restore(const State& state) {
  const size_t n = static_cast<size_t>(model_.segment_count());
  if (state.bodies.size() != n || state.x_prev.size() != n || state.q_prev.size() != n ||
      state.user_force.size() != n || state.user_torque.size() != n ||
      state.tremble_offset.size() != n || state.pin_count < 0 || state.pin_count > kMaxPins ||
      state.grab_count < 0 || state.grab_count > kMaxPins - state.pin_count ||
      state.slot_count != state.pin_count + state.grab_count) {
    throw std::invalid_argument("restore: a state of another model");
  }
  auto on_model = [&](const Pin& pin) {
    return pin.segment >= 0 && pin.segment < model_.segment_count();
  };
  for (int i = 0; i < state.pin_count; ++i) {
    if (!on_model(state.pins[i])) {
      throw std::invalid_argument("restore: a pin on a segment that does not exist");
    }
  }
  for (int i = 0; i < state.grab_count; ++i) {
    if (!on_model(state.grabs[i])) {
      throw std::invalid_argument("restore: a grab on a segment that does not exist");
    }
  }
  for (int k = 0; k < state.slot_count; ++k) {
    const int slot = state.slots[k];
    if (slot >= state.pin_count || -1 - slot >= state.grab_count) {
      throw std::invalid_argument("restore: a pin slot out of range");
    }
  }
  state_ = state;  // same sizes: copies into the existing storage
}

void Solver::set_pins(std::span<const Pin> pins) {
  if (pins.size() > kMaxPins) throw std::invalid_argument("too many pins");
  for (const Pin& pin : pins) {
    if (pin.segment < 0 || pin.segment >= model_.segment_count()) {
      throw std::invalid_argument("pin on a segment that does not exist");
    }
  }
  state_.pin_count = 0;
  state_.grab_count = 0;
  state_.slot_count = static_cast<int>(pins.size());
  for (size_t k = 0; k < pins.size(); ++k) {
    if (pins[k].is_grab()) {
      const int i = state_.grab_count++;
      state_.grabs[i] = pins[k];
      state_.grab_previous_target[i] = pins[k].target;
      state_.slots[k] = -1 - i;
    } else {
      const int i = state_.pin_count++;
      state_.pins[i] = pins[k];
      state_.pin_previous_target[i] = pins[k].target;
      state_.pin_force[i] = 0.0;
      state_.slots[k] = i;
    }
  }
}

void Solver::set_pin_targets(std::span<const Vector3d> targets) {
  const int count = std::min(static_cast<int>(targets.size()), state_.slot_count);
  for (int k = 0; k < count; ++k) {
    const int slot = state_.slots[k];
    (slot >= 0 ? state_.pins[slot] : state_.grabs[-1 - slot]).target = targets[k];
  }
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
  for (int i = 0; i < state_.grab_count; ++i) {
    state_.grab_previous_target[i] = state_.grabs[i].target;
  }
}

std::span<const Wrench> Solver::user_wrenches() const { return workspace_->user_wrenches; }

void Solver::substep(double h, double target_fraction) {
  // the pins' targets at the end of this substep
  for (int i = 0; i < state_.pin_count; ++i) {
    substep_targets_[i] = state_.pin_previous_target[i] +
                          target_fraction * (state_.pins[i].target - state_.pin_previous_target[i]);
  }
  for (int i = 0; i < state_.grab_count; ++i) {
    substep_grabs_[i] = state_.grabs[i];
    substep_grabs_[i].target =
        state_.grab_previous_target[i] +
        target_fraction * (state_.grabs[i].target - state_.grab_previous_target[i]);
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
  Workspace& ws = *workspace_;
  switch (stage) {
    case kUpdate:
      // the user's forces on the state at the start of the substep, as every engine applies them
      // (none to compute without a grab or the tremble: the update then adds nothing)
      if (state_.grab_count > 0 || environment_.tremble) {
        puppet::user_wrenches(model_, environment_,
                              std::span<const Pin>(substep_grabs_.data(), state_.grab_count),
                              state_.bodies, state_.time, ws.user_wrenches);
        ws.user_pulled = true;
      } else {
        if (ws.user_pulled) std::fill(ws.user_wrenches.begin(), ws.user_wrenches.end(), Wrench{});
        ws.user_pulled = false;
      }
      if (joint_springs_) {
        // the joints' springs and dampers, forces like the user's (the damper implicit per joint)
        std::copy(ws.user_wrenches.begin(), ws.user_wrenches.end(), ws.applied_wrenches.begin());
        add_joint_spring_wrenches(model_, state_.bodies, h, ws.applied_wrenches);
        update(model_, environment_, ws.applied_wrenches, state_, h);
      } else {
        update(
            model_, environment_,
            ws.user_pulled ? std::span<const Wrench>(ws.user_wrenches) : std::span<const Wrench>(),
            state_, h);
      }
      if (settings_.tremble) tremble(model_, settings_, state_, h, ws.tremble_delta);
      break;
    case kAdjust: {
      const int anchor = state_.pin_count > 0 && !state_.root_held ? state_.pins[0].segment : 0;
      if (limit_pass_) begin_limit_marks(state_, ws);
      adjust(model_, settings_, environment_, *tables_, anchor, substep_targets_, state_, ws, h);
      break;
    }
    case kContacts:
      if (environment_.ground) {
        contacts(model_, settings_, environment_, *tables_, substep_targets_, state_, ws);
      }
      break;
    case kVelocities:
      if (!settings_.derive_velocities) break;
      derive_velocities(model_, state_, ws.tremble_delta, h);
      if (limit_pass_)
        limit_velocity_pass(model_, *tables_, settings_.limit_restitution, ws, state_);
      if (environment_.ground && needs_ground_velocity_pass(settings_.rule)) {
        ground_velocity_pass(model_, environment_, state_);
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
  prefetch_range(workspace_->tremble_delta);
  const int anchor = state_.pin_count > 0 && !state_.root_held ? state_.pins[0].segment : 0;
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
