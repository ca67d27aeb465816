// Joint frames that are not principal frames of their child, in every solver. Turning a hinge's
// frame about its own axis, or a ball's frame with a round swing cone about its twist axis,
// changes no physics: the same joint angles are measured from the same rest pose. So a model
// whose frames are turned that way (and so are no longer principal: the children are boxes with
// three different moments) must move as the model with aligned frames does, with its limits
// engaged.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "puppet/compare/engines.h"
#include "puppet/compare/metrics.h"
#include "puppet/compare/run.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"

namespace puppet::compare {
namespace {

constexpr double kPi = std::numbers::pi;

// three boxes hanging from the first: a hinge about world x (range −10°…+8°), then a ball with a
// swing ellipse of half-angles `swing_x`, `swing_y` (deg) and a 6° twist; `turn_deg` turns the
// hinge's frame about x and the ball's about z. `open` opens every limit.
Model three_boxes(double turn_deg, bool open = false, double swing_x = 12.0,
                  double swing_y = 12.0) {
  const double half = 0.5 * turn_deg * kPi / 180.0;
  char text[4096];
  std::snprintf(text, sizeof text, R"({"name": "three-boxes", "segments": [
        {"name": "top", "mass": 2.0, "position": [0, 0, 1.5],
         "shape": {"type": "box", "half_extents": [0.06, 0.03, 0.15]}},
        {"name": "mid", "mass": 1.5, "position": [0, 0, 1.2],
         "shape": {"type": "box", "half_extents": [0.05, 0.02, 0.15]}},
        {"name": "low", "mass": 1.0, "position": [0, 0, 0.9],
         "shape": {"type": "box", "half_extents": [0.04, 0.025, 0.15]}}],
      "joints": [
        {"name": "hinge", "parent": "top", "child": "mid", "anchor": [0, 0, 1.35],
         "type": "hinge", "axis": [1, 0, 0], "range_deg": [%g, %g],
         "frame": [%.17g, %.17g, 0, 0]},
        {"name": "ball", "parent": "mid", "child": "low", "anchor": [0, 0, 1.05],
         "type": "ball", "swing_deg": [%g, %g], "twist_deg": %g,
         "frame": [%.17g, 0, 0, %.17g]}]})",
                open ? -180.0 : -10.0, open ? 180.0 : 8.0, std::cos(half), std::sin(half),
                open ? 180.0 : swing_x, open ? 180.0 : swing_y, open ? 180.0 : 6.0, std::cos(half),
                std::sin(half));
  return parse_model(text, "three-boxes");
}

// rotates segments [first, end) about `pivot`
void turn(std::vector<BodyState>& bodies, int first, const Quaterniond& q, const Vector3d& pivot) {
  for (size_t i = first; i < bodies.size(); ++i) {
    bodies[i].x = pivot + q * (bodies[i].x - pivot);
    bodies[i].q = q * bodies[i].q;
  }
}

// hang, started with both joints bent against their limits and swinging into them
Scenario bent_hang(const Model& model) {
  Scenario s = make_scenario("hang", model);
  std::vector<BodyState>& b = s.initial;
  turn(b, 1, Quaterniond(Eigen::AngleAxisd(7.0 * kPi / 180.0, Vector3d::UnitX())),
       model.joints[0].anchor_world);
  const Vector3d ball = b[1].x + b[1].q * model.joints[1].anchor_in_parent;
  turn(b, 2,
       Quaterniond(Eigen::AngleAxisd(4.0 * kPi / 180.0, Vector3d(1, 1, 0).normalized()) *
                   Eigen::AngleAxisd(5.0 * kPi / 180.0, Vector3d::UnitZ())),
       ball);
  // spinning the bottom box about its long axis drives the twist into its limit
  b[2].w = Vector3d(0.0, 0.0, 3.0);
  b[2].v = b[2].w.cross(b[2].x - ball);
  return s;
}

// the state after 1 s at 1/480 s, and the largest violation on the way of the limits of
// `limits` (deg)
std::vector<BodyState> after_one_second(const std::string& solver, const Model& model,
                                        double* worst_violation_deg = nullptr,
                                        const Model* limits = nullptr) {
  auto simulator = make_simulator(solver, {});
  const Scenario scenario = bent_hang(model);
  simulator->reset(model, scenario);
  std::vector<Vector3d> targets;
  std::vector<BodyState> out(model.segment_count());
  std::vector<double> violations(model.joint_count());
  constexpr double kDt = 1.0 / 480.0;
  double worst = 0.0;
  for (int k = 1; k <= 480; ++k) {
    scenario.targets_at(k * kDt, targets);
    simulator->set_pin_targets(targets);
    simulator->step(kDt);
    simulator->read_state(out);
    limit_violations_deg(limits ? *limits : model, out, violations);
    for (double v : violations) worst = std::max(worst, v);
  }
  EXPECT_FALSE(simulator->diverged()) << solver;
  if (worst_violation_deg) *worst_violation_deg = worst;
  return out;
}

