// The viewer's session: steps, the user's grab and shake, reconfiguring without losing the
// state, and each solver's divergence reported on its own.
#include "puppet/viewer/session.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "puppet/compare/metrics.h"
#include "puppet/compare/run.h"
#include "support/source_dir.h"

namespace puppet::viewer {
namespace {

constexpr double kFrame = 1.0 / 60.0;

Vector3d world_point(const Session& session, int run, int segment, const Vector3d& local) {
  const BodyState& b = session.run(run).bodies[segment];
  return b.x + b.q * local;
}

void run_for(Session& session, double seconds) {
  for (int f = 0; f < std::lround(seconds / kFrame); ++f) session.advance(kFrame, 100);
}

// after half a second, the right hand's tip grabbed where it is
struct HandGrab {
  int forearm;
  Vector3d tip, held;
};
HandGrab grab_the_hand(Session& session) {
  run_for(session, 0.5);
  const int forearm = session.model().find_segment("r_forearm");
  const Vector3d tip{0, 0, -0.14};
  const Vector3d held = world_point(session, 0, forearm, tip);
  session.grab(forearm, tip, held);
  return {forearm, tip, held};
}

TEST(History, KeepsTheLastValuesInPlotOrder) {
  History h(3);
  h.push(1);
  h.push(5);
  h.push(2);
  h.push(4);  // overwrites 1
  EXPECT_EQ(h.latest(), 4.0f);
  EXPECT_EQ(h.max(), 5.0f);
  EXPECT_EQ(h.offset(), 1);
  EXPECT_EQ(h.values()[h.offset()], 5.0f);  // the oldest
}

TEST(Session, BadInputNamesTheProblem) {
  // the option and the message of the error a default config changed by `change` raises (the
  // option is the config's field: the viewer's command line adds its flag)
  auto message = [](const auto& change) {
    SessionConfig c;
    change(c);
    try {
      Session session(c);
    } catch (const compare::ScenarioError& e) {
      return e.option + ": " + e.what();
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto npos = std::string::npos;
  EXPECT_EQ(message([](SessionConfig& c) { c.dt = 0.0; }).find("dt: "), 0u);
  EXPECT_EQ(message([](SessionConfig& c) { c.dt = std::nan(""); }).find("dt: "), 0u);
  EXPECT_EQ(message([](SessionConfig& c) { c.scenario = "float"; }),
            "scenario: unknown scenario \"float\"");
  EXPECT_EQ(message([](SessionConfig& c) { c.ghost = "havok"; }),
            "ghost: unknown solver \"havok\"");
  EXPECT_EQ(message([](SessionConfig& c) { c.anchor = "head"; }).find("anchor: "), 0u);
  EXPECT_NE(message([](SessionConfig& c) {
              c.model = "/nonexistent/puppet.json";
            }).find("/nonexistent/puppet.json"),
            npos);
  EXPECT_EQ(message([](SessionConfig& c) { c.start = "7"; }).find("start: expected SEED:INDEX"),
            0u);
  EXPECT_EQ(message([](SessionConfig& c) { c.start = "7:-1"; }).find("start: "), 0u);
  EXPECT_EQ(message([](SessionConfig&) {}), "no error");
}

// what the viewer calls diverged is what the testbed does, at the same step: it judges after
// every step, not once a frame (a start of testbed robustness where relaxed diverges at 0.16 s
// by energy while the frame's last step looks calm)
TEST(Session, ARunDivergesAtTheTestbedsStep) {
  SessionConfig c;
  c.model = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio-swing-twist.json";  // its start
  c.scenario = "marionette";  // the hand on a hard pin, as drag's was when this start was found
  c.start = "1:36";
  c.options.procedural.rule = procedural::Rule::kRelaxed;  // the rule it diverges in
  Session session(c);
  run_for(session, 0.5);
  ASSERT_TRUE(session.run(0).diverged);

  compare::ScenarioOptions options;
  options.start = compare::random_start(session.model(), 1, 36);
  const compare::Scenario scenario = compare::make_scenario("marionette", session.model(), options);
  auto simulator = compare::make_simulator("procedural", c.options);
  compare::RunOptions run;
  run.duration = 0.5;
  run.timing = false;
  run.sample_hz = 1;
  const compare::RunResult result =
      compare::run_scenario(*simulator, session.model(), scenario, run);
  ASSERT_TRUE(result.diverged);
  EXPECT_NEAR(session.run(0).diverged_at, result.diverged_at, 1e-9);
  EXPECT_STREQ(session.run(0).diverged_reason, result.diverged_reason.c_str());
}

// --start replays testbed robustness's start: the same initial state, the same pins
TEST(Session, AStartIsTheTestbedsRandomStart) {
  SessionConfig c;
  c.scenario = "drag";
  c.start = "1:4";
  Session session(c);
  compare::ScenarioOptions options;
  options.start = compare::random_start(session.model(), 1, 4);
  const compare::Scenario expected = compare::make_scenario("drag", session.model(), options);
  for (int s = 0; s < session.model().segment_count(); ++s) {
    EXPECT_EQ(session.run(0).bodies[s].x, expected.initial[s].x);
    EXPECT_EQ(session.run(0).bodies[s].w, expected.initial[s].w);
  }
  ASSERT_EQ(session.pins().size(), expected.pins.size());
  EXPECT_EQ(session.pins()[1].local_point, expected.pins[1].pin.local_point);
  // another start is another state; no start, the scenario's own
  c.start = "1:5";
  session.configure(c);
  EXPECT_NE(session.run(0).bodies[3].x, expected.initial[3].x);
  c.start.clear();
  session.configure(c);
  EXPECT_EQ(session.run(0).bodies[3].x,
            compare::make_scenario("drag", session.model()).initial[3].x);
}

TEST(Session, AdvanceTakesWholeStepsAndCarriesTheRest) {
  SessionConfig c;
  c.dt = 1.0 / 100.0;
  Session session(c);
  EXPECT_EQ(session.advance(kFrame, 10), 1);  // 1.67 steps: 1, 0.67 carried
  EXPECT_EQ(session.advance(kFrame, 10), 2);  // 2.33
  EXPECT_EQ(session.advance(kFrame, 10), 2);  // 2.0 (up to rounding)
  EXPECT_NEAR(session.time(), 5 * c.dt, 1e-12);
  // too slow for real time: at most max_steps, and the backlog is dropped
  EXPECT_EQ(session.advance(1.0, 3), 3);
  EXPECT_EQ(session.advance(kFrame, 10), 1);
}

// By default the mouse grabs as the verdict's scenarios do: the same law (drag's GrabSpring), a
// force in every solver. Lifted 0.2 m and held, every solver's hand settles below the mouse by
// the arm's weight on the spring, and the solvers agree where (the same system, solved twice).
TEST(Session, TheMouseGrabsWithTheVerdictsGrab) {
  SessionConfig c;
  c.options.procedural.rule = procedural::Rule::kTree;
  c.ghost = "bullet-multibody";
  Session session(c);
  Environment air = session.scenario().environment;
  air.air_drag = 2.0;  // 1/s: settles the swing within seconds
  session.set_environment(air);
  const auto [forearm, tip, held] = grab_the_hand(session);
  const Pin& grab = session.pins()[session.grab_index()];
  ASSERT_TRUE(grab.is_grab());
  const compare::Scenario drag = compare::make_scenario("drag", session.model());
  EXPECT_EQ(grab.grab.hz, drag.pins.back().pin.grab.hz);
  EXPECT_EQ(grab.grab.damping_ratio, drag.pins.back().pin.grab.damping_ratio);
  EXPECT_EQ(grab.grab.max_force, drag.pins.back().pin.grab.max_force);
  const Vector3d lifted = held + Vector3d(0.0, 0.0, 0.2);
  session.move_grab(lifted);
  run_for(session, 6.0);
  Vector3d points[2];
  for (int r = 0; r < session.run_count(); ++r) {
    SCOPED_TRACE(session.run(r).label);
    EXPECT_FALSE(session.run(r).diverged);
    points[r] = world_point(session, r, forearm, tip);
    EXPECT_LT(points[r].z(), lifted.z() - 0.01);  // a spring holds the weight by stretching
    EXPECT_GT(points[r].z(), held.z());           // and still lifts the hand
  }
  EXPECT_LE((points[0] - points[1]).norm(), 0.005);
}

// with a pin (grab_pin), the grabbed point follows its target in every solver, the ghost with the
// solver
// (on the swing–twist Pinocchio: with the box limits relaxed holds this grab only within 0.18 m,
// its shoulder against two faces of its box; REPORT.md's findings)
TEST(Session, AGrabHoldsThePointAndTheGhostFollowsTheSameTarget) {
  SessionConfig c;
  c.grab_pin = true;
  c.model = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio-swing-twist.json";
  c.ghost = "bullet-multibody";
  Session session(c);
  const auto [forearm, tip, held] = grab_the_hand(session);
  ASSERT_EQ(session.pins().size(), 2u);
  EXPECT_EQ(session.pins()[session.grab_index()].segment, forearm);
  const Vector3d lifted = held + Vector3d(0.1, -0.1, 0.2);
  session.move_grab(lifted);
  run_for(session, 1.0);
  EXPECT_TRUE(session.targets()[session.grab_index()].isApprox(lifted));
  for (int r = 0; r < session.run_count(); ++r) {
    SCOPED_TRACE(session.run(r).label);
    EXPECT_FALSE(session.run(r).diverged);
    EXPECT_LE((world_point(session, r, forearm, tip) - lifted).norm(), 0.01);
  }
  session.release();
  EXPECT_EQ(session.pins().size(), 1u);
  run_for(session, 0.3);
  for (int r = 0; r < session.run_count(); ++r) {
    EXPECT_LT(world_point(session, r, forearm, tip).z(), lifted.z() - 0.05);
  }
}

// with a pin (grab_pin), the grabbed point is held on the mouse
// grabbing the hand that scenario marionette moves on its circle takes it from the circle: one pin
// on the forearm, not two fighting over it (which threw the exact tree projection out at once), and
// the circle's pin is back on release; tree, xpbd and Bullet hold the hand where the mouse is
TEST(Session, AGrabTakesOverTheScenarioPinOfItsSegment) {
  for (const char* rule : {"tree", "xpbd", "relaxed"}) {
    SCOPED_TRACE(rule);
    SessionConfig c;
    c.scenario = "marionette";
    c.grab_pin = true;
    c.options.procedural.rule = *procedural::parse_rule(rule);
    c.ghost = "bullet-multibody";
    Session session(c);
    ASSERT_EQ(session.pins().size(), 2u);  // head and hand
    const auto [forearm, tip, held] = grab_the_hand(session);
    EXPECT_EQ(session.released_pin(), 1);
    ASSERT_EQ(session.pins().size(), 2u);
    int on_forearm = 0;
    for (const Pin& pin : session.pins()) on_forearm += pin.segment == forearm ? 1 : 0;
    EXPECT_EQ(on_forearm, 1);
    EXPECT_EQ(session.pins()[session.grab_index()].local_point, tip);
    const Vector3d lifted = held + Vector3d(0.1, 0.0, 0.15);
    session.move_grab(lifted);
    run_for(session, 1.0);
    for (int r = 0; r < session.run_count(); ++r) {
      SCOPED_TRACE(session.run(r).label);
      const char* reason = session.run(r).diverged_reason;
      EXPECT_FALSE(session.run(r).diverged) << (reason != nullptr ? reason : "");
      const double gap = (world_point(session, r, forearm, tip) - lifted).norm();
      // relaxed's final one-sided pass lets the shoulder's limit win over the second pin (its
      // known weakness, docs/solver.md): reported, not required
      if (r == 0 && std::string(rule) == "relaxed") {
        std::printf("[ grab     ] relaxed holds the taken hand %.3f m from the mouse\n", gap);
      } else {
        EXPECT_LE(gap, 0.01);
      }
    }
    session.release();
    EXPECT_EQ(session.released_pin(), -1);
    ASSERT_EQ(session.pins().size(), 2u);
    EXPECT_EQ(session.pins()[1].segment, forearm);  // back on its circle
  }
}

// a compliant mouse: the grab is a spring of stiffness 1/C in every solver of the session (tree,
// whose exact system holds it, and the Bullet ghost, which applies it as a force); lifted 0.3 m
// and held still (air drag settles it), the hand hangs below the cursor, by less than its
// weight alone would stretch the spring (the string holds the rest), and both agree
TEST(Session, ACompliantGrabHangsTheHandBelowTheCursorInEverySolver) {
  SessionConfig c;
  c.options.procedural.rule = procedural::Rule::kTree;
  c.ghost = "bullet-multibody";
  c.grab_pin = true;
  c.grab_compliance = 1e-3;  // m/N
  Session session(c);
  Environment air = session.scenario().environment;
  air.air_drag = 2.0;  // 1/s: settles the swing and the spring within seconds
  session.set_environment(air);
  const auto [forearm, tip, held] = grab_the_hand(session);
  EXPECT_EQ(session.pins()[session.grab_index()].compliance, 1e-3);
  const Vector3d lifted = held + Vector3d(0.0, 0.0, 0.3);
  session.move_grab(lifted);
  run_for(session, 6.0);
  double sag[2];
  for (int r = 0; r < session.run_count(); ++r) {
    SCOPED_TRACE(session.run(r).label);
    EXPECT_FALSE(session.run(r).diverged);
    const Vector3d point = world_point(session, r, forearm, tip);
    sag[r] = lifted.z() - point.z();
    std::printf("[ grab     ] %s: the hand %.4f m below the cursor\n", session.run(r).label.c_str(),
                sag[r]);
    EXPECT_GT(sag[r], 0.002);  // the spring stretches
    EXPECT_LT(sag[r], session.model().total_mass * 9.81 * 1e-3);
  }
  EXPECT_NEAR(sag[0], sag[1], 0.2 * sag[1]);
}

// a grab with a pin comes first: the one-sided rules start their pass from it, as the seed anchors
// the adjust at the dragged segment, so the held point is exactly at the mouse and the scenario's
// string is what stays open
TEST(Session, TheGrabAnchorsTheProceduralPass) {
  SessionConfig c;
  c.grab_pin = true;
  c.options.procedural.rule = procedural::Rule::kLiteral;
  Session session(c);
  const auto [forearm, tip, held] = grab_the_hand(session);
  EXPECT_EQ(session.grab_index(), 0);
  const Vector3d lifted = held + Vector3d(0.1, -0.1, 0.2);
  session.move_grab(lifted);
  run_for(session, 1.0);
  EXPECT_LE((world_point(session, 0, forearm, tip) - lifted).norm(), 1e-9);
  EXPECT_LE(session.run(0).pin_gap_max, 0.5);
  EXPECT_GT(session.run(0).pin_gap_max, 1e-3);  // the head's string, left open

  // the rotating rules keep the scenario's anchor by default; either can be asked for
  c.options.procedural.rule = procedural::Rule::kRelaxed;
  session.configure(c);
  EXPECT_EQ(session.grab_index(), 1);
  EXPECT_EQ(session.pins()[1].segment, forearm);
  c.anchor = "grab";
  session.configure(c);
  EXPECT_EQ(session.grab_index(), 0);
  EXPECT_EQ(session.pins()[0].segment, forearm);
  EXPECT_TRUE(session.targets()[0].isApprox(lifted));
  c.anchor = "head";
  EXPECT_THROW(session.configure(c), compare::ScenarioError);
}

TEST(Session, ShakeMovesTheTargetSinusoidallyAboutTheHeldPoint) {
  SessionConfig c;
  Session session(c);
  const int forearm = session.model().find_segment("r_forearm");
  const Vector3d held = world_point(session, 0, forearm, Vector3d::Zero());
  session.grab(forearm, Vector3d::Zero(), held);
  const Vector3d axis{0, 1, 0};
  session.set_shake(true, axis);
  const double t0 = session.time();
  for (int k = 1; k <= 30; ++k) {
    session.step();
    const double expected =
        c.shake_amplitude * std::sin(2 * M_PI * c.shake_hz * (session.time() - t0));
    EXPECT_LE((session.targets()[session.grab_index()] - (held + expected * axis)).norm(), 1e-12)
        << k;
  }
  session.set_shake(false, axis);
  session.step();
  EXPECT_TRUE(session.targets()[session.grab_index()].isApprox(held));
}

TEST(Session, ReconfiguringKeepsTheStateAndANewScenarioStartsOver) {
  SessionConfig c;
  Session session(c);
  run_for(session, 0.5);
  const std::vector<BodyState> before = session.run(0).bodies;
  const double t = session.time();
  c.options.procedural.rule = procedural::Rule::kLiteral;
  c.ghost = "bullet-rigid";
  session.configure(c);
  EXPECT_EQ(session.run(0).label, "procedural (literal)");
  ASSERT_EQ(session.run_count(), 2);
  EXPECT_EQ(session.time(), t);
  for (int r = 0; r < 2; ++r) {
    for (size_t s = 0; s < before.size(); ++s) {
      EXPECT_LE((session.run(r).bodies[s].x - before[s].x).norm(), 1e-9) << r << " " << s;
    }
  }
  // bad input leaves everything as it was
  SessionConfig bad = c;
  bad.solver = "physx";
  EXPECT_THROW(session.configure(bad), compare::ScenarioError);
  EXPECT_EQ(session.config().solver, "procedural");
  EXPECT_EQ(session.run_count(), 2);
  c.scenario = "drop";
  session.configure(c);
  EXPECT_EQ(session.time(), 0.0);
  EXPECT_TRUE(session.scenario().environment.ground);

  // the panel's "load model": another model starts over; a bad file changes nothing
  c.model = "chain:8";
  session.configure(c);
  EXPECT_EQ(session.model().segment_count(), 8);
  EXPECT_EQ(session.run(0).bodies.size(), 8u);
  EXPECT_EQ(session.run(1).bodies.size(), 8u);
  bad = c;
  bad.model = "/nonexistent/puppet.json";
  EXPECT_THROW(session.configure(bad), ModelError);
  EXPECT_EQ(session.config().model, "chain:8");
  EXPECT_EQ(session.model().segment_count(), 8);
}

// switching gravity on mid-flight: a free body's centre of mass falls ½ g t² (up to the O(dt)
// error of Bullet's semi-implicit Euler, ½ g t dt)
TEST(Session, TheEnvironmentChangesMidRun) {
  SessionConfig c;
  c.scenario = "spin";  // free, no gravity
  c.solver = "bullet-multibody";
  Session session(c);
  run_for(session, 0.25);
  const Model& model = session.model();
  const Vector3d com0 = compare::centre_of_mass(model, session.run(0).bodies);
  const Vector3d p0 = compare::linear_momentum(model, session.run(0).bodies);
  Environment e = session.scenario().environment;
  e.gravity = {0, 0, -9.81};
  session.set_environment(e);
  const double t = 0.5;
  run_for(session, t);
  const Vector3d com = compare::centre_of_mass(model, session.run(0).bodies);
  const Vector3d drift = p0 / model.total_mass * t;
  EXPECT_NEAR(com.z() - com0.z() - drift.z(), -0.5 * 9.81 * t * t, 0.5 * 9.81 * t * c.dt + 1e-6);
}

// each run is judged on its own: at dt = 1/50 the hand-held puppet (yank) tears the ragdoll's
// joints open (results/frontier/frontier.csv: bullet-rigid fails from dt = 0.018 s by its joint
// gap) while the procedural solver, whose joints are closed by construction, goes on
TEST(Session, EachRunReportsItsOwnDivergence) {
  SessionConfig c;
  c.scenario = "yank";
  c.options.procedural.rule = procedural::Rule::kLiteral;
  c.ghost = "bullet-rigid";
  c.dt = 1.0 / 50.0;
  Session session(c);
  run_for(session, 5.0);
  EXPECT_FALSE(session.run(0).diverged);
  ASSERT_TRUE(session.run(1).diverged);
  EXPECT_GT(session.run(1).diverged_at, 0.0);
  const double t = session.time();
  run_for(session, 0.5);  // a diverged run stays where it stopped; the other goes on
  EXPECT_GT(session.time(), t);
  session.reset();
  EXPECT_FALSE(session.run(1).diverged);
  EXPECT_EQ(session.time(), 0.0);
}

}  // namespace
}  // namespace puppet::viewer
