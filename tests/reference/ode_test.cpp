// The ODE reference against the model it was built from, the analytic pendulum, the static
// deflection of a compliant pin, the Euler motor's signs, and its own determinism; and the models
// it refuses, by its own check, before anything runs. Its limits are also held with every
// engine's in limit_test.cpp (a box's faces and corners, a hinge's stops, their rebound), in both
// steppers, and a swing–twist limb's stop in bullet_test.cpp's Limits test.
#include "puppet/reference/ode.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/compare/metrics.h"
#include "puppet/compare/run.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/rotation.h"
#include "support/pendulum.h"
#include "support/reference_runs.h"
#include "support/rule_runs.h"
#include "support/source_dir.h"

namespace puppet::reference {
namespace {

const std::string& kPinocchio = test::kPinocchioPath;
const std::string kSwingTwist =
    std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio-swing-twist.json";
constexpr double kDt = 1.0 / 240.0;

struct Stepper {
  const char* name;
  OdeSettings settings;
};
const Stepper kSteppers[] = {{"quick", {.stepper = OdeStepper::kQuick}},
                             {"step", {.stepper = OdeStepper::kStep}}};

compare::SolverOptions options_for(const OdeSettings& settings) {
  compare::SolverOptions options;
  options.ode = settings;
  return options;
}

// what ODE holds is what the model says: masses, inertias, rest poses, joint anchors
TEST(Ode, HoldsTheModel) {
  for (const Model& model : {load_model(kPinocchio), load_model(kSwingTwist), make_chain(5)}) {
    SCOPED_TRACE(model.name);
    test::expect_holds_the_model(*make_ode(model, Environment{}), model);
  }
}

// A rod pinned at its top, released at 10°: the physical pendulum's period with its
// finite-amplitude correction, within 0.1 % at 1/240 s in both steppers. The pin is a ball joint
// to the world whose error ODE reduces by ERP each step; the integrator is semi-implicit Euler.
TEST(Ode, PendulumPeriodWithinATenthOfAPercent) {
  const Model model = test::rods(1);
  const double expected = test::analytic_period(10.0 * M_PI / 180.0);
  for (const Stepper& stepper : kSteppers) {
    auto solver = make_ode(model, Environment{}, stepper.settings);
    const double period = test::released_rod_period(*solver, kDt);
    std::printf("[ period   ] ode %-5s %.6f s vs analytic %.6f s: %+.4f %%\n", stepper.name, period,
                expected, 100 * (period / expected - 1));
    EXPECT_NEAR(period / expected, 1.0, 0.001) << stepper.name;
  }
}

// Two rods hanging still from a compliant pin (a spring applied as a force, as in every
// reference), air drag to settle them: the pin point sags by the weight it holds times C
TEST(Ode, CompliantGrabSettlesAtTheStaticDeflection) {
  const Model model = test::rods(2);
  Environment air;
  air.air_drag = 2.0;
  constexpr double kCompliance = 5e-4;  // m/N: 2 kg stretch it by 9.8 mm
  for (const Stepper& stepper : kSteppers) {
    auto solver = make_ode(model, air, stepper.settings);
    const double ratio = test::compliant_sag_ratio(*solver, kCompliance, kDt);
    std::printf("[ grab     ] ode %-5s static deflection / (weight x C): %+.2f %%\n", stepper.name,
                100 * (ratio - 1));
    EXPECT_NEAR(ratio, 1.0, 0.01) << stepper.name;
  }
}

compare::RunResult run(const compare::SolverOptions& options, const Model& model,
                       const std::string& scenario) {
  auto simulator = compare::make_simulator("ode", options);
  compare::RunOptions run_options;
  run_options.dt = kDt;
  run_options.timing = false;
  return compare::run_scenario(*simulator, model, compare::make_scenario(scenario, model),
                               run_options);
}

// The ragdoll's joints drift under ERP, as every maximal-coordinate ragdoll's: hanging from the
// head, Pinocchio's joints stay within a millimetre (Bullet's ragdoll: 0.6 mm), the gap stated
TEST(Ode, HangJointGapBelowAMillimetre) {
  const Model model = load_model(kPinocchio);
  for (const Stepper& stepper : kSteppers) {
    const auto result = run(options_for(stepper.settings), model, "hang");
    std::printf("[ gap      ] ode %-5s hang: max joint gap %.2e m, pin gap %.2e m\n", stepper.name,
                result.value("joint_gap_m", "max"), result.value("pin_gap_m", "max"));
    ASSERT_FALSE(result.diverged) << stepper.name;
    EXPECT_LT(result.value("joint_gap_m", "max"), 1e-3) << stepper.name;
  }
}

// every scenario on both models runs to its end with finite values, or is reported as diverged
// with its time
TEST(Ode, EveryScenarioEndsOrIsReportedDiverged) {
  for (const std::string& path :
       {kPinocchio, std::string(PUPPET_SOURCE_DIR) + "/models/humanoid.xml"}) {
    const Model model = load_model(path);
    for (const std::string& name : compare::scenario_names()) {
      const auto result = run({}, model, name);
      SCOPED_TRACE(model.name + " " + name);
      if (result.diverged) {
        EXPECT_GT(result.diverged_at, 0.0);
        continue;
      }
      EXPECT_NEAR(result.trace.back().t, compare::make_scenario(name, model).duration, 1e-9);
      for (const auto& m : result.trace) ASSERT_TRUE(m.finite);
    }
  }
}

// ODE's Euler motor measures the box's own angles, each negated, its middle axis a₂ × a₀: the
// stops are right only if those signs are. A limb spun at 2 rad/s, without gravity, towards
// each face of a box (orders yxz, Pinocchio's, whose ODE middle axis is −x; xyz, whose is +y;
// zyx, −y) reaches that face and goes no further than a step's travel (0.48°) past it
TEST(Ode, AnEulerMotorStopsAtEachBoxFace) {
  for (const char* order : {"yxz", "xyz", "zyx"}) {
    const Model model = parse_model(std::string(R"({"name":"box","segments":[
      {"name":"base","mass":5,"position":[0,0,1],"shape":{"type":"box","half_extents":[0.1,0.1,0.1]}},
      {"name":"rod","mass":1,"position":[0,0,0.75],"shape":{"type":"capsule","radius":0.03,"half_length":0.1}}],
     "joints":[{"name":"j","parent":"base","child":"rod","anchor":[0,0,0.9],"type":"ball",
      "box_deg":{"order":")") + order + R"(","lower":[-20,-30,-10],"upper":[40,15,25]}}]})",
                                    "box");
    const Joint& joint = model.joints[0];
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {-1.0, 1.0}) {
        SCOPED_TRACE(std::string(order) + " axis " + std::to_string(axis) +
                     (sign > 0 ? " upper" : " lower"));
        auto solver = make_ode(model, Environment{.gravity = Vector3d::Zero()},
                               {.stepper = OdeStepper::kStep});
        std::vector<BodyState> bodies = rest_pose(model);
        const Vector3d base = bodies[0].x;
        const Pin pins[] = {{0, Vector3d(0, 0, 0), base},
                            {0, Vector3d(0.1, 0, 0), base + Vector3d(0.1, 0, 0)},
                            {0, Vector3d(0, 0.1, 0), base + Vector3d(0, 0.1, 0)}};
        solver->set_pins(pins);
        const Vector3d w =
            2.0 * sign *
            (bodies[0].q * joint.frame_in_parent * Vector3d::Unit(joint.box_order.axes[axis]));
        bodies[1].w = w;
        bodies[1].v = w.cross(bodies[1].x - joint.anchor_world);
        solver->set_state(bodies);
        double furthest = 0.0;
        for (int k = 0; k < 240; ++k) {
          solver->step(kDt);
          solver->read_state(bodies);
          const Vector3d angles = euler_angles(
              joint.box_order, joint_relative_rotation(joint, bodies[0].q, bodies[1].q));
          furthest = sign > 0 ? std::max(furthest, angles[axis]) : std::min(furthest, angles[axis]);
        }
        const double bound = sign > 0 ? joint.box_upper[axis] : joint.box_lower[axis];
        EXPECT_NEAR(furthest * 180 / M_PI, bound * 180 / M_PI, 0.5);
      }
    }
  }
}

