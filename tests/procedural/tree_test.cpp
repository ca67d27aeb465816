// Rule tree against independent answers: one Newton iteration against the dense KKT solve of
// the same linearisation (Jacobians by finite differences, Eigen's LDLT), Newton's convergence,
// the analytic physical pendulum, the Lagrangian double pendulum and its convergence with dt,
// conservation of angular momentum, and every Pinocchio scenario's joints and limits.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "puppet/compare/scenario.h"
#include "puppet/model/rotation.h"
#include "puppet/procedural/solver.h"
#include "support/rule_runs.h"
#include "support/spinning_box.h"

namespace puppet::procedural {
namespace {

constexpr double kDt = 1.0 / 240.0;
// pinned: any change to tree's arithmetic shows here first (update it deliberately)
constexpr uint64_t kExpectedTreeDragHash = 0x0d22ae2172639ddcULL;

Settings tree() {
  Settings settings;
  settings.rule = Rule::kTree;
  return settings;
}

TEST(Tree, RuleDefaults) {
  const Settings settings = rule_defaults(tree());
  EXPECT_EQ(settings.iterations, kTreeIterations);
  EXPECT_EQ(settings.substeps, kTreeSubsteps);
}

// Pinocchio with every joint a ball that no pose reaches the limit of: the system is then the
// joints' points and the pins alone, which a dense solve can build independently
Model unlimited_pinocchio() {
  Model model = load_model(test::kPinocchioPath);
  for (Joint& joint : model.joints) {
    joint.type = JointType::kBall;
    joint.swing_x = joint.swing_y = 3.0;
    joint.twist = 3.1;
    derive_limit_terms(joint);
  }
  return model;
}

Vector3d world_point(const BodyState& body, const Vector3d& local) {
  return body.x + body.q * local;
}

// every joint's point gap (world), then every pin's
Eigen::VectorXd constraint_values(const Model& model, std::span<const BodyState> bodies,
                                  std::span<const Pin> pins) {
  Eigen::VectorXd c(3 * (model.joint_count() + static_cast<int>(pins.size())));
  for (int j = 0; j < model.joint_count(); ++j) {
    const Joint& joint = model.joints[j];
    c.segment<3>(3 * j) = world_point(bodies[joint.parent], joint.anchor_in_parent) -
                          world_point(bodies[joint.child], joint.anchor_in_child);
  }
  for (size_t i = 0; i < pins.size(); ++i) {
    c.segment<3>(3 * (model.joint_count() + i)) =
        world_point(bodies[pins[i].segment], pins[i].local_point) - pins[i].target;
  }
  return c;
}

// each segment moved by (Δx world, Δθ in its frame)
std::vector<BodyState> moved(std::vector<BodyState> bodies, const Eigen::VectorXd& delta) {
  for (size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].x += delta.segment<3>(6 * i);
    bodies[i].q = times_exp(bodies[i].q, delta.segment<3>(6 * i + 3)).normalized();
  }
  return bodies;
}

// Pinocchio's rest pose with every segment displaced by ~5 cm and turned by ~3°, still, without
// gravity, held by the head and one hand (a loop through the world) whose targets are 3 cm off:
// one step of one substep and one Newton iteration is then exactly one projection
struct Perturbed {
  Model model = unlimited_pinocchio();
  std::vector<BodyState> bodies;
  std::vector<Pin> pins;
  // with `more_loops`, both shins held as well: four pins, three loops, the most a solver takes
  explicit Perturbed(bool more_loops = false) {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.05);
    const auto rest = rest_pose(model);
    bodies.assign(rest.begin(), rest.end());
    // drawn in a stated order: the order of a call's arguments is the compiler's (GCC's is
    // right to left, clang's left to right), so Vector3d(noise(rng), ...) is another start
    auto draw = [&] {
      const double z = noise(rng), y = noise(rng), x = noise(rng);
      return Vector3d(x, y, z);
    };
    for (BodyState& body : bodies) {
      body.x += draw();
      body.q = times_exp(body.q, draw());
    }
    const int head = model.find_segment("head"), hand = model.find_segment("r_forearm");
    pins = {Pin{head, Vector3d(0.01, 0.02, 0.05)}, Pin{hand, Vector3d(0.0, 0.01, -0.1)}};
    if (more_loops) {
      pins.push_back(Pin{model.find_segment("l_shin"), Vector3d(0.01, 0.0, -0.15)});
      pins.push_back(Pin{model.find_segment("r_shin"), Vector3d(-0.01, 0.01, -0.12)});
    }
    for (Pin& pin : pins) {
      pin.target = world_point(bodies[pin.segment], pin.local_point) + Vector3d(0.03, -0.02, 0.01);
    }
  }
  // the poses after `iterations` Newton iterations of the tree rule
  std::vector<BodyState> solved(int iterations) const {
    Environment space;
    space.gravity.setZero();
    Settings settings = tree();
    settings.substeps = 1;
    settings.iterations = iterations;
    Solver solver(model, settings, space);
    solver.reset(bodies);
    solver.set_pins(pins);
    solver.step(kDt);
    return solver.state().bodies;
  }
};

