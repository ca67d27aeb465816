// The seed's tremble read as position noise (tremble.cpp, §3.4; the rule option
// --position-tremble): bounded by its amplitude, present only under a pull, reproducible from its
// seed. The tremble scenario's tremble is a force (user_forces_test.cpp).
#include <gtest/gtest.h>

#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/procedural/solver.h"
#include "support/source_dir.h"
#include "support/state_hash.h"

namespace puppet::procedural {
namespace {

constexpr double kDt = 1.0 / 240.0;
constexpr double kMaxAmplitude = 3e-3;  // a_max (m), tremble.cpp

struct TrembleRun {
  double largest = 0.0;  // largest offset component seen (m)
  uint64_t hash = 0;
};

TrembleRun run_tremble(uint64_t seed, bool pinned) {
  const Model model = load_model(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json");
  // the hand on a hard pin: the pull the position tremble reads is the pins' corrections
  const compare::Scenario scenario = compare::make_scenario("marionette", model);
  compare::SolverOptions options;
  options.procedural.tremble = true;
  Settings settings = compare::procedural_settings(options);
  EXPECT_TRUE(settings.tremble);
  settings.tremble_seed = seed;
  Solver solver(model, settings, scenario.environment);
  solver.reset(scenario.initial);
  if (pinned) solver.set_pins(scenario.initial_pins());
  std::vector<Vector3d> targets;
  TrembleRun run;
  for (int k = 0; k < 240 * 3; ++k) {
    if (pinned) {
      scenario.targets_at((k + 1) * kDt, targets);
      solver.set_pin_targets(targets);
    }
    solver.step(kDt);
    for (const Vector3d& offset : solver.state().tremble_offset) {
      run.largest = std::max(run.largest, offset.cwiseAbs().maxCoeff());
    }
  }
  run.hash = test::state_hash(solver.state().bodies);
  return run;
}

TEST(Tremble, BoundedByItsAmplitudeAndOnlyUnderAPull) {
  const TrembleRun pulled = run_tremble(2001, true);
  EXPECT_LE(pulled.largest, kMaxAmplitude);
  EXPECT_GT(pulled.largest, 1e-4);  // it does tremble while the hand is dragged
  // falling freely nothing pulls: x̂ = 0, so the amplitude a_max |sin γ| e^(−x̂) is 0
  EXPECT_EQ(run_tremble(2001, false).largest, 0.0);
}

TEST(Tremble, ReproducibleFromItsSeed) {
  EXPECT_EQ(run_tremble(2001, true).hash, run_tremble(2001, true).hash);
  EXPECT_NE(run_tremble(2001, true).hash, run_tremble(7, true).hash);
}

}  // namespace
}  // namespace puppet::procedural
