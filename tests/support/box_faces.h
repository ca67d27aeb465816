// The six faces and eight corners of a box of Euler angles, as directions in angle space: a face
// pushes one angle (±1), a corner all three.
#pragma once

#include <vector>

#include "puppet/model/model.h"

namespace puppet::test {

inline std::vector<Vector3d> faces_and_corners() {
  std::vector<Vector3d> out;
  for (int k = 0; k < 3; ++k) {
    for (double sign : {-1.0, 1.0}) out.push_back(sign * Vector3d::Unit(k));
  }
  for (double a : {-1.0, 1.0}) {
    for (double b : {-1.0, 1.0}) {
      for (double c : {-1.0, 1.0}) out.push_back(Vector3d(a, b, c));
    }
  }
  return out;
}

}  // namespace puppet::test
