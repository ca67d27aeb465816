// Random rotations and vectors for the tests, drawn in a stated order (a call's arguments are
// evaluated in a different order by GCC and clang, so each draw is its own statement).
#pragma once

#include <random>

#include "puppet/model/model.h"

namespace puppet::test {

// uniform over rotations: a normalised 4-D Gaussian
inline Quaterniond random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  const double w = normal(rng), x = normal(rng), y = normal(rng), z = normal(rng);
  return Quaterniond(w, x, y, z).normalized();
}

// uniform in the cube [−scale, scale]³
inline Vector3d random_vector(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  const double x = u(rng), y = u(rng), z = u(rng);
  return {x, y, z};
}

}  // namespace puppet::test
