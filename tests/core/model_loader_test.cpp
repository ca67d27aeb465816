#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "puppet/model/mjcf.h"
#include "puppet/model/model.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"
#include "support/source_dir.h"

namespace puppet {
namespace {

const std::string kData = std::string(PUPPET_SOURCE_DIR) + "/tests/data/";

TEST(ModelLoader, DesignExampleLoads) {
  const Model model = load_model(kData + "two_rods.json");
  ASSERT_EQ(model.segment_count(), 2);
  ASSERT_EQ(model.joint_count(), 1);
  EXPECT_DOUBLE_EQ(model.total_mass, 2.5);
  EXPECT_EQ(model.segments[0].inertia, Vector3d(0.08, 0.08, 0.0001));  // as given
  // the box's default inertia is the solid box's
  EXPECT_NEAR(model.segments[1].inertia.x(), 1.0 / 12.0 * (0.04 * 0.04 + 0.6 * 0.6), 1e-15);
  // local anchors reproduce the world anchor at rest
  const Joint& elbow = model.joints[0];
  EXPECT_NEAR(
      (model.segments[0].rest_position + elbow.anchor_in_parent - Vector3d(0, 0, 1.2)).norm(), 0,
      1e-15);
  EXPECT_NEAR(
      (model.segments[1].rest_position + elbow.anchor_in_child - Vector3d(0, 0, 1.2)).norm(), 0,
      1e-15);
  EXPECT_NEAR(elbow.swing_x, 60 * M_PI / 180, 1e-15);
  EXPECT_NEAR(elbow.twist, 30 * M_PI / 180, 1e-15);
}

TEST(ModelLoader, PinocchioIsTheSeedsFigure) {
  const Model model = load_model(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json");
  EXPECT_EQ(model.segment_count(), 14);
  EXPECT_EQ(model.joint_count(), 13);
  EXPECT_NEAR(model.total_mass, 69.6, 1e-9);
  EXPECT_GT(model.rest_height, 1.6);
  EXPECT_LT(model.rest_height, 1.8);
  EXPECT_EQ(model.segments[0].name, "pelvis");
  // parent before child, joint j places segment j + 1
  for (int i = 1; i < model.segment_count(); ++i) {
    EXPECT_LT(model.segments[i].parent, i);
    EXPECT_EQ(model.joints[i - 1].child, i);
  }
  // q_rel is the identity at rest for every joint
  for (const Joint& j : model.joints) {
    const Quaterniond q_rel = joint_relative_rotation(j, model.segments[j.parent].rest_orientation,
                                                      model.segments[j.child].rest_orientation);
    EXPECT_NEAR(angle_between(q_rel, Quaterniond::Identity()), 0.0, 1e-12) << j.name;
  }
}

TEST(ModelLoader, SingleSegmentWithoutJoints) {
  const Model model = parse_model(
      R"({"name":"one","segments":[{"name":"s","mass":2,"position":[0,0,1],"shape":{"type":"sphere","radius":0.1}}]})",
      "one.json");
  EXPECT_EQ(model.segment_count(), 1);
  EXPECT_EQ(model.joint_count(), 0);
  EXPECT_NEAR(model.segments[0].inertia.x(), 0.4 * 2 * 0.01, 1e-15);
}

TEST(ModelLoader, OrdersSegmentsParentFirst) {
  // the child is listed before its parent in the file
  const Model model = parse_model(R"({"name":"rev","segments":[
      {"name":"low","mass":1,"position":[0,0,0],"shape":{"type":"sphere","radius":0.1}},
      {"name":"top","mass":1,"position":[0,0,0.2],"shape":{"type":"sphere","radius":0.1}}],
    "joints":[{"name":"j","parent":"top","child":"low","anchor":[0,0,0.1],"type":"fixed"}]})",
                                  "rev.json");
  EXPECT_EQ(model.segments[0].name, "top");
  EXPECT_EQ(model.segments[1].name, "low");
  EXPECT_EQ(model.joints[0].parent, 0);
}

TEST(ModelLoader, Chain) {
  const Model model = load_model("chain:6");
  EXPECT_EQ(model.segment_count(), 6);
  EXPECT_EQ(model.joint_count(), 5);
  EXPECT_NEAR(model.rest_height, 1.5, 1e-12);
  EXPECT_THROW(load_model("chain:0"), ModelError);
  EXPECT_THROW(load_model("chain:x"), ModelError);
}

TEST(ModelLoader, MissingFileNamesTheFile) {
  try {
    load_model("/nonexistent/model.json");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/nonexistent/model.json: cannot open the file (No such file or directory)");
  }
}

