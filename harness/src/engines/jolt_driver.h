// The jolt engine's driver (reference/jolt/server.mjs) as the testbed reaches it, and what it
// computes itself, asked directly (tests/reference/jolt_test.cpp compares that with the
// testbed's own formulas).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "node_process.h"
#include "puppet/model/environment.h"

namespace puppet::compare {

namespace jolt {
// why the engine cannot run here (empty when it can): Node.js and the pinned package
std::string absent_reason();
bool available();
// why no driver answers here (empty when one does): a driver taken from the pool or started, and
// asked its version (under an address-space limit node cannot reserve WebAssembly's memory, and
// every run would read as diverged); the driver goes back to the pool for the runs
std::string driver_problem();
// the bodies a Jolt world of the driver holds at most (JoltSettings' default mMaxBodies, 10240):
// a segment each, the ground, and a kinematic body per hard pin
inline constexpr int kMaxBodies = 10240;
// a running driver, from the pool or started (throws std::runtime_error when it cannot start),
// and back to the pool when it is still healthy
std::unique_ptr<NodeProcess> take_driver();
void give_back(std::unique_ptr<NodeProcess> driver);
// the requests' parts: the model (box limits as their Jolt pyramid, jolt_box.h), the
// environment, the pins and states (per segment x, q (x, y, z, w), v, ω, flat)
nlohmann::json model_json(const Model& model);
nlohmann::json environment_json(const Environment& environment);
nlohmann::json pins_json(std::span<const Pin> pins);
nlohmann::json states_json(std::span<const BodyState> bodies);
}  // namespace jolt

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
