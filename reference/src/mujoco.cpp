// The model in MuJoCo (mujoco.h). Every body's frame is its segment's frame, so MuJoCo's world
// poses are the segments' poses. With B a body's compiled orientation in its parent and q_P, q_b
// the parent's and the body's world orientations, a joint's rotation is Q = B⁻¹ q_P⁻¹ q_b:
//   free   qpos = (x, q_b), qvel = (v, q_b⁻¹ ω) (the angular part in the body frame)
//   ball   qpos = Q, qvel = q_b⁻¹ (ω_b − ω_P) (in the body frame)
//   hinge  qpos = θ with Q = rotation by θ about the axis a, qvel = a · q_b⁻¹ (ω_b − ω_P)
//   box    three hinges in one body, Q = R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂) (set_hinge_triple); two
//          where the third angle is held at 0
// The pins' configuration (which one hangs the tree, which are mocap-driven) is part of the
// compiled model: a change rebuilds it and carries the state over through world poses.
#include "puppet/reference/mujoco.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "mujoco_library.h"
#include "pin_springs.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/mjcf.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/text.h"
#include "world_poses.h"

namespace puppet::reference {
namespace {

using detail::compile;
using detail::guarded;

Vector3d vec3(const mjtNum* p) { return {p[0], p[1], p[2]}; }
const EulerOrder kXyz{{0, 1, 2}};

// the bytes of the solver stack MuJoCo 2.2.2's compiler sizes for the document write_mjcf gives
// (user_model.cc: nstack = 5 (njmax + neq + nv)², njmax as mjcf_writer.cpp writes it with two
// driven pins)
double arena_bytes(const Model& model) {
  double nv = 6.0;
  for (const Joint& joint : model.joints) {
    nv += joint.type == JointType::kBall ? 3.0 : joint.type == JointType::kFixed ? 0.0 : 1.0;
  }
  const double pins = 2.0;
  const double njmax = 24.0 * model.segment_count() + 3.0 * pins + 32.0;
  const double rows = njmax + pins + nv;
  return 5.0 * rows * rows * sizeof(mjtNum);
}
Quaterniond quat4(const mjtNum* p) { return Quaterniond(p[0], p[1], p[2], p[3]); }

}  // namespace

std::string mujoco_model_problem(const Model& model) {
  if (std::string problem = mjcf_write_problem(model); !problem.empty()) return problem;
  if (const double bytes = arena_bytes(model); bytes > kMujocoMaxArenaBytes) {
    return "its solver stack would take " + std::to_string(std::lround(bytes / (1 << 20))) +
           " MiB (at most " + std::to_string(std::lround(kMujocoMaxArenaBytes / (1 << 20))) +
           "): " + std::to_string(model.segment_count()) + " segments are too many for MuJoCo";
  }
  // the compiler's own verdict, on the document a solver would build (names the model's own)
  MjcfOptions options;
  options.environment.gravity = model.gravity;
  options.stiff_constraints = true;
  options.user_data = false;
  try {
    mjModel* m = compile(write_mjcf(model, options));
    mjData* d = nullptr;
    std::string error;
    const bool made = guarded([&] { d = mj_makeData(m); }, error) && d != nullptr;
    if (d) mj_deleteData(d);
    mj_deleteModel(m);
    if (!made) return "MuJoCo could not make its data" + (error.empty() ? "" : ": " + error);
  } catch (const ModelError& e) {
    std::string what = e.what();
    const std::string prefix = "mujoco: ";
    return what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
  }
  return {};
}

namespace {

bool same_point(const Pin& a, const Pin& b) {
  return a.segment == b.segment && a.local_point == b.local_point;
}

// MuJoCo builds the joints' springs and dampers itself (stiffness, damping and springref in the
// MJCF write_mjcf gives), its Euler integrating the damping implicitly
detail::PinSprings mujoco_springs() {
  detail::PinSprings springs;
  springs.joint_springs = false;
  return springs;
}

class MujocoSolver final : public Solver {
 public:
  MujocoSolver(const Model& model, const Environment& environment, const MujocoSettings& settings)
      : model_(model), environment_(environment), settings_(settings) {
    bodies_ = rest_pose(model);
    build();
    set_state(bodies_);
  }
  ~MujocoSolver() override { release(); }