// The same inputs give the same bits, a restored snapshot repeats the steps that followed it,
// and a run beside another on a second thread is the run alone: dWorldQuickStep shuffles its
// rows with ODE's one process-wide random generator, which each solver keeps for itself
TEST(Ode, RunsAgreeBitwiseAloneBesideAnotherAndFromASnapshot) {
  const Model model = load_model(kPinocchio);
  for (const Stepper& stepper : kSteppers) {
    for (const std::string name : {"drag", "drop"}) {
      SCOPED_TRACE(std::string(stepper.name) + " " + name);
      const compare::Scenario scenario = compare::make_scenario(name, model);
      const auto fresh = [&] {
        auto simulator = compare::make_simulator("ode", options_for(stepper.settings));
        simulator->reset(model, scenario);
        return simulator;
      };
      test::expect_runs_agree_bitwise(fresh, scenario, kDt);
    }
  }
}

// A non-finite state, a runaway one, a non-finite pin target: each is flagged as diverged, and
// stepping on changes nothing and stops nothing. ODE itself would stop the process at the first
// non-finite quaternion (an internal assertion), so none reaches it.
TEST(Ode, NonFiniteOrRunawayInputIsDiverged) {
  const Model model = load_model(kPinocchio);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Stepper& stepper : kSteppers) {
    for (int hostile = 0; hostile < 4; ++hostile) {
      SCOPED_TRACE(std::string(stepper.name) + " input " + std::to_string(hostile));
      auto solver = make_ode(model, Environment{.ground = true}, stepper.settings);
      std::vector<BodyState> bodies = rest_pose(model);
      const Pin pin{3, Vector3d(0, 0, 0), bodies[3].x};
      solver->set_pins(std::span(&pin, 1));
      if (hostile == 0) bodies[3].w.x() = nan;
      if (hostile == 1) bodies[3].q.coeffs() << nan, 0, 0, 1;
      if (hostile == 2) bodies[3].v.z() = 1e9;
      solver->set_state(bodies);
      if (hostile == 3) {
        const Vector3d target(nan, 0, 1);
        solver->set_pin_targets(std::span(&target, 1));
      }
      solver->step(kDt);
      EXPECT_TRUE(solver->diverged());
      solver->step(kDt);
      EXPECT_TRUE(solver->diverged());
      std::vector<BodyState> read(model.segment_count());
      solver->read_state(read);
      EXPECT_EQ(all_finite(read), hostile == 2 || hostile == 3);
    }
  }
}

