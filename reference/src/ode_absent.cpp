// A build without ODE (libode-dev missing when it was configured): no ode reference.
#include <stdexcept>

#include "puppet/reference/ode.h"

namespace puppet::reference {

std::string validate(const OdeSettings&) { return {}; }

bool have_ode() { return false; }

std::string ode_model_problem(const Model&) {
  return "this build has no ODE (install libode-dev and rebuild)";
}

std::unique_ptr<Solver> make_ode(const Model&, const Environment&, const OdeSettings&) {
  throw ModelError("ode: this build has no ODE (install libode-dev and rebuild)");
}

}  // namespace puppet::reference
