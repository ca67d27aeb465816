// Joint limits in every reference engine. The box limit (euler_box.h: MuJoCo's three hinges, the
// multibody's own rows, the ragdoll's 6-dof joint): each holds a joint's rotation as the model's
// Euler angles, and a joint spun into each face or corner of its box stops there. And what an
// impact at a limit gives back, in every engine (near-inelastic) and procedural rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "puppet/model/euler_box.h"
#include "puppet/model/model.h"
#include "puppet/model/rotation.h"
#include "puppet/procedural/rule.h"
#include "puppet/procedural/solver.h"
#include "puppet/reference/bullet.h"
#include "puppet/reference/mujoco.h"
#include "puppet/reference/ode.h"
#include "support/box_faces.h"
#include "support/source_dir.h"

namespace puppet::reference {
namespace {

constexpr double kDeg = M_PI / 180.0;

Model box_model() {
  return load_model(std::string(PUPPET_SOURCE_DIR) + "/tests/data/two_rods_box.json");
}

struct Engine {
  std::string name;
  std::unique_ptr<Solver> (*make)(const Model&, const Environment&);
};

// Bullet's sequential impulses run to convergence: the limits are tested, not the sweep budget
constexpr int kIterations = 200;

// the engines, Bullet's at kIterations
std::vector<Engine> engines() {
  std::vector<Engine> out;
  out.push_back({"bullet-multibody", [](const Model& model, const Environment& environment) {
                   return make_solver(Kind::kMultibody, model, environment,
                                      {.iterations = kIterations});
                 }});
  out.push_back({"bullet-rigid", [](const Model& model, const Environment& environment) {
                   return make_solver(Kind::kRigid, model, environment,
                                      {.iterations = kIterations});
                 }});
  if (have_mujoco()) {
    out.push_back({"mujoco", [](const Model& model, const Environment& environment) {
                     return make_mujoco(model, environment);
                   }});
  }
  if (have_ode()) {
    // the exact LCP, and Gauss–Seidel run to convergence
    out.push_back({"ode", [](const Model& model, const Environment& environment) {
                     return make_ode(model, environment, {.stepper = OdeStepper::kStep});
                   }});
    out.push_back({"ode-quick", [](const Model& model, const Environment& environment) {
                     return make_ode(model, environment, {.iterations = kIterations});
                   }});
  }
  return out;
}

// three pins that hold the upper rod still: its centre and two points 10 cm off its axis
std::vector<Pin> upper_rod_held(const Model& model) {
  const Segment& upper = model.segments[0];
  std::vector<Pin> pins;
  for (const Vector3d& local : {Vector3d(0, 0, 0), Vector3d(0.1, 0, 0), Vector3d(0, 0.1, 0)}) {
    pins.push_back({.segment = 0,
                    .local_point = local,
                    .target = upper.rest_position + upper.rest_orientation * local});
  }
  return pins;
}

// the upper rod held still, no gravity: the lower rod turns about the elbow alone
std::unique_ptr<Solver> held(const Engine& engine, const Model& model) {
  auto solver = engine.make(model, Environment{.gravity = Vector3d::Zero()});
  solver->set_pins(upper_rod_held(model));
  return solver;
}

// the pose with the lower rod turned about the elbow so that q_rel = R_box(angles), and the
// relative angular velocity w (world)
std::vector<BodyState> turned(const Model& model, const Vector3d& angles, const Vector3d& w) {
  const Joint& joint = model.joints[0];
  std::vector<BodyState> bodies = rest_pose(model);
  const Quaterniond frame = bodies[0].q * joint.frame_in_parent;
  bodies[1].q = frame * euler_rotation(joint.box_order, angles) * joint.frame_in_child.conjugate();
  bodies[1].x = joint.anchor_world - bodies[1].q * joint.anchor_in_child;
  bodies[1].w = w;
  bodies[1].v = w.cross(bodies[1].x - joint.anchor_world);
  return bodies;
}

Vector3d box_angles(const Model& model, const std::vector<BodyState>& bodies) {
  const Joint& joint = model.joints[0];
  return euler_angles(joint.box_order, joint_relative_rotation(joint, bodies[0].q, bodies[1].q));
}

// A pose inside the box with a spin, written into the engine and read back, is the same pose
// and spin: the engine's coordinates (MuJoCo's three hinge angles and rates) hold the model's
// Euler angles. Twice: from the upper rod, and with the tree hung from the elbow on the lower
// rod (MuJoCo then roots its tree there and writes the box from the child's side, inverted)
TEST(BoxLimit, EveryEngineHoldsTheModelsAngles) {
  const Model model = box_model();
  const Joint& joint = model.joints[0];
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0), spin(-5.0, 5.0);
  for (const Engine& engine : engines()) {
    for (const int hung : {-1, 1}) {
      SCOPED_TRACE(engine.name + (hung < 0 ? "" : " hung from the lower rod"));
      auto solver = engine.make(model, Environment{.gravity = Vector3d::Zero()});
      if (hung >= 0) {
        const Pin pin{
            .segment = hung, .local_point = joint.anchor_in_child, .target = joint.anchor_world};
        solver->set_pins({&pin, 1});
      }
      for (int trial = 0; trial < 200; ++trial) {
        Vector3d angles;
        for (int k = 0; k < 3; ++k) {
          angles[k] = joint.box_lower[k] + unit(rng) * (joint.box_upper[k] - joint.box_lower[k]);
        }
        const Vector3d w(spin(rng), spin(rng), spin(rng));
        const std::vector<BodyState> bodies = turned(model, angles, w);
        solver->set_state(bodies);
        std::vector<BodyState> read(2);
        solver->read_state(read);
        EXPECT_LT((box_angles(model, read) - angles).cwiseAbs().maxCoeff(), 1e-9);
        EXPECT_LT((read[1].w - read[0].w - w).norm(), 1e-9);
        EXPECT_LT((read[1].x - bodies[1].x).norm(), 1e-9);
      }
    }
  }
}

using test::faces_and_corners;

constexpr double kStepDt = 1.0 / 960.0;

// the pushed angles of a face (one ±1) or corner (three) at their faces, the others 0
Vector3d face_angles(const Joint& joint, const Vector3d& push) {
  Vector3d out;
  for (int k = 0; k < 3; ++k) {
    out[k] = push[k] > 0.0 ? joint.box_upper[k] : push[k] < 0.0 ? joint.box_lower[k] : 0.0;
  }
  return out;
}

// A joint spun into each face and each corner of its box stops there: the lower rod starts at
// rest angles with the pushed angles turning at 3 rad/s towards their faces, at dt = 1/960 s. Over
// the second that follows no angle is ever more than 1° outside its range, and a face's angle
// reaches its face (within 1°). MuJoCo's limit acts once an angle is past it, as a spring of time
// constant τ = 2·dt: at ω ≤ 5 rad/s it gives way by less than ω·(dt + τ) = 0.9°; Bullet's are
// one-sided impulses, solved here to convergence (kIterations). A corner's angles need not all
// reach their faces: the rod turns freely until a limit acts, and each limit's reaction turns
// the other angles through the joint-space inertia, so a corner is asked to hold.
TEST(BoxLimit, AJointSpunIntoEachFaceOrCornerStopsThere) {
  const Model model = box_model();
  const Joint& joint = model.joints[0];
  for (const Engine& engine : engines()) {
    for (const Vector3d& push : faces_and_corners()) {
      SCOPED_TRACE(engine.name + " push " + std::to_string(push.x()) + "," +
                   std::to_string(push.y()) + "," + std::to_string(push.z()));
      auto solver = held(engine, model);
      // at rest angles, the angles' rates are turns about the frame's axes
      const Quaterniond frame = model.segments[0].rest_orientation * joint.frame_in_parent;
      Vector3d w = Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        w += frame * (3.0 * push[k] * Vector3d::Unit(joint.box_order.axes[k]));
      }
      solver->set_state(turned(model, Vector3d::Zero(), w));
      std::vector<BodyState> bodies(2);
      const bool face = push.cwiseAbs().sum() == 1.0;
      int k = 0;
      push.cwiseAbs().maxCoeff(&k);
      double reached = 0.0, worst = 0.0;
      for (int step = 0; step < 960; ++step) {
        solver->step(kStepDt);
        solver->read_state(bodies);
        const Quaterniond q_rel = joint_relative_rotation(joint, bodies[0].q, bodies[1].q);
        worst =
            std::max(worst, box_excess(joint.box_order, joint.box_lower, joint.box_upper, q_rel));
        reached = std::max(reached, push[k] * box_angles(model, bodies)[k]);
      }
      if (face) {
        EXPECT_GT(reached, push[k] * face_angles(joint, push)[k] - 1.0 * kDeg);
      }
      EXPECT_LT(worst, 1.0 * kDeg);
      EXPECT_FALSE(solver->diverged());
    }
  }
}