// what ODE cannot build is refused by its own check, in one line naming the part, before
// anything runs; settings out of range likewise
TEST(Ode, ModelsItCannotBuildAreRefusedUpFront) {
  const Model ellipsoid = parse_model(R"({"name":"egg","segments":[
    {"name":"egg","mass":1,"position":[0,0,1],"shape":{"type":"ellipsoid","half_extents":[0.1,0.2,0.3]}}],
    "joints":[]})",
                                      "egg");
  EXPECT_NE(ode_model_problem(ellipsoid).find("segment \"egg\" has an ellipsoid"),
            std::string::npos)
      << ode_model_problem(ellipsoid);
  EXPECT_THROW(make_ode(ellipsoid, Environment{}), ModelError);

  for (const Model& model : {load_model(kPinocchio), load_model(kSwingTwist), make_chain(3)}) {
    EXPECT_TRUE(ode_model_problem(model).empty()) << model.name;
  }
  EXPECT_THROW(make_ode(make_chain(2), Environment{}, {.iterations = 0}), std::invalid_argument);
  EXPECT_THROW(make_ode(make_chain(2), Environment{}, {.erp = 1.5}), std::invalid_argument);
  EXPECT_EQ(compare::engine_model_problem("ode", ellipsoid),
            "segment \"egg\" has an ellipsoid, for which ODE has no geom");
}

}  // namespace
}  // namespace puppet::reference
