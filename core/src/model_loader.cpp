// Model files (docs/design.md, "The model"): JSON in world coordinates at rest. Everything is
// validated here, once; a bad file raises one ModelError naming the file, the element and the
// problem, and nothing half-built escapes.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "json_element.h"
#include "model_builder.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/file.h"
#include "puppet/model/mjcf.h"
#include "puppet/model/model.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/rotation.h"

namespace puppet {
namespace {

using detail::Element;
using nlohmann::json;

constexpr double kDegToRad = M_PI / 180.0;

// the fields that place one of a segment's "shapes" (an initializer list at namespace scope: its
// array lives as long as the program)
constexpr std::initializer_list<const char*> kPlacedFields = {"position", "orientation"};
constexpr std::initializer_list<const char*> kNoFields = {};

// a shape's type and size; `placed`: one of a segment's "shapes", which also gives its centre
// ("position") and axes ("orientation") in world at rest
Shape read_shape(const Element& e, bool placed) {
  e.require_object();
  Shape shape;
  const std::string type = e.string("type");
  const std::initializer_list<const char*> pose = placed ? kPlacedFields : kNoFields;
  if (type == "capsule" || type == "cylinder") {
    e.reject_unknown({"type", "radius", "half_length"}, pose);
    shape.type = type == "capsule" ? ShapeType::kCapsule : ShapeType::kCylinder;
    shape.radius = e.positive("radius");
    shape.half_length = e.positive("half_length");
  } else if (type == "sphere") {
    e.reject_unknown({"type", "radius"}, pose);
    shape.type = ShapeType::kSphere;
    shape.radius = e.positive("radius");
  } else if (type == "box" || type == "ellipsoid") {
    e.reject_unknown({"type", "half_extents"}, pose);
    shape.type = type == "box" ? ShapeType::kBox : ShapeType::kEllipsoid;
    shape.half_extents = e.vector<3>("half_extents");
    if ((shape.half_extents.array() <= 0.0).any()) {
      e.fail("field \"half_extents\" must be positive");
    }
  } else {
    e.fail("unknown shape type " + detail::shown(type) +
           " (expected capsule, box, cylinder, sphere or ellipsoid)");
  }
  if (placed) {
    shape.position = e.vector<3>("position");
    if (e.has("orientation")) shape.orientation = e.quaternion("orientation");
  }
  return shape;
}

constexpr size_t kMaxShapes = 64;  // per segment (MuJoCo's humanoid100 has 22 on one body)

// A segment: its mass, and either one "shape" centred on its "position" (its centre of mass)
// with its "orientation", or several "shapes" placed in world, whose composition (uniform
// density, MuJoCo's reading of a body's geoms) gives the centre of mass and principal frame. An
// "inertia" (principal moments) replaces the solid's; with "shapes" it needs the segment's
// "position" and "orientation", the frame it is diagonal in.
Segment read_segment(const Element& e) {
  e.require_object();
  e.reject_unknown({"name", "mass", "position", "orientation", "shape", "shapes", "inertia"});
  Segment s;
  s.mass = e.positive("mass");
  if (e.has("shape") == e.has("shapes")) e.fail("give either \"shape\" or \"shapes\"");
  if (e.has("shape")) {
    s.rest_position = e.vector<3>("position");
    if (e.has("orientation")) s.rest_orientation = e.quaternion("orientation");
    s.shapes.push_back(read_shape(e.child("shape", "shape"), false));
    s.inertia = solid_inertia(s.shapes[0], s.mass);
  } else {
    const json& list = e.field("shapes");
    if (!list.is_array() || list.empty() || list.size() > kMaxShapes) {
      e.fail("field \"shapes\" must be an array of 1 to " + std::to_string(kMaxShapes) + " shapes");
    }
    std::vector<Shape> solids;
    double volume = 0.0;
    for (size_t k = 0; k < list.size(); ++k) {
      solids.push_back(read_shape(e.item(list[k], "shape #" + std::to_string(k)), true));
      volume += shape_volume(solids.back());
    }
    std::vector<double> masses;
    for (const Shape& solid : solids) masses.push_back(s.mass * shape_volume(solid) / volume);
    if (e.has("inertia")) {
      // the shapes stay where they are; the segment frame is the one given
      s.rest_position = e.vector<3>("position");
      if (!e.has("orientation")) e.fail("\"shapes\" with \"inertia\" need \"orientation\"");
      s.rest_orientation = e.quaternion("orientation");
      for (Shape& solid : solids) {
        solid.position = s.rest_orientation.conjugate() * (solid.position - s.rest_position);
        solid.orientation = (s.rest_orientation.conjugate() * solid.orientation).normalized();
      }
      s.shapes = solids;
    } else {
      if (e.has("position") || e.has("orientation")) {
        e.fail(
            "with \"shapes\" the position and orientation come from the shapes (give them "
            "only with \"inertia\")");
      }
      detail::place_solids(solids, masses, Vector3d::Zero(), Quaterniond::Identity(), s);
    }
  }
  if (e.has("inertia")) {
    s.inertia = e.vector<3>("inertia");
    if ((s.inertia.array() <= 0.0).any()) e.fail("field \"inertia\" must be positive");
  }
  derive_mass_terms(s);
  return s;
}

// a joint's optional spring, damper and armature (MuJoCo's stiffness, damping and armature; a
// hinge's springref), the same on each of its angles
void read_springs(const Element& e, Joint& j) {
  JointPassive spring;
  if (e.has("stiffness")) spring.stiffness = e.non_negative("stiffness");
  if (e.has("damping")) spring.damping = e.non_negative("damping");
  if (e.has("armature")) spring.armature = e.non_negative("armature");
  if (j.type == JointType::kSlide && e.has("springref_m")) {
    spring.spring_ref = e.number("springref_m");
    if (std::abs(spring.spring_ref) > detail::kMaxCoordinate) {
      e.fail("field \"springref_m\" must lie within " + Element::fmt(detail::kMaxCoordinate) +
             " m");
    }
  } else if (e.has("springref_deg")) {
    const double ref = e.number("springref_deg");
    if (std::abs(ref) > 180.0) e.fail("field \"springref_deg\" must lie in [-180, 180]");
    spring.spring_ref = ref * kDegToRad;
  }
  j.passive.fill(spring);
}

detail::RawJoint read_joint(const Element& e) {
  e.require_object();
  detail::RawJoint raw;
  Joint& j = raw.joint;
  const std::string type = e.string("type");
  if (type == "ball" && e.has("box_deg")) {
    // a box of intrinsic Euler angles: {"order": "xyz", "lower": [..], "upper": [..]} (deg)
    e.reject_unknown({"name", "parent", "child", "anchor", "type", "frame", "box_deg", "stiffness",
                      "damping", "armature"});
    j.type = JointType::kBall;
    j.ball_limit = BallLimit::kEulerBox;
    j.swing_x = j.swing_y = j.twist = M_PI;
    const Element box = e.child("box_deg", "box_deg");
    box.require_object();
    box.reject_unknown({"order", "lower", "upper"});
    if (!parse_euler_order(box.string("order"), &j.box_order)) {
      box.fail("field \"order\" must be three different axes of x, y, z (such as \"xyz\")");
    }
    const Vector3d lower = box.vector<3>("lower"), upper = box.vector<3>("upper");
    for (int k = 0; k < 3; ++k) {
      if (lower[k] > 0.0 || upper[k] < 0.0) {
        box.fail("angle " + std::to_string(k) + "'s range [" + Element::fmt(lower[k]) + ", " +
                 Element::fmt(upper[k]) + "] must contain 0, the rest angle");
      }
      const double bound = k == 1 ? kMaxBoxMiddle / kDegToRad : 180.0;
      if (lower[k] < -bound || upper[k] > bound) {
        box.fail("angle " + std::to_string(k) + "'s range must lie in [-" + Element::fmt(bound) +
                 ", " + Element::fmt(bound) + "]" +
                 (k == 1 ? " (the middle angle: Euler angles lose an axis at 90 degrees)" : ""));
      }
    }
    j.box_lower = lower * kDegToRad;
    j.box_upper = upper * kDegToRad;
  } else if (type == "ball") {
    e.reject_unknown({"name", "parent", "child", "anchor", "type", "frame", "swing_deg",
                      "twist_deg", "box_deg", "stiffness", "damping", "armature"});
    j.type = JointType::kBall;
    const Eigen::Vector2d swing = e.vector<2>("swing_deg");
    if ((swing.array() < 0.0).any()) e.fail("field \"swing_deg\" must not be negative");
    if ((swing.array() > 180.0).any()) e.fail("field \"swing_deg\" must be at most 180");
    j.swing_x = swing.x() * kDegToRad;
    j.swing_y = swing.y() * kDegToRad;
    const double twist = e.non_negative("twist_deg");
    if (twist > 180.0) e.fail("field \"twist_deg\" must be at most 180");
    j.twist = twist * kDegToRad;
  } else if (type == "hinge") {
    e.reject_unknown({"name", "parent", "child", "anchor", "type", "frame", "axis", "range_deg",
                      "stiffness", "damping", "springref_deg", "armature"});
    j.type = JointType::kHinge;
    raw.hinge_axis_world = e.direction<3>("axis");
    const Eigen::Vector2d range = e.vector<2>("range_deg");
    if (range.x() > range.y()) {
      e.fail("field \"range_deg\" has lo > hi (" + Element::fmt(range.x()) + " > " +
             Element::fmt(range.y()) + ")");
    }
    if (range.x() > 0.0 || range.y() < 0.0) {
      e.fail("field \"range_deg\" must contain the rest angle 0");
    }
    if (range.x() < -180.0 || range.y() > 180.0)
      e.fail("field \"range_deg\" must lie in [-180, 180]");
    j.lower = range.x() * kDegToRad;
    j.upper = range.y() * kDegToRad;
  } else if (type == "slide") {
    e.reject_unknown({"name", "parent", "child", "anchor", "type", "frame", "axis", "range_m",
                      "stiffness", "damping", "springref_m", "armature"});
    j.type = JointType::kSlide;
    raw.hinge_axis_world = e.direction<3>("axis");
    j.lower = -INFINITY;
    j.upper = INFINITY;
    if (e.has("range_m")) {
      const Eigen::Vector2d range = e.vector<2>("range_m");
      if (range.x() >= range.y()) {
        e.fail("field \"range_m\" must have lo < hi (" + Element::fmt(range.x()) +
               " >= " + Element::fmt(range.y()) + ")");
      }
      if (range.x() > 0.0 || range.y() < 0.0) e.fail("field \"range_m\" must contain the rest 0");
      if (range.x() < -detail::kMaxCoordinate || range.y() > detail::kMaxCoordinate) {
        e.fail("field \"range_m\" must lie within " + Element::fmt(detail::kMaxCoordinate) +
               " m of 0");
      }
      j.lower = range.x();
      j.upper = range.y();
    }
  } else if (type == "fixed") {
    e.reject_unknown({"name", "parent", "child", "anchor", "type", "frame"});
    j.type = JointType::kFixed;
  } else {
    e.fail("unknown joint type " + detail::shown(type) + " (expected ball, hinge, slide or fixed)");
  }
  if (j.type != JointType::kFixed) read_springs(e, j);
  derive_limit_terms(j);
  raw.parent_name = e.name("parent");
  raw.child_name = e.name("child");
  j.anchor_world = e.vector<3>("anchor");
  if (e.has("frame")) j.frame_world = e.quaternion("frame");
  return raw;
}

// The world's hold on the root (model.h, RootJoint): {"hold": "weld" | "hinge" | "slide" | "ball" |
// "planar", "anchor": [x, y, z] (world, rest; none for a weld, whose point is the root's centre),
// a weld's or a ball's optional "name" (the root segment's by default), "dofs": [...]} with one dof
// for a hinge or a slide and three for a planar root (two slides, then the hinge about their
// plane's normal), each {"name", "axis", a hinge's "range_deg" or a slide's "range_m" (a planar
// root's are unlimited), "stiffness", "damping", a hinge's "springref_deg" or a slide's
// "springref_m", "armature"}, as MJCF's root joints say. The anchor in the root's frame is set once
// the root is placed.
RootJoint read_root(const Element& e, const std::string& root_name) {
  e.require_object();
  e.reject_unknown({"hold", "anchor", "dofs", "name"});
  RootJoint root;
  const std::string hold = e.string("hold");
  const RootHold holds[] = {RootHold::kWeld, RootHold::kHinge, RootHold::kSlide, RootHold::kBall,
                            RootHold::kPlanar};
  const auto found = std::find_if(std::begin(holds), std::end(holds),
                                  [&](RootHold h) { return hold == root_hold_name(h); });
  if (found == std::end(holds)) {
    e.fail("field \"hold\" must be weld, hinge, slide, ball or planar (got " + detail::shown(hold) +
           "; a free root gives no \"root\")");
  }
  root.hold = *found;
  const int slides = root_slide_count(root.hold), dofs = root_coordinate_count(root.hold);
  if (root.hold == RootHold::kWeld) {
    if (e.has("anchor")) e.fail("a weld holds the root at its centre: it gives no \"anchor\"");
  } else {
    root.anchor_world = e.vector<3>("anchor");
  }
  if (dofs == 0) {
    if (e.has("dofs")) e.fail(std::string("a ") + hold + " root has no \"dofs\"");
    root.names[0] = e.has("name") ? e.name("name") : root_name;
    return root;
  }
  if (e.has("name")) e.fail("a " + hold + " root names each of its \"dofs\"");
  const json& list = e.field("dofs");
  if (!list.is_array() || static_cast<int>(list.size()) != dofs) {
    e.fail("field \"dofs\" must be an array of " + std::to_string(dofs) + " (" +
           (dofs == 1 ? std::string("the ") + hold + "'s" : "two slides, then the hinge") + ")");
  }
  for (int k = 0; k < dofs; ++k) {
    const bool slide = k < slides;
    const Element d = e.item(list[static_cast<size_t>(k)], "dof #" + std::to_string(k));
    d.require_object();
    const char* range = slide ? "range_m" : "range_deg";
    const char* ref = slide ? "springref_m" : "springref_deg";
    d.reject_unknown({"name", "axis", range, "stiffness", "damping", ref, "armature"});
    const size_t i = static_cast<size_t>(k);
    root.names[i] = d.name("name");
    root.axes[i] = d.direction<3>("axis");
    JointPassive& spring = root.passive[i];
    if (d.has("stiffness")) spring.stiffness = d.non_negative("stiffness");
    if (d.has("damping")) spring.damping = d.non_negative("damping");
    if (d.has("armature")) spring.armature = d.non_negative("armature");
    const double unit = slide ? 1.0 : kDegToRad;
    if (d.has(ref)) spring.spring_ref = d.number(ref) * unit;
    if (!d.has(range)) continue;
    if (dofs == 3) d.fail("a planar root's dofs are unlimited (as dm_control's are)");
    const Eigen::Vector2d r = d.vector<2>(range);
    if (r.x() > r.y()) d.fail(std::string("field \"") + range + "\" has lo > hi");
    if (r.x() > 0.0 || r.y() < 0.0) {
      d.fail(std::string("field \"") + range + "\" must contain 0, the rest");
    }
    if (!slide && (r.x() < -180.0 || r.y() > 180.0)) {
      d.fail("field \"range_deg\" must lie in [-180, 180]");
    }
    root.limited = true;
    root.lower = r.x() * unit;
    root.upper = r.y() * unit;
  }
  for (int a = 0; a < dofs; ++a) {
    for (int b = a + 1; b < dofs; ++b) {
      if (std::abs(root.axes[static_cast<size_t>(a)].dot(root.axes[static_cast<size_t>(b)])) >
          1e-6) {
        e.fail("a planar root's slides and hinge must have orthogonal axes");
      }
    }
  }
  return root;
}

// A duplicate key is refused: JSON leaves it open, nlohmann keeps the last value silently. A
// SAX pass of its own (linear: the callback parser rescans an array at each object's end),
// before the document is built; syntax errors are left to the parse that builds it.
void refuse_duplicate_keys(const std::string& text, const std::string& source) {
  struct Keys : nlohmann::json_sax<json> {
    std::vector<std::set<std::string>> open;  // the keys of each object being read
    const std::string* source = nullptr;
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override {
      open.emplace_back();
      return true;
    }
    bool key(string_t& key) override {
      if (!open.back().insert(key).second) {
        throw ModelError(*source + ": malformed JSON: the key " + detail::shown(key) +
                         " appears twice in one object");
      }
      return true;
    }
    bool end_object() override {
      open.pop_back();
      return true;
    }
    bool start_array(std::size_t) override { return true; }
    bool end_array() override { return true; }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
      return false;
    }
  } keys;
  keys.source = &source;
  json::sax_parse(text, &keys);
}

Model build(const json& root_json, const std::string& source) {
  Element root(root_json, source, "model");
  root.require_object();
  root.reject_unknown({"name", "segments", "joints", "gravity", "root"});
  const std::string name = root.name("name");

  const json& segments_json = root.field("segments");
  if (!segments_json.is_array()) root.fail("field \"segments\" must be an array");
  if (segments_json.empty()) root.fail("field \"segments\" must not be empty");
  std::vector<Segment> segments;
  for (size_t i = 0; i < segments_json.size(); ++i) {
    Element e(segments_json[i], source, "segment #" + std::to_string(i));
    e.require_object();
    const std::string segment_name = e.name("name");
    Segment s = read_segment(Element(segments_json[i], source, "segment \"" + segment_name + "\""));
    s.name = segment_name;
    segments.push_back(std::move(s));
  }

  std::vector<detail::RawJoint> joints;
  if (root.has("joints")) {
    const json& joints_json = root.field("joints");
    if (!joints_json.is_array()) root.fail("field \"joints\" must be an array");
    for (size_t i = 0; i < joints_json.size(); ++i) {
      Element e(joints_json[i], source, "joint #" + std::to_string(i));
      e.require_object();
      const std::string joint_name = e.name("name");
      detail::RawJoint raw =
          read_joint(Element(joints_json[i], source, "joint \"" + joint_name + "\""));
      raw.joint.name = joint_name;
      joints.push_back(std::move(raw));
    }
  }
  // by name: assemble consumes the segments and joints
  std::vector<std::string> segment_names, joint_names;
  for (const Segment& seg : segments) segment_names.push_back(seg.name);
  for (const detail::RawJoint& raw : joints) joint_names.push_back(raw.joint.name);
  auto locate = [&](detail::Part part, int index) {
    switch (part) {
      case detail::Part::kSegment:
        return source + ": segment \"" + segment_names[index] + "\"";
      case detail::Part::kJoint:
        return source + ": joint \"" + joint_names[index] + "\"";
      case detail::Part::kModel:
        break;
    }
    return source + ": model";
  };
  Model model = detail::assemble(name, std::move(segments), std::move(joints), locate);
  if (root.has("root")) {
    const Segment& base = model.segments[0];
    model.root = read_root(root.child("root", "root"), base.name);
    if (model.root.hold == RootHold::kWeld) model.root.anchor_world = base.rest_position;
    model.root.anchor_in_root =
        base.rest_orientation.conjugate() * (model.root.anchor_world - base.rest_position);
  }
  if (root.has("gravity")) {
    model.gravity = root.vector<3>("gravity");
    if (std::string problem = detail::gravity_problem(model.gravity); !problem.empty()) {
      root.fail("field \"gravity\": " + problem);
    }
  }
  return model;
}

}  // namespace

