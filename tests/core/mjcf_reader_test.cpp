// mjcf_reader.cpp: MJCF back into the model. Pinocchio through write_mjcf and back is the same
// model bit for bit (and so moves the same), without user data it is the same bodies with
// MuJoCo's cone for each ball limit, and a file written by hand is read in MuJoCo's own terms
// (degrees, Euler sequences, fromto, default classes, masses from geom densities).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/mjcf.h"
#include "puppet/model/model.h"
#include "puppet/model/rotation.h"
#include "support/random.h"
#include "support/source_dir.h"

namespace puppet {
namespace {

constexpr double kPi = std::numbers::pi;

Model pinocchio() { return load_model(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json"); }

void expect_same_vector(const Vector3d& a, const Vector3d& b, const std::string& what) {
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a[k], b[k]) << what << "[" << k << "]";
}

void expect_same_quaternion(const Quaterniond& a, const Quaterniond& b, const std::string& what) {
  EXPECT_EQ(a.coeffs(), b.coeffs()) << what;
}

// A root the world holds is written as its joints and read back the same, bit for bit (the user
// data holds each joint's anchor and axis in world): the hold, names, axes, range and springs
TEST(MjcfReader, HeldRootsRoundTripBitForBit) {
  for (const char* name :
       {"held_hinge.xml", "held_slide.xml", "held_planar.xml", "held_weld.xml"}) {
    SCOPED_TRACE(name);
    const Model a = load_model(std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/" + name);
    ASSERT_NE(a.root.hold, RootHold::kFree);
    MjcfOptions options;
    options.environment.gravity = a.gravity;
    const std::string written = write_mjcf(a, options);
    const Model b = parse_mjcf(written, name);
    EXPECT_TRUE(b.root == a.root);
    expect_same_vector(b.root.anchor_in_root, a.root.anchor_in_root, "anchor_in_root");
    EXPECT_EQ(write_mjcf(b, options), written);
  }
}

TEST(MjcfReader, PinocchioRoundTripsBitForBit) {
  const Model a = pinocchio();
  MjcfOptions options;
  options.environment.gravity = a.gravity;
  const Model b = parse_mjcf(write_mjcf(a, options), "pinocchio.xml");
  EXPECT_EQ(b.name, a.name);
  ASSERT_EQ(b.segment_count(), a.segment_count());
  ASSERT_EQ(b.joint_count(), a.joint_count());
  EXPECT_EQ(b.total_mass, a.total_mass);
  EXPECT_EQ(b.rest_height, a.rest_height);
  expect_same_vector(b.gravity, a.gravity, "gravity");
  for (int i = 0; i < a.segment_count(); ++i) {
    const Segment &s = a.segments[i], &t = b.segments[i];
    SCOPED_TRACE(s.name);
    EXPECT_EQ(t.name, s.name);
    EXPECT_EQ(t.mass, s.mass);
    EXPECT_EQ(t.inv_mass, s.inv_mass);
    expect_same_vector(t.inertia, s.inertia, "inertia");
    expect_same_vector(t.inv_inertia, s.inv_inertia, "inv_inertia");
    ASSERT_EQ(t.shapes.size(), s.shapes.size());
    for (size_t k = 0; k < s.shapes.size(); ++k) {
      EXPECT_EQ(t.shapes[k].type, s.shapes[k].type);
      EXPECT_EQ(t.shapes[k].radius, s.shapes[k].radius);
      EXPECT_EQ(t.shapes[k].half_length, s.shapes[k].half_length);
      expect_same_vector(t.shapes[k].half_extents, s.shapes[k].half_extents, "half_extents");
      expect_same_vector(t.shapes[k].position, s.shapes[k].position, "shape position");
      expect_same_quaternion(t.shapes[k].orientation, s.shapes[k].orientation, "shape axes");
    }
    expect_same_vector(t.rest_position, s.rest_position, "rest_position");
    expect_same_quaternion(t.rest_orientation, s.rest_orientation, "rest_orientation");
    EXPECT_EQ(t.parent, s.parent);
    EXPECT_EQ(t.parent_joint, s.parent_joint);
  }
  for (int j = 0; j < a.joint_count(); ++j) {
    const Joint &p = a.joints[j], &q = b.joints[j];
    SCOPED_TRACE(p.name);
    EXPECT_EQ(q.name, p.name);
    EXPECT_EQ(q.type, p.type);
    EXPECT_EQ(q.parent, p.parent);
    EXPECT_EQ(q.child, p.child);
    expect_same_vector(q.anchor_world, p.anchor_world, "anchor_world");
    expect_same_vector(q.anchor_in_parent, p.anchor_in_parent, "anchor_in_parent");
    expect_same_vector(q.anchor_in_child, p.anchor_in_child, "anchor_in_child");
    expect_same_quaternion(q.frame_world, p.frame_world, "frame_world");
    expect_same_quaternion(q.frame_in_parent, p.frame_in_parent, "frame_in_parent");
    expect_same_quaternion(q.frame_in_child, p.frame_in_child, "frame_in_child");
    EXPECT_EQ(q.swing_x, p.swing_x);
    EXPECT_EQ(q.swing_y, p.swing_y);
    EXPECT_EQ(q.twist, p.twist);
    expect_same_vector(q.hinge_axis, p.hinge_axis, "hinge_axis");
    EXPECT_EQ(q.lower, p.lower);
    EXPECT_EQ(q.upper, p.upper);
    EXPECT_EQ(q.twist_half_sin, p.twist_half_sin);
    EXPECT_EQ(q.lower_half_cos, p.lower_half_cos);
  }

  // and so the same hang, step for step
  std::vector<std::vector<BodyState>> states;
  for (const Model* model : {&a, &b}) {
    auto simulator = compare::make_simulator("procedural", {});
    const compare::Scenario hang = compare::make_scenario("hang", *model);
    simulator->reset(*model, hang);
    std::vector<Vector3d> targets;
    for (int k = 1; k <= 240; ++k) {
      hang.targets_at(k / 240.0, targets);
      simulator->set_pin_targets(targets);
      simulator->step(1.0 / 240.0);
    }
    states.emplace_back(model->segment_count());
    simulator->read_state(states.back());
  }
  for (int i = 0; i < a.segment_count(); ++i) {
    expect_same_vector(states[1][i].x, states[0][i].x, "x after 1 s");
    expect_same_quaternion(states[1][i].q, states[0][i].q, "q after 1 s");
  }
}

// A box limit is written as three hinges in the child's body and read back as the same box: with
// user data bit for bit (order, ranges, frame); without it as the box of the three hinges' axes
// in the order x, y, z of a frame made of them, which holds the same rotations: every rotation's
// most outside angle is the same in both readings
TEST(MjcfReader, ABoxLimitIsThreeHingesAndComesBack) {
  const Model a = load_model(std::string(PUPPET_SOURCE_DIR) + "/tests/data/two_rods_box.json");
  const std::string xml = write_mjcf(a);
  EXPECT_NE(xml.find("<joint name=\"elbow:z\""), std::string::npos) << xml;
  const Model b = parse_mjcf(xml, "box.xml");
  ASSERT_EQ(b.joint_count(), 1);
  const Joint &p = a.joints[0], &q = b.joints[0];
  EXPECT_EQ(q.name, "elbow");
  EXPECT_EQ(q.ball_limit, BallLimit::kEulerBox);
  EXPECT_EQ(q.box_order, p.box_order);
  expect_same_vector(q.box_lower, p.box_lower, "lower");
  expect_same_vector(q.box_upper, p.box_upper, "upper");
  expect_same_quaternion(q.frame_world, p.frame_world, "frame");
  expect_same_vector(q.anchor_world, p.anchor_world, "anchor");

  MjcfOptions bare;
  bare.user_data = false;
  const Model c = parse_mjcf(write_mjcf(a, bare), "bare.xml");
  const Joint& r = c.joints[0];
  EXPECT_EQ(r.ball_limit, BallLimit::kEulerBox);
  EXPECT_EQ(euler_order_name(r.box_order), "xyz");
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 1000; ++trial) {
    const Quaterniond parent = test::random_rotation(rng), child = test::random_rotation(rng);
    EXPECT_NEAR(limit_violation(r, joint_relative_rotation(r, parent, child)),
                limit_violation(p, joint_relative_rotation(p, parent, child)), 1e-9);
  }
}

// Several joints in one body are read only as a box: two or three hinges about orthogonal axes
// (two: the third angle, about a₀ × a₁, held at 0), at one point or several (box_offsets)
TEST(MjcfReader, ABoxNeedsTwoOrThreeOrthogonalHinges) {
  auto read = [](const std::string& joints) {
    return "<mujoco><compiler angle=\"degree\"/><worldbody><body name=\"a\"><freejoint/>"
           "<geom type=\"sphere\" size=\"0.1\"/><body name=\"b\" pos=\"0 0 -0.3\">" +
           joints + "<geom type=\"sphere\" size=\"0.1\"/></body></body></worldbody></mujoco>";
  };
  auto hinge = [](const char* axis, const char* pos = "0 0 0.15") {
    return std::string("<joint type=\"hinge\" limited=\"true\" range=\"-20 30\" axis=\"") + axis +
           "\" pos=\"" + pos + "\"/>";
  };
  auto refused = [&](const std::string& joints, const std::string& message) {
    try {
      parse_mjcf(read(joints), "t.xml");
      ADD_FAILURE() << "accepted: " << joints;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  // left-handed axes: the third is turned round with its range
  const Model m = parse_mjcf(read(hinge("1 0 0") + hinge("0 0 1") + hinge("0 1 0")), "t.xml");
  const Joint& j = m.joints[0];
  EXPECT_EQ(j.ball_limit, BallLimit::kEulerBox);
  EXPECT_NEAR(j.box_lower[2], -30.0 * kPi / 180.0, 1e-15);
  EXPECT_NEAR(j.box_upper[2], 20.0 * kPi / 180.0, 1e-15);
  EXPECT_LT((j.frame_world * Vector3d::UnitZ() - Vector3d(0, -1, 0)).norm(), 1e-15);
  // two hinges: the same rotations, R(a₀, θ₀) R(a₁, θ₁), their third axis a₀ × a₁ held at 0
  const Model two = parse_mjcf(read(hinge("0 1 1") + hinge("0 -1 1")), "t.xml");
  const Joint& pair = two.joints[0];
  EXPECT_EQ(pair.ball_limit, BallLimit::kEulerBox);
  EXPECT_NEAR(pair.box_lower[1], -20.0 * kPi / 180.0, 1e-15);
  EXPECT_EQ(pair.box_lower[2], 0.0);
  EXPECT_EQ(pair.box_upper[2], 0.0);
  const Vector3d a0 = Vector3d(0, 1, 1).normalized(), a1 = Vector3d(0, -1, 1).normalized();
  EXPECT_LT((pair.frame_world * Vector3d::Unit(pair.box_order.axes[0]) - a0).norm(), 1e-15);
  EXPECT_LT((pair.frame_world * Vector3d::Unit(pair.box_order.axes[2]) - a0.cross(a1)).norm(),
            1e-15);
  refused(hinge("1 0 0") + hinge("0 1 0") + hinge("0 0 1") + hinge("1 0 0"),
          "a fourth joint in body \"b\"");
  refused(hinge("1 0 0") + hinge("0 1 0") + hinge("1 1 0"), "orthogonal axes");
  refused(hinge("1 0 0") + hinge("1 1 0"), "orthogonal axes");
  // hinges at different points: each point less the one before, in world at rest; the anchor
  // the first's on the parent's side, the last's on the child's
  const Model apart =
      parse_mjcf(read(hinge("1 0 0") + hinge("0 1 0") + hinge("0 0 1", "0 0 0.1")), "t.xml");
  const Joint& three = apart.joints[0];
  EXPECT_TRUE(has_box_offsets(three));
  EXPECT_EQ(three.box_offsets[0], Vector3d::Zero());
  EXPECT_LT((three.box_offsets[1] - Vector3d(0, 0, -0.05)).norm(), 1e-15);
  EXPECT_LT((three.anchor_world - Vector3d(0, 0, -0.15)).norm(), 1e-15);
  const Segment& b = apart.segments[1];
  EXPECT_LT(
      (b.rest_position + b.rest_orientation * three.anchor_in_child - Vector3d(0, 0, -0.2)).norm(),
      1e-15);
  const Model ankle = parse_mjcf(read(hinge("1 0 0", "0 0 0.08") + hinge("0 1 0")), "t.xml");
  EXPECT_LT((ankle.joints[0].box_offsets[0] - Vector3d(0, 0, 0.07)).norm(), 1e-15);
  EXPECT_EQ(ankle.joints[0].box_offsets[1], Vector3d::Zero());
  refused(hinge("1 0 0") + "<joint type=\"ball\" pos=\"0 0 0.15\"/>" + hinge("0 0 1"),
          "only as two or three hinges");
  // the middle angle within ±85°
  refused(
      hinge("1 0 0") + "<joint type=\"hinge\" axis=\"0 1 0\" pos=\"0 0 0.15\"/>" + hinge("0 0 1"),
      "must contain 0 and lie within");
}

// Without user data the file is read in MuJoCo's terms: the same bodies to rounding, each ball
// limit MuJoCo's cone (write_mjcf gives it the model's largest half-angle) on swing and twist
TEST(MjcfReader, WithoutUserDataBallLimitsAreCones) {
  const Model a = load_model(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio-swing-twist.json");
  MjcfOptions options;
  options.user_data = false;
  const Model b = parse_mjcf(write_mjcf(a, options), "pinocchio.xml");
  ASSERT_EQ(b.segment_count(), a.segment_count());
  for (int i = 0; i < a.segment_count(); ++i) {
    EXPECT_EQ(b.segments[i].mass, a.segments[i].mass);
    EXPECT_LT((b.segments[i].inertia - a.segments[i].inertia).norm(), 1e-15);
    EXPECT_LT((b.segments[i].rest_position - a.segments[i].rest_position).norm(), 1e-12);
    EXPECT_LT(b.segments[i].rest_orientation.angularDistance(a.segments[i].rest_orientation),
              1e-12);
  }
  for (int j = 0; j < a.joint_count(); ++j) {
    const Joint &p = a.joints[j], &q = b.joints[j];
    SCOPED_TRACE(p.name);
    EXPECT_LT((q.anchor_world - p.anchor_world).norm(), 1e-12);
    if (p.type == JointType::kBall) {
      const double cone = mjcf_ball_range(p);
      EXPECT_NEAR(q.swing_x, cone, 1e-15);
      EXPECT_NEAR(q.swing_y, cone, 1e-15);
      EXPECT_NEAR(q.twist, cone, 1e-15);
    } else {
      EXPECT_NEAR(q.lower, p.lower, 1e-15);
      EXPECT_NEAR(q.upper, p.upper, 1e-15);
      // the axis in world is the model's
      EXPECT_LT((q.frame_world * q.hinge_axis - p.frame_world * p.hinge_axis).norm(), 1e-12);
    }
  }
}

// a file as a user would write it; every figure below is worked out by hand from it
constexpr const char* kHandWritten = R"(<mujoco model="arm">
  <compiler angle="degree" eulerseq="zyx"/>
  <option gravity="0 0 -1.62"/>
  <default>
    <geom density="500"/>
    <default class="limb">
      <geom type="capsule" size="0.05"/>
      <joint type="hinge" limited="true"/>
    </default>
  </default>
  <worldbody>
    <geom type="plane" size="5 5 0.1"/>
    <light pos="0 0 3"/>
    <body name="torso" pos="0 0 1.5" childclass="limb">
      <freejoint name="root"/>
      <geom type="box" size="0.1 0.2 0.3" mass="20"/>
      <body name="upper" pos="0 0.22 0.25" euler="90 0 0">
        <joint name="shoulder" type="ball" range="0 60"/>
        <geom fromto="0 0 0 0 0 -0.3"/>
        <body name="lower" pos="0 0 -0.35">
          <joint name="elbow" axis="0 1 0" range="-10 150" pos="0 0 0.05"/>
          <inertial pos="0 0 -0.15" mass="1.2" diaginertia="0.01 0.01 0.002"/>
          <geom pos="0 0 -0.15" size="0.04 0.15"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>)";

TEST(MjcfReader, HandWrittenFileInMujocosTerms) {
  const Model m = parse_mjcf(kHandWritten, "arm.xml");
  EXPECT_EQ(m.name, "arm");
  EXPECT_EQ(m.gravity, Vector3d(0, 0, -1.62));
  ASSERT_EQ(m.segment_count(), 3);
  const Segment& torso = m.segments[0];
  EXPECT_EQ(torso.mass, 20.0);
  EXPECT_EQ(torso.shapes[0].type, ShapeType::kBox);
  EXPECT_NEAR(torso.inertia.x(), 20.0 / 12.0 * (0.4 * 0.4 + 0.6 * 0.6), 1e-12);

  // zyx Euler: 90° about z turns the body's frame; fromto makes the capsule's axis −z of it
  const Segment& upper = m.segments[1];
  const double r = 0.05, h = 0.15;
  const double volume = kPi * r * r * 2 * h + 4.0 / 3.0 * kPi * r * r * r;
  EXPECT_NEAR(upper.mass, 500.0 * volume, 1e-12);
  EXPECT_EQ(upper.shapes[0].type, ShapeType::kCapsule);
  EXPECT_NEAR(upper.shapes[0].half_length, h, 1e-15);
  EXPECT_LT((upper.rest_position - Vector3d(0, 0.22, 1.6)).norm(), 1e-12);
  EXPECT_LT((upper.rest_orientation * Vector3d::UnitZ() - Vector3d(0, 0, -1)).norm(), 1e-12);
  const Joint& shoulder = m.joints[0];
  EXPECT_EQ(shoulder.type, JointType::kBall);
  EXPECT_NEAR(shoulder.swing_x, kPi / 3, 1e-15);
  EXPECT_NEAR(shoulder.twist, kPi / 3, 1e-15);
  EXPECT_LT((shoulder.anchor_world - Vector3d(0, 0.22, 1.75)).norm(), 1e-12);

  // the elbow: its axis (0 1 0) in a frame turned 90° about z is world −x; the inertial is read
  // as given, in degrees the range is −10°…150°
  const Segment& lower = m.segments[2];
  EXPECT_EQ(lower.mass, 1.2);
  EXPECT_LT((lower.inertia - Vector3d(0.01, 0.01, 0.002)).norm(), 1e-15);
  EXPECT_LT((lower.rest_position - Vector3d(0, 0.22, 1.25)).norm(), 1e-12);
  const Joint& elbow = m.joints[1];
  EXPECT_EQ(elbow.type, JointType::kHinge);
  EXPECT_LT((elbow.frame_world * elbow.hinge_axis - Vector3d(-1, 0, 0)).norm(), 1e-12);
  EXPECT_NEAR(elbow.lower, -10 * kPi / 180, 1e-15);
  EXPECT_NEAR(elbow.upper, 150 * kPi / 180, 1e-15);
  EXPECT_LT((elbow.anchor_world - Vector3d(0, 0.22, 1.45)).norm(), 1e-12);

  // the scenarios take the file's gravity
  const compare::Scenario hang = compare::make_scenario("hang", m);
  EXPECT_EQ(hang.environment.gravity, Vector3d(0, 0, -1.62));
}

// A lone hinge whose range leaves out the pose as written (dm_control's hopper: its knee's
// [5°, 150°]) is read with its body turned to the range's nearer end: the same model as the file
// that writes the body at that angle and says so with ref (MuJoCo's qpos at the pose as written),
// its range and springref then measured from there; the note says so
// a leg of my own whose knee (a lone hinge) has what `shin` and `knee` add
std::string leg_with_knee(const std::string& shin, const std::string& knee) {
  return R"(<mujoco model="leg"><compiler angle="degree" autolimits="true"/><worldbody>
      <body name="thigh" pos="0 0 1"><freejoint/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.05"/>
        <body name="shin" pos="0 0 -0.45" )" +
         shin + R"(>
          <joint name="knee" axis="0 1 0" )" +
         knee + R"( stiffness="3" springref="20"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.04"/>
          <body name="foot" pos="0.05 0 -0.45">
            <joint name="ankle" axis="0 1 0" range="-30 30"/>
            <geom type="box" size="0.1 0.04 0.02"/>
          </body></body></body></worldbody></mujoco>)";
}

// the same rest pose, joints, ranges and springs in both
void expect_same_rest(const Model& turned, const Model& written) {
  ASSERT_EQ(turned.segment_count(), written.segment_count());
  for (int s = 0; s < turned.segment_count(); ++s) {
    const std::string name = turned.segments[s].name;
    EXPECT_LT((turned.segments[s].rest_position - written.segments[s].rest_position).norm(), 1e-12)
        << name;
    EXPECT_LT(
        turned.segments[s].rest_orientation.angularDistance(written.segments[s].rest_orientation),
        1e-12)
        << name;
  }
  ASSERT_EQ(turned.joints.size(), written.joints.size());
  for (size_t j = 0; j < turned.joints.size(); ++j) {
    const Joint &a = turned.joints[j], &b = written.joints[j];
    EXPECT_NEAR(a.lower, b.lower, 1e-15) << a.name;
    EXPECT_NEAR(a.upper, b.upper, 1e-15) << a.name;
    EXPECT_NEAR(a.passive[0].spring_ref, b.passive[0].spring_ref, 1e-15) << a.name;
    EXPECT_LT((a.anchor_world - b.anchor_world).norm(), 1e-12) << a.name;
  }
}

TEST(MjcfReader, AHingeOutsideItsRangeRestsAtItsNearerEnd) {
  std::string note;
  const Model turned = parse_mjcf(leg_with_knee("", R"(range="5 150")"), "leg.xml", {}, &note);
  EXPECT_NE(note.find("1 <joint> whose range leaves out the pose as written, its rest turned to "
                      "the nearer end"),
            std::string::npos)
      << note;
  const Model written = parse_mjcf(
      leg_with_knee(R"(axisangle="0 1 0 5")", R"(range="5 150" ref="5")"), "leg_at_5.xml");
  ASSERT_EQ(turned.segment_count(), 3);
  expect_same_rest(turned, written);
  // the foot (its centre 0.05 m ahead of the knee, 0.45 m below) turned by 5° about y with it
  const double five = 5 * kPi / 180;
  EXPECT_NEAR(turned.segments[2].rest_position.x(), 0.05 * std::cos(five) - 0.45 * std::sin(five),
              1e-12);
  const Joint& knee = turned.joints[0];
  EXPECT_EQ(knee.name, "knee");
  EXPECT_NEAR(knee.lower, 0.0, 1e-15);
  EXPECT_NEAR(knee.upper, 145 * kPi / 180, 1e-15);
  EXPECT_NEAR(knee.passive[0].spring_ref, 15 * kPi / 180, 1e-15);
  // the other way: the upper end, the nearer one for a range wholly below the pose as written
  const Model below = parse_mjcf(leg_with_knee("", R"(range="-150 -5")"), "leg.xml");
  EXPECT_NEAR(below.joints[0].lower, -145 * kPi / 180, 1e-15);
  EXPECT_NEAR(below.joints[0].upper, 0.0, 1e-15);
  // a box's hinges and the root's still must hold the pose as written
  EXPECT_THROW(parse_mjcf(R"(<mujoco><worldbody><body><geom size="0.1"/>
      <joint type="hinge" axis="0 1 0" limited="true" range="0.1 1"/></body></worldbody></mujoco>)",
                          "root.xml"),
               ModelError);
}

// dm_control's cheetah: its back foot's range [-230°, 50°] holds the pose as written but passes
// half a turn, which a hinge's angle (read within half a turn of its rest) cannot hold
TEST(MjcfReader, AHingeRangePastHalfATurnRestsAtItsMiddle) {
  std::string note;
  const Model turned = parse_mjcf(leg_with_knee("", R"(range="-230 50")"), "leg.xml", {}, &note);
  EXPECT_NE(note.find("1 <joint> whose range passes 180 degrees from the pose as written, its "
                      "rest turned to the range's middle"),
            std::string::npos)
      << note;
  const Model written = parse_mjcf(
      leg_with_knee(R"(axisangle="0 1 0 -90")", R"(range="-230 50" ref="-90")"), "leg_at_-90.xml");
  expect_same_rest(turned, written);
  const Joint& knee = turned.joints[0];
  EXPECT_NEAR(knee.lower, -140 * kPi / 180, 1e-15);
  EXPECT_NEAR(knee.upper, 140 * kPi / 180, 1e-15);
  EXPECT_NEAR(knee.passive[0].spring_ref, 110 * kPi / 180, 1e-15);
  // a range of a whole turn or more is no hinge limit the testbed can hold: refused
  for (const char* range : {R"(range="-200 160")", R"(range="-190 190")"}) {
    try {
      parse_mjcf(leg_with_knee("", range), "leg.xml");
      ADD_FAILURE() << range;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("past 180 degrees"), std::string::npos) << e.what();
    }
  }
}

