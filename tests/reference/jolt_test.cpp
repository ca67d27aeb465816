// The jolt engine (Jolt Physics' WebAssembly build driven through Node.js) against the analytic
// pendulum, the static deflection of a compliant pin, the testbed's own forces (which its driver
// computes in JavaScript), its own determinism and snapshots; and the models it refuses, by its
// own check, before anything runs. Its limits are held with every engine's in limit_test.cpp (a
// box's faces and corners, a hinge's stops, their rebound), and a swing–twist limb's stop in
// bullet_test.cpp's Limits test. Without Node.js or the package, each test is skipped.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "jolt_box.h"
#include "jolt_driver.h"
#include "puppet/compare/engines.h"
#include "puppet/compare/run.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/joint_springs.h"
#include "puppet/model/mjcf.h"
#include "puppet/model/rotation.h"
#include "puppet/model/user_forces.h"
#include "support/pendulum.h"
#include "support/reference_runs.h"
#include "support/rule_runs.h"
#include "support/simulator_solver.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

const std::string& kPinocchio = test::kPinocchioPath;
constexpr double kDt = 1.0 / 240.0;

#define SKIP_WITHOUT_JOLT()                                              \
  if (!find_engine("jolt")) {                                            \
    GTEST_SKIP() << "jolt is not built here: " << find_missing_reason(); \
  }

std::string find_missing_reason() {
  for (const Engine& engine : engines()) {
    if (engine.name == "jolt" && engine.missing) return engine.missing();
  }
  return {};
}

// A rod pinned at its top, released at 10°: the physical pendulum's period with its
// finite-amplitude correction, within 0.1 % at 1/240 s. The pin is a point constraint to a
// kinematic body; Jolt integrates by semi-implicit Euler in single precision.
TEST(Jolt, PendulumPeriodWithinATenthOfAPercent) {
  SKIP_WITHOUT_JOLT();
  const Model model = test::rods(1);
  const double expected = test::analytic_period(10.0 * M_PI / 180.0);
  test::SimulatorSolver solver("jolt", model, Environment{});
  const double period = test::released_rod_period(solver, kDt);
  std::printf("[ period   ] jolt %.6f s vs analytic %.6f s: %+.4f %%\n", period, expected,
              100 * (period / expected - 1));
  EXPECT_NEAR(period / expected, 1.0, 0.001);
}

// Two rods hanging still from a compliant pin (a spring applied as a force, as in every
// reference), air drag to settle them: the pin point sags by the weight it holds times C
TEST(Jolt, CompliantGrabSettlesAtTheStaticDeflection) {
  SKIP_WITHOUT_JOLT();
  const Model model = test::rods(2);
  Environment air;
  air.air_drag = 2.0;
  constexpr double kCompliance = 5e-4;  // m/N: 2 kg stretch it by 9.8 mm
  test::SimulatorSolver solver("jolt", model, air);
  const double ratio = test::compliant_sag_ratio(solver, kCompliance, kDt);
  std::printf("[ grab     ] jolt static deflection / (weight x C): %+.2f %%\n", 100 * (ratio - 1));
  EXPECT_NEAR(ratio, 1.0, 0.01);
}

RunResult run(const SolverOptions& options, const Model& model, const std::string& scenario) {
  auto simulator = make_simulator("jolt", options);
  RunOptions run_options;
  run_options.dt = kDt;
  run_options.timing = false;
  return run_scenario(*simulator, model, make_scenario(scenario, model), run_options);
}

// Hanging from the head, Pinocchio's joints stay within a millimetre (ode: 0.5 mm, Bullet's
// ragdoll 0.6 mm), the gap stated
TEST(Jolt, HangJointGapBelowAMillimetre) {
  SKIP_WITHOUT_JOLT();
  const Model model = load_model(kPinocchio);
  const auto result = run({}, model, "hang");
  std::printf("[ gap      ] jolt hang: max joint gap %.2e m, pin gap %.2e m\n",
              result.value("joint_gap_m", "max"), result.value("pin_gap_m", "max"));
  ASSERT_FALSE(result.diverged);
  EXPECT_LT(result.value("joint_gap_m", "max"), 1e-3);
}