// Two rods, the lower one on a hinge about y with the range [−30°, 45°] at the elbow
Model hinge_model() {
  Model model = box_model();
  Joint& joint = model.joints[0];
  joint.type = JointType::kHinge;
  joint.hinge_axis = Vector3d::UnitY();
  joint.frame_world = Quaterniond::Identity();
  joint.frame_in_parent = model.segments[0].rest_orientation.conjugate();
  joint.frame_in_child = model.segments[1].rest_orientation.conjugate();
  joint.lower = -30.0 * kDeg;
  joint.upper = 45.0 * kDeg;
  derive_limit_terms(joint);
  return model;
}

// the hinge's angle
double limited_angle(const Model& model, const std::vector<BodyState>& bodies) {
  const Joint& joint = model.joints[0];
  const Quaterniond q_rel = joint_relative_rotation(joint, bodies[0].q, bodies[1].q);
  return decompose_swing_twist(q_rel, joint.hinge_axis).twist_angle;
}

// the hinge's axis in world at rest
Vector3d limited_axis(const Model& model) {
  const Joint& joint = model.joints[0];
  return model.segments[0].rest_orientation * joint.frame_in_parent * joint.hinge_axis;
}

constexpr double kImpactSpeed = 3.0;  // rad/s
constexpr double kImpactDt = 1.0 / 240.0;