TEST(MjcfReader, LoadModelReadsXmlFiles) {
  const Model m = load_model(std::string(PUPPET_SOURCE_DIR) + "/models/humanoid.xml");
  EXPECT_EQ(m.name, "humanoid");
  EXPECT_GE(m.segment_count(), 13);
}

// the message of parse_mjcf's refusal, or "loaded"
std::string refusal(const std::string& xml) {
  try {
    parse_mjcf(xml, "t.xml");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "loaded";
}

std::string one_body(const std::string& defaults, const std::string& geom) {
  return "<mujoco model=\"m\">" + defaults + "<worldbody><body name=\"b\"><freejoint/><geom " +
         geom + "/></body></worldbody></mujoco>";
}

// tinyxml2 compares each attribute with all the earlier ones of its element: 200,000 of them on
// one body would take minutes. A linear pass refuses them first, by count.
TEST(MjcfReader, AttributesAreCountedBeforeTheQuadraticParser) {
  std::string attributes;
  for (int k = 0; k < 200000; ++k) attributes += " a" + std::to_string(k) + "=\"1\"";
  EXPECT_EQ(refusal(one_body("", "size=\"0.1\"" + attributes)),
            "t.xml:1: <geom>: more than 64 attributes (an MJCF element has at most 33)");
  // a comment or CDATA holding '=' and '<' counts for nothing; a quoted '>' does not end a tag
  EXPECT_EQ(refusal(one_body("<!-- <a b=1 c=2> -->", "size=\"0.1\" rgba=\"1 1 1 1\"")), "loaded");
}

// A default class is looked up along its parents, never copied: a class 95 deep reads what its
// ancestors set, the nearest one winning, and 8,000 classes with all a geom's attributes cost
// what they hold
TEST(MjcfReader, DefaultClassesInheritByReference) {
  std::string open, close;
  for (int k = 0; k < 95; ++k) {
    open += "<default class=\"c" + std::to_string(k) + "\">";
    if (k == 0) open += "<geom size=\"0.2\" density=\"500\"/>";
    if (k == 50) open += "<geom density=\"2000\"/>";
    close += "</default>";
  }
  const Model deep =
      parse_mjcf(one_body("<default>" + open + close + "</default>", "class=\"c94\""), "deep.xml");
  const double volume = 4.0 / 3.0 * kPi * 0.2 * 0.2 * 0.2;
  EXPECT_NEAR(deep.segments[0].mass, 2000 * volume, 1e-12);  // c50's density, c0's size
  std::string wide = "<default>";
  for (int k = 0; k < 8000; ++k) {
    wide += "<default class=\"w" + std::to_string(k) +
            "\"><geom type=\"sphere\" size=\"0.1\" mass=\"1\" rgba=\"1 1 1 1\" "
            "friction=\"1 0.1 0.1\" contype=\"1\" conaffinity=\"1\" condim=\"3\" "
            "group=\"1\" priority=\"0\" margin=\"0\" gap=\"0\" solmix=\"1\"/></default>";
  }
  wide += "</default>";
  EXPECT_EQ(parse_mjcf(one_body(wide, "class=\"w7999\""), "wide.xml").segments[0].mass, 1.0);
}

// what the subset reads is all it takes: no unknown attribute or element anywhere it reads, no
// second root, no character reference to a control character, booleans spelled true or false
TEST(MjcfReader, TheSubsetIsStrict) {
  EXPECT_EQ(refusal(one_body("", "size=\"0.1\" name=\"a&#0;b\"")),
            "t.xml:1: <geom>: a character reference to a control character (&#0;)");
  EXPECT_EQ(parse_mjcf(one_body("", "size=\"0.1\" name=\"a&#66;c\""), "ok.xml").name, "m");
  EXPECT_EQ(refusal(one_body("", "size=\"0.1\"") + "<mujoco/>"),
            "t.xml:1: <mujoco>: a second root element (a file holds one <mujoco>)");
  EXPECT_EQ(refusal(one_body("<default><geom group=\"1\" gruop=\"2\"/></default>", "size=\"0.1\"")),
            "t.xml:1: <geom>: attribute \"gruop\" is not supported in a default");
  EXPECT_EQ(refusal(one_body("<size nuser_body=\"1\" nuser_bdy=\"1\"/>", "size=\"0.1\"")),
            "t.xml:1: <size>: attribute \"nuser_bdy\" is not supported");
  EXPECT_EQ(refusal(one_body("<compiler autolimits=\"1\"/>", "size=\"0.1\"")),
            "t.xml:1: <compiler>: autolimits must be true or false");
}

// An include that is missing from the model's own folder is missing, not outside, whichever way
// the model's path is written (relative from its folder: "m.xml", whose folder is empty)
TEST(MjcfReader, AMissingIncludeIsMissingWhereverTheModelIsNamedFrom) {
  const std::filesystem::path folder = std::string(PUPPET_SOURCE_DIR) + "/tests/data/bad";
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(folder);
  for (const std::string& name : std::vector<std::string>{"mjcf_include.xml", "./mjcf_include.xml",
                                                          (folder / "mjcf_include.xml").string()}) {
    try {
      load_model(name);
      ADD_FAILURE() << name << " loaded";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("cannot read \"other.xml\": cannot open the file"),
                std::string::npos)
          << name << ": " << e.what();
    }
  }
  // and one outside is still outside, named from its folder too
  try {
    load_model("mjcf_include_outside.xml");
    ADD_FAILURE() << "an include outside the folder loaded";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("is outside the model's folder"), std::string::npos)
        << e.what();
  }
  std::filesystem::current_path(before);
}

