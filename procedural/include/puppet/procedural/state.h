/// \file
/// A procedural solver's state: everything that changes during a run (the segments' poses and
/// velocities, the pins and grabs, the tremble's phase), apart from the solver that advances it
/// so that its stages can be declared without the solver.
#pragma once

#include <array>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::procedural {

constexpr int kMaxPins = 4;

/// everything that changes during a run; allocated once, plain contiguous data
struct State {
  std::vector<BodyState> bodies;  ///< per segment
  std::vector<Vector3d> x_prev;   ///< poses at the start of the (sub)step
  std::vector<Quaterniond> q_prev;
  std::vector<Vector3d> user_force;  ///< world, at the COM; left in place between steps
  std::vector<Vector3d> user_torque;
  std::vector<Vector3d> tremble_offset;  ///< current tremble displacement per segment
  std::array<Pin, kMaxPins> pins{};
  std::array<Vector3d, kMaxPins> pin_previous_target{};
  std::array<double, kMaxPins> pin_force{};  ///< last correction expressed as a force (N)
  int pin_count = 0;
  /// the model's root is joined to the world (RootJoint): the hold, not the first pin, anchors
  /// the adjust, and every pin is held as a pin beside it
  bool root_held = false;
  /// the grabs (Pin::is_grab): forces, not constraints, applied in the update (user_forces.h)
  std::array<Pin, kMaxPins> grabs{};
  std::array<Vector3d, kMaxPins> grab_previous_target{};
  int grab_count = 0;
  /// what set_pins was given, in its order: pin k is pins[slots[k]] when that is ≥ 0, else
  /// grabs[−1 − slots[k]]
  std::array<int, kMaxPins> slots{};
  int slot_count = 0;
  double tremble_phase = 0.0;
  double time = 0.0;
  bool diverged = false;  ///< a non-finite value appeared; the state is no longer advanced
  double diverged_time = 0.0;
};

}  // namespace puppet::procedural
