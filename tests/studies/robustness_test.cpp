// Random starts (start.cpp) and robustness sweeps (robustness.cpp): the generator is reproducible
// to the bit on any compiler (its first draws are pinned), draws inside its stated ranges and the
// joints' limits, and poses a figure whose joints are closed and whose velocities agree at every
// joint; the Wilson interval against its quadratic definition and its coverage over simulated
// trials; a sharded sweep gives the unsharded rows, and the rows survive their CSV.
#include "puppet/compare/robustness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "puppet/compare/metrics.h"
#include "puppet/compare/start.h"
#include "puppet/model/joint_springs.h"
#include "puppet/model/mjcf.h"
#include "puppet/model/rotation.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

Vector3d point_velocity(const BodyState& b, const Vector3d& world_point) {
  return b.v + b.w.cross(world_point - b.x);
}

TEST(Start, TheGeneratorIsReproducibleToTheBit) {
  const Model model = load_named_model("pinocchio");
  // pinned: SplitMix64 and the draw order of start.h; any change shows here first, and a
  // compiler or library that drew differently would too
  const StartInputs s = random_start(model, 1, 0);
  EXPECT_NEAR(s.tilt_deg, 22.4773417, 1e-7);
  EXPECT_NEAR(s.hz, 0.529295067, 1e-9);
  EXPECT_NEAR(s.phase * 180.0 / M_PI, 157.782206, 1e-6);
  const StartInputs again = random_start(model, 1, 0);
  for (int j = 0; j < model.joint_count(); ++j) {
    EXPECT_EQ(s.joint_rotation[j].coeffs(), again.joint_rotation[j].coeffs());
    EXPECT_EQ(s.joint_velocity[j], again.joint_velocity[j]);
  }
  EXPECT_NE(random_start(model, 1, 1).tilt_deg, s.tilt_deg);
  EXPECT_NE(random_start(model, 2, 0).tilt_deg, s.tilt_deg);
}

TEST(Start, DrawsInsideItsRangesAndTheLimits) {
  const Model model = load_named_model("pinocchio");
  double hz_low = 1e9, hz_high = 0, tilt_low = 1e9, tilt_high = -1e9;
  for (int k = 0; k < 2000; ++k) {
    const StartInputs s = random_start(model, 7, k);
    hz_low = std::min(hz_low, s.hz);
    hz_high = std::max(hz_high, s.hz);
    tilt_low = std::min(tilt_low, s.tilt_deg);
    tilt_high = std::max(tilt_high, s.tilt_deg);
    EXPECT_GE(s.phase, 0.0);
    EXPECT_LT(s.phase, 2 * M_PI);
    EXPECT_NEAR(s.grab_direction.norm(), 1.0, 1e-12);
    for (int j = 0; j < model.joint_count(); ++j) {
      const Joint& joint = model.joints[j];
      EXPECT_LT(limit_violation(joint, s.joint_rotation[j]), 1e-12) << joint.name;
      if (joint.type == JointType::kHinge) {
        EXPECT_LE(s.joint_velocity[j].norm(), kStartJointSpeed);
        EXPECT_LT(s.joint_velocity[j].cross(joint.hinge_axis).norm(), 1e-12);
      } else {
        EXPECT_LE(s.joint_velocity[j].norm(), kStartJointSpeed * (1 + 1e-12));
      }
    }
  }
  // the draws fill their ranges
  EXPECT_LT(hz_low, kStartHzLow + 0.01);
  EXPECT_GT(hz_high, kStartHzHigh - 0.01);
  EXPECT_LT(tilt_low, -kStartTiltDeg + 1);
  EXPECT_GT(tilt_high, kStartTiltDeg - 1);
}