// every scenario on both models runs to its end with finite values, or is reported as diverged
// with its time
TEST(Jolt, EveryScenarioEndsOrIsReportedDiverged) {
  SKIP_WITHOUT_JOLT();
  for (const std::string& path :
       {kPinocchio, std::string(PUPPET_SOURCE_DIR) + "/models/humanoid.xml"}) {
    const Model model = load_model(path);
    for (const std::string& name : scenario_names()) {
      const auto result = run({}, model, name);
      SCOPED_TRACE(model.name + " " + name);
      if (result.diverged) {
        EXPECT_GT(result.diverged_at, 0.0);
        continue;
      }
      EXPECT_NEAR(result.trace.back().t, make_scenario(name, model).duration, 1e-9);
      for (const auto& m : result.trace) ASSERT_TRUE(m.finite);
    }
  }
}

// The driver computes the environment's and the user's forces itself, in JavaScript: on random
// states of Pinocchio, half in water, trembling, with a grab and a compliant pin, they are the
// testbed's (environment_wrench, user_wrenches, pin_spring_wrench) to 1e-12 of the largest force.
// The driver's 3×3 solve of the grab's effective mass is not Eigen's, hence not bit for bit.
TEST(Jolt, ForcesAgreeWithTheTestbeds) {
  SKIP_WITHOUT_JOLT();
  const Model model = load_model(kPinocchio);
  Environment environment;
  environment.water = true;
  environment.water_level = 0.6;
  environment.water_drag = 3.0;
  environment.air_drag = 0.5;
  environment.tremble = true;
  environment.tremble_seed = 0xfedcba9876543210ULL;  // past 2⁵³: read as 64 bits, not a double
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<BodyState> bodies = rest_pose(model);
    for (BodyState& b : bodies) {
      b.x += 0.3 * Vector3d(u(rng), u(rng), u(rng));
      b.q = Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
      b.v = 2.0 * Vector3d(u(rng), u(rng), u(rng));
      b.w = 5.0 * Vector3d(u(rng), u(rng), u(rng));
    }
    Pin grab{.segment = 3, .local_point = Vector3d(0, 0, -0.1), .target = Vector3d(0.2, 0.1, 1)};
    grab.grab = {.hz = 2.0, .damping_ratio = 1.0, .max_force = 150.0 + 500.0 * (trial % 2)};
    const Pin spring{.segment = 5,
                     .local_point = Vector3d(0.01, 0, 0),
                     .target = Vector3d(0, 0.3, 1.2),
                     .compliance = 1e-3};
    const Pin pins[] = {grab, spring};
    const double time = 0.37 * trial;
    const double h = trial % 3 == 0 ? 1.0 / 30.0 : kDt;
    std::vector<Wrench> applied, user, expected_user(model.segment_count());
    std::string error;
    ASSERT_TRUE(jolt_driver_forces(model, environment, pins, bodies, time, h, applied, user, error))
        << error;
    ASSERT_EQ(applied.size(), bodies.size());
    user_wrenches(model, environment, pins, bodies, time, expected_user);
    double largest = 0.0, worst = 0.0;
    for (int s = 0; s < model.segment_count(); ++s) {
      Wrench expected = environment_wrench(model.segments[s], environment, bodies[s], h);
      expected.force += expected_user[s].force;
      expected.torque += expected_user[s].torque;
      if (s == spring.segment) {
        const Wrench pull = pin_spring_wrench(spring, bodies[s]);
        expected.force += pull.force;
        expected.torque += pull.torque;
      }
      largest = std::max({largest, expected.force.norm(), expected.torque.norm()});
      worst = std::max({worst, (applied[s].force - expected.force).norm(),
                        (applied[s].torque - expected.torque).norm(),
                        (user[s].force - expected_user[s].force).norm(),
                        (user[s].torque - expected_user[s].torque).norm()});
    }
    EXPECT_LE(worst, 1e-12 * largest) << "trial " << trial;
  }
}