  void set_pins(std::span<const Pin> pins) override {
    read_state(bodies_);
    // the exact pin stays exact while it is among the pins, hard, and its target unchanged
    int exact = -1;
    for (size_t k = 0; k < pins.size(); ++k) {
      if (exact_ >= 0 && pins[k].is_hard() && same_point(pins[k], pins_[exact_]) &&
          pins[k].target == pins_[exact_].target) {
        exact = static_cast<int>(k);
      }
    }
    // else the first hard pin whose point is on its target (a pin that must first pull its
    // point there is a constraint, not a joint); none when the world holds the root already
    for (size_t k = 0; exact < 0 && !root_held(model_) && k < pins.size(); ++k) {
      const Pin& pin = pins[k];
      const BodyState& b = bodies_[pin.segment];
      if (pin.is_hard() && (b.x + b.q * pin.local_point - pin.target).norm() <= 1e-9) {
        exact = static_cast<int>(k);
      }
    }
    pins_.assign(pins.begin(), pins.end());
    exact_ = exact;
    rebuild();
  }

  void set_pin_targets(std::span<const Vector3d> targets) override {
    for (size_t k = 0; k < targets.size() && k < pins_.size(); ++k) {
      previous_targets_[k] = pins_[k].target;
      if (static_cast<int>(k) == exact_ && targets[k] != pins_[k].target) {
        // the exact pin's target moves: from now on it is a driven pin
        read_state(bodies_);
        exact_ = -1;
        pins_[k].target = targets[k];
        rebuild();
      }
      pins_[k].target = targets[k];
      springs_.retarget(k, targets[k]);
    }
  }

  void step(double dt) override {
    m_->opt.timestep = dt;
    // the mocap bodies 2τ·v_target ahead of the targets, τ = 2·dt unless set (see mujoco.h)
    const double lead = 2.0 * std::max(settings_.constraint_time_constant, 2.0 * dt);
    for (size_t k = 0; k < mocap_of_pin_.size(); ++k) {
      if (mocap_of_pin_[k] < 0) continue;
      const Vector3d velocity = (pins_[k].target - previous_targets_[k]) / dt;
      const Vector3d at = pins_[k].target + lead * velocity;
      std::copy_n(at.data(), 3, d_->mocap_pos + 3 * mocap_of_pin_[k]);
      previous_targets_[k] = pins_[k].target;
    }
    if (engine_error_) return;  // MuJoCo's data is past use
    std::string error;
    bool stepped = false;
    if (settings_.integrator == MujocoIntegrator::kRk4) {
      // RK4 holds the applied wrenches over its four stages: they are evaluated at the start
      refresh();
      apply_wrenches();
      stepped = guarded([&] { mj_step(m_, d_); }, error);
    } else {
      // positions and velocities at the start of the step, which body_state reads (MuJoCo's
      // split step serves Euler and implicit alike)
      stepped = guarded([&] { mj_step1(m_, d_); }, error);
      if (stepped) {
        apply_wrenches();
        stepped = guarded([&] { mj_step2(m_, d_); }, error);
      }
    }
    kinematics_current_ = false;
    if (!stepped) {
      stop_on_error(error);
      return;
    }
    // MuJoCo meets a non-finite qpos, qvel or qacc by resetting the state to its initial one
    // and counting a warning: the count is what says the run diverged
    for (int w : {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC}) {
      if (d_->warning[w].number > 0) diverged_ = true;
    }
  }

  void set_time(double time) override { d_->time = time; }
  std::span<const Wrench> user_wrenches() const override { return springs_.user; }