// A segment of several shapes in JSON: the mass split by volume (uniform density), the centre
// of mass and the principal moments by the parallel-axis theorem, checked against the sum
// written out by hand for two spheres on a rod along x (centred, so the frame keeps its axes)
TEST(ModelLoader, ShapesComposeAtUniformDensity) {
  const Model m = parse_model(R"({"name": "dumbbell", "segments": [{"name": "bell", "mass": 3.0,
      "shapes": [{"type": "sphere", "radius": 0.08, "position": [-0.25, 0, 1]},
                 {"type": "cylinder", "radius": 0.02, "half_length": 0.2, "position": [0, 0, 1],
                  "orientation": [0.7071067811865476, 0, 0.7071067811865476, 0]},
                 {"type": "sphere", "radius": 0.08, "position": [0.25, 0, 1]}]}]})",
                              "dumbbell.json");
  const Segment& s = m.segments[0];
  const double ball = 4.0 / 3.0 * M_PI * std::pow(0.08, 3), rod = M_PI * 0.02 * 0.02 * 0.4;
  const double m_ball = 3.0 * ball / (2 * ball + rod), m_rod = 3.0 * rod / (2 * ball + rod);
  EXPECT_NEAR((s.rest_position - Vector3d(0, 0, 1)).norm(), 0.0, 1e-15);
  const double own = 0.4 * m_ball * 0.08 * 0.08;
  const double along = 2 * own + 0.5 * m_rod * 0.02 * 0.02;
  const double across =
      2 * (own + m_ball * 0.25 * 0.25) + m_rod * (3 * 0.02 * 0.02 + 0.4 * 0.4) / 12;
  // the moments in the segment's axes, whichever order its principal frame takes them in
  const Matrix3d r = s.rest_orientation.toRotationMatrix();
  const Matrix3d world = r * s.inertia.asDiagonal() * r.transpose();
  EXPECT_NEAR(world(0, 0), along, 1e-12);
  EXPECT_NEAR(world(1, 1), across, 1e-12);
  EXPECT_NEAR(world(2, 2), across, 1e-12);
  EXPECT_NEAR(s.mass, 3.0, 1e-15);
  // each shape where it was put, seen from the segment
  for (int k : {0, 2}) {
    EXPECT_NEAR((s.rest_position + s.rest_orientation * s.shapes[k].position -
                 Vector3d(k == 0 ? -0.25 : 0.25, 0, 1))
                    .norm(),
                0.0, 1e-15);
  }
}

// every file of the malformed corpus fails with one line: "<file>: <element>: <problem>"
TEST(ModelLoader, MalformedCorpus) {
  std::ifstream manifest(kData + "bad/expected.tsv");
  ASSERT_TRUE(manifest);
  std::string line;
  int cases = 0;
  while (std::getline(manifest, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto tab = line.find('\t');
    const std::string file = kData + "bad/" + line.substr(0, tab);
    const bool mjcf = file.size() > 4 && file.compare(file.size() - 4, 4, ".xml") == 0;
    // an error in an included file names that file (under bad/parts/)
    const std::string message_start = line.substr(tab + 1);
    const std::string expected = message_start.rfind("parts/", 0) == 0
                                     ? kData + "bad/" + message_start
                                     : file + (mjcf ? ":" : ": ") + message_start;
    ++cases;
    try {
      load_model(file);
      ADD_FAILURE() << file << " loaded";
    } catch (const ModelError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(expected, 0), 0u)
          << "got:      " << message << "\nexpected: " << expected;
      // one bounded line of printable ASCII, whatever the file holds (a 100 kB name, newlines)
      EXPECT_LE(message.size(), 400u) << file;
      EXPECT_TRUE(std::all_of(message.begin(), message.end(), [](char c) {
        return c >= 0x20 && c < 0x7f;
      })) << message;
    }
  }
  EXPECT_GE(cases, 78 + 74);  // JSON, and MJCF
  // and every file in the folder is listed
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kData + "bad")) {
    files += entry.path().extension() == ".json" || entry.path().extension() == ".xml";
  }
  EXPECT_EQ(files, cases);
}

