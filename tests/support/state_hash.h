// A determinism fingerprint: FNV-1a over the bytes of every pose and velocity.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>

#include "puppet/model/environment.h"

namespace puppet::test {

inline uint64_t state_hash(std::span<const BodyState> bodies) {
  uint64_t hash = 1469598103934665603ULL;
  auto mix = [&](double value) {
    unsigned char bytes[sizeof(double)];
    std::memcpy(bytes, &value, sizeof value);
    for (unsigned char b : bytes) hash = (hash ^ b) * 1099511628211ULL;
  };
  for (const BodyState& b : bodies) {
    for (double v : {b.x.x(), b.x.y(), b.x.z(), b.q.w(), b.q.x(), b.q.y(), b.q.z(), b.v.x(),
                     b.v.y(), b.v.z(), b.w.x(), b.w.y(), b.w.z()}) {
      mix(v);
    }
  }
  return hash;
}

}  // namespace puppet::test