// The rebound of an impact: the limited angle turns at kImpactSpeed towards its upper end from
// rest, at dt = 1/240 s; `advance` steps and returns the bodies. The rebound is the fastest the
// angle moves back in the quarter second after it first comes within 1° of the end, over the
// speed it came in with.
template <typename Angle, typename Advance>
double rebound_of(Angle&& angle_of, double upper, Advance&& advance, double window = 0.25) {
  double before = angle_of(advance(0));
  double reached = -1.0, fastest_back = 0.0;
  for (int step = 1; step < 240; ++step) {
    const double angle = angle_of(advance(step));
    const double rate = (angle - before) / kImpactDt;
    before = angle;
    if (reached < 0.0 && angle > upper - 1.0 * kDeg) reached = step * kImpactDt;
    if (reached >= 0.0 && step * kImpactDt <= reached + window) {
      fastest_back = std::max(fastest_back, -rate);
    }
  }
  EXPECT_GE(reached, 0.0) << "the angle never reached its end";
  return fastest_back / kImpactSpeed;
}
template <typename Advance>
double rebound(const Model& model, double upper, Advance&& advance) {
  return rebound_of(
      [&](const std::vector<BodyState>& bodies) { return limited_angle(model, bodies); }, upper,
      advance);
}

// the model with its upper rod 10⁶ times heavier: a procedural solver's still parent (the
// engines hang their tree from a pin, a fixed base; a rod that several hard pins hold in a
// position pass is not still: measured, 1.3 rad/s after the impact, which the rebound would read)
Model with_still_parent(Model model) {
  Segment& upper = model.segments[0];
  upper.mass *= 1e6;
  upper.inv_mass /= 1e6;
  upper.inertia *= 1e6;
  upper.inv_inertia /= 1e6;
  return model;
}

// a procedural rule on `model` (still parent, no gravity, the rule's defaults)
procedural::Solver procedural_solver(const Model& model, procedural::Rule rule,
                                     bool limit_pass = true) {
  procedural::Settings settings;
  settings.rule = rule;
  settings.limit_velocity_pass = limit_pass;
  return procedural::Solver(model, settings, Environment{.gravity = Vector3d::Zero()});
}