TEST(Start, APoseHasClosedJointsAndConsistentVelocities) {
  const Model model = load_named_model("pinocchio");
  for (const int anchor : {0, model.find_segment("head"), model.find_segment("r_forearm")}) {
    for (int k = 0; k < 50; ++k) {
      const StartInputs s = random_start(model, 3, k);
      const std::vector<BodyState> bodies = posed_start(model, s, anchor);
      const std::vector<BodyState> rest = rest_pose(model);
      // the anchor keeps its rest pose, at rest
      EXPECT_EQ(bodies[anchor].x, rest[anchor].x);
      EXPECT_EQ(bodies[anchor].v, Vector3d::Zero());
      EXPECT_EQ(bodies[anchor].w, Vector3d::Zero());
      for (int j = 0; j < model.joint_count(); ++j) {
        const Joint& joint = model.joints[j];
        const BodyState& p = bodies[joint.parent];
        const BodyState& c = bodies[joint.child];
        const Vector3d cp = p.x + p.q * joint.anchor_in_parent;
        const Vector3d cc = c.x + c.q * joint.anchor_in_child;
        EXPECT_LT((cp - cc).norm(), 1e-14) << joint.name;
        // the drawn relative rotation and velocity, read back
        const Quaterniond q_rel = joint_relative_rotation(joint, p.q, c.q);
        EXPECT_LT(q_rel.angularDistance(s.joint_rotation[j]), 1e-12) << joint.name;
        const Vector3d w_rel = (p.q * joint.frame_in_parent).conjugate() * (c.w - p.w);
        EXPECT_LT((w_rel - s.joint_velocity[j]).norm(), 1e-12) << joint.name;
        EXPECT_LT((point_velocity(p, cp) - point_velocity(c, cp)).norm(), 1e-12) << joint.name;
      }
    }
  }
}

