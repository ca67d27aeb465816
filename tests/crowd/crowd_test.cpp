#include "puppet/procedural/crowd.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include <memory>
#include <utility>
#include <vector>

#include "model_tables.h"
#include "puppet/compare/scenario.h"
#include "puppet/procedural/solver.h"
#include "support/source_dir.h"

namespace puppet::procedural {
namespace {

// every puppet of a crowd, on 1 and on 3 threads, reaches bit for bit the state of a lone solver
// given the same start and targets; the puppets differ (tilt) so that a mix-up would show
TEST(Crowd, EveryPuppetMatchesALoneSolverBitForBit) {
  const Model model = compare::load_named_model("pinocchio");
  constexpr int kPuppets = 5;
  constexpr double kDt = 1.0 / 240.0;
  std::vector<compare::Scenario> scenarios;
  for (int k = 0; k < kPuppets; ++k) {
    compare::ScenarioOptions options;
    options.tilt_deg = 10.0 + 8.0 * k;
    scenarios.push_back(compare::make_scenario("marionette", model, options));
  }
  Settings settings;
  settings.rule = Rule::kWeighted;
  const Environment& environment = scenarios[0].environment;

  std::vector<std::vector<BodyState>> lone(kPuppets);
  for (int k = 0; k < kPuppets; ++k) {
    Solver solver(model, settings, environment);
    solver.reset(scenarios[k].initial);
    solver.set_pins(scenarios[k].initial_pins());
    std::vector<Vector3d> targets;
    for (int step = 0; step < 120; ++step) {
      scenarios[k].targets_at((step + 1) * kDt, targets);
      solver.set_pin_targets(targets);
      solver.step(kDt);
    }
    lone[k] = solver.state().bodies;
  }

  // targets set by the caller between steps, or by the crowd's control on the stepping threads
  for (auto [threads, with_control] : {std::pair{1, false}, {3, false}, {1, true}, {3, true}}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads, control " << with_control);
    Crowd crowd(model, settings, environment, kPuppets, threads);
    ASSERT_EQ(crowd.threads(), threads);
    for (int k = 0; k < kPuppets; ++k) {
      crowd.puppet(k).reset(scenarios[k].initial);
      crowd.puppet(k).set_pins(scenarios[k].initial_pins());
    }
    std::vector<std::vector<Vector3d>> targets(kPuppets);  // one buffer per puppet: no race
    double t = 0.0;
    const Crowd::Control control = [&](int k, Solver& puppet) {
      scenarios[k].targets_at(t, targets[k]);
      puppet.set_pin_targets(targets[k]);
    };
    for (int step = 0; step < 120; ++step) {
      t = (step + 1) * kDt;
      if (with_control) {
        crowd.step(kDt, control);
        continue;
      }
      for (int k = 0; k < kPuppets; ++k) control(k, crowd.puppet(k));
      crowd.step(kDt);
    }
    for (int k = 0; k < kPuppets; ++k) {
      const auto& bodies = crowd.puppet(k).state().bodies;
      for (size_t s = 0; s < bodies.size(); ++s) {
        EXPECT_EQ(bodies[s].x, lone[k][s].x) << "puppet " << k;
        EXPECT_EQ(bodies[s].q.coeffs(), lone[k][s].q.coeffs());
        EXPECT_EQ(bodies[s].v, lone[k][s].v);
        EXPECT_EQ(bodies[s].w, lone[k][s].w);
      }
    }
  }
  // and the puppets really differ
  EXPECT_NE(lone[0][5].x, lone[1][5].x);
}

// xpbd's puppets in lanes against lone solvers, in the scenarios a crowd meets (drag: two pins,
// one moving, air drag; shake: a pin shaken; a compliant grab; compliant joints and limits; a
// user's force and torque). Seven puppets of differing tilt: one batch of 4 and one of 3 on the
// AVX2 path (the last lane repeats the first), and one puppet with other pins (a single pin) that
// its batch steps alone.
struct LaneCase {
  const char* scenario;
  double pin_compliance, joint_compliance, limit_compliance;
  bool push;
  const char* model = "pinocchio";  // its balls are Euler boxes; -swing-twist's are cones
};

struct LaneRun {
  std::vector<std::vector<BodyState>> bodies;  // by puppet
  std::vector<double> time;
};

constexpr int kLanePuppets = 7, kLaneSteps = 120;
constexpr double kLaneDt = 1.0 / 240.0;

std::vector<compare::Scenario> lane_scenarios(const Model& model, const LaneCase& c) {
  std::vector<compare::Scenario> scenarios;
  for (int k = 0; k < kLanePuppets; ++k) {
    compare::ScenarioOptions options;
    options.tilt_deg = 4.0 + 6.0 * k;
    scenarios.push_back(compare::make_scenario(c.scenario, model, options));
    for (compare::PinPath& path : scenarios.back().pins) {
      path.pin.grab = {};  // the lanes hold pins (a grabbed puppet steps alone: crowd.h)
      path.pin.compliance = c.pin_compliance;
    }
  }
  // the fifth puppet keeps its first pin only
  scenarios[4].pins.resize(1);
  return scenarios;
}

Settings lane_settings(const LaneCase& c) {
  Settings settings;
  settings.rule = Rule::kXpbd;
  settings.joint_compliance = c.joint_compliance;
  settings.limit_compliance = c.limit_compliance;
  return settings;
}

// one step's control of puppet k at time t: its pins' targets, and a push on its chest
void lane_control(const LaneCase& c, const compare::Scenario& scenario, double t, int k,
                  std::vector<Vector3d>& targets, Solver& puppet) {
  scenario.targets_at(t, targets);
  puppet.set_pin_targets(targets);
  if (c.push) {  // the state's own fields: the solver has no setter for a user's force
    State state = puppet.state();
    state.user_force[2] = Vector3d(40.0 * std::sin(9.0 * t + k), 0.0, 15.0);
    state.user_torque[2] = Vector3d(0.0, 3.0, 6.0 * std::cos(7.0 * t));
    puppet.restore(state);
  }
}

LaneRun run_lone(const Model& model, const LaneCase& c) {
  const std::vector<compare::Scenario> scenarios = lane_scenarios(model, c);
  LaneRun run;
  for (int k = 0; k < kLanePuppets; ++k) {
    Solver solver(model, lane_settings(c), scenarios[k].environment);
    solver.reset(scenarios[k].initial);
    solver.set_pins(scenarios[k].initial_pins());
    std::vector<Vector3d> targets;
    for (int step = 0; step < kLaneSteps; ++step) {
      lane_control(c, scenarios[k], (step + 1) * kLaneDt, k, targets, solver);
      solver.step(kLaneDt);
    }
    run.bodies.push_back(solver.state().bodies);
    run.time.push_back(solver.state().time);
  }
  return run;
}

LaneRun run_crowd(const Model& model, const LaneCase& c, CrowdLanes lanes, int threads,
                  int* width) {
  const std::vector<compare::Scenario> scenarios = lane_scenarios(model, c);
  Crowd crowd(model, lane_settings(c), scenarios[0].environment, kLanePuppets, threads, lanes);
  *width = crowd.lanes();
  for (int k = 0; k < kLanePuppets; ++k) {
    crowd.puppet(k).reset(scenarios[k].initial);
    crowd.puppet(k).set_pins(scenarios[k].initial_pins());
  }
  std::vector<std::vector<Vector3d>> targets(kLanePuppets);
  double t = 0.0;
  const Crowd::Control control = [&](int k, Solver& puppet) {
    lane_control(c, scenarios[k], t, k, targets[k], puppet);
  };
  for (int step = 0; step < kLaneSteps; ++step) {
    t = (step + 1) * kLaneDt;
    crowd.step(kLaneDt, control);
  }
  LaneRun run;
  for (int k = 0; k < kLanePuppets; ++k) {
    run.bodies.push_back(crowd.puppet(k).state().bodies);
    run.time.push_back(crowd.puppet(k).state().time);
  }
  return run;
}

TEST(CrowdLanes, XpbdLanesMatchLoneSolversToRounding) {
  const std::string models = std::string(PUPPET_SOURCE_DIR) + "/models/";
  for (const LaneCase& c :
       {LaneCase{"marionette", 0.0, 0.0, 0.0, false}, LaneCase{"shake", 0.0, 0.0, 0.0, false},
        LaneCase{"marionette", 1e-3, 1e-7, 1e-5, false},
        LaneCase{"marionette", 0.0, 0.0, 0.0, true},
        LaneCase{"shake", 0.0, 0.0, 0.0, true, "pinocchio-swing-twist"}}) {
    SCOPED_TRACE(::testing::Message() << c.scenario << " " << c.model);
    const Model model = load_model(models + c.model + ".json");
    const LaneRun lone = run_lone(model, c);
    int width = 0;
    const LaneRun lanes = run_crowd(model, c, CrowdLanes::kWidest, 2, &width);
    EXPECT_GE(width, 2);
    double worst_x = 0.0, worst_q = 0.0, worst_v = 0.0;
    for (int k = 0; k < kLanePuppets; ++k) {
      for (size_t s = 0; s < lone.bodies[k].size(); ++s) {
        const BodyState& a = lone.bodies[k][s];
        const BodyState& b = lanes.bodies[k][s];
        worst_x = std::max(worst_x, (a.x - b.x).norm());
        worst_q = std::max(worst_q, std::min((a.q.coeffs() - b.q.coeffs()).norm(),
                                             (a.q.coeffs() + b.q.coeffs()).norm()));
        worst_v = std::max(worst_v, (a.v - b.v).norm());
      }
      EXPECT_EQ(lone.time[k], lanes.time[k]);
    }
    // measured: x 1.0–5.8e-12 m, q 4.2e-12–4.6e-10, v 8.8e-12–3.5e-10 m/s after 0.5 s. The bounds
    // are 20–300× that: rounding grows with the motion's chaos (most near a cone's limit), but a
    // wrong term moves a puppet by millimetres in 0.5 s (a limit test inverted: 23 mm, q 0.86)
    EXPECT_LT(worst_x, 1e-9);
    EXPECT_LT(worst_q, 1e-8);
    EXPECT_LT(worst_v, 1e-7);
  }
}

// AVX-512's and AVX2's lanes give the same bits as SSE2's two, on 1 thread and on 2: a puppet's
// result depends neither on the processor nor on its batch
TEST(CrowdLanes, EveryWidthGivesTheSameBits) {
  const Model model = compare::load_named_model("pinocchio");
  const LaneCase c{"marionette", 1e-3, 0.0, 0.0, true};
  int two = 0;
  const LaneRun reference = run_crowd(model, c, CrowdLanes::kTwo, 1, &two);
  ASSERT_EQ(two, 2);
  int compared = 0;
  for (CrowdLanes lanes : {CrowdLanes::kFour, CrowdLanes::kWidest}) {
    int width = 0;
    const LaneRun wide = run_crowd(model, c, lanes, 2, &width);
    if (width == 2) continue;  // this processor has no wider lanes
    ++compared;
    for (int k = 0; k < kLanePuppets; ++k) {
      for (size_t s = 0; s < reference.bodies[k].size(); ++s) {
        EXPECT_EQ(wide.bodies[k][s].x, reference.bodies[k][s].x) << width << " lanes, puppet " << k;
        EXPECT_EQ(wide.bodies[k][s].q.coeffs(), reference.bodies[k][s].q.coeffs());
        EXPECT_EQ(wide.bodies[k][s].w, reference.bodies[k][s].w);
      }
    }
  }
  if (compared == 0) GTEST_SKIP() << "this processor has no lanes wider than SSE2's";
}

// a puppet of a batch that meets a non-finite value is flagged at the substep a lone solver
// flags it (it is stepped again alone); its batch's other puppets go on untouched
TEST(CrowdLanes, ADivergingLaneIsFlaggedAsALoneSolverFlagsIt) {
  const Model model = compare::load_named_model("pinocchio");
  const compare::Scenario scenario = compare::make_scenario("marionette", model);
  Settings settings;
  settings.rule = Rule::kXpbd;
  const auto poison = [](Solver& puppet) {
    State state = puppet.state();
    state.user_force[3] = Vector3d(0.0, 0.0, std::numeric_limits<double>::infinity());
    puppet.restore(state);
  };
  Solver lone(model, settings, scenario.environment);
  lone.reset(scenario.initial);
  lone.set_pins(scenario.initial_pins());
  Solver healthy(model, settings, scenario.environment);
  healthy.reset(scenario.initial);
  healthy.set_pins(scenario.initial_pins());
  Crowd crowd(model, settings, scenario.environment, 4, 1, CrowdLanes::kTwo);
  ASSERT_EQ(crowd.lanes(), 2);
  for (int k = 0; k < 4; ++k) {
    crowd.puppet(k).reset(scenario.initial);
    crowd.puppet(k).set_pins(scenario.initial_pins());
  }
  for (int step = 0; step < 3; ++step) {
    if (step == 1) {
      poison(lone);
      poison(crowd.puppet(1));
    }
    lone.step(kLaneDt);
    healthy.step(kLaneDt);
    crowd.step(kLaneDt);
  }
  ASSERT_TRUE(lone.state().diverged);
  EXPECT_TRUE(crowd.puppet(1).state().diverged);
  EXPECT_EQ(crowd.puppet(1).state().diverged_time, lone.state().diverged_time);
  EXPECT_EQ(crowd.puppet(1).state().time, lone.state().time);
  for (int k : {0, 2, 3}) {
    EXPECT_FALSE(crowd.puppet(k).state().diverged) << "puppet " << k;
    EXPECT_LT((crowd.puppet(k).state().bodies[5].x - healthy.state().bodies[5].x).norm(), 1e-12);
  }
}

// the crowd uses lanes only where the kernel does what a lone solver does
TEST(CrowdLanes, OnlyXpbdInAirIsSteppedInLanes) {
  const Model model = compare::load_named_model("pinocchio");
  Settings xpbd;
  xpbd.rule = Rule::kXpbd;
  EXPECT_GE(Crowd(model, xpbd, Environment{}, 2, 1).lanes(), 2);
  EXPECT_EQ(Crowd(model, xpbd, Environment{}, 2, 1, CrowdLanes::kNone).lanes(), 1);
  Environment ground, water;
  ground.ground = true;
  water.water = true;
  EXPECT_EQ(Crowd(model, xpbd, ground, 2, 1).lanes(), 1);
  EXPECT_EQ(Crowd(model, xpbd, water, 2, 1).lanes(), 1);
  Settings trembling = xpbd;
  trembling.tremble = true;
  EXPECT_EQ(Crowd(model, trembling, Environment{}, 2, 1).lanes(), 1);
  for (Rule rule : kAllRules) {
    if (rule == Rule::kXpbd) continue;
    Settings other;
    other.rule = rule;
    EXPECT_EQ(Crowd(model, other, Environment{}, 2, 1).lanes(), 1) << rule_name(rule);
  }
}

// A thread done with its own range takes puppets from the back of another's: every puppet is
// still stepped exactly once per step, and the same as alone. The first thread's puppets are made
// slow (its control sleeps), so the other thread runs out of work and must take some of them.
TEST(Crowd, AThreadDoneEarlyTakesTheOthersPuppetsEachSteppedOnce) {
  const Model model = compare::load_named_model("pinocchio");
  constexpr int kPuppets = 96, kSteps = 5;  // 48 per thread: 3 of the chunks a thread takes
  constexpr double kDt = 1.0 / 240.0;
  Settings settings;
  settings.rule = Rule::kWeighted;
  const Environment environment;
  Crowd crowd(model, settings, environment, kPuppets, 2);
  std::array<std::atomic<int>, kPuppets> calls{};
  std::atomic<int> taken{0};  // slow puppets stepped by another thread than the caller's
  const std::thread::id caller = std::this_thread::get_id();
  const Crowd::Control control = [&](int k, Solver&) {
    calls[k].fetch_add(1);
    if (k < kPuppets / 2) {
      if (std::this_thread::get_id() != caller) taken.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
  for (int step = 0; step < kSteps; ++step) crowd.step(kDt, control);

  Solver lone(model, settings, environment);
  for (int step = 0; step < kSteps; ++step) lone.step(kDt);
  for (int k = 0; k < kPuppets; ++k) {
    EXPECT_EQ(calls[k].load(), kSteps) << "puppet " << k;
    const auto& bodies = crowd.puppet(k).state().bodies;
    for (size_t s = 0; s < bodies.size(); ++s) {
      EXPECT_EQ(bodies[s].x, lone.state().bodies[s].x) << "puppet " << k;
      EXPECT_EQ(bodies[s].q.coeffs(), lone.state().bodies[s].q.coeffs()) << "puppet " << k;
    }
  }
  EXPECT_GT(taken.load(), 0);
}

// a crowd's puppets share one set of model tables; tables built for another model are refused
TEST(Crowd, ModelTablesAreSharedOnlyWithinAModel) {
  const Model model = compare::load_named_model("pinocchio");
  const std::shared_ptr<const ModelTables> tables = make_model_tables(model);
  ASSERT_EQ(static_cast<int>(tables->orders.size()), model.segment_count());
  ASSERT_EQ(static_cast<int>(tables->joints.size()), model.joint_count());
  for (int anchor = 0; anchor < model.segment_count(); ++anchor) {
    EXPECT_EQ(tables->orders[anchor].anchor, anchor);
    EXPECT_EQ(static_cast<int>(tables->orders[anchor].links.size()), model.joint_count());
  }
  EXPECT_NO_THROW(Solver(model, Settings{}, Environment{}, tables));
  const Model chain = make_chain(3);
  EXPECT_THROW(Solver(chain, Settings{}, Environment{}, tables), std::invalid_argument);
}

TEST(Crowd, RejectsEmptyCounts) {
  const Model model = compare::load_named_model("pinocchio");
  EXPECT_THROW(Crowd(model, Settings{}, Environment{}, 0, 1), std::invalid_argument);
  EXPECT_THROW(Crowd(model, Settings{}, Environment{}, 1, 0), std::invalid_argument);
}

}  // namespace
}  // namespace puppet::procedural