// The driver's joint springs and dampers (forces.mjs, addJointSpringWrenches and
// addRootSpringWrench) are the testbed's (add_joint_spring_wrenches) on random states near rest
// of a model with hinges, a ball and a box of three hinges with springs
// (tests/data/mjcf/springs.xml), of Pinocchio with a spring and a damper on every joint, and of
// two roots the world holds (planar; a hinge) with one on each coordinate, to 1e-12 of the
// largest torque or force; each body's quaternion is handed over with either sign; the damper's
// implicit factor is taken at h = 1/30 s, where it matters.
TEST(Jolt, JointSpringsAgreeWithTheTestbeds) {
  SKIP_WITHOUT_JOLT();
  Model sprung_pinocchio = load_model(kPinocchio);
  for (size_t j = 0; j < sprung_pinocchio.joints.size(); ++j) {
    for (JointPassive& spring : sprung_pinocchio.joints[j].passive) {
      spring = {.stiffness = 3.0 + j, .damping = 0.2 + 0.1 * j, .spring_ref = 0.0};
    }
    if (sprung_pinocchio.joints[j].type == JointType::kHinge) {
      sprung_pinocchio.joints[j].passive[0].spring_ref = 0.3;
    }
  }
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Environment environment;
  // roots the world holds, with a spring and a damper on each coordinate
  const auto held = [](const std::string& joints) {
    return parse_mjcf(R"(<mujoco><worldbody><body name="torso" pos="0 0 1">)" + joints + R"(
      <geom type="capsule" fromto="0 0 -0.2 0 0 0.2" size="0.06" mass="4"/>
      <body name="leg" pos="0 0 -0.25"><joint name="hip" axis="0 1 0" stiffness="5" damping="0.3"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04" mass="1"/></body>
      </body></worldbody></mujoco>)",
                      "held.xml");
  };
  const Model planar = held(R"(
      <joint name="x" type="slide" axis="1 0 0" stiffness="30" springref="0.1" damping="2"/>
      <joint name="z" type="slide" axis="0 0 1" stiffness="40" damping="3"/>
      <joint name="y" type="hinge" axis="0 1 0" pos="0.03 0 0.1" stiffness="7" springref="0.2"
             damping="0.5"/>)");
  const Model hinged = held(
      R"(<joint name="pivot" type="hinge" axis="1 1 0" pos="0 0 0.2" stiffness="40" damping="3"/>)");
  for (const Model& model :
       {load_model(std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/springs.xml"),
        load_model(std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/slides.xml"),
        sprung_pinocchio, planar, hinged}) {
    SCOPED_TRACE(model.name);
    ASSERT_TRUE(has_joint_springs(model));
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<BodyState> bodies = rest_pose(model);
      for (size_t k = 0; k < bodies.size(); ++k) {
        BodyState& b = bodies[k];
        // within ±0.6 rad of rest: a box's middle angle stays far from its lock
        b.q = (b.q * quat_exp(0.35 * Vector3d(u(rng), u(rng), u(rng)))).normalized();
        b.x += 0.1 * Vector3d(u(rng), u(rng), u(rng));
        b.v = Vector3d(u(rng), u(rng), u(rng));
        b.w = 5.0 * Vector3d(u(rng), u(rng), u(rng));
        // the same turn either sign, as an engine may hand it over
        if ((k + trial) % 2 == 1) b.q.coeffs() = -b.q.coeffs();
      }
      const double h = trial % 2 == 0 ? 1.0 / 30.0 : kDt;
      std::vector<Wrench> applied, user;
      std::string error;
      ASSERT_TRUE(jolt_driver_forces(model, environment, {}, bodies, 0.0, h, applied, user, error))
          << error;
      std::vector<Wrench> expected(model.segment_count());
      for (int s = 0; s < model.segment_count(); ++s) {
        expected[s] = environment_wrench(model.segments[s], environment, bodies[s], h);
      }
      std::vector<Wrench> springs(model.segment_count());
      add_joint_spring_wrenches(model, bodies, h, springs);
      double largest = 0.0, worst = 0.0;
      for (int s = 0; s < model.segment_count(); ++s) {
        largest = std::max({largest, springs[s].torque.norm(), springs[s].force.norm()});
        worst = std::max({worst, (applied[s].force - expected[s].force - springs[s].force).norm(),
                          (applied[s].torque - expected[s].torque - springs[s].torque).norm()});
      }
      EXPECT_GT(largest, 0.1);  // N m or N: the springs pull
      EXPECT_LE(worst, 1e-12 * largest) << "trial " << trial;
    }
  }
}