TEST(JointFrames, TurnedFramesAreNotPrincipal) {
  const Model turned = three_boxes(30.0);
  EXPECT_FALSE(is_principal_frame(turned.segments[1], turned.joints[0].frame_in_child));
  EXPECT_FALSE(is_principal_frame(turned.segments[2], turned.joints[1].frame_in_child));
  const Model aligned = three_boxes(0.0);
  EXPECT_TRUE(is_principal_frame(aligned.segments[1], aligned.joints[0].frame_in_child));
  // the hinge axis in the turned frame is still the frame's x
  EXPECT_NEAR((turned.joints[0].hinge_axis - Vector3d::UnitX()).norm(), 0.0, 1e-15);
}

// Every solver: the turned model follows the aligned one. The tolerance is rounding grown over
// 480 steps of a motion that hits its limits (the solvers' paths differ only in the order of
// floating-point operations); the limits matter, since opening them moves the boxes by
// centimetres.
TEST(JointFrames, TurnedFramesMoveAsAlignedOnesInEverySolver) {
  const Model aligned = three_boxes(0.0), turned = three_boxes(30.0), free = three_boxes(0.0, true);
  for (const std::string& solver : solver_names()) {
    SCOPED_TRACE(solver);
    const auto a = after_one_second(solver, aligned);
    const auto t = after_one_second(solver, turned);
    const auto f = after_one_second(solver, free);
    // single precision (jolt): a position's last bit is 6e-8 m near 1 m, and the two runs'
    // roundings grow over the same 480 steps (measured 2.2e-5 m); a frame read wrongly moves the
    // boxes by centimetres
    EXPECT_LT(pose_error(t, a), find_engine(solver)->single_precision ? 1e-4 : 1e-7);
    EXPECT_GT(pose_error(f, a), 0.01);
  }
}

// An elliptic swing limit (14° by 5°) in a non-principal frame, where the frame's axes matter.
// Turned by 90° about z the frame is principal again (the boxes' axes map onto each other), and
// bullet-multibody then takes its link frames from the joint frames, not from the segments; at
// 89.999° it takes the other path. Both must agree to the 1e-5 rad the frames differ by, and the
// model's own measure of the limit (the metrics') must see the ellipse held. MuJoCo is left out
// of the limit check: its ball limit is a round cone of the larger half-angle (docs/mujoco.md).
TEST(JointFrames, EllipticLimitInAFrameThatIsNotPrincipal) {
  const Model principal = three_boxes(90.0, false, 14.0, 5.0);
  const Model turned = three_boxes(89.999, false, 14.0, 5.0);
  ASSERT_TRUE(is_principal_frame(principal.segments[2], principal.joints[1].frame_in_child));
  ASSERT_FALSE(is_principal_frame(turned.segments[2], turned.joints[1].frame_in_child));
  const Model off = three_boxes(60.0, false, 14.0, 5.0);
  for (const std::string& solver : solver_names()) {
    SCOPED_TRACE(solver);
    const auto a = after_one_second(solver, principal);
    const auto t = after_one_second(solver, turned);
    // measured: the difference shrinks tenfold with each tenfold smaller turn (bullet-multibody
    // 1.2e-6, 1.2e-7, 1.2e-8 m; the solvers with one path 5e-4, 5e-5, 5e-6 m; bullet-rigid's box
    // limits less regularly); a link frame that does not match its joint would be off by cm
    EXPECT_LT(pose_error(t, a), solver == "bullet-multibody" ? 1e-6 : 1e-3);
    if (solver == "mujoco") continue;
    // Bullet's speculative limits overshoot by up to 1° in this motion with principal frames
    // (0.5° aligned, 0.96° at 90°); a limit held in the wrong axes is off by 5.7°–8°
    double worst = 0.0;
    after_one_second(solver, off, &worst);
    EXPECT_LT(worst, 2.0);
  }
  // and the motion does press on the ellipse: without limits it leaves it by far
  double free_violation = 0.0;
  after_one_second("procedural", three_boxes(60.0, true), &free_violation, &off);
  EXPECT_GT(free_violation, 10.0);
}

}  // namespace
}  // namespace puppet::compare
