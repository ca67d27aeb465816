// The one interface every solver sits behind (docs/design.md, "The references"). Coarse
// grained: one virtual call per step, never per joint.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/procedural/solver.h"
#include "puppet/reference/bullet.h"
#include "puppet/reference/mujoco.h"
#include "puppet/reference/ode.h"

namespace puppet::compare {

// a solver's complete state, opaque to the harness
class Snapshot {
 public:
  virtual ~Snapshot() = default;
};

class Simulator {
 public:
  virtual ~Simulator() = default;

  // "procedural", "bullet-multibody", ...
  virtual std::string name() const = 0;
  // the adjust rule, empty for solvers without one
  virtual std::string rule() const { return {}; }
  virtual int substeps() const { return 1; }

  // builds the model in its initial state, environment and pins; the model must outlive it
  virtual void reset(const Model& model, const Scenario& scenario) = 0;
  // replaces the scenario's pins (a user grabbing a point, letting go); the state is kept
  virtual void set_pins(std::span<const Pin> pins) = 0;
  // targets of the pins (world), in the pins' order, for the end of the next step
  virtual void set_pin_targets(std::span<const Vector3d> targets) = 0;
  virtual void step(double dt) = 0;
  // the clock the tremble reads (s), advanced by every step; a harness that places a state in
  // the middle of a run (set_state) sets it
  virtual void set_time(double time) = 0;
  // the user's forces the last step applied (grabs and tremble: user_wrenches, user_forces.h),
  // per segment, world, at the COM
  virtual std::span<const Wrench> user_wrenches() const = 0;
  // per segment, in the model's segment frames: COM, orientation, v, ω (world)
  virtual void read_state(std::span<BodyState> out) const = 0;
  // place every segment (a joint-consistent state, e.g. from another solver's trajectory); the
  // pins keep their current targets, as if the state had been reached under them
  virtual void set_state(std::span<const BodyState> bodies) = 0;
  virtual std::unique_ptr<Snapshot> snapshot() const = 0;
  virtual void restore(const Snapshot& snapshot) = 0;
  // the solver itself met a non-finite value, or its engine stopped a step with an error
  virtual bool diverged() const = 0;
  // the engine stopped a step with its own error (reference::Solver::engine_error): the run's
  // divergence reason is "engine error"
  virtual bool engine_error() const { return false; }

  // the seconds the engine itself timed its last step (< 0: none; the caller times step()). An
  // engine that steps a whole run ahead of the calls (jolt) times each step where it runs it
  virtual double own_step_seconds() const { return -1.0; }

  // per-stage wall time of the last step (empty when the solver has no stages)
  virtual std::vector<std::string_view> stage_names() const { return {}; }
  virtual void set_stage_timing(bool /*on*/) {}
  virtual std::vector<double> stage_seconds() const { return {}; }
};

// jolt (harness/src/engines/jolt.cpp): Jolt's solver settings, its defaults (velocity and
// position sweeps per step, and the fraction of a position error removed per position sweep)
struct JoltSettings {
  int velocity_steps = 10;
  int position_steps = 2;
  double baumgarte = 0.2;
};

// options a solver may use: the procedural solver's settings (its rule, iteration counts and
// switches, as procedural::Solver takes them) and each reference engine's own settings (an
// engine's row in engines.h adds its flags for its part)
struct SolverOptions {
  // procedural: Settings::tremble is the seed's tremble read as position noise in the update, in
  // any scenario (--position-tremble); the tremble scenario's is a force every engine feels
  // (environment.tremble). time_stages is the run's to set (Simulator::set_stage_timing).
  procedural::Settings procedural;
  // bullet-multibody and bullet-rigid: sequential-impulse sweeps (Bullet's default 10), ERP, and
  // Bullet's own Euler-box ball limits
  reference::Settings bullet;
  // mujoco: the integrator and the constraints' time constant (0: 2·dt)
  reference::MujocoSettings mujoco;
  // ode: dWorldQuickStep (and its sweeps) or dWorldStep, ERP and CFM
  reference::OdeSettings ode;
  // jolt: Jolt's velocity and position sweeps and Baumgarte factor
  JoltSettings jolt;
};
// the names of the engines this build has, in the catalogue's order (engines.h)
const std::vector<std::string>& solver_names();
// throws ScenarioError for an unknown solver or invalid settings
std::unique_ptr<Simulator> make_simulator(const std::string& solver, const SolverOptions& options);
// the settings make_simulator("procedural", options) gives its solver, for code that drives
// procedural::Solver directly (benchmarks of its stages, crowds); throws ScenarioError
procedural::Settings procedural_settings(const SolverOptions& options);

}  // namespace puppet::compare