// The same inputs give the same bits, a restored snapshot repeats the steps that followed it
// (the driver builds the world again and replays the course to it), a run beside another on a
// second thread is the run alone, and targets the driver did not guess (it steps ahead on the
// scenario's) give what it gives when told each step
TEST(Jolt, RunsAgreeBitwiseAloneBesideAnotherAndFromASnapshot) {
  SKIP_WITHOUT_JOLT();
  const Model model = load_model(kPinocchio);
  for (const std::string name : {"drag", "drop"}) {
    SCOPED_TRACE(name);
    const Scenario scenario = make_scenario(name, model);
    const auto fresh = [&] {
      auto simulator = make_simulator("jolt", {});
      simulator->reset(model, scenario);
      return simulator;
    };
    const auto first = test::expect_runs_agree_bitwise(fresh, scenario, kDt);
    auto run_steps = [&](Simulator& simulator, int from, int to, Vector3d offset = {0, 0, 0}) {
      return test::run_steps(simulator, scenario, from, to, kDt, offset);
    };
    if (scenario.pins.empty()) continue;
    // off the scenario's targets by 1 mm from step 150: the guesses are dropped
    auto e = fresh();
    run_steps(*e, 0, 150);
    const auto moved = run_steps(*e, 150, 200, Vector3d(0.001, 0, 0));
    auto f = fresh();
    run_steps(*f, 0, 150);
    for (int k = 150; k < 200; ++k) {
      const auto s = f->snapshot();  // restoring every step: the driver replays each step alone
      f->restore(*s);
      run_steps(*f, k, k + 1, Vector3d(0.001, 0, 0));
    }
    std::vector<BodyState> told(model.segment_count());
    f->read_state(told);
    EXPECT_TRUE(test::bitwise_equal(moved, told)) << "targets it did not guess";
    EXPECT_FALSE(test::bitwise_equal(first, moved)) << "the targets moved the figure";
  }
}

// A non-finite state, a runaway one, a non-finite pin target: each is flagged as diverged before
// it reaches the driver (JSON has no NaN), and stepping on changes nothing and stops nothing
TEST(Jolt, NonFiniteOrRunawayInputIsDiverged) {
  SKIP_WITHOUT_JOLT();
  const Model model = load_model(kPinocchio);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int hostile = 0; hostile < 4; ++hostile) {
    SCOPED_TRACE("input " + std::to_string(hostile));
    test::SimulatorSolver solver("jolt", model, Environment{.ground = true});
    std::vector<BodyState> bodies = rest_pose(model);
    const Pin pin{3, Vector3d(0, 0, 0), bodies[3].x};
    solver.set_pins(std::span(&pin, 1));
    if (hostile == 0) bodies[3].w.x() = nan;
    if (hostile == 1) bodies[3].q.coeffs() << nan, 0, 0, 1;
    if (hostile == 2) bodies[3].v.z() = 1e9;
    solver.set_state(bodies);
    if (hostile == 3) {
      const Vector3d target(nan, 0, 1);
      solver.set_pin_targets(std::span(&target, 1));
    }
    solver.step(kDt);
    EXPECT_TRUE(solver.diverged());
    solver.step(kDt);
    EXPECT_TRUE(solver.diverged());
  }
}