// a model is read only from a regular file of at most 16 MiB: a FIFO would wait for a writer,
// /dev/zero never ends, and neither may hang or exhaust memory
TEST(ModelLoader, ReadsOnlyBoundedRegularFiles) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("puppet-loader-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  auto message_of = [](const std::string& path) {
    try {
      load_model(path);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  const std::string fifo = (folder / "model.json").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(message_of(fifo), fifo + ": is not a regular file (a FIFO, a device or a socket)");
  EXPECT_EQ(message_of("/dev/zero"),
            "/dev/zero: is not a regular file (a FIFO, a device or a socket)");
  EXPECT_EQ(message_of(folder.string()), folder.string() + ": is a folder, not a file");
  const std::string big = (folder / "big.json").string();
  { std::ofstream(big) << "{}"; }
  std::filesystem::resize_file(big, (size_t{16} << 20) + 1);  // sparse: no 16 MiB written
  EXPECT_EQ(message_of(big), big + ": is 16777217 bytes (at most 16777216 are read)");
  std::filesystem::remove_all(folder);
}

// a rotation given with a large but finite norm is normalised, not turned to zero
TEST(ModelLoader, NormalisesLargeQuaternionsOrRefusesThem) {
  const std::string text = R"({"name": "one", "segments": [{"name": "a", "mass": 1,
      "position": [0, 0, 1], "orientation": [1e8, 0, 0, 1e8],
      "shape": {"type": "sphere", "radius": 0.1}}]})";
  const Model model = parse_model(text, "large.json");
  EXPECT_NEAR(model.segments[0].rest_orientation.angularDistance(
                  Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitZ()))),
              0.0, 1e-12);
}

// A root the world holds, given in JSON ("root": hold, anchor, dofs), reads as the same root
// written as MJCF's root-body joints does: each hold's anchor (world and in the root's frame),
// axes, range, springs and names, on a box turned 10° about z so that the root's frame is not
// the world's (MJCF: its geom turned in a body that is not, so that the joints' pos and axis are
// in world as JSON's are)
TEST(ModelLoader, ARootHeldByTheWorldReadsAsMjcfSaysIt) {
  struct Form {
    const char* json;  // the "root" object
    const char* mjcf;  // the root body's joints
  };
  const Form forms[] = {
      {R"({"hold":"weld"})", ""},
      {R"({"hold":"hinge","anchor":[0.05,0,1.1],"dofs":[{"name":"pivot","axis":[0.2,1,0],
          "range_deg":[-30,60],"stiffness":2,"damping":0.1,"springref_deg":15,"armature":0.03}]})",
       R"(<joint name="pivot" type="hinge" pos="0.05 0 0.1" axis="0.2 1 0" range="-30 60"
          stiffness="2" damping="0.1" springref="15" armature="0.03"/>)"},
      {R"({"hold":"slide","anchor":[0,0,1],"dofs":[{"name":"rail","axis":[1,0,0],
          "range_m":[-2,2],"stiffness":1.5,"damping":0.3,"springref_m":0.1}]})",
       R"(<joint name="rail" type="slide" axis="1 0 0" range="-2 2" stiffness="1.5"
          damping="0.3" springref="0.1"/>)"},
      {R"({"hold":"ball","anchor":[0,0.1,1],"name":"b"})",
       R"(<joint name="b" type="ball" pos="0 0.1 0"/>)"},
      {R"({"hold":"planar","anchor":[0.03,0,1.05],"dofs":[{"name":"x","axis":[1,0,0]},
          {"name":"z","axis":[0,0,1],"stiffness":4},{"name":"y","axis":[0,1,0],"damping":0.5}]})",
       R"(<joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"
          stiffness="4"/><joint name="y" type="hinge" axis="0 1 0" pos="0.03 0 0.05"
          damping="0.5"/>)"},
  };
  // the box turned 10° about z: w, z of the quaternion
  const double w = std::cos(5.0 * M_PI / 180.0), z = std::sin(5.0 * M_PI / 180.0);
  for (const Form& form : forms) {
    SCOPED_TRACE(form.json);
    const Model from_json = parse_model(
        std::string(R"({"name":"held","segments":[{"name":"box","mass":2,"position":[0,0,1],
        "orientation":[)") +
            std::to_string(w) + ",0,0," + std::to_string(z) +
            R"(],"shape":{"type":"box","half_extents":[0.2,0.12,0.08]}}],"root":)" + form.json +
            "}",
        "held.json");
    const std::string turn = std::to_string(w) + " 0 0 " + std::to_string(z);
    const Model from_mjcf =
        parse_mjcf(std::string(R"(<mujoco><compiler angle="degree" autolimits="true"/><worldbody>
        <body name="box" pos="0 0 1">)") +
                       form.mjcf + R"(<geom type="box" size="0.2 0.12 0.08" mass="2" quat=")" +
                       turn + R"("/></body></worldbody></mujoco>)",
                   "held.xml");
    const RootJoint &a = from_json.root, &b = from_mjcf.root;
    EXPECT_EQ(a.hold, b.hold);
    EXPECT_EQ(a.names, b.names);
    EXPECT_LT((a.anchor_world - b.anchor_world).norm(), 1e-12);
    // each anchor in its root's frame is the world one (the two may pick the box's principal
    // axes in another order)
    for (const Model* m : {&from_json, &from_mjcf}) {
      const Segment& box = m->segments[0];
      EXPECT_LT(
          (box.rest_position + box.rest_orientation * m->root.anchor_in_root - m->root.anchor_world)
              .norm(),
          1e-12);
    }
    // the axes of its degrees of freedom (a weld and a ball have none), and a range if any
    const int dofs = root_coordinate_count(a.hold);
    for (int k = 0; k < dofs; ++k) EXPECT_LT((a.axes[k] - b.axes[k]).norm(), 1e-12) << k;
    EXPECT_EQ(a.limited, b.limited);
    if (a.limited) {
      EXPECT_NEAR(a.lower, b.lower, 1e-12);
      EXPECT_NEAR(a.upper, b.upper, 1e-12);
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(a.passive[k].stiffness, b.passive[k].stiffness, 1e-12) << k;
      EXPECT_NEAR(a.passive[k].damping, b.passive[k].damping, 1e-12) << k;
      EXPECT_NEAR(a.passive[k].spring_ref, b.passive[k].spring_ref, 1e-12) << k;
      EXPECT_NEAR(a.passive[k].armature, b.passive[k].armature, 1e-12) << k;
    }
  }
}

