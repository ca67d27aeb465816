/// \file
/// The seed paper's procedural solver (Bae, Baek, Lee & Ryu 2001): each segment moves alone
/// under its forces (update), then a geometric pass over the tree rotates and translates
/// segments so that joints meet again and limits hold (adjust). The seed's rules and xpbd solve
/// no linear system, only 3×3 blocks per constraint; rule tree factors the whole projection's
/// (sparse, on the tree, in O(n)).
///
///   step(dt) = for each substep: update → adjust → contacts → velocities
///
/// docs/design.md, "The procedural solver", defines each stage; docs/solver.md the rules.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"
#include "puppet/procedural/rule.h"
#include "puppet/procedural/settings.h"
#include "puppet/procedural/state.h"

namespace puppet::procedural {

enum Stage { kUpdate, kAdjust, kContacts, kVelocities, kStageCount };
inline constexpr std::array<std::string_view, kStageCount> kStageNames = {"update", "adjust",
                                                                          "contacts", "velocities"};

/// Everything a solver reads that depends on the model alone (the tree's orders from each anchor,
/// the joints' constant terms), built once. Solvers of one model (a crowd's puppets) may share
/// one instead of each building its own.
struct ModelTables;
std::shared_ptr<const ModelTables> make_model_tables(const Model& model);

/// why `rule` cannot step the model (empty when it can): a root the world holds is held by xpbd's
/// sweep and tree's system alone, and no rule gives a slide's armature an inertia
std::string rule_model_problem(const Model& model, Rule rule);

struct Workspace;  ///< a solver's scratch (private)
namespace lanes {
class LaneStepper;  ///< the crowd's lane path (private)
}

class Solver {
 public:
  /// the model must outlive the solver; throws std::invalid_argument on invalid settings.
  /// `tables`: make_model_tables(model), to share them with other solvers of the model (built
  /// here when null; tables of another model throw std::invalid_argument)
  Solver(const Model& model, const Settings& settings, const Environment& environment,
         std::shared_ptr<const ModelTables> tables = nullptr);
  /// a temporary model would not outlive the solver
  Solver(Model&&, const Settings&, const Environment&,
         std::shared_ptr<const ModelTables> = nullptr) = delete;
  ~Solver();
  Solver(Solver&&) noexcept;
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;
  Solver& operator=(Solver&&) = delete;

  /// place every segment (poses and velocities in world); clears pins, forces and time
  void reset(std::span<const BodyState> bodies);
  /// Move every segment to `bodies` (poses and velocities in world) in the middle of a run: pins,
  /// user forces, tremble and time are kept, the next step starts from these poses (its previous
  /// poses are these), the pins' motion restarts from their current targets, and a diverged flag
  /// is cleared. Throws std::invalid_argument unless there is one state per segment.
  void place(std::span<const BodyState> bodies);
  /// Put back a whole state that state() returned, of this solver or of another solver of the same
  /// model (a snapshot, or a benchmark's fixed start): the run continues from it bit for bit as it
  /// did. Throws std::invalid_argument for a state of another size.
  void restore(const State& state);
  /// pins change rarely (a user grabs or lets go). At most kMaxPins; the first pin that is not a
  /// grab is the adjust pass's anchor. A grab (Pin::is_grab) is a force in the update, not a
  /// constraint of the adjust.
  void set_pins(std::span<const Pin> pins);
  /// move the pins' targets (world) for the end of the next step
  void set_pin_targets(std::span<const Vector3d> targets);
  void step(double dt);
  /// the clock the tremble reads (State::time), for a state placed in the middle of a run
  void set_time(double time) { state_.time = time; }
  /// One stage of a substep of length h on the current state, with the pins' targets of the last
  /// substep: step() runs kUpdate … kVelocities in order; benchmarks time them one at a time.
  void run_stage(Stage stage, double h);
  /// asks the cache for everything step() reads, without waiting for it: a crowd issues this for
  /// the next puppet while it steps the current one
  void prefetch() const;

  const Model& model() const { return model_; }
  const Settings& settings() const { return settings_; }
  const Environment& environment() const { return environment_; }
  const State& state() const { return state_; }
  /// the user's forces (grabs and tremble: user_wrenches) the last substep applied, per segment
  std::span<const Wrench> user_wrenches() const;
  /// wall time (s) of each stage in the last step; zeros unless settings.time_stages
  const std::array<double, kStageCount>& stage_seconds() const { return stage_seconds_; }

 private:
  /// steps a batch of solvers' states together, as step() would each
  friend class lanes::LaneStepper;
  void substep(double h, double target_fraction);
  void check_finite();

  const Model& model_;
  Settings settings_;
  bool joint_springs_ = false;  ///< the model's joints have springs or dampers
  bool limit_pass_ = false;     ///< the limits' velocity pass runs (settings and the rule's row)
  Environment environment_;
  State state_;
  std::unique_ptr<Workspace> workspace_;  ///< never null but in a moved-from solver
  std::shared_ptr<const ModelTables> tables_;
  std::array<double, kStageCount> stage_seconds_{};
  std::array<Vector3d, kMaxPins> substep_targets_{};  ///< pins' targets at the end of the substep
  std::array<Pin, kMaxPins> substep_grabs_{};         ///< the grabs with their targets at its end
};

}  // namespace puppet::procedural
