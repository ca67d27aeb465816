#include "puppet/compare/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "puppet/model/rotation.h"
#include "support/source_dir.h"

namespace puppet::compare {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

TEST(Metrics, JointGapOfAKnownOffset) {
  const Model model = load_model(kPinocchio);
  auto bodies = rest_pose(model);
  std::vector<double> gaps(model.joint_count());
  joint_gaps(model, bodies, gaps);
  for (double g : gaps) EXPECT_NEAR(g, 0.0, 1e-15);
  const int head = model.find_segment("head");
  bodies[head].x += Vector3d(0.003, 0.004, 0);  // 5 mm
  joint_gaps(model, bodies, gaps);
  EXPECT_NEAR(gaps[model.segments[head].parent_joint], 0.005, 1e-15);
}

TEST(Metrics, LimitViolationOfAKnownRotation) {
  const Model model = load_model(kPinocchio);
  auto bodies = rest_pose(model);
  const int forearm = model.find_segment("l_forearm");
  const Joint& elbow = model.joints[model.segments[forearm].parent_joint];
  // bend the elbow 10° the wrong way (its range starts at −5°), about its own axis, in world
  const Vector3d axis_world = elbow.frame_world * elbow.hinge_axis;
  bodies[forearm].q =
      Quaterniond(Eigen::AngleAxisd(-15.0 * M_PI / 180, axis_world)) * bodies[forearm].q;
  std::vector<double> violations(model.joint_count());
  limit_violations_deg(model, bodies, violations);
  EXPECT_NEAR(violations[model.segments[forearm].parent_joint], 10.0, 1e-9);
}

// accuracy against hand-computed cases: a known offset, a known bend, a rigid motion
TEST(Metrics, PoseAndJointAngleErrorsOfKnownChanges) {
  const Model model = make_chain(3);
  const auto truth = rest_pose(model);
  EXPECT_EQ(pose_error(truth, truth), 0.0);
  EXPECT_EQ(joint_angle_error_deg(model, truth, truth), 0.0);

  // one segment 5 cm away: RMS over three segments
  auto moved = truth;
  moved[1].x += Vector3d(0.03, 0.04, 0.0);
  EXPECT_NEAR(pose_error(moved, truth), 0.05 / std::sqrt(3.0), 1e-15);

  // the last segment bent 12° about its joint: one of two joints off by 12°
  auto bent = truth;
  const Joint& last = model.joints[1];
  const Quaterniond r(Eigen::AngleAxisd(12.0 * M_PI / 180, Vector3d(0, 0.6, 0.8)));
  bent[2].q = r * bent[2].q;
  bent[2].x = last.anchor_world + r * (bent[2].x - last.anchor_world);
  EXPECT_NEAR(joint_angle_error_deg(model, bent, truth), 12.0 / std::sqrt(2.0), 1e-9);

  // the whole body turned 30° and carried 1 m: not bent at all, every COM moved
  auto carried = truth;
  const Quaterniond turn(Eigen::AngleAxisd(M_PI / 6, Vector3d::UnitX()));
  for (BodyState& b : carried) {
    b.q = turn * b.q;
    b.x = turn * b.x + Vector3d(1.0, 0.0, 0.0);
  }
  EXPECT_NEAR(joint_angle_error_deg(model, carried, truth), 0.0, 1e-6);
  double sum = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) sum += (carried[i].x - truth[i].x).squaredNorm();
  EXPECT_NEAR(pose_error(carried, truth), std::sqrt(sum / 3.0), 1e-15);
  EXPECT_GT(pose_error(carried, truth), 1.0);
}

TEST(Metrics, EnergyMomentumOfARigidSpin) {
  const Model model = load_model(kPinocchio);
  auto bodies = rest_pose(model);
  const Vector3d omega(0, 0, 2), com = centre_of_mass(model, bodies);
  double expected_ke = 0;
  Matrix3d inertia_about_com = Matrix3d::Zero();
  for (int i = 0; i < model.segment_count(); ++i) {
    bodies[i].w = omega;
    bodies[i].v = omega.cross(bodies[i].x - com);
    const Vector3d r = bodies[i].x - com;
    inertia_about_com +=
        world_inertia(model.segments[i], bodies[i].q) +
        model.segments[i].mass * (r.squaredNorm() * Matrix3d::Identity() - r * r.transpose());
  }
  expected_ke = 0.5 * omega.dot(inertia_about_com * omega);
  EXPECT_NEAR(kinetic_energy(model, bodies), expected_ke, 1e-12);
  EXPECT_NEAR(linear_momentum(model, bodies).norm(), 0.0, 1e-12);
  EXPECT_LT((angular_momentum(model, bodies) - inertia_about_com * omega).norm(), 1e-12);
}