  void read_state(std::span<BodyState> out) const override {
    refresh();
    for (int s = 0; s < model_.segment_count(); ++s) out[s] = body_state(s);
  }

  void set_state(std::span<const BodyState> bodies) override {
    if (exact_ >= 0) {
      // a state whose point is off the exact pin's target cannot be written in coordinates
      // hung from it: the pin is driven from now on, and the state is kept as given
      const Pin& pin = pins_[exact_];
      const BodyState& b = bodies[pin.segment];
      if ((b.x + b.q * pin.local_point - pin.target).norm() > 1e-9) {
        exact_ = -1;
        build();
      }
    }
    for (int s = 0; s < model_.segment_count(); ++s) {
      const int b = body_of_[s];
      const int parent = m_->body_parentid[b];
      const int ps = parent > 0 ? segment_of_[parent] : -1;
      const Quaterniond qp = ps >= 0 ? bodies[ps].q : Quaterniond::Identity();
      const Vector3d wp = ps >= 0 ? bodies[ps].w : Vector3d::Zero();
      const BodyState& body = bodies[s];
      if (m_->body_jntnum[b] == 0) continue;
      const int j = m_->body_jntadr[b];
      mjtNum* qpos = d_->qpos + m_->jnt_qposadr[j];
      mjtNum* qvel = d_->qvel + m_->jnt_dofadr[j];
      if (s == 0 && exact_ < 0 && root_held(model_) && model_.root.hold != RootHold::kBall) {
        // the world's hinge, slide or planar joints: one qpos and one qvel each, in order
        const RootCoordinates c = root_coordinates(model_, body);
        for (int k = 0; k < c.count; ++k) {
          qpos[m_->jnt_qposadr[j + k] - m_->jnt_qposadr[j]] = c.value[k];
          qvel[m_->jnt_dofadr[j + k] - m_->jnt_dofadr[j]] = c.rate[k];
        }
        continue;
      }
      const Vector3d relative_w = body.q.conjugate() * (body.w - wp);
      if (m_->body_jntnum[b] >= 2) {
        // a box limit's two or three hinges (their coordinates are consecutive)
        const Quaterniond q = quat4(m_->body_quat + 4 * b).conjugate() * qp.conjugate() * body.q;
        set_hinge_triple(j, m_->body_jntnum[b], q, relative_w, qpos, qvel);
        continue;
      }
      switch (m_->jnt_type[j]) {
        case mjJNT_FREE: {
          std::copy_n(body.x.data(), 3, qpos);
          const Quaterniond q = body.q.normalized();
          qpos[3] = q.w(), qpos[4] = q.x(), qpos[5] = q.y(), qpos[6] = q.z();
          std::copy_n(body.v.data(), 3, qvel);
          std::copy_n(relative_w.data(), 3, qvel + 3);
          break;
        }
        case mjJNT_BALL: {
          const Quaterniond q =
              (quat4(m_->body_quat + 4 * b).conjugate() * qp.conjugate() * body.q).normalized();
          qpos[0] = q.w(), qpos[1] = q.x(), qpos[2] = q.y(), qpos[3] = q.z();
          std::copy_n(relative_w.data(), 3, qvel);
          break;
        }
        case mjJNT_HINGE: {
          const Quaterniond q = quat4(m_->body_quat + 4 * b).conjugate() * qp.conjugate() * body.q;
          const Vector3d axis = vec3(m_->jnt_axis + 3 * j);
          qpos[0] = 2.0 * std::atan2(q.vec().dot(axis), q.w());
          qvel[0] = axis.dot(relative_w);
          break;
        }
        case mjJNT_SLIDE: {
          // the body's place along the axis from where its parent puts it at qpos 0, and that
          // place's rate as the parent (turning) carries the axis: a·(v − v_p − ω_p × (x − x_p))
          const Vector3d xp = ps >= 0 ? bodies[ps].x : Vector3d::Zero();
          const Vector3d vp = ps >= 0 ? bodies[ps].v : Vector3d::Zero();
          const Vector3d axis = body.q * vec3(m_->jnt_axis + 3 * j);
          const Vector3d zero = xp + qp * vec3(m_->body_pos + 3 * b);
          qpos[0] = axis.dot(body.x - zero);
          qvel[0] = axis.dot(body.v - vp - wp.cross(body.x - xp));
          break;
        }
        default:
          break;
      }
    }
    // history the same state must not carry: the constraint solver's warm start
    mju_zero(d_->qacc_warmstart, m_->nv);
    kinematics_current_ = false;
  }