// The minimum-energy correction of the linearised constraints, min ½ΔᵀMΔ subject to
// C + JΔ = 0, is Δ = M⁻¹Jᵀλ with (J M⁻¹ Jᵀ) λ = −C: built densely here, with J by central
// differences, it must match the tree's O(n) solve, loops included, to the Jacobian's accuracy.
// The step 1e-5 is near the best: at 1e-7 rounding left the poses 5.7e-8 apart, at 1e-5 its
// truncation leaves ~3e-9 (both measured), so 1e-8 holds with room. One loop (head and hand) and
// three (the shins too): the loops' columns are solved on their segments' ancestors alone, which
// three loops share in part.
void expect_dense_kkt_solve(bool more_loops) {
  const Perturbed p(more_loops);
  const int n = p.model.segment_count();
  const Eigen::VectorXd c = constraint_values(p.model, p.bodies, p.pins);
  Eigen::MatrixXd jacobian(c.size(), 6 * n);
  for (int k = 0; k < 6 * n; ++k) {
    Eigen::VectorXd step = Eigen::VectorXd::Zero(6 * n);
    step(k) = 1e-5;
    jacobian.col(k) = (constraint_values(p.model, moved(p.bodies, step), p.pins) -
                       constraint_values(p.model, moved(p.bodies, -step), p.pins)) /
                      2e-5;
  }
  Eigen::VectorXd inverse_mass(6 * n);
  for (int i = 0; i < n; ++i) {
    inverse_mass.segment<3>(6 * i).setConstant(p.model.segments[i].inv_mass);
    inverse_mass.segment<3>(6 * i + 3) = p.model.segments[i].inv_inertia;
  }
  const Eigen::MatrixXd k = jacobian * inverse_mass.asDiagonal() * jacobian.transpose();
  const Eigen::VectorXd lambda = k.ldlt().solve(-c);
  const auto dense = moved(p.bodies, inverse_mass.asDiagonal() * jacobian.transpose() * lambda);
  const auto solved = p.solved(1);
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    worst = std::max(worst, (solved[i].x - dense[i].x).norm());
    worst = std::max(worst, angle_between(solved[i].q, dense[i].q));
  }
  std::printf("[ dense    ] |C| %.3e m; tree and dense poses differ by %.2e (m or rad)\n", c.norm(),
              worst);
  EXPECT_GT(c.norm(), 0.1);  // a real correction: every joint open by centimetres
  EXPECT_LT(worst, 1e-8);
}

TEST(Tree, OneNewtonIterationIsTheDenseKktSolve) { expect_dense_kkt_solve(false); }
TEST(Tree, OneNewtonIterationWithThreeLoopsIsTheDenseKktSolve) { expect_dense_kkt_solve(true); }