// Every engine's limits are near-inelastic: a hinge driven into its end gives back at most 5% of
// its speed (Bullet's speculative rows and its hinge without restitution, MuJoCo's limit spring
// damped at kLimitDampingRatio 2: measured 2%, 0.9%, 1.0%; at ratio 1 MuJoCo gave back 4.2%,
// and Bullet's hinge at its default relaxation factor, which is its restitution, 30%). So the
// truths and the solvers they judge share one impact law. A hinge, not a box: past a box's face the
// rod slides along it into the next face, whose impact turns the first angle too (the box's face
// below). The procedural rules give back at most 3%: the ones that clamp (and relaxed, whose last
// pass clamps) nothing at all; xpbd and tree, whose velocities come from their own corrections,
// hold it with the limits' velocity pass, which sets a corrected limit's rate to its
// restitution's (0). Without the pass xpbd gave back 0.42 of the speed (next test).
TEST(LimitImpact, EveryEngineIsNearInelastic) {
  const Model model = hinge_model();
  const Joint& joint = model.joints[0];
  const Vector3d w = kImpactSpeed * limited_axis(model);
  std::vector<BodyState> start = rest_pose(model);
  start[1].w = w;
  start[1].v = w.cross(start[1].x - joint.anchor_world);
  for (const Engine& engine : engines()) {
    SCOPED_TRACE(engine.name);
    auto solver = held(engine, model);
    solver->set_state(start);
    std::vector<BodyState> bodies(2);
    const double back = rebound(model, joint.upper, [&](int step) {
      if (step > 0) solver->step(kImpactDt);
      solver->read_state(bodies);
      return bodies;
    });
    std::printf("[ rebound  ] %-16s %.3f of the impact speed\n", engine.name.c_str(), back);
    EXPECT_LT(back, 0.05);
  }
  const Model still = with_still_parent(model);
  for (const procedural::Rule rule : procedural::kAllRules) {
    const std::string name(procedural::rule_name(rule));
    SCOPED_TRACE(name);
    procedural::Solver solver = procedural_solver(still, rule);
    solver.reset(start);
    std::vector<BodyState> bodies;
    const double back = rebound(model, joint.upper, [&](int step) {
      if (step > 0) solver.step(kImpactDt);
      bodies = solver.state().bodies;
      return bodies;
    });
    std::printf("[ rebound  ] %-16s %.3f of the impact speed\n", name.c_str(), back);
    EXPECT_LT(back, 0.03);
  }
}

// The velocity pass is what holds it: without it xpbd gives the impact back (the test fails if
// the pass stops acting)
TEST(LimitImpact, WithoutTheVelocityPassXpbdGivesTheImpactBack) {
  const Model model = hinge_model();
  const Joint& joint = model.joints[0];
  std::vector<BodyState> start = rest_pose(model);
  start[1].w = kImpactSpeed * limited_axis(model);
  start[1].v = start[1].w.cross(start[1].x - joint.anchor_world);
  const Model still = with_still_parent(model);  // the solver keeps a reference to its model
  procedural::Solver solver = procedural_solver(still, procedural::Rule::kXpbd, false);
  solver.reset(start);
  const double back = rebound(model, joint.upper, [&](int step) {
    if (step > 0) solver.step(kImpactDt);
    return solver.state().bodies;
  });
  std::printf("[ rebound  ] xpbd, no pass     %.3f of the impact speed\n", back);
  EXPECT_GT(back, 0.2);
}

// The same on a box's face: the lower rod turned at 3 rad/s about the box's first axis into its
// upper face (the other two angles at rest), its rate back read over the 1/20 s after the impact
// (later the rod, whose turn is not about a principal axis, slides along the face and the first
// angle moves back with it: over a quarter second the engines read 4–19%). Measured: the engines
// give back 1.8% (bullet-multibody), 0% (bullet-rigid), 6.5% (MuJoCo's limit spring, which acts
// over a few steps), and the procedural rules at most 3% (measured ≤ 1.9%; without the velocity
// pass xpbd gave 6.7%).
constexpr double kFaceWindow = 0.05;
TEST(LimitImpact, ABoxFaceIsNearInelasticInEveryEngine) {
  const Model model = box_model();
  const Joint& joint = model.joints[0];
  const Quaterniond frame = model.segments[0].rest_orientation * joint.frame_in_parent;
  const Vector3d w = frame * (kImpactSpeed * Vector3d::Unit(joint.box_order.axes[0]));
  const std::vector<BodyState> start = turned(model, Vector3d::Zero(), w);
  const auto first_angle = [&](const std::vector<BodyState>& bodies) {
    return box_angles(model, bodies)[0];
  };
  for (const Engine& engine : engines()) {
    SCOPED_TRACE(engine.name);
    auto solver = held(engine, model);
    solver->set_state(start);
    std::vector<BodyState> bodies(2);
    const double back = rebound_of(
        first_angle, joint.box_upper[0],
        [&](int step) {
          if (step > 0) solver->step(kImpactDt);
          solver->read_state(bodies);
          return bodies;
        },
        kFaceWindow);
    std::printf("[ rebound  ] %-16s %.3f of the impact speed (box face)\n", engine.name.c_str(),
                back);
    EXPECT_LT(back, 0.1);
  }
  const Model still = with_still_parent(model);
  for (const procedural::Rule rule : procedural::kAllRules) {
    const std::string name(procedural::rule_name(rule));
    SCOPED_TRACE(name);
    procedural::Solver solver = procedural_solver(still, rule);
    solver.reset(start);
    const double back = rebound_of(
        first_angle, joint.box_upper[0],
        [&](int step) {
          if (step > 0) solver.step(kImpactDt);
          return solver.state().bodies;
        },
        kFaceWindow);
    std::printf("[ rebound  ] %-16s %.3f of the impact speed (box face)\n", name.c_str(), back);
    EXPECT_LT(back, 0.03);
  }
}

