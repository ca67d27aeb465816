// Rule xpbd against independent answers: the analytic physical pendulum, the Lagrangian double
// pendulum (and its convergence with dt), a compliant grab's static deflection, conservation of
// angular momentum, and the residual its sweeps leave in the joints of the Pinocchio scenarios.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "puppet/compare/scenario.h"
#include "puppet/procedural/solver.h"
#include "support/rule_runs.h"
#include "support/spinning_box.h"

namespace puppet::procedural {
namespace {

constexpr double kDt = 1.0 / 240.0;
// pinned: any change to xpbd's arithmetic shows here first (update it deliberately)
constexpr uint64_t kExpectedXpbdDragHash = 0x68045c74109a2fdeULL;

Settings xpbd() {
  Settings settings;
  settings.rule = Rule::kXpbd;
  return settings;
}

TEST(Xpbd, RuleDefaultsAreOneSweepOfManySubsteps) {
  const Settings settings = rule_defaults(xpbd());
  EXPECT_EQ(settings.iterations, 1);
  EXPECT_EQ(settings.substeps, kXpbdSubsteps);
  Settings relaxed;
  relaxed.rule = Rule::kRelaxed;
  relaxed = rule_defaults(relaxed);
  EXPECT_EQ(relaxed.iterations, 4);
  EXPECT_EQ(relaxed.substeps, 1);
}

// one rod swinging 10° about its top: the period of the physical pendulum to 0.1 %
TEST(Xpbd, PendulumPeriodWithinATenthOfAPercent) {
  const double ratio = test::pendulum_period_ratio(xpbd(), 10.0 * M_PI / 180.0, kDt);
  std::printf("[ period   ] xpbd period / analytic: %+.4f %%\n", 100 * (ratio - 1));
  EXPECT_NEAR(ratio, 1.0, 1e-3);
}

TEST(Xpbd, DoublePendulumWithinFiveMillimetresAndConverging) {
  const double coarse = test::double_pendulum_error(xpbd(), 1.0 / 240.0);
  const double fine = test::double_pendulum_error(xpbd(), 1.0 / 960.0);
  std::printf("[ 2 rods   ] xpbd mean pose error over 5 s: %.5f m at 1/240, %.5f m at 1/960\n",
              coarse, fine);
  EXPECT_LT(coarse, 0.005);
  EXPECT_LT(fine, coarse);
}

// two rods hanging still from a compliant pin: the pin stretches by the weight it holds times C.
// xpbd, tree and relaxed share the pin's correction with the whole chain (sweeps or the exact
// system), so the chain hangs from the spring; a one-sided pass moves the pinned rod alone and
// carries its child along, so its spring feels only that rod (reported).
TEST(Xpbd, CompliantGrabSettlesAtTheStaticDeflection) {
  constexpr double kCompliance = 5e-4;  // m/N: 2 kg stretch it by 9.8 mm
  for (Rule rule : kAllRules) {
    Settings settings;
    settings.rule = rule;
    const double ratio = test::static_deflection_ratio(settings, kCompliance);
    std::printf("[ grab     ] %-8s static deflection / (weight x C): %+.1f %%\n",
                std::string(rule_name(rule)).c_str(), 100 * (ratio - 1));
    if (rule == Rule::kXpbd || rule == Rule::kRelaxed || rule == Rule::kTree) {
      EXPECT_NEAR(ratio, 1.0, 0.05) << rule_name(rule);
    }
  }
}

// the free spinning box of solver_test: no joint, so xpbd is its update alone
TEST(Xpbd, SpinningBoxKeepsItsAngularMomentum) {
  const test::SpinResult spin = test::spin_box(xpbd(), kDt);
  EXPECT_NEAR(spin.momentum_ratio, 1.0, 1e-3);
  EXPECT_LT(spin.direction_drift, 1e-3);
}

// Pinocchio's scenarios at 1/240 with the default substeps: never diverged (yank's grab circling
// at 2 Hz), hang's joints within 1 mm after every step (the residual of one sweep per substep).
// Drag, shake and tremble run with the air drag 2 % either side as well, because their worst gap
// is not a property of the rule but of the inputs: measured, tremble's is 0.66 mm to 5.5 cm
// across that band (0.77 mm with the old explicit drag factor, 7.2 mm with the exact decay, which
// changes the drag's effect per substep by 3e-5 of itself), drag's 0.66 to 1.06 mm, shake's
// 0.48 to 1.07 mm. Required there: no joint opens past 10 cm, half a forearm (the puppet holds
// together); the spread is the finding. Reported, not required: water's residual (1.6 mm). More,
// shorter substeps (16 or 32 at 1/240) diverge in some drags and trembles: one Gauss–Seidel sweep
// bounces a limit's correction between a shoulder at its twist limit and the elbow's hinge (each
// pass leaves the other ~0.8 of the error), and velocities from poses feed it back; the same
// bounce is what opens tremble's joints by centimetres in part of the band.
TEST(Xpbd, EveryScenarioStaysOkAndItsJointsHold) {
  const Model model = load_model(test::kPinocchioPath);
  for (const std::string& name : compare::scenario_names()) {
    compare::ScenarioOptions options;
    if (name == "yank") options.hz = 2.0;
    const compare::Scenario nominal = compare::make_scenario(name, model, options);
    const bool banded = name == "hang" || name == "drag" || name == "shake" || name == "tremble";
    double worst = 0.0, least = INFINITY;
    for (const double scale :
         banded ? std::vector<double>{0.98, 0.99, 1.0, 1.01, 1.02} : std::vector<double>{1.0}) {
      compare::Scenario scenario = nominal;
      scenario.environment.air_drag *= scale;
      const test::ScenarioRun run = test::run_scenario(model, scenario, xpbd(), kDt);
      EXPECT_FALSE(run.diverged) << name << " drag x" << scale;
      worst = std::max(worst, run.worst_gap);
      least = std::min(least, run.worst_gap);
    }
    std::printf("[ %-8s ] xpbd max joint gap %.2e to %.2e m\n", name.c_str(), least, worst);
    if (name == "hang") {
      EXPECT_LT(worst, 1e-3) << name;
    } else if (banded) {
      EXPECT_LT(worst, 0.1) << name;
    }
  }
}

TEST(Xpbd, DeterministicDragAfterThousandSteps) {
  const uint64_t first = test::drag_hash(xpbd());
  std::printf("[ hash     ] %016llx\n", static_cast<unsigned long long>(first));
  EXPECT_EQ(test::drag_hash(xpbd()), first);
  EXPECT_EQ(first, kExpectedXpbdDragHash);
}

}  // namespace
}  // namespace puppet::procedural