// Newton on the nonlinear constraints: from gaps of centimetres (|C| 0.44 m over 13 joints and
// 2 pins) it closes them to rounding, and once within a millimetre each iteration squares the
// error, times a constant of about 10/m here (quadratic convergence: the exact Jacobian of the
// joints and pins; a linear rate ρ would leave ρ·|C|, far above 100·|C|² below a millimetre)
TEST(Tree, NewtonIterationsConvergeQuadratically) {
  const Perturbed p;
  double previous = constraint_values(p.model, p.bodies, p.pins).norm();
  for (int iterations = 1; iterations <= 7; ++iterations) {
    const double error = constraint_values(p.model, p.solved(iterations), p.pins).norm();
    std::printf("[ newton   ] %d iteration(s): |C| %.3e m\n", iterations, error);
    EXPECT_LT(error, previous) << iterations;
    if (previous < 1e-3 && previous > 1e-10) {
      EXPECT_LT(error, 100.0 * previous * previous) << iterations;
    }
    previous = error;
  }
  EXPECT_LT(previous, 1e-12);
}

TEST(Tree, PendulumPeriodWithinATenthOfAPercent) {
  const double ratio = test::pendulum_period_ratio(tree(), 10.0 * M_PI / 180.0, kDt);
  std::printf("[ period   ] tree period / analytic: %+.4f %%\n", 100 * (ratio - 1));
  EXPECT_NEAR(ratio, 1.0, 1e-3);
}

TEST(Tree, DoublePendulumWithinFiveMillimetresAndConverging) {
  const double coarse = test::double_pendulum_error(tree(), 1.0 / 240.0);
  const double fine = test::double_pendulum_error(tree(), 1.0 / 960.0);
  std::printf("[ 2 rods   ] tree mean pose error over 5 s: %.5f m at 1/240, %.5f m at 1/960\n",
              coarse, fine);
  EXPECT_LT(coarse, 0.005);
  EXPECT_LT(fine, coarse);
}

TEST(Tree, SpinningBoxKeepsItsAngularMomentum) {
  const test::SpinResult spin = test::spin_box(tree(), kDt);
  EXPECT_NEAR(spin.momentum_ratio, 1.0, 1e-3);
  EXPECT_LT(spin.direction_drift, 1e-3);
}

// Pinocchio's scenarios at 1/240 with the defaults: never diverged (yank's grab circling at
// 2 Hz), and the joints closed after every step to 0.1 mm in the scenarios without ground or
// yank (one Newton iteration per substep leaves its second-order remainder: ~1e-7 m, 3.5e-5 m in
// tremble, which displaces segments every substep; xpbd's sweep leaves ~1e-3 m), and to 1 mm in
// drop (the ground pushed out before each solve) and yank (measured 0.17 and 0.10 mm)
TEST(Tree, EveryScenarioStaysOkWithItsJointsClosed) {
  const Model model = load_model(test::kPinocchioPath);
  for (const std::string& name : compare::scenario_names()) {
    compare::ScenarioOptions options;
    if (name == "yank") options.hz = 2.0;
    const compare::Scenario scenario = compare::make_scenario(name, model, options);
    const test::ScenarioRun run = test::run_scenario(model, scenario, tree(), kDt);
    std::printf("[ %-8s ] tree max joint gap %.2e m\n", name.c_str(), run.worst_gap);
    EXPECT_FALSE(run.diverged) << name;
    EXPECT_LT(run.worst_gap, name == "drop" || name == "yank" ? 1e-3 : 1e-4) << name;
  }
}

TEST(Tree, DeterministicDragAfterThousandSteps) {
  const uint64_t first = test::drag_hash(tree());
  std::printf("[ hash     ] %016llx\n", static_cast<unsigned long long>(first));
  EXPECT_EQ(test::drag_hash(tree()), first);
  EXPECT_EQ(first, kExpectedTreeDragHash);
}

}  // namespace
}  // namespace puppet::procedural
