// The interface every reference engine's world sits behind (Bullet's two, MuJoCo's, ODE's; Jolt's
// is a driver process behind the harness's Simulator, harness/src/engines/jolt.cpp): one model in
// one engine, driven by the same environment forces and pins as the procedural solver, read back
// in the model's own frames. Engine types stay inside reference/src: this header speaks the
// model's language only.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::reference {

// One engine's world holding one model. Not copyable; one step(dt) is one internal step.
class Solver {
 public:
  virtual ~Solver() = default;

  // holds each pin's point at its target, replacing any pins set before
  virtual void set_pins(std::span<const Pin> pins) = 0;
  // the targets of the pins, in order, for the end of the next step
  virtual void set_pin_targets(std::span<const Vector3d> targets) = 0;
  virtual void step(double dt) = 0;
  /// the clock the tremble reads (s), advanced by every step: a harness that places a state in
  /// the middle of a run sets it
  virtual void set_time(double time) = 0;
  /// the user's forces (grabs and tremble: user_wrenches in user_forces.h) the last step applied,
  /// per segment (world, at the COM)
  virtual std::span<const Wrench> user_wrenches() const = 0;
  // per segment, in the model's segment frames: COM, orientation, v, ω (world)
  virtual void read_state(std::span<BodyState> out) const = 0;
  // places every segment; a reduced-coordinate world reads the base's pose and velocity and each
  // joint's relative rotation and angular velocity, so the state must be joint-consistent
  virtual void set_state(std::span<const BodyState> bodies) = 0;
  // the complete state as numbers (exact: restoring it and stepping repeats the same result)
  virtual std::vector<double> save() const = 0;
  virtual void load(std::span<const double> saved) = 0;
  // a non-finite value appeared in the state, or the engine stopped a step with its own error
  virtual bool diverged() const = 0;
  // the engine itself stopped a step with its error (MuJoCo's mju_error, ODE's internal checks):
  // the run is diverged, and one line on stderr named the engine and its message
  virtual bool engine_error() const { return false; }

  // what the engine was given, read back from its own objects (correspondence tests): a
  // segment's mass, its inertia (diagonal, segment frame), and a joint's anchor as each of its
  // two segments carries it, in world
  virtual double segment_mass(int segment) const = 0;
  virtual Vector3d segment_inertia(int segment) const = 0;
  virtual void joint_anchors(int joint, Vector3d* on_parent, Vector3d* on_child) const = 0;
};

}  // namespace puppet::reference