// Export is a fixed point: a model written as MJCF, read back and written again gives the same
// bytes (no quaternion normalised twice, no -0), for the models shipped and the MJCF corpus
TEST(MjcfReader, ExportReadExportIsAFixedPoint) {
  std::vector<std::string> files;
  for (const char* folder : {"/models", "/tests/data/mjcf", "/tests/data/mjcf_classes"}) {
    for (const auto& entry :
         std::filesystem::directory_iterator(std::string(PUPPET_SOURCE_DIR) + folder)) {
      const auto extension = entry.path().extension();
      if (extension == ".xml" || extension == ".json") files.push_back(entry.path().string());
    }
  }
  ASSERT_GE(files.size(), 12u);
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const std::string once = write_mjcf(load_model(file));
    const std::string twice = write_mjcf(parse_mjcf(once, "exported.xml"));
    EXPECT_EQ(once, twice);
  }
}

// What the testbed does not model but that leaves the passive dynamics MuJoCo's is skipped with
// one note naming each element kind and its count; read strictly it is refused at the first one
TEST(MjcfReader, WhatIsNotModelledIsSkippedWithANoteOrRefusedStrictly) {
  const std::string path = std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/published_style.xml";
  std::string note;
  const Model model = load_model(path, {}, &note);
  EXPECT_EQ(note, "1 <camera>, 1 <jointpos>, 1 <light>, 2 <motor>, 1 <numeric>");
  EXPECT_EQ(model.name, "planar_walker__published_style_");  // its free text, in the charset
  try {
    load_model(path, ReadOptions{.strict = true});
    ADD_FAILURE() << "read strictly";
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()),
              path +
                  ":28: <motor name=\"right_hip\">: is not modelled by the testbed (skipped "
                  "unless --strict)");
  }
  // a file with nothing to skip has no note
  load_model(std::string(PUPPET_SOURCE_DIR) + "/models/humanoid.xml", {}, &note);
  EXPECT_EQ(note, "");
}

