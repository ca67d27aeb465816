// The part of a reference's saved state that any layout of it can read: every segment's world
// pose and velocity, 13 numbers each, written just before the diverged flag that ends the save.
// A restore into another configuration (other pins, another rooting) takes the state from it.
#pragma once

#include <span>
#include <vector>

#include "puppet/model/environment.h"

namespace puppet::reference::detail {

inline void append_world_poses(std::span<const BodyState> bodies, std::vector<double>& out) {
  for (const BodyState& b : bodies) {
    out.insert(out.end(), b.x.data(), b.x.data() + 3);
    out.insert(out.end(), b.q.coeffs().data(), b.q.coeffs().data() + 4);
    out.insert(out.end(), b.v.data(), b.v.data() + 3);
    out.insert(out.end(), b.w.data(), b.w.data() + 3);
  }
}

// reads them back from a save that ends with them and the flag
inline void read_world_poses(std::span<const double> saved, std::span<BodyState> bodies) {
  size_t at = saved.size() - 1 - 13 * bodies.size();
  for (BodyState& b : bodies) {
    b.x = Vector3d(saved[at], saved[at + 1], saved[at + 2]);
    b.q.coeffs() = Eigen::Vector4d(saved[at + 3], saved[at + 4], saved[at + 5], saved[at + 6]);
    b.v = Vector3d(saved[at + 7], saved[at + 8], saved[at + 9]);
    b.w = Vector3d(saved[at + 10], saved[at + 11], saved[at + 12]);
    at += 13;
  }
}

}  // namespace puppet::reference::detail