// A slide below the root in JSON ("type": "slide", its "axis", "range_m" and "springref_m") is
// the model MJCF's slide gives: the same direction, range (m), spring and anchor; without a range
// it is not limited (infinite at both ends)
TEST(ModelLoader, ASlideReadsAsMjcfSaysIt) {
  const std::string segments = R"("segments":[
      {"name":"base","mass":4,"position":[0,0,1],"shape":{"type":"box","half_extents":[0.1,0.1,0.1]}},
      {"name":"carriage","mass":1,"position":[0,0,0.8],
       "shape":{"type":"box","half_extents":[0.05,0.05,0.05]}}])";
  for (const bool limited : {true, false}) {
    SCOPED_TRACE(limited ? "limited" : "not limited");
    const Model from_json = parse_model(
        R"({"name":"slid",)" + segments +
            R"(,"joints":[{"name":"rail","parent":"base","child":"carriage","type":"slide",
            "anchor":[0,0,0.88],"axis":[1,0,1],"stiffness":20,"damping":0.5,"springref_m":0.05)" +
            (limited ? R"(,"range_m":[-0.3,0.1])" : "") + "}]}",
        "slid.json");
    const Model from_mjcf = parse_mjcf(
        std::string(R"(<mujoco><worldbody><body name="base" pos="0 0 1">
        <geom type="box" size="0.1 0.1 0.1" mass="4"/><body name="carriage" pos="0 0 -0.2">
        <joint name="rail" type="slide" pos="0 0 0.08" axis="1 0 1" stiffness="20" damping="0.5"
        springref="0.05" )") +
            (limited ? R"(limited="true" range="-0.3 0.1")" : "") +
            R"(/><geom type="box" size="0.05 0.05 0.05" mass="1"/></body></body></worldbody>
        </mujoco>)",
        "slid.xml");
    ASSERT_EQ(from_json.joints.size(), 1u);
    const Joint &a = from_json.joints[0], &b = from_mjcf.joints[0];
    EXPECT_EQ(a.type, JointType::kSlide);
    EXPECT_EQ(b.type, JointType::kSlide);
    EXPECT_LT((a.frame_world * a.hinge_axis - Vector3d(1, 0, 1).normalized()).norm(), 1e-15);
    EXPECT_LT((b.frame_world * b.hinge_axis - Vector3d(1, 0, 1).normalized()).norm(), 1e-15);
    EXPECT_LT((a.anchor_world - b.anchor_world).norm(), 1e-15);
    EXPECT_EQ(a.lower, limited ? -0.3 : -INFINITY);
    EXPECT_EQ(a.upper, limited ? 0.1 : INFINITY);
    EXPECT_EQ(b.lower, a.lower);
    EXPECT_EQ(b.upper, a.upper);
    EXPECT_EQ(a.passive[0], b.passive[0]);
    EXPECT_EQ(a.passive[0].spring_ref, 0.05);
  }
}

}  // namespace
}  // namespace puppet