// <option><flag>s that change the dynamics are honoured or named: passive="disable" switches the
// joints' springs and dampers off (not their armature), as in MuJoCo; contact switched off or
// overridden is the scenarios' to decide, so it is named in the note (refused with --strict)
TEST(MjcfReader, FlagsThatChangeTheDynamicsAreHonouredOrNamed) {
  const auto text = [](const std::string& flags) {
    return "<mujoco model=\"m\"><option><flag " + flags +
           "/></option><worldbody><body name=\"a\"><freejoint/><geom type=\"sphere\" "
           "size=\"0.1\"/><body name=\"b\" pos=\"0 0 -0.2\"><joint name=\"h\" "
           "type=\"hinge\" pos=\"0 0 0.1\" stiffness=\"3\" damping=\"1\" "
           "armature=\"0.01\"/><geom type=\"capsule\" size=\"0.05 0.1\"/></body></body>"
           "</worldbody></mujoco>";
  };
  std::string note;
  const Model sprung = parse_mjcf(text("energy=\"enable\""), "m.xml", {}, &note);
  EXPECT_EQ(sprung.joints[0].passive[0].stiffness, 3.0);
  EXPECT_EQ(note, "");
  const Model limp = parse_mjcf(text("passive=\"disable\""), "m.xml", {}, &note);
  EXPECT_EQ(limp.joints[0].passive[0].stiffness, 0.0);
  EXPECT_EQ(limp.joints[0].passive[0].damping, 0.0);
  EXPECT_EQ(limp.joints[0].passive[0].armature, 0.01);
  parse_mjcf(text("contact=\"disable\" override=\"enable\""), "m.xml", {}, &note);
  EXPECT_EQ(note, "1 <flag contact=\"disable\">, 1 <flag override=\"enable\">");
  try {
    parse_mjcf(text("contact=\"disable\""), "m.xml", ReadOptions{.strict = true});
    ADD_FAILURE() << "read strictly";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("flag contact=\"disable\" is not modelled by the "
                                         "testbed: the scenarios decide the ground"),
              std::string::npos)
        << e.what();
  }
}

