// A build without MuJoCo (libmujoco-dev missing when it was configured): no mujoco reference.
#include "puppet/reference/mujoco.h"

namespace puppet::reference {

bool have_mujoco() { return false; }

std::string mujoco_model_problem(const Model&) {
  return "this build has no MuJoCo (install libmujoco-dev and rebuild)";
}

std::unique_ptr<Solver> make_mujoco(const Model&, const Environment&, const MujocoSettings&) {
  throw ModelError("mujoco: this build has no MuJoCo (install libmujoco-dev and rebuild)");
}

}  // namespace puppet::reference
