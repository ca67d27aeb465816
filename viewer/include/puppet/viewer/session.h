// The simulation side of the viewer: a model and a scenario from the harness, one solver and an
// optional ghost driven by the same pin targets, and the user's grab. No window: the viewer, its
// scripts and its tests drive it alike.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"

namespace puppet::viewer {

// the last `capacity` values of one number per frame, oldest at offset() (ImGui's PlotLines
// takes values, count and offset in this layout)
class History {
 public:
  explicit History(int capacity = 300) : values_(capacity, 0.0f) {}
  void push(float value);
  std::span<const float> values() const { return values_; }
  int offset() const { return next_; }
  float latest() const;
  float max() const;

 private:
  std::vector<float> values_;
  int next_ = 0;
};

struct SessionConfig {
  std::string model = "pinocchio";  // "pinocchio", a model file or chain:N
  std::string scenario = "hang";
  std::string solver{compare::kProceduralEngine};
  std::string ghost;  // a second solver drawn as a ghost; empty for none
  compare::SolverOptions options;
  double dt = 1.0 / 240.0;
  double shake_amplitude = 0.08;  // m, along the camera's right axis
  double shake_hz = 3.0;
  // which pin the procedural solver's adjust pass starts from while the user holds a point with
  // a pin (grab_pin):
  // "grab" (the seed anchors the pass at the dragged segment), "scenario" (the scenario's first
  // pin, the string the puppet hangs from) or "auto": grab for literal, whose translations are
  // stable from any anchor, scenario for the rotating rules, which anchored at a hand lose the
  // puppet within a second (as in yank, results/frontier/frontier.csv). Bullet does not care.
  std::string anchor = "auto";
  // the mouse's grab: the law drag, shake, water and tremble judge (compare::GrabSettings: a
  // capped spring–damper, the same force in every engine), so that what a user feels here is
  // what the verdict measured; or with grab_pin a pin on the cursor's ray, hard (the seed's
  // marionette string) or of compliance C > 0 (m/N)
  compare::GrabSettings grab_spring;
  bool grab_pin = false;
  double grab_compliance = 0.0;
  // "SEED:INDEX": a random start of testbed robustness (harness/.../start.h), replayed; empty for
  // the scenario's own start
  std::string start;
};

// "bad input: one message naming it" for a config (dt, names), empty when valid
// nullopt when valid, else what is wrong and with which field ("dt", "scenario", "solver",
// "grab_compliance", "grab_hz", "grab_ratio", "grab_cap", "anchor", "ghost", "shake"); the
// viewer's command line adds its flag
std::optional<compare::ScenarioError> validate(const SessionConfig& config);

// one solver of the session and what the viewer shows of it
struct Run {
  std::string label;  // "procedural (relaxed)", "bullet-multibody"
  std::unique_ptr<compare::Simulator> simulator;
  std::vector<BodyState> bodies;
  std::vector<double> joint_gaps;  // m, per joint, after the last step
  double pin_gap_max = 0.0;        // m, over the pins, after the last step
  // the testbed's energy criterion: E and E_ref when the run was (re)built
  double energy_start = 0.0, energy_reference = 1.0;
  bool diverged = false;
  double diverged_at = 0.0;               // s
  const char* diverged_reason = nullptr;  // "non-finite", "joint gap" or "energy"
  History gap_mm;                         // max joint gap after each frame
  History step_us;                        // mean wall time per step over each frame
  // an engine that times its own steps (jolt, out of this process): their mean over the last
  // frame (µs), < 0 for the others; step_us is then what a step costs with the round trip
  float own_step_us = -1.0f;
};

class Session {
 public:
  // throws ModelError or ScenarioError naming the problem
  explicit Session(const SessionConfig& config);

  const SessionConfig& config() const { return config_; }
  const Model& model() const { return *model_; }
  const compare::Scenario& scenario() const { return scenario_; }
  double time() const { return time_; }

  // a new model or scenario starts over; anything else rebuilds the runs from their current
  // states (a new ghost starts from the solver's). Throws as the constructor, and then leaves
  // the session as it was.
  void configure(const SessionConfig& config);
  // gravity, air drag, water, ground and tremble; the runs keep their states
  void set_environment(const Environment& environment);
  // the scenario's initial state at t = 0, nothing grabbed
  void reset();

  // steps every run by dt as often as fits in `seconds` plus what was left over last time, at
  // most max_steps; returns the steps taken
  int advance(double seconds, int max_steps);
  // exactly one step
  void step() { step_frame(1); }

  // the user's grab: a point of a segment (segment frame) held at a target (world). A segment
  // the scenario pins (drag's hand on its circle) is taken from that pin while it is held, as a
  // user takes the hand from the string: two pins on one segment at two targets would fight.
  void grab(int segment, const Vector3d& local_point, const Vector3d& target);
  void move_grab(const Vector3d& target);
  void release();
  bool grabbing() const { return grab_segment_ >= 0; }
  int grabbed_segment() const { return grab_segment_; }
  const Vector3d& grab_target() const { return grab_target_; }
  // while grabbing, the target oscillates along `axis` (unit) about the held target
  void set_shake(bool on, const Vector3d& axis);
  bool shaking() const { return shake_; }

  // every pin with its target at the current time, the anchor first (SessionConfig::anchor);
  // one-sided rules leave the other pins open, which the runs' pin gap shows
  std::span<const Pin> pins() const { return pins_; }
  std::span<const Vector3d> targets() const { return targets_; }
  // whether the grab is the first pin, and where it is among the pins (-1: nothing held)
  bool grab_anchors() const;
  int grab_index() const;
  // the scenario's pin the grab took over (its index among the scenario's pins), or -1
  int released_pin() const { return released_pin_; }

  // the solver first, then the ghost when there is one
  int run_count() const { return static_cast<int>(runs_.size()); }
  const Run& run(int i) const { return runs_[i]; }

 private:
  void start_over();
  // builds the run's simulator for the current scenario and pins, and places it in `bodies`
  void rebuild(Run& run, std::span<const BodyState> bodies) const;
  // the pins' targets at time t, the grab's `along` of the way from where it was at the last
  // frame to where the mouse has put it
  void compute_targets(double t, double along = 1.0);
  // pins_ from the scenario's pins and the grab, at targets_
  void collect_pins();
  // collect_pins, and every run holds the new pins
  void pins_changed();
  void step_frame(int steps);
  // reads a run's state after a step and judges it by the testbed's criteria, as the testbed
  // does after every step (a frame of 4 steps would miss a spike the testbed sees)
  void judge(Run& run, double t);

  SessionConfig config_;
  std::unique_ptr<Model> model_;  // runs hold a reference: its address never changes
  compare::Scenario scenario_;
  std::vector<Run> runs_;
  double time_ = 0.0;
  double leftover_ = 0.0;

  int grab_segment_ = -1;
  int released_pin_ = -1;
  Vector3d grab_local_{0, 0, 0}, grab_target_{0, 0, 0};
  Vector3d grab_from_{0, 0, 0};  // the grab's target at the end of the last frame
  bool shake_ = false;
  Vector3d shake_axis_{1, 0, 0};
  double shake_start_ = 0.0;

  std::vector<Pin> pins_;
  std::vector<Vector3d> targets_;
  std::vector<double> pin_gaps_;  // judge()'s scratch
};

}  // namespace puppet::viewer