// A hinge between a hanging pin and the model's root is built from its child's side (MuJoCo
// writes it in the upper rod's body under the lower rod's, bullet-multibody makes the upper rod
// the lower rod's child link), and keeps the model's range: the tree hung from the lower rod at
// the hinge, no gravity, the upper rod turned to 2° inside each end and spun towards it at
// 1 rad/s stops at that end and no earlier.
TEST(Rooting, AHingeBuiltFromItsChildsSideKeepsItsRange) {
  const Model model = hinge_model();
  const Joint& joint = model.joints[0];
  const Segment& lower = model.segments[1];
  const Vector3d axis = lower.rest_orientation * joint.frame_in_child * joint.hinge_axis;
  for (const Engine& engine : engines()) {
    for (const double end : {joint.lower, joint.upper}) {
      SCOPED_TRACE(engine.name + (end > 0.0 ? " upper end" : " lower end"));
      const double sign = end > 0.0 ? 1.0 : -1.0;
      const double angle = end - sign * 2.0 * kDeg;
      auto solver = engine.make(model, Environment{.gravity = Vector3d::Zero()});
      const Pin pin{
          .segment = 1, .local_point = joint.anchor_in_child, .target = joint.anchor_world};
      solver->set_pins({&pin, 1});
      // q_rel = R(a, θ) with the lower rod at rest: the upper rod at q_c F_c R(a, −θ) F_p⁻¹
      std::vector<BodyState> bodies = rest_pose(model);
      bodies[0].q = lower.rest_orientation * joint.frame_in_child *
                    Quaterniond(Eigen::AngleAxisd(-angle, joint.hinge_axis)) *
                    joint.frame_in_parent.conjugate();
      bodies[0].x = joint.anchor_world - bodies[0].q * joint.anchor_in_parent;
      bodies[0].w = -sign * 1.0 * axis;  // ω_child − ω_parent = sign · 1 rad/s about the axis
      bodies[0].v = bodies[0].w.cross(bodies[0].x - joint.anchor_world);
      solver->set_state(bodies);
      solver->read_state(bodies);
      EXPECT_NEAR(limited_angle(model, bodies), angle, 1e-9);
      double furthest = angle;
      for (int step = 0; step < 120; ++step) {
        solver->step(kImpactDt);
        solver->read_state(bodies);
        furthest = sign > 0.0 ? std::max(furthest, limited_angle(model, bodies))
                              : std::min(furthest, limited_angle(model, bodies));
      }
      EXPECT_NEAR(furthest, end, 1.0 * kDeg);
      // ODE's stop removes the step's overshoot d as a velocity, ERP·d/dt, which stays (its
      // Baumgarte rows have no split impulse): up to ERP (0.2) of the 1 rad/s impact comes back,
      // and drifts the rod off the end for the rest of the run (measured 3.1° of the 5.7° that
      // allows; docs/references.md)
      const double rebound_drift =
          engine.name.starts_with("ode") ? 0.2 * 1.0 * (120 * kImpactDt) : 0.0;
      EXPECT_NEAR(limited_angle(model, bodies), end, 1.0 * kDeg + rebound_drift);
    }
  }
}

}  // namespace
}  // namespace puppet::reference
