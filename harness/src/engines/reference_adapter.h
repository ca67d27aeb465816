// A reference engine's world (reference::Solver) behind the Simulator interface: what every
// reference engine's row makes, given how to build its world.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "puppet/compare/simulator.h"
#include "puppet/reference/solver.h"

namespace puppet::compare {

// builds the engine's world for the model in the scenario's environment
using ReferenceFactory = std::function<std::unique_ptr<reference::Solver>(
    const Model& model, const Environment& environment)>;

// `exact_armature`: the engine builds joint armature itself (MuJoCo); else the world is built from
// armature_in_inertia's model (joint_springs.h), which the simulator keeps
std::unique_ptr<Simulator> make_reference_simulator(std::string name, ReferenceFactory factory,
                                                    bool exact_armature = false);

}  // namespace puppet::compare