// The compiler's options on mass, as MuJoCo applies them: a body's mass and moments raised to
// boundmass and boundinertia, moments that break the triangle inequality balanced to their
// mean, then every mass and moment scaled to settotalmass
TEST(MjcfReader, TheCompilersMassOptionsActAsInMujoco) {
  const auto model = [](const std::string& compiler, const std::string& inertial) {
    return parse_mjcf("<mujoco model=\"m\"><compiler " + compiler +
                          "/><worldbody><body name=\"b\"><freejoint/>" + inertial +
                          "<geom size=\"0.1\"/><body name=\"c\" pos=\"0 0 -0.15\"><joint "
                          "type=\"ball\"/><geom size=\"0.05\" mass=\"2\"/></body></body>"
                          "</worldbody></mujoco>",
                      "m.xml");
  };
  const std::string light =
      "<inertial pos=\"0 0 0\" mass=\"1e-5\" diaginertia=\"1e-9 2e-9 2e-9\"/>";
  const Model bounded = model("boundmass=\"0.5\" boundinertia=\"1e-4\"", light);
  EXPECT_EQ(bounded.segments[0].mass, 0.5);
  EXPECT_EQ(bounded.segments[0].inertia, Vector3d(1e-4, 1e-4, 1e-4));
  const std::string flat = "<inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"1 1 3\"/>";
  EXPECT_EQ(model("balanceinertia=\"true\"", flat).segments[0].inertia,
            Vector3d(5.0 / 3.0, 5.0 / 3.0, 5.0 / 3.0));
  const Model scaled = model("settotalmass=\"6\"",
                             "<inertial pos=\"0 0 0\" mass=\"1\" "
                             "diaginertia=\"0.1 0.2 0.25\"/>");
  EXPECT_DOUBLE_EQ(scaled.total_mass, 6.0);
  EXPECT_DOUBLE_EQ(scaled.segments[0].mass, 2.0);  // 1 of 3 kg, times 2
  EXPECT_DOUBLE_EQ(scaled.segments[0].inertia.z(), 0.5);
}

}  // namespace
}  // namespace puppet