  std::vector<double> save() const override {
    // first: MuJoCo's kinematics normalise the quaternions in qpos in place, so the state is
    // saved as it is after they ran (as the next step will find it)
    read_state(bodies_);
    std::vector<double> out;
    out.push_back(static_cast<double>(generation_));
    out.push_back(d_->time);
    out.insert(out.end(), d_->qpos, d_->qpos + m_->nq);
    out.insert(out.end(), d_->qvel, d_->qvel + m_->nv);
    out.insert(out.end(), d_->qacc_warmstart, d_->qacc_warmstart + m_->nv);
    for (size_t k = 0; k < pins_.size(); ++k) {
      out.insert(out.end(), pins_[k].target.data(), pins_[k].target.data() + 3);
      out.insert(out.end(), previous_targets_[k].data(), previous_targets_[k].data() + 3);
    }
    // world poses, for a restore into another pin configuration
    detail::append_world_poses(bodies_, out);
    out.push_back(diverged_ ? 1.0 : 0.0);
    return out;
  }

  void load(std::span<const double> saved) override {
    size_t at = 0;
    const auto generation = static_cast<long>(saved[at++]);
    const double time = saved[at++];
    const double* qpos = &saved[at];
    at += m_->nq;
    const double* qvel = &saved[at];
    at += m_->nv;
    const double* warm = &saved[at];
    at += m_->nv;

    const double* targets = &saved[at];
    at += 6 * pins_.size();
    if (generation == generation_) {
      for (size_t k = 0; k < pins_.size(); ++k) {
        const double* t = targets + 6 * k;
        pins_[k].target = Vector3d(t[0], t[1], t[2]);
        previous_targets_[k] = Vector3d(t[3], t[4], t[5]);
        springs_.retarget(k, pins_[k].target);
      }
      std::copy_n(qpos, m_->nq, d_->qpos);
      std::copy_n(qvel, m_->nv, d_->qvel);
      std::copy_n(warm, m_->nv, d_->qacc_warmstart);

      d_->time = time;
      kinematics_current_ = false;
    } else {
      // saved under another pin configuration: only the world state carries over (its layout
      // after the qpos part is sized by that configuration, so it is read from the end)
      detail::read_world_poses(saved, bodies_);
      set_state(bodies_);
    }
    diverged_ = saved.back() != 0.0;
    engine_error_ = false;  // a state from before the error: MuJoCo's data holds it again
  }

  bool diverged() const override { return diverged_; }
  bool engine_error() const override { return engine_error_; }

  double segment_mass(int segment) const override { return m_->body_mass[body_of_[segment]]; }
  Vector3d segment_inertia(int segment) const override {
    return vec3(m_->body_inertia + 3 * body_of_[segment]);
  }
  void joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const override {
    refresh();
    const Joint& j = model_.joints[joint];
    const BodyState p = body_state(j.parent);
    const BodyState c = body_state(j.child);
    *on_parent = p.x + p.q * parent_anchor(j, p.q, c.q);
    *on_child = c.x + c.q * j.anchor_in_child;
  }

 private:
  void release() {
    if (d_ != nullptr) mj_deleteData(d_);
    if (m_ != nullptr) mj_deleteModel(m_);
    d_ = nullptr;
    m_ = nullptr;
  }