// A limb on a box (orders yxz, Pinocchio's; xyz; zyx), spun at 2 rad/s without gravity about
// one of the box's axes from the rest pose, towards each face: the turn is about one axis, which
// either reading of the box as Jolt's pyramid holds exactly (jolt_box.h), so the limb reaches
// that face and goes no further than a step's travel (0.48°) past it, whichever reading the
// engine took. The base is a 5 kg box held by three pins, as in ode_test.cpp.
Model limb_on_a_box(const std::string& joint) {
  return parse_model(std::string(R"({"name":"box","segments":[
      {"name":"base","mass":5,"position":[0,0,1],"shape":{"type":"box","half_extents":[0.1,0.1,0.1]}},
      {"name":"rod","mass":1,"position":[0,0,0.75],"shape":{"type":"capsule","radius":0.03,"half_length":0.1}}],
     "joints":[{"name":"j","parent":"base","child":"rod","anchor":[0,0,0.9],)") +
                         joint + R"(}]})",
                     "box");
}

std::vector<BodyState> spun_limb(const Model& model, const Vector3d& axis_in_frame, double rate) {
  const Joint& joint = model.joints[0];
  std::vector<BodyState> bodies = rest_pose(model);
  const Vector3d w = rate * (bodies[0].q * joint.frame_in_parent * axis_in_frame);
  bodies[1].w = w;
  bodies[1].v = w.cross(bodies[1].x - joint.anchor_world);
  return bodies;
}

std::unique_ptr<test::SimulatorSolver> held_base(const Model& model) {
  auto solver = std::make_unique<test::SimulatorSolver>("jolt", model,
                                                        Environment{.gravity = Vector3d::Zero()});
  const Vector3d base = model.segments[0].rest_position;
  const Pin pins[] = {{0, Vector3d(0, 0, 0), base},
                      {0, Vector3d(0.1, 0, 0), base + Vector3d(0.1, 0, 0)},
                      {0, Vector3d(0, 0.1, 0), base + Vector3d(0, 0.1, 0)}};
  solver->set_pins(pins);
  return solver;
}

TEST(Jolt, ABoxStopsAtEachFace) {
  SKIP_WITHOUT_JOLT();
  for (const char* order : {"yxz", "xyz", "zyx"}) {
    const Model model = limb_on_a_box(std::string(R"("type":"ball","box_deg":{"order":")") + order +
                                      R"(","lower":[-20,-30,-10],"upper":[40,15,25]})");
    const Joint& joint = model.joints[0];
    const JoltPyramid reading = nearest_jolt_pyramid(joint);
    std::printf(
        "[ box      ] %s: twist %s, the pyramid %.1f° outside the box, the box %.1f° "
        "outside it\n",
        order, reading.twist_first ? "first" : "last", reading.beyond_deg, reading.cut_deg);
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {-1.0, 1.0}) {
        SCOPED_TRACE(std::string(order) + " axis " + std::to_string(axis) +
                     (sign > 0 ? " upper" : " lower"));
        auto solver = held_base(model);
        solver->set_state(spun_limb(model, Vector3d::Unit(joint.box_order.axes[axis]), 2.0 * sign));
        std::vector<BodyState> bodies(2);
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

// Neither reading of a box as Jolt's pyramid is the box: over Pinocchio's box joints the engine's
// reading reaches past the box and cuts into it by the computed gaps printed here (the worst of
// the two readings' is larger: the nearer one is taken). Swing–twist limits are Jolt's cone,
// within 0.16° of the model's ellipse (docs/references.md).
TEST(Jolt, BoxReadingsAreTheNearerOfTwo) {
  const Model model = load_model(kPinocchio);
  for (const Joint& joint : model.joints) {
    if (joint.type != JointType::kBall || joint.ball_limit != BallLimit::kEulerBox) continue;
    const JoltPyramid last = jolt_pyramid(joint, false), first = jolt_pyramid(joint, true);
    const JoltPyramid taken = nearest_jolt_pyramid(joint);
    std::printf("[ box      ] %-14s twist last %5.1f° / %5.1f°, first %5.1f° / %5.1f°: %s\n",
                joint.name.c_str(), last.beyond_deg, last.cut_deg, first.beyond_deg, first.cut_deg,
                taken.twist_first ? "first" : "last");
    EXPECT_LE(std::max(taken.beyond_deg, taken.cut_deg),
              std::min(std::max(last.beyond_deg, last.cut_deg),
                       std::max(first.beyond_deg, first.cut_deg)));
    // a box of one axis is read exactly
  }
  Joint hinge_like = model.joints[0];
  hinge_like.type = JointType::kBall;
  hinge_like.ball_limit = BallLimit::kEulerBox;
  hinge_like.box_lower = Vector3d(-0.5, 0.0, 0.0);
  hinge_like.box_upper = Vector3d(0.7, 0.0, 0.0);
  const JoltPyramid one = nearest_jolt_pyramid(hinge_like);
  EXPECT_LT(std::max(one.beyond_deg, one.cut_deg), 1e-9);
}

// A hinge driven at 3 rad/s into each of its stops from 2° inside stops there, and the speed it
// gives back is Jolt's: its limit's velocity row is inelastic, its position pass pushes the
// overshoot back (measured about 5% of the speed, as a velocity that stays)
TEST(Jolt, AHingeStopsAtEachEnd) {
  SKIP_WITHOUT_JOLT();
  const Model model = limb_on_a_box(R"("type":"hinge","axis":[0,1,0],"range_deg":[-30,45])");
  const Joint& joint = model.joints[0];
  for (const double sign : {-1.0, 1.0}) {
    SCOPED_TRACE(sign > 0 ? "upper" : "lower");
    auto solver = held_base(model);
    solver->set_state(spun_limb(model, joint.hinge_axis, 3.0 * sign));
    std::vector<BodyState> bodies(2);
    double furthest = 0.0;
    for (int k = 0; k < 240; ++k) {
      solver->step(kDt);
      solver->read_state(bodies);
      const double angle =
          decompose_swing_twist(joint_relative_rotation(joint, bodies[0].q, bodies[1].q),
                                joint.hinge_axis)
              .twist_angle;
      furthest = sign > 0 ? std::max(furthest, angle) : std::min(furthest, angle);
    }
    const double end = sign > 0 ? joint.upper : joint.lower;
    std::printf("[ hinge    ] jolt furthest %.2f° at the %s end %.0f°\n", furthest * 180 / M_PI,
                sign > 0 ? "upper" : "lower", end * 180 / M_PI);
    EXPECT_NEAR(furthest * 180 / M_PI, end * 180 / M_PI, 0.75);
  }
}

// A driver serves run after run: building Pinocchio 300 times in one driver leaves its heap where
// the tenth build left it (every object a build makes is destroyed with its world)
TEST(Jolt, ADriversHeapDoesNotGrowWithBuilds) {
  SKIP_WITHOUT_JOLT();
  std::vector<double> used;
  std::string error;
  ASSERT_TRUE(jolt_driver_heap_after_builds(load_model(kPinocchio), 300, used, error)) << error;
  std::printf("[ heap     ] jolt driver: %.0f bytes after 10 builds, %.0f after 300\n", used[9],
              used.back());
  EXPECT_LE(used.back(), used[9]);
}

// what Jolt cannot build is refused by its own check, in one line naming the part, before
// anything runs; settings out of range likewise
TEST(Jolt, ModelsItCannotBuildAreRefusedUpFront) {
  const Model ellipsoid = parse_model(R"({"name":"egg","segments":[
    {"name":"egg","mass":1,"position":[0,0,1],"shape":{"type":"ellipsoid","half_extents":[0.1,0.2,0.3]}}],
    "joints":[]})",
                                      "egg");
  Model bent = test::rods(2);
  Joint& knee = bent.joints[0];
  knee.type = JointType::kHinge;
  knee.hinge_axis = Vector3d::UnitX();
  knee.lower = 0.1;
  knee.upper = 2.0;
  derive_limit_terms(knee);
  const Engine* row = nullptr;
  for (const Engine& engine : engines()) {
    if (engine.name == "jolt") row = &engine;
  }
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->model_problem(ellipsoid),
            "segment \"egg\" has an ellipsoid, for which Jolt has no shape");
  EXPECT_NE(row->model_problem(bent).find("Jolt's hinge limits must hold the rest angle 0"),
            std::string::npos);
  // (a model it can build is refused only where the driver is missing)
  SKIP_WITHOUT_JOLT();
  for (const Model& model : {load_model(kPinocchio), make_chain(3),
                             load_model(std::string(PUPPET_SOURCE_DIR) + "/models/humanoid.xml")}) {
    EXPECT_TRUE(row->model_problem(model).empty()) << model.name;
  }
  EXPECT_EQ(engine_model_problem("jolt", ellipsoid),
            "segment \"egg\" has an ellipsoid, for which Jolt has no shape");
  SolverOptions options;
  options.jolt.velocity_steps = 0;
  EXPECT_THROW(make_simulator("jolt", options), ScenarioError);
}

}  // namespace
}  // namespace puppet::compare
