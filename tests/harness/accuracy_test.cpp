#include "puppet/compare/accuracy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/source_dir.h"

namespace puppet::compare {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

// a run compared with itself, and the truth with itself, has no error at all
TEST(Accuracy, ATrajectoryAgainstItselfHasZeroError) {
  const Model model = load_model(kPinocchio);
  const Scenario hang = make_scenario("hang", model);
  for (const std::string solver : {"procedural", "bullet-multibody"}) {
    auto simulator = make_simulator(solver, {});
    const Trajectory run = record_trajectory(*simulator, model, hang, 1.0 / 240, 1.0);
    ASSERT_EQ(run.samples.size(), 31u) << solver;  // t = 0, 1/30, ..., 1 s
    const ErrorSeries errors = trajectory_errors(model, run, run);
    for (size_t k = 0; k < errors.pose_m.size(); ++k) {
      EXPECT_EQ(errors.pose_m[k], 0.0);
      EXPECT_EQ(errors.joint_angle_deg[k], 0.0);
    }
    // a second, independent run of the same solver is the same trajectory
    auto again = make_simulator(solver, {});
    const ErrorSeries repeat =
        trajectory_errors(model, record_trajectory(*again, model, hang, 1.0 / 240, 1.0), run);
    EXPECT_EQ(repeat.pose_m.back(), 0.0) << solver;
  }
}

// re-seeding a solver from its own trajectory at the same dt reproduces it up to the rounding
// of set_state (the multibody recomputes joint coordinates from poses); a coarser dt does not
TEST(Accuracy, ReseededFromItselfIsNearlyExactAndCoarserIsNot) {
  const Model model = load_model(kPinocchio);
  const Scenario drag = make_scenario("drag", model);
  auto simulator = make_simulator("bullet-multibody", {});
  const Trajectory truth = record_trajectory(*simulator, model, drag, 1.0 / 960, 2.0);
  const ReseededError self = reseeded_error(*simulator, model, drag, truth, 1.0 / 960);
  ASSERT_EQ(self.seed_times.size(), 8u);
  EXPECT_EQ(self.seed_times.front(), 0.0);
  EXPECT_NEAR(self.seed_times.back(), 1.5, 1e-12);  // 0.5 s before the end
  const ReseededError coarse = reseeded_error(*simulator, model, drag, truth, 1.0 / 60);
  std::printf("[ reseeded ] bullet-multibody drag vs itself at 1/960: %.1e m; at 1/60: %.1e m\n",
              self.mean_pose_m, coarse.mean_pose_m);
  EXPECT_LT(self.mean_pose_m, 1e-9);
  EXPECT_GT(coarse.mean_pose_m, 100 * self.mean_pose_m);
}

TEST(Accuracy, DtMustDivideTheSampleInterval) {
  const Model model = make_chain(2);
  const Scenario hang = make_scenario("hang", model);
  auto simulator = make_simulator("procedural", {});
  EXPECT_THROW(record_trajectory(*simulator, model, hang, 1.0 / 100, 1.0), ScenarioError);
  EXPECT_NO_THROW(record_trajectory(*simulator, model, hang, 1.0 / 3840, 0.1));
}

}  // namespace
}  // namespace puppet::compare
