// The model's Euler box (euler_box.h) read as Jolt's swing–twist pyramid, which is what Jolt's
// SixDOF constraint limits: q = swing·twist, the twist about the constraint's x, the swing's two
// angles y = 2 atan2(s_y, s_w) and z = 2 atan2(s_z, s_w), each within a range. A box
// R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂) is close to R_Z(z) R_Y(y) R_X(τ), read two ways: twist about a₂
// (from the parent to the child), or about a₀ (from the child to the parent, on the inverse
// rotation). Neither is the box; the jolt engine takes, joint by joint, the one nearer to it.
#pragma once

#include "puppet/model/model.h"

namespace puppet::compare {

struct JoltPyramid {
  bool twist_first = false;       // twist about a₀, the constraint from the child to the parent
  int x = 2, y = 1, z = 0;        // the joint frame's axes that are the constraint's X, ±Y, Z
  double y_sign = 1.0;            // Y = y_sign · e_y, so that X × Y = Z
  double lower[3]{}, upper[3]{};  // the ranges of τ, y, z (rad)
  // how far the pyramid reaches outside the box (the most an Euler angle of a rotation on the
  // pyramid's boundary is outside its range) and the box outside the pyramid (the most a
  // pyramid angle of one on the box's boundary is outside its range), in degrees, over a grid
  double beyond_deg = 0.0, cut_deg = 0.0;
};

// the reading of a box joint's limits, twist last or first
JoltPyramid jolt_pyramid(const Joint& joint, bool twist_first);
// the nearer of the two: the smaller of each one's larger gap
JoltPyramid nearest_jolt_pyramid(const Joint& joint);

}  // namespace puppet::compare
