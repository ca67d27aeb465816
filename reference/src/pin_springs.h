// How a reference holds its pins: hard ones as its own constraints, compliant ones as springs
// applied as external forces (pin_spring_wrench), evaluated at the start of each step.
#pragma once

#include <span>
#include <vector>

#include "puppet/model/environment.h"

namespace puppet::reference::detail {

// A reference's pins: the hard ones are its own constraints, the compliant ones
// springs applied as forces (pin_spring_wrench). Pin k is hard pin slots[k] when that is ≥ 0,
// else spring −1 − slots[k].
struct PinSprings {
  std::vector<Pin> springs;
  std::vector<int> slots;

  void clear() {
    springs.clear();
    slots.clear();
  }
  // records `pin`; true when it is hard, and then it is the solver's hard pin `hard_count`
  bool add(const Pin& pin, int hard_count) {
    const bool hard = pin.compliance <= 0.0;
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
  // the environment's wrench on a segment over a step of length h plus its springs' pull (world,
  // at the COM)
  Wrench wrench(const Segment& segment, const Environment& environment, int index,
                const BodyState& body, double h) const {
    Wrench w = environment_wrench(segment, environment, body, h);
    for (const Pin& spring : springs) {
      if (spring.segment != index) continue;
      const Wrench pull = pin_spring_wrench(spring, body);
      w.force += pull.force;
      w.torque += pull.torque;
    }
    return w;
  }
};

}  // namespace puppet::reference::detail
