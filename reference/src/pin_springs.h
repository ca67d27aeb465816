// How a reference holds its pins: hard ones as its own constraints, compliant ones as springs and
// grabs as capped spring–dampers (user_forces.h), both applied as external forces with the
// environment's, the tremble and the joints' springs and dampers, evaluated on the state at the
// start of each step.
#pragma once

#include <span>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/joint_springs.h"
#include "puppet/model/user_forces.h"

namespace puppet::reference::detail {

// A reference's pins: the hard ones are its own constraints, the others forces. Pin k is hard pin
// slots[k] when that is ≥ 0, else spring −1 − slots[k] (compliant: pin_spring_wrench; a grab:
// grab_force).
struct PinSprings {
  std::vector<Pin> springs;
  std::vector<int> slots;
  std::vector<Wrench> user;     // the user's forces of the last step, per segment
  double time = 0.0;            // the time the tremble reads, advanced by every step
  bool joint_springs = true;    // whether the joints' springs and dampers are forces here too
                                // (false where the engine builds them: MuJoCo)
  std::vector<Wrench> applied;  // every external force of the last step, per segment

  void clear() {
    springs.clear();
    slots.clear();
  }
  // records `pin`; true when it is hard, and then it is the solver's hard pin `hard_count`
  bool add(const Pin& pin, int hard_count) {
    const bool hard = pin.is_hard();
    slots.push_back(hard ? hard_count : -1 - static_cast<int>(springs.size()));
    if (!hard) springs.push_back(pin);
    return hard;
  }
  // the hard pin that pin k is, or −1 once its spring has taken the target
  int retarget(size_t k, const Vector3d& target) {
    if (slots[k] >= 0) return slots[k];
    springs[-1 - slots[k]].target = target;
    return -1;
  }
  // every segment's external wrench for a step of length h from `bodies` (world, at the COM):
  // the environment's, the compliant springs', the grabs', the tremble and the joints' springs
  // and dampers (into `applied`)
  std::span<const Wrench> wrenches(const Model& model, const Environment& environment,
                                   std::span<const BodyState> bodies, double h) {
    const size_t n = static_cast<size_t>(model.segment_count());
    user.resize(n);
    applied.resize(n);
    user_wrenches(model, environment, springs, bodies, time, user);
    for (size_t s = 0; s < n; ++s) {
      Wrench w = environment_wrench(model.segments[s], environment, bodies[s], h);
      w.force += user[s].force;
      w.torque += user[s].torque;
      applied[s] = w;
    }
    for (const Pin& spring : springs) {
      if (spring.is_grab()) continue;
      const Wrench pull = pin_spring_wrench(spring, bodies[spring.segment]);
      applied[spring.segment].force += pull.force;
      applied[spring.segment].torque += pull.torque;
    }
    if (joint_springs) add_joint_spring_wrenches(model, bodies, h, applied);
    return applied;
  }
};

}  // namespace puppet::reference::detail