int Model::find_segment(const std::string& segment_name) const {
  for (int i = 0; i < segment_count(); ++i) {
    if (segments[i].name == segment_name) return i;
  }
  return -1;
}

Model parse_model(const std::string& json_text, const std::string& source) {
  if (std::string problem = detail::text_problem(json_text); !problem.empty()) {
    throw ModelError(source + ": " + problem);
  }
  json document;
  try {
    refuse_duplicate_keys(json_text, source);
    document = json::parse(json_text);
  } catch (const json::exception& error) {
    // nlohmann's message begins "[json.exception.parse_error.101] parse error at line…"
    std::string what = error.what();
    const auto bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    // it quotes the last token read, which may be a whole (100 kB) string
    throw ModelError(source + ": malformed JSON: " + detail::printable(what, 200));
  }
  return build(document, source);
}

Model load_model_file(const std::string& path_or_builtin, const ReadOptions& options,
                      std::string* note) {
  if (note) note->clear();
  const std::string chain_prefix = "chain:";
  if (path_or_builtin.rfind(chain_prefix, 0) == 0) {
    const std::string count = path_or_builtin.substr(chain_prefix.size());
    size_t used = 0;
    int n = 0;
    try {
      n = std::stoi(count, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != count.size() || count.empty() || n < 1 || n > 100000) {
      throw ModelError(detail::printable(path_or_builtin, 64) +
                       ": chain length must be an integer in [1, 100000]");
    }
    return make_chain(n);
  }
  const std::string& path = path_or_builtin;
  const std::string source = detail::printable(path, 256);  // names the file in every message
  std::string text, problem;
  // the system would read the path only up to its NUL: another file than the one named
  if (path.find('\0') != std::string::npos) {
    throw ModelError(source + ": a path with a NUL byte names no file");
  }
  if (!read_regular_file(path, detail::kMaxFileBytes, &text, &problem)) {
    throw ModelError(source + ": " + problem);
  }
  const bool xml = path.size() > 4 && path.compare(path.size() - 4, 4, ".xml") == 0;
  return xml ? parse_mjcf(text, source, options, note) : parse_model(text, source);
}

}  // namespace puppet
