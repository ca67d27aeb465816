#include "puppet/compare/metrics.h"

#include <gtest/gtest.h>

#include "puppet/model/rotation.h"

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

}  // namespace
}  // namespace puppet::compare
