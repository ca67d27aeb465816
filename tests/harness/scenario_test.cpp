#include "puppet/compare/scenario.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "puppet/compare/metrics.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

TEST(Scenario, EveryScenarioBuildsOnEveryKindOfModel) {
  for (const std::string& model_name : {kPinocchio, std::string("chain:5")}) {
    const Model model = load_model(model_name);
    for (const std::string& name : scenario_names()) {
      const Scenario s = make_scenario(name, model);
      EXPECT_EQ(static_cast<int>(s.initial.size()), model.segment_count());
      // initial poses keep every joint closed, pins start on their points
      std::vector<double> gaps(model.joint_count());
      joint_gaps(model, s.initial, gaps);
      for (double g : gaps) EXPECT_LT(g, 1e-12) << name;
      std::vector<Vector3d> targets;
      s.targets_at(0.0, targets);
      const auto pins = s.initial_pins();
      std::vector<double> pin_gap(pins.size());
      pin_gaps(pins, targets, s.initial, pin_gap);
      for (double g : pin_gap) EXPECT_LT(g, 1e-12) << name;
    }
  }
}

// the catalogue names a headline, and it is one of its scenarios
TEST(Scenario, TheHeadlineIsAScenarioOfTheCatalogue) {
  const auto& names = scenario_names();
  EXPECT_NE(std::find(names.begin(), names.end(), headline_scenario()), names.end())
      << "headline: \"" << headline_scenario() << "\"";
}

TEST(Scenario, PinocchioChoices) {
  const Model model = load_model(kPinocchio);
  const Scenario drag = make_scenario("drag", model);
  ASSERT_EQ(drag.pins.size(), 2u);
  EXPECT_EQ(model.segments[drag.pins[0].pin.segment].name, "head");
  EXPECT_EQ(model.segments[drag.pins[1].pin.segment].name, "r_forearm");
  // the head's pin is the top of its cap, the hand the tip of the forearm's far cap
  EXPECT_TRUE(drag.pins[0].pin.local_point.isApprox(Vector3d(0, 0, 0.11)));
  EXPECT_TRUE(drag.pins[1].pin.local_point.isApprox(Vector3d(0, 0, -0.14)));
  EXPECT_EQ(model.segments[make_scenario("shake", model).pins[1].pin.segment].name, "l_forearm");
  EXPECT_EQ(make_scenario("yank", model).pins.size(), 1u);
  EXPECT_TRUE(make_scenario("spin", model).pins.empty());
}

// a character's hands by the names published ones give them (MuJoCo's humanoid: right_hand;
// models/humanoid.xml: hand_right), a figure without them by its lowest segment
TEST(Scenario, APublishedCharacterIsGrabbedByItsHands) {
  const Model model = load_model(std::string(PUPPET_SOURCE_DIR) + "/models/humanoid.xml");
  const auto grabbed = [&](const char* scenario) {
    return model.segments[make_scenario(scenario, model).pins[1].pin.segment].name;
  };
  EXPECT_EQ(grabbed("drag"), "hand_right");
  EXPECT_EQ(grabbed("shake"), "hand_left");
  const Model chain = load_model("chain:5");
  EXPECT_EQ(make_scenario("drag", chain).pins[1].pin.segment, 4);  // the lowest link
}

// the user's scenarios hold the hand with the grab, the paper's with a hard pin; the head is a
// hard pin in both
TEST(Scenario, TheUsersScenariosGrabAndTheMarionetteIsPinned) {
  const Model model = load_model(kPinocchio);
  for (const char* name : {"drag", "shake", "water", "tremble"}) {
    const Scenario s = make_scenario(name, model);
    SCOPED_TRACE(name);
    ASSERT_EQ(s.pins.size(), 2u);
    EXPECT_TRUE(s.pins[0].pin.is_hard());
    EXPECT_TRUE(s.pins[1].pin.is_grab());
    EXPECT_EQ(s.pins[1].pin.grab.hz, 2.0);
    EXPECT_EQ(s.pins[1].pin.grab.damping_ratio, 1.0);
    EXPECT_DOUBLE_EQ(s.pins[1].pin.grab.max_force, model.total_mass * 9.81);
    EXPECT_EQ(s.environment.tremble, std::string(name) == "tremble");
  }
  const Scenario marionette = make_scenario("marionette", model);
  EXPECT_TRUE(marionette.pins[1].pin.is_hard());
  EXPECT_EQ(marionette.pins[1].path, make_scenario("drag", model).pins[1].path);
  EXPECT_TRUE(make_scenario("yank", model).pins[0].pin.is_hard());
}