  // compiles the model for the current pins
  void build() {
    MjcfOptions options;
    options.environment = environment_;
    options.environment.gravity.setZero();  // gravity comes with the environment's wrench
    options.integrator = settings_.integrator == MujocoIntegrator::kRk4 ? MjcfIntegrator::kRk4
                         : settings_.integrator == MujocoIntegrator::kImplicit
                             ? MjcfIntegrator::kImplicit
                             : MjcfIntegrator::kEuler;
    options.stiff_constraints = true;
    options.constraint_time_constant = settings_.constraint_time_constant;
    options.user_data = false;
    options.model_names = false;
    springs_.clear();
    mocap_of_pin_.assign(pins_.size(), -1);
    previous_targets_.resize(pins_.size());
    for (size_t k = 0; k < pins_.size(); ++k) previous_targets_[k] = pins_[k].target;
    for (size_t k = 0; k < pins_.size(); ++k) {
      const Pin& pin = pins_[k];
      if (!springs_.add(pin, 0)) continue;  // compliant: a spring force
      if (static_cast<int>(k) == exact_) {
        options.pinned_segment = pin.segment;
        options.pinned_point = pin.local_point;
        options.pinned_target = pin.target;
      } else {
        mocap_of_pin_[k] = static_cast<int>(options.driven_pins.size());
        options.driven_pins.push_back(pin);
      }
    }
    release();
    m_ = compile(write_mjcf(model_, options));
    std::string error;
    if (!guarded([&] { d_ = mj_makeData(m_); }, error) || d_ == nullptr) {
      d_ = nullptr;
      release();
      throw ModelError("mujoco: MuJoCo could not make its data" +
                       (error.empty() ? std::string() : ": " + error));
    }
    // a connect holds body1's anchor on body2's point that coincided with it in the written
    // configuration: the mocap body's origin, up to that configuration's rounding
    for (int e = 0; e < m_->neq; ++e) mju_zero(m_->eq_data + mjNEQDATA * e + 3, 3);
    body_of_.assign(model_.segment_count(), -1);
    segment_of_.assign(m_->nbody, -1);
    for (int s = 0; s < model_.segment_count(); ++s) {
      body_of_[s] = mj_name2id(m_, mjOBJ_BODY, mjcf_segment_body(s).c_str());
      segment_of_[body_of_[s]] = s;
    }
    ++generation_;
    kinematics_current_ = false;
  }

  void rebuild() {
    build();
    set_state(bodies_);
  }

  // Three hinges about orthonormal axes a₀, a₁, a₂ of the body turn it by
  // Q = R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂) = A R_xyz(θ) A⁻¹ with A = [a₀ a₁ a₂] (right-handed; the
  // third axis and angle negated if not), so θ are the xyz Euler angles of A⁻¹ Q A. MuJoCo turns
  // hinge k about its axis after the earlier hinges' turns, so the body-frame relative angular
  // velocity is ω = R₂ᵀR₁ᵀ a₀ θ̇₀ + R₂ᵀ a₁ θ̇₁ + a₂ θ̇₂, solved for θ̇. Two hinges (`count` 2)
  // are three whose third, about a₀ × a₁, is held at 0: its angle and rate are left out.
  void set_hinge_triple(int first, int count, const Quaterniond& q, const Vector3d& relative_w,
                        mjtNum* qpos, mjtNum* qvel) const {
    Eigen::Matrix3d axes;
    for (int k = 0; k < count; ++k) axes.col(k) = vec3(m_->jnt_axis + 3 * (first + k));
    if (count == 2) axes.col(2) = axes.col(0).cross(axes.col(1)).normalized();
    const double handed = axes.determinant() < 0.0 ? -1.0 : 1.0;
    axes.col(2) *= handed;
    const Quaterniond a(axes);
    Vector3d angles = euler_angles(kXyz, a.conjugate() * q * a);
    angles.z() *= handed;
    axes.col(2) *= handed;
    const Eigen::AngleAxisd r1(angles.y(), axes.col(1)), r2(angles.z(), axes.col(2));
    Eigen::Matrix3d rates;
    rates.col(0) = (r1 * r2).inverse() * axes.col(0);
    rates.col(1) = r2.inverse() * axes.col(1);
    rates.col(2) = axes.col(2);
    const Vector3d angle_rates = rates.partialPivLu().solve(relative_w);
    for (int k = 0; k < count; ++k) {
      qpos[m_->jnt_qposadr[first + k] - m_->jnt_qposadr[first]] = angles[k];
      qvel[m_->jnt_dofadr[first + k] - m_->jnt_dofadr[first]] = angle_rates[k];
    }
  }

