// Abuse, at random, in every solver: pins grabbed and let go anywhere on any segment, hard and
// compliant; targets that wander and jump by metres (a yank, a teleported hand); the whole
// puppet teleported and flung (up to 50 m/s, 50 rad/s); dt changed every few steps anywhere in
// the testbed's range (1e-5 to 0.1 s). Required: no step throws, and no non-finite state escapes
// a solver that does not say it diverged. A diverged solver is reset and the abuse goes on.
//
// PUPPET_SOAK_STEPS sets the steps per solver (default 2000, the CI's); the long run is
//   PUPPET_SOAK_STEPS=1000000 build/release/tests/unit_tests --gtest_filter='Soak.*'
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>

#include "puppet/compare/metrics.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/environment.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

long soak_steps() {
  const char* text = std::getenv("PUPPET_SOAK_STEPS");
  const long steps = text ? std::atol(text) : 2000;
  return steps > 0 ? steps : 2000;
}

struct Abuser {
  std::mt19937_64 random;
  double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(random); }
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  Vector3d vector(double magnitude) {
    return {uniform(-magnitude, magnitude), uniform(-magnitude, magnitude),
            uniform(-magnitude, magnitude)};
  }
};

struct SoakCount {
  long steps = 0, diverged = 0, escaped = 0, pin_changes = 0, teleports = 0;
};

SoakCount soak(const Model& model, const std::string& solver, const std::string& rule, long steps,
               uint64_t seed) {
  SolverOptions options;
  if (!rule.empty()) options.procedural.rule = *procedural::parse_rule(rule);
  auto simulator = make_simulator(solver, options);
  const Scenario scenario = make_scenario("drop", model);  // ground, gravity, air drag
  simulator->reset(model, scenario);
  Abuser abuse{std::mt19937_64(seed)};
  std::vector<BodyState> bodies(model.segment_count());
  std::vector<Pin> pins;
  std::vector<Vector3d> targets;
  double dt = 1.0 / 240.0;
  SoakCount count;
  for (long k = 0; k < steps; ++k) {
    if (abuse.chance(0.005)) {  // grab somewhere, let go, or grab a second point
      pins.clear();
      const int n = static_cast<int>(abuse.uniform(0.0, 2.999));
      simulator->read_state(bodies);
      for (int p = 0; p < n; ++p) {
        Pin pin;
        pin.segment = static_cast<int>(abuse.uniform(0.0, model.segment_count() - 1e-9));
        pin.local_point = abuse.vector(0.2);
        pin.compliance = abuse.chance(0.5) ? 0.0 : abuse.log_uniform(1e-6, 1e-1);
        pin.target = bodies[pin.segment].x + bodies[pin.segment].q * pin.local_point;
        pins.push_back(pin);
      }
      simulator->set_pins(pins);
      targets.resize(pins.size());
      for (size_t p = 0; p < pins.size(); ++p) targets[p] = pins[p].target;
      ++count.pin_changes;
    }
    for (Vector3d& target : targets) {
      target += abuse.chance(0.01) ? abuse.vector(2.0) : abuse.vector(0.02);  // a yank, or a drag
    }
    if (!targets.empty()) simulator->set_pin_targets(targets);
    if (abuse.chance(0.002)) {  // the whole puppet moved and flung, joints kept
      simulator->read_state(bodies);
      const Quaterniond turn = Quaterniond::UnitRandom();
      const Vector3d shift = abuse.vector(5.0) + Vector3d(0, 0, 5.0);
      const Vector3d v = abuse.vector(50.0), w = abuse.vector(50.0);
      const Vector3d centre = bodies[0].x;
      for (BodyState& b : bodies) {
        b.x = centre + shift + turn * (b.x - centre);
        b.q = turn * b.q;
        b.v = v + w.cross(b.x - centre - shift);
        b.w = w;
      }
      simulator->set_state(bodies);
      ++count.teleports;
    }
    if (abuse.chance(0.02)) dt = abuse.log_uniform(1e-5, 0.1);
    simulator->step(dt);
    simulator->read_state(bodies);
    ++count.steps;
    const bool finite = all_finite(bodies);
    if (!finite && !simulator->diverged()) ++count.escaped;
    if (simulator->diverged() || !finite) {
      ++count.diverged;
      simulator->reset(model, scenario);
      pins.clear();
      targets.clear();
    }
  }
  return count;
}

TEST(Soak, NoNonFiniteStateEscapesAnySolver) {
  const Model model = load_model(kPinocchio);
  const long steps = soak_steps();
  uint64_t seed = 1;
  for (const std::string& solver : solver_names()) {
    for (const std::string& rule :
         solver == "procedural" ? std::vector<std::string>{"literal", "smoothed", "weighted",
                                                           "subtree", "relaxed", "xpbd", "tree"}
                                : std::vector<std::string>{""}) {
      SCOPED_TRACE(solver + " " + rule);
      SoakCount count;
      EXPECT_NO_THROW(count = soak(model, solver, rule, steps, seed++));
      std::printf("[ soak     ] %-16s %-8s %ld steps, %ld grabs, %ld teleports: %ld diverged\n",
                  solver.c_str(), rule.c_str(), count.steps, count.pin_changes, count.teleports,
                  count.diverged);
      EXPECT_EQ(count.steps, steps);
      EXPECT_EQ(count.escaped, 0);
    }
  }
}

}  // namespace
}  // namespace puppet::compare