// the reach between two hard pins: the figure's chain from the head's top to the hand's tip is
// what it can span. The marionette's own circle is within it; led round a circle 3 m wide it is
// not; a grab is no pin, so drag has nothing to reach.
TEST(Scenario, TheReachBetweenTwoHardPins) {
  const Model model = load_model(kPinocchio);
  Scenario marionette = make_scenario("marionette", model);
  EXPECT_LT(reach_shortfall(model, marionette), 0.0);
  marionette.pins[1].radius = 3.0;
  EXPECT_GT(reach_shortfall(model, marionette), 1.0);
  EXPECT_EQ(reach_shortfall(model, make_scenario("drag", model)), -INFINITY);
  // at rest the two points are no further apart than the span (the chain is its longest
  // straight): the shortfall of a fixed pair of pins at their rest points is at most 0
  Scenario still = make_scenario("marionette", model);
  still.pins[1].path = TargetPath::kFixed;
  EXPECT_LE(reach_shortfall(model, still), 1e-12);
}

TEST(Scenario, CircleTargetAfterTheRamp) {
  const Model model = load_model(kPinocchio);
  const Scenario drag = make_scenario("drag", model);
  std::vector<Vector3d> targets;
  const Vector3d start = drag.pins[1].pin.target;
  drag.targets_at(1.0, targets);  // half a turn at 0.5 Hz: the top of the circle
  EXPECT_LT((targets[1] - (start + Vector3d(0, 0, 0.6))).norm(), 1e-12);
  drag.targets_at(0.5, targets);  // a quarter turn, ramp complete
  EXPECT_LT((targets[1] - (start + Vector3d(0.3, 0, 0.3))).norm(), 1e-12);
  EXPECT_LT((targets[0] - drag.pins[0].pin.target).norm(), 1e-15);
}

TEST(Scenario, TiltAndOverrides) {
  const Model model = load_model(kPinocchio);
  ScenarioOptions options;
  options.tilt_deg = 0.0;
  options.pin = PointChoice{"chest", Vector3d(0, 0.1, 0)};
  options.gravity = Vector3d(0, 0, -1.62);
  const Scenario hang = make_scenario("hang", model, options);
  EXPECT_EQ(hang.pins[0].pin.segment, model.find_segment("chest"));
  EXPECT_EQ(hang.environment.gravity, Vector3d(0, 0, -1.62));
  EXPECT_TRUE(hang.initial[0].x.isApprox(model.segments[0].rest_position));
  options.pin = PointChoice{"tail", std::nullopt};
  EXPECT_THROW(make_scenario("hang", model, options), ScenarioError);
  EXPECT_THROW(make_scenario("swim", model), ScenarioError);
}

TEST(Scenario, DropStartsOneMetreUp) {
  const Model model = load_model(kPinocchio);
  const Scenario drop = make_scenario("drop", model);
  double lowest = 1e9;
  for (int i = 0; i < model.segment_count(); ++i) {
    double low = 0, high = 0;
    vertical_extent(model.segments[i], drop.initial[i].q, drop.initial[i].x, &low, &high);
    lowest = std::min(lowest, low);
  }
  EXPECT_NEAR(lowest, 1.0, 1e-12);
  EXPECT_TRUE(drop.environment.ground);
}

}  // namespace
}  // namespace puppet::compare
