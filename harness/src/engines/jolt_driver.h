// What the jolt engine's driver computes itself, asked directly (tests/reference/jolt_test.cpp
// compares it with the testbed's own formulas).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "puppet/model/environment.h"

namespace puppet::compare {

// the forces one of the driver's steps of length h would apply from `bodies` at `time`
// (reference/jolt/forces.mjs): per segment every external wrench (`applied`: the environment's,
// the grabs', the tremble and the compliant pins') and the user's alone (`user`); false with
// `error` when the driver could not answer
bool jolt_driver_forces(const Model& model, const Environment& environment,
                        std::span<const Pin> pins, std::span<const BodyState> bodies, double time,
                        double h, std::vector<Wrench>& applied, std::vector<Wrench>& user,
                        std::string& error);

// the bytes of the driver's heap in use after each of `builds` builds of the model at rest, in
// one driver (a driver serves many runs: its heap must not grow with them)
bool jolt_driver_heap_after_builds(const Model& model, int builds, std::vector<double>& used,
                                   std::string& error);

}  // namespace puppet::compare