// A slide's start (tests/data/mjcf/slides.xml): a limited one somewhere in the middle 80 % of its
// range, an unlimited one at its rest, each moving along its direction at a drawn rate, neither
// turning against its parent; posed from either end of the tree, each slide's coordinate and rate
// read back are the drawn ones and the child's point stays on the slide's line
TEST(Start, ASlideStartsAlongItsRangeAndNeverTurns) {
  const Model model = load_model(std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/slides.xml");
  const int reach = 0, stroke = 2;
  ASSERT_EQ(model.joints[reach].type, JointType::kSlide);
  ASSERT_EQ(model.joints[stroke].type, JointType::kSlide);
  double lowest = INFINITY, highest = -INFINITY;
  for (int k = 0; k < 200; ++k) {
    const StartInputs s = random_start(model, 5, k);
    const Joint& limited = model.joints[reach];
    const double margin = (1.0 - kStartLimitFraction) / 2.0 * (limited.upper - limited.lower);
    EXPECT_GE(s.joint_offset[reach], limited.lower + margin - 1e-12);
    EXPECT_LE(s.joint_offset[reach], limited.upper - margin + 1e-12);
    lowest = std::min(lowest, s.joint_offset[reach]);
    highest = std::max(highest, s.joint_offset[reach]);
    EXPECT_EQ(s.joint_offset[stroke], 0.0);
    for (const int anchor : {0, model.find_segment("hand")}) {
      const std::vector<BodyState> bodies = posed_start(model, s, anchor);
      for (const int j : {reach, stroke}) {
        const Joint& joint = model.joints[j];
        const BodyState& p = bodies[joint.parent];
        const BodyState& c = bodies[joint.child];
        const JointCoordinates coordinates = joint_coordinates(joint, p, c);
        EXPECT_NEAR(coordinates.angle[0], s.joint_offset[j], 1e-12) << joint.name;
        EXPECT_NEAR(coordinates.rate[0], s.joint_velocity[j].dot(joint.hinge_axis), 1e-12)
            << joint.name;
        EXPECT_LE(std::abs(coordinates.rate[0]), kStartSlideSpeed);
        EXPECT_LT(
            p.q.angularDistance(c.q * joint.frame_in_child * joint.frame_in_parent.conjugate()),
            1e-12)
            << joint.name;
        EXPECT_LT((p.w - c.w).norm(), 1e-12) << joint.name;
        std::vector<double> gaps(model.joints.size());
        joint_gaps(model, bodies, gaps);
        EXPECT_LT(gaps[j], 1e-12) << joint.name;
      }
    }
  }
  // the draws fill that middle part
  const Joint& limited = model.joints[reach];
  const double span = limited.upper - limited.lower;
  EXPECT_LT(lowest, limited.lower + 0.15 * span);
  EXPECT_GT(highest, limited.upper - 0.15 * span);
}

TEST(Start, ScenariosStartStillWhereTheyAreHeld) {
  const Model model = load_named_model("pinocchio");
  for (const std::string name : {"hang", "drag", "shake", "yank", "spin", "drop"}) {
    ScenarioOptions options;
    options.start = random_start(model, 5, 3);
    const Scenario s = make_scenario(name, model, options);
    std::vector<Vector3d> targets;
    s.targets_at(0.0, targets);
    for (size_t i = 0; i < s.pins.size(); ++i) {
      const Pin& pin = s.pins[i].pin;
      const BodyState& b = s.initial[pin.segment];
      const Vector3d point = b.x + b.q * pin.local_point;
      EXPECT_LT((point - targets[i]).norm(), 1e-12) << name;
      // the first pin's segment is the pose's anchor: the held point does not move at t = 0
      if (i == 0) {
        EXPECT_LT(point_velocity(b, point).norm(), 1e-12) << name;
      }
    }
    if (name == "drag") {
      // after the ramp the target is on the default circle (lowest point: the initial point)
      const PinPath& grab = s.pins[1];
      s.targets_at(1.0, targets);
      const Vector3d centre = grab.pin.target + Vector3d(0, 0, grab.radius);
      EXPECT_NEAR((targets[1] - centre).norm(), grab.radius, 1e-12);
      EXPECT_EQ(grab.hz, options.start->hz);
    }
  }
}

TEST(Wilson, TheIntervalSolvesItsQuadratic) {
  // the Wilson interval is the p with (p̂ − p)² = z² p (1 − p) / n
  const double z = 1.959963984540054;
  for (const auto& [k, n] :
       std::vector<std::pair<int, int>>{{0, 20}, {13, 20}, {20, 20}, {1, 1000}, {500, 1000}}) {
    const Interval ci = wilson_interval(k, n);
    const double p = static_cast<double>(k) / n;
    const double a = 1 + z * z / n, b = -(2 * p + z * z / n), c = p * p;
    const double root = std::sqrt(b * b - 4 * a * c);
    EXPECT_NEAR(ci.low, (-b - root) / (2 * a), 1e-12) << k << "/" << n;
    EXPECT_NEAR(ci.high, (-b + root) / (2 * a), 1e-12) << k << "/" << n;
  }
  EXPECT_NEAR(wilson_interval(0, 20).high, z * z / (20 + z * z), 1e-12);
}

TEST(Wilson, CoversTheTrueRateNinetyFivePercentOfTheTime) {
  // 4000 simulated sweeps of n runs at a known rate: the 95 % interval holds it in about 95 % of
  // them (Wilson's coverage stays near nominal even at small rates, where the normal one fails)
  std::mt19937_64 rng(2024);
  for (const double rate : {0.02, 0.1, 0.5}) {
    for (const int n : {50, 500}) {
      std::bernoulli_distribution trial(rate);
      int covered = 0;
      const int sweeps = 4000;
      for (int s = 0; s < sweeps; ++s) {
        int k = 0;
        for (int i = 0; i < n; ++i) k += trial(rng) ? 1 : 0;
        const Interval ci = wilson_interval(k, n);
        covered += (ci.low <= rate && rate <= ci.high) ? 1 : 0;
      }
      const double coverage = static_cast<double>(covered) / sweeps;
      EXPECT_GT(coverage, 0.92) << rate << " " << n;
      EXPECT_LT(coverage, 0.985) << rate << " " << n;
    }
  }
}

TEST(Robustness, ShardsRunTheUnshardedRowsAndTheRowsSurviveTheirCsv) {
  const Model model = load_named_model("chain:4");
  RobustnessSpec spec;
  spec.model = &model;
  spec.model_name = "chain:4";
  spec.scenarios = {"hang", "yank"};
  spec.configs = {{"procedural", {}}, {"bullet-rigid", {}}};
  spec.dts = {1.0 / 120};
  spec.starts = 5;
  spec.duration = 0.5;
  spec.jobs = 2;
  const std::vector<RobustnessRow> all = run_robustness(spec);
  ASSERT_EQ(static_cast<int64_t>(all.size()), robustness_job_count(spec));
  std::vector<RobustnessRow> merged;
  for (int shard = 2; shard >= 0; --shard) {
    RobustnessSpec part = spec;
    part.shard = shard;
    part.shards = 3;
    for (const RobustnessRow& r : run_robustness(part)) {
      EXPECT_EQ(r.job % 3, shard);
      merged.push_back(r);
    }
  }
  std::sort(merged.begin(), merged.end(),
            [](const RobustnessRow& a, const RobustnessRow& b) { return a.job < b.job; });
  EXPECT_EQ(robustness_csv(merged), robustness_csv(all));
  const std::string csv = robustness_csv(all);
  EXPECT_EQ(robustness_csv(parse_robustness_csv(csv, "test")), csv);
  EXPECT_THROW(parse_robustness_csv("job,scenario\n", "bad"), std::runtime_error);
  EXPECT_THROW(parse_robustness_csv(csv + "1,2,3\n", "short"), std::runtime_error);
}

}  // namespace
}  // namespace puppet::compare