  // positions and velocities of every body (mj_step leaves them at the start of the last step)
  void refresh() const {
    if (kinematics_current_ || engine_error_) return;
    std::string error;
    const bool done = guarded(
        [&] {
          mj_kinematics(m_, d_);
          mj_comPos(m_, d_);
          mj_comVel(m_, d_);
        },
        error);
    if (!done) {
      const_cast<MujocoSolver*>(this)->stop_on_error(error);
      return;
    }
    kinematics_current_ = true;
  }

  // MuJoCo raised its error inside a step: the run is diverged, its state the last one read, and
  // MuJoCo is not called again for it; one line says why
  void stop_on_error(const std::string& error) {
    diverged_ = true;
    engine_error_ = true;
    d_->pstack = 0;  // the step's scratch, left allocated by the jump
    std::fprintf(stderr,
                 "mujoco: MuJoCo stopped a step with its error \"%s\"; the run reads as "
                 "diverged\n",
                 error.c_str());
  }

  BodyState body_state(int s) const {
    const int b = body_of_[s];
    BodyState out;
    out.x = vec3(d_->xpos + 3 * b);
    out.q = quat4(d_->xquat + 4 * b);
    mjtNum velocity[6];
    mj_objectVelocity(m_, d_, mjOBJ_BODY, b, velocity, 0);
    out.w = vec3(velocity);
    out.v = vec3(velocity + 3);
    return out;
  }

  void apply_wrenches() {
    for (int s = 0; s < model_.segment_count(); ++s) bodies_[s] = body_state(s);
    springs_.time = d_->time;
    const std::span<const Wrench> wrenches =
        springs_.wrenches(model_, environment_, bodies_, m_->opt.timestep);
    for (int s = 0; s < model_.segment_count(); ++s) {
      mjtNum* out = d_->xfrc_applied + 6 * body_of_[s];
      std::copy_n(wrenches[s].force.data(), 3, out);
      std::copy_n(wrenches[s].torque.data(), 3, out + 3);
    }
  }

  const Model& model_;
  Environment environment_;
  MujocoSettings settings_;
  std::vector<Pin> pins_;
  int exact_ = -1;
  detail::PinSprings springs_ = mujoco_springs();
  std::vector<int> mocap_of_pin_;           // the mocap body driving each pin, −1 for none
  std::vector<Vector3d> previous_targets_;  // each pin's target one step before
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<int> body_of_, segment_of_;
  long generation_ = 0;
  mutable bool kinematics_current_ = false;
  mutable std::vector<BodyState> bodies_;
  bool diverged_ = false;
  bool engine_error_ = false;  // MuJoCo raised its error (stop_on_error)
};

}  // namespace

bool have_mujoco() { return true; }

std::unique_ptr<Solver> make_mujoco(const Model& model, const Environment& environment,
                                    const MujocoSettings& settings) {
  if (std::string problem = mjcf_write_problem(model); !problem.empty()) {
    throw ModelError("mujoco: " + problem);
  }
  return std::make_unique<MujocoSolver>(model, environment, settings);
}

}  // namespace puppet::reference