TEST(Metrics, ProbeDriftsAreZeroAtTheStart) {
  const Model model = load_model(kPinocchio);
  const auto bodies = rest_pose(model);
  MetricsProbe probe(model, Environment{}, {}, bodies);
  const StepMetrics m = probe.measure(0.0, bodies, {});
  EXPECT_EQ(m.energy_drift, 0.0);
  EXPECT_LT(m.joint_gap_max, 1e-15);
  // lift everything 1 m: drift = M g / E_ref
  auto lifted = bodies;
  for (auto& b : lifted) b.x.z() += 1.0;
  const StepMetrics up = probe.measure(1.0, lifted, {});
  EXPECT_NEAR(up.energy_drift, 1.0 / model.rest_height, 1e-12);
}

TEST(Metrics, PenetrationOfASunkBody) {
  const Model model = load_model(kPinocchio);
  auto bodies = rest_pose(model);
  for (auto& b : bodies) b.x.z() -= 0.02;  // the feet's lowest point was 1 cm up
  EXPECT_NEAR(ground_penetration(model, bodies), 0.01, 1e-12);
}

// the energy scale comes from the model's mass and height, never zero: weightless and at rest,
// a small motion is a small drift (it was 0/0 or x/0, and every pinned run diverged at once)
TEST(Metrics, EnergyDriftIsFiniteWithoutGravity) {
  const Model model = load_model(kPinocchio);
  Environment weightless;
  weightless.gravity = Vector3d::Zero();
  const auto bodies = rest_pose(model);
  EXPECT_NEAR(energy_reference(model, weightless, bodies),
              model.total_mass * kStandardGravity * model.rest_height, 1e-9);
  MetricsProbe probe(model, weightless, {}, bodies);
  auto moved = bodies;
  moved[0].v = {0.1, 0, 0};
  const StepMetrics m = probe.measure(0.1, moved, {});
  const double expected = 0.5 * model.segments[0].mass * 0.01 /
                          (model.total_mass * kStandardGravity * model.rest_height);
  EXPECT_NEAR(m.energy_drift, expected, 1e-12);
  EXPECT_EQ(divergence_reason(m), nullptr);
}

// the drift does not depend on where the model is: 10 km up, the same fall gives the same drift
TEST(Metrics, EnergyDriftIgnoresAnOffset) {
  const Model model = load_model(kPinocchio);
  const Environment environment;
  auto drift_of = [&](double offset) {
    auto bodies = rest_pose(model);
    for (BodyState& b : bodies) b.x.z() += offset;
    MetricsProbe probe(model, environment, {}, bodies);
    for (BodyState& b : bodies) {
      b.x.z() -= 0.01;
      b.v.z() = -0.3;
    }
    return probe.measure(0.1, bodies, {}).energy_drift;
  };
  EXPECT_NEAR(drift_of(1e4), drift_of(0.0), 1e-12);
}

// a metric that is not a number is never ok, whatever the state looks like
TEST(Metrics, ANonFiniteMetricIsDiverged) {
  for (double StepMetrics::*field :
       {&StepMetrics::joint_gap_max, &StepMetrics::pin_gap_max, &StepMetrics::energy_drift,
        &StepMetrics::angular_momentum_drift, &StepMetrics::peak_speed}) {
    StepMetrics m;
    EXPECT_EQ(divergence_reason(m), nullptr);
    m.*field = std::numeric_limits<double>::quiet_NaN();
    ASSERT_NE(divergence_reason(m), nullptr);
    EXPECT_STREQ(divergence_reason(m), "non-finite metric");
    m.*field = -INFINITY;
    EXPECT_STREQ(divergence_reason(m), "non-finite metric");
  }
}

}  // namespace
}  // namespace puppet::compare
