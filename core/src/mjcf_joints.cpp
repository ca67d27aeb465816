// MJCF's joints (mjcf_reader.h): the root body's joints into the world's hold on it (free, weld,
// hinge, slide, ball, planar); every other body's into its joint to its parent: a weld, a hinge, a
// slide, a ball, or several hinges at one point as an Euler box; user data written by write_mjcf
// gives back the exact rest values
#include "mjcf_reader.h"

#include <cstdio>
#include <limits>

namespace puppet::mjcf {

namespace {
// half a turn, as rounded: a hinge's angle is read within it either way
constexpr double kHalfTurn = kPi * (1.0 + 1e-12);
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

bool Reader::is_free(const XMLElement* joint, const std::string& class_name) const {
  if (std::string(joint->Name()) == "freejoint") return true;
  return value(joint, "type", class_of(joint, class_name)).value_or("hinge") == "free";
}

void Reader::check_free(const XMLElement* joint, const std::string& class_name) const {
  if (std::string(joint->Name()) == "freejoint") {
    check_attributes(joint, {"name", "group"});
    return;
  }
  check_attributes(joint, kJointAttributes);
  const std::string cls = class_of(joint, class_name);
  for (const char* physics : {"damping", "armature", "stiffness", "frictionloss"}) {
    const auto v = value(joint, physics, cls);
    if (v && single(joint, physics, *v) != 0.0) {
      fail(joint, std::string(physics) + " on the free root is not supported" +
                      set_by(joint, physics, cls));
    }
  }
  if (value(joint, "limited", cls).value_or("false") == "true") {
    fail(joint, "a limited free joint (MuJoCo refuses it too)");
  }
}

Quaterniond Reader::unit_quaternion(const Quaterniond& q) {
  return std::abs(q.squaredNorm() - 1.0) <= 8.0 * std::numeric_limits<double>::epsilon()
             ? q
             : q.normalized();
}

std::optional<std::vector<double>> Reader::user_data(const XMLElement* e, int declared, int size,
                                                     const std::string& class_name) const {
  const auto text = value(e, "user", class_name);
  if (!text || declared < size) return std::nullopt;
  auto v = numbers(e, "user", *text);
  if (v.size() < static_cast<size_t>(size)) return std::nullopt;
  return v;
}

Reader::JointElement Reader::read_joint_element(const XMLElement* e, int child, const Vector3d& x,
                                                const Quaterniond& q, const std::string& class_name,
                                                bool may_turn) const {
  if (std::string(e->Name()) == "freejoint") fail(e, "a free joint below the root");
  const std::string cls = class_of(e, class_name);
  check_attributes(e, kJointAttributes);
  JointElement out;
  out.name = attribute(e, "name").value_or(segments_[child].name);
  if (std::string problem = detail::name_problem(out.name); !problem.empty()) fail(e, problem);
  if (const auto v = value(e, "frictionloss", cls); v && single(e, "frictionloss", *v) != 0.0) {
    fail(e,
         "frictionloss is not supported (the testbed's joints have springs and dampers, no dry "
         "friction)" +
             set_by(e, "frictionloss", cls));
  }
  out.type = value(e, "type", cls).value_or("hinge");
  for (auto [physics, field] : {std::pair{"stiffness", &JointPassive::stiffness},
                                std::pair{"damping", &JointPassive::damping},
                                std::pair{"armature", &JointPassive::armature}}) {
    const auto v = value(e, physics, cls);
    const double given = v ? single(e, physics, *v) : 0.0;
    if (given < 0.0) {
      fail(e, std::string(physics) + " must not be negative" + set_by(e, physics, cls));
    }
    out.spring.*field = given;
  }
  // MuJoCo reads ref and springref for hinges (an angle) and slides (a distance, m) only
  const bool slide = out.type == "slide";
  const auto coordinate = [&](double v) { return slide ? v : angle(v); };
  const auto angle_of = [&](const char* key) {
    const auto v = value(e, key, cls);
    return v && (out.type == "hinge" || slide) ? coordinate(single(e, key, *v)) : 0.0;
  };
  const double ref = angle_of("ref");
  out.spring.spring_ref = angle_of("springref") - ref;
  out.anchor_world = x + q * vector3(e, "pos", cls, {0, 0, 0});
  const auto limited_text = value(e, "limited", cls).value_or("auto");
  const auto range_text = value(e, "range", cls);
  if (limited_text != "true" && limited_text != "false" && limited_text != "auto") {
    fail(e, "limited must be true, false or auto");
  }
  if (limited_text == "auto" && range_text && !auto_limits_) {
    // MuJoCo 2.2's compiler refuses it the same way
    fail(e, "has a range but no limited (give limited, or compiler autolimits=\"true\")");
  }
  out.limited = !limits_off_ && (limited_text == "true" || (limited_text == "auto" && range_text));
  if (out.limited) {
    if (!range_text) fail(e, "limited but has no range");
    out.range = numbers(e, "range", *range_text);
    if (out.range.size() != 2) fail(e, "attribute \"range\" must have 2 numbers");
    out.range = {coordinate(out.range[0]) - ref, coordinate(out.range[1]) - ref};
  }
  out.user = user_data(e, user_joint_, kJointUserSize, cls);
  if (out.type == "hinge" || slide) {
    const Vector3d axis = vector3(e, "axis", cls, {0, 0, 1});
    check_norm(e, "axis", axis);
    out.axis_world = detail::normalized(Vector3d(q * axis));
    if (out.limited) {
      if (out.range[0] > out.range[1]) fail(e, "its range has lo > hi");
      if (may_turn && !slide && (out.range[0] > 0.0 || out.range[1] < 0.0)) {
        // MuJoCo starts such a joint outside its range, and its limit pushes it in at once;
        // dm_control starts its figures inside their ranges: the rest pose is turned to the
        // nearer end, the range's and springref's angles then measured from there
        out.rest_turn = {out.range[0] > 0.0 ? out.range[0] : out.range[1],
                         "<joint> whose range leaves out the pose as written, its rest turned to "
                         "the nearer end"};
      } else if (may_turn && !slide && (out.range[0] < -kHalfTurn || out.range[1] > kHalfTurn) &&
                 out.range[1] - out.range[0] < 2.0 * kPi * (1.0 - 1e-12)) {
        // a hinge's angle is read within half a turn of its rest: a range that passes half a
        // turn but spans less than a whole one is held about its middle, the rest turned there
        out.rest_turn = {0.5 * (out.range[0] + out.range[1]),
                         "<joint> whose range passes 180 degrees from the pose as written, its "
                         "rest turned to the range's middle"};
      }
      out.range = {out.range[0] - out.rest_turn.angle, out.range[1] - out.rest_turn.angle};
      out.spring.spring_ref -= out.rest_turn.angle;
      if (out.range[0] > 0.0 || out.range[1] < 0.0) {
        fail(e, slide ? "its range must contain ref (0 unless given), the body's place as written"
                      : "its range must contain ref (0 unless given), the angle of the body as "
                        "written");
      }
    }
  }
  if (slide && out.limited) {
    out.lower = out.range[0];
    out.upper = out.range[1];
  }
  if (out.type == "hinge" && out.limited) {
    // a hinge's angle is read within half a turn either way (±180° is a free hinge): a wider
    // range is one the model cannot hold, and would be read as no limit at all
    if (out.range[0] < -kHalfTurn || out.range[1] > kHalfTurn) {
      fail(e, may_turn ? "its range goes past 180 degrees either way and spans a whole turn or "
                         "more, which the testbed's hinges cannot hold (their angle is read "
                         "within half a turn of the rest, and a whole turn is a free hinge)"
                       : "its range goes past 180 degrees either way, which the testbed's hinges "
                         "in a box or at the root cannot hold (their angle is read within "
                         "[-180, 180] degrees, and that whole range is a free hinge)");
    }
    out.lower = std::max(out.range[0], -kPi);
    out.upper = std::min(out.range[1], kPi);
  }
  return out;
}

Vector3d Reader::user_anchor(const XMLElement* e, const std::vector<double>& u,
                             const Vector3d& anchor_world) const {
  const Vector3d anchor(u[0], u[1], u[2]);
  if ((anchor - anchor_world).norm() > 1e-6) {
    fail(e, "its user data (a rest anchor) disagrees with its pos");
  }
  return anchor;
}

detail::RawJoint Reader::read_box(const std::vector<const XMLElement*>& hinges, int child,
                                  int parent, const Vector3d& x, const Quaterniond& q,
                                  const std::string& class_name) {
  detail::RawJoint raw;
  Joint& j = raw.joint;
  raw.parent_name = segments_[parent].name;
  raw.child_name = segments_[child].name;
  joint_where_.push_back(where(hinges[0]));
  const int count = static_cast<int>(hinges.size());  // 2 or 3
  std::array<JointElement, 3> h;
  for (int k = 0; k < count; ++k) {
    h[k] = read_joint_element(hinges[k], child, x, q, class_name);
    if (h[k].type != "hinge") {
      fail(hinges[k],
           "several joints in one body are read only as two or three hinges at one "
           "point (a box limit)");
    }
    for (int m = 0; m < k; ++m) {
      if (std::abs(h[k].axis_world.dot(h[m].axis_world)) > 1e-6) {
        fail(hinges[k], "a box limit's hinges must have orthogonal axes");
      }
    }
  }
  if (count == 2) {
    // two hinges are a box whose third angle, about the axis they leave, is held at 0: the same
    // rotations, R(a₀, θ₀) R(a₁, θ₁), composed in MuJoCo's order
    h[2].name = h[1].name;
    h[2].anchor_world = h[1].anchor_world;
    h[2].axis_world = h[0].axis_world.cross(h[1].axis_world).normalized();
    h[2].lower = h[2].upper = 0.0;
  }
  j.type = JointType::kBall;
  j.ball_limit = BallLimit::kEulerBox;
  j.swing_x = j.swing_y = j.twist = kPi;
  j.anchor_world = h[0].anchor_world;
  for (int k = 0; k < 3; ++k) {
    j.box_lower[k] = h[k].lower;
    j.box_upper[k] = h[k].upper;
    j.passive[static_cast<size_t>(k)] = h[k].spring;
  }
  const std::string stem = h[0].name.substr(0, h[0].name.rfind(':'));
  j.name = h[0].name;
  for (int k = 0; k < count; ++k) {
    const std::string& name = h[k].name;
    if (stem.empty() || name.size() != stem.size() + 2 || name.compare(0, stem.size(), stem) ||
        name[stem.size()] != ':') {
      break;
    }
    if (k == count - 1) j.name = stem;
  }
  if (h[0].user && h[1].user && (count == 2 || h[2].user)) {
    const auto& u = *h[0].user;
    j.anchor_world = user_anchor(hinges[0], u, j.anchor_world);
    for (int k = 1; k < count; ++k) {
      h[k].anchor_world = user_anchor(hinges[k], *h[k].user, h[k].anchor_world);
    }
    if (count == 2) h[2].anchor_world = h[1].anchor_world;
    j.frame_world = unit_quaternion(Quaterniond(u[3], u[4], u[5], u[6]));
    for (int k = 0; k < count; ++k) {
      const auto& uk = *h[k].user;
      const Vector3d e(uk[7], uk[8], uk[9]);
      int axis = 0;
      e.cwiseAbs().maxCoeff(&axis);
      if ((e - Vector3d::Unit(axis)).norm() > 1e-12 ||
          (j.frame_world * e - h[k].axis_world).norm() > 1e-6) {
        fail(hinges[k], "its user data (an axis of the box's frame) disagrees with its axis");
      }
      j.box_order.axes[k] = axis;
    }
    // two hinges: the third axis is the one they leave
    if (count == 2) j.box_order.axes[2] = 3 - j.box_order.axes[0] - j.box_order.axes[1];
    if (j.box_order.axes[0] == j.box_order.axes[1] || j.box_order.axes[1] == j.box_order.axes[2] ||
        j.box_order.axes[2] == j.box_order.axes[0]) {
      fail(hinges[count - 1], "its user data names a box frame's axis twice");
    }
  } else {
    Eigen::Matrix3d frame;
    frame << h[0].axis_world, h[1].axis_world, h[2].axis_world;
    if (frame.determinant() < 0.0) {
      frame.col(2) = -frame.col(2);
      j.box_lower[2] = -h[2].upper;
      j.box_upper[2] = -h[2].lower;
      j.passive[2].spring_ref = -h[2].spring.spring_ref;
    }
    j.frame_world = Quaterniond(frame).normalized();
  }
  // hinges at different points (the humanoids' ankles): each later hinge's point turns with the
  // earlier hinges, as MuJoCo composes them (Joint::box_offsets); exactly zero at one point
  for (int k = 0; k < 2; ++k) {
    const Vector3d offset = h[k + 1].anchor_world - (k == 0 ? j.anchor_world : h[1].anchor_world);
    j.box_offsets[static_cast<size_t>(k)] = offset.norm() > 1e-9 ? offset : Vector3d::Zero();
  }
  derive_limit_terms(j);
  return raw;
}

detail::RawJoint Reader::read_joint(const XMLElement* body, const XMLElement* e, int child,
                                    int parent, const Vector3d& x, const Quaterniond& q,
                                    const std::string& class_name, RestTurn* rest_turn) {
  *rest_turn = {};
  detail::RawJoint raw;
  Joint& j = raw.joint;
  raw.parent_name = segments_[parent].name;
  raw.child_name = segments_[child].name;
  if (e == nullptr) {
    // no joint: MuJoCo welds the body to its parent. A weld has no point of its own; the
    // anchor is taken between the two shapes, halfway from each one's surface point facing
    // the other's centre
    j.type = JointType::kFixed;
    j.name = segments_[child].name;
    const Segment& p = segments_[parent];
    const Segment& c = segments_[child];
    auto facing = [](const Segment& from, const Vector3d& towards) {
      const Vector3d d = from.rest_orientation.conjugate() * (towards - from.rest_position);
      if (d.norm() < 1e-12) return from.rest_position;
      return Vector3d(from.rest_position + from.rest_orientation * support_point(from, d));
    };
    j.anchor_world = 0.5 * (facing(p, c.rest_position) + facing(c, p.rest_position));
    derive_limit_terms(j);
    joint_where_.push_back(where(body));
    return raw;
  }
  joint_where_.push_back(where(e));
  const JointElement element = read_joint_element(e, child, x, q, class_name, true);
  *rest_turn = element.rest_turn;
  j.name = element.name;
  j.anchor_world = element.anchor_world;
  const auto& user = element.user;
  j.passive[0] = element.spring;
  if (element.type == "ball") {
    j.type = JointType::kBall;
    // the twist axis is the segment's own z: its long axis for a capsule
    j.frame_world = segments_[child].rest_orientation;
    j.swing_x = j.swing_y = j.twist = kPi;
    if (element.limited) {
      const auto& range = element.range;
      if (range[0] != 0.0) fail(e, "a ball joint's range must start at 0");
      if (!(range[1] > 0.0)) fail(e, "a ball joint's range must end above 0");
      j.swing_x = j.swing_y = j.twist = std::min(range[1], kPi);
    }
  } else if (element.type == "hinge") {
    j.type = JointType::kHinge;
    raw.hinge_axis_world = element.axis_world;
    j.lower = element.lower;
    j.upper = element.upper;
  } else if (element.type == "slide") {
    j.type = JointType::kSlide;
    raw.hinge_axis_world = element.axis_world;
    j.lower = element.limited ? element.lower : -kInfinity;
    j.upper = element.limited ? element.upper : kInfinity;
  } else {
    fail(e, "type \"" + one_line(element.type) + "\" is not a joint type (hinge, slide or ball)");
  }
  if (user) {
    // write_mjcf's exact rest anchor, frame and limits
    const auto& u = *user;
    j.anchor_world = user_anchor(e, u, j.anchor_world);
    j.frame_world = unit_quaternion(Quaterniond(u[3], u[4], u[5], u[6]));
    if (j.type == JointType::kBall) {
      j.swing_x = u[7];
      j.swing_y = u[8];
      j.twist = u[9];
    } else {
      j.hinge_axis = Vector3d(u[7], u[8], u[9]);
      raw.hinge_axis_in_frame = true;
    }
  }
  derive_limit_terms(j);
  return raw;
}

RootJoint Reader::read_root(const std::vector<const XMLElement*>& joints, const Vector3d& x,
                            const Quaterniond& q, const std::string& class_name) {
  RootJoint root;
  const Segment& segment = segments_[0];
  if (joints.size() == 1 && is_free(joints[0], class_name)) {
    check_free(joints[0], class_name);
    return root;
  }
  if (joints.empty()) {
    // no joint: MuJoCo welds the root body to the world
    root.hold = RootHold::kWeld;
    root.names[0] = segment.name;
    root.anchor_world = segment.rest_position;
    return root;
  }
  for (const XMLElement* e : joints) {
    if (is_free(e, class_name)) fail(e, "a free joint beside other joints in the root body");
  }
  std::vector<JointElement> elements;
  for (const XMLElement* e : joints) elements.push_back(read_joint_element(e, 0, x, q, class_name));
  const char* kForms =
      "the root body's joints must be one free joint, none (a weld to the world), one hinge, "
      "slide or ball, or two orthogonal slides then a hinge about their plane's normal (planar)";
  const JointElement& first = elements[0];
  if (elements.size() == 1) {
    if (first.type == "hinge") {
      root.hold = RootHold::kHinge;
    } else if (first.type == "slide") {
      root.hold = RootHold::kSlide;
    } else if (first.type == "ball") {
      root.hold = RootHold::kBall;
      if (first.limited) {
        fail(joints[0],
             "a limited ball joint on the root is not modelled (a ball's limit is held "
             "between two segments)");
      }
      if (first.spring != JointPassive{}) {
        fail(joints[0], "springs, dampers and armature on a ball root are not modelled");
      }
    } else {
      fail(joints[0], std::string(kForms));
    }
    root.axes[0] = first.axis_world;
    root.limited = first.limited;
    root.lower = first.lower;
    root.upper = first.upper;
  } else if (elements.size() == 3 && elements[0].type == "slide" && elements[1].type == "slide" &&
             elements[2].type == "hinge") {
    root.hold = RootHold::kPlanar;
    for (int k = 0; k < 3; ++k) {
      if (elements[k].limited) {
        fail(joints[k], "a planar root's joints must be unlimited (as dm_control's are)");
      }
      root.axes[k] = elements[k].axis_world;
    }
    if (std::abs(root.axes[0].dot(root.axes[1])) > 1e-6 ||
        std::abs(root.axes[0].dot(root.axes[2])) > 1e-6 ||
        std::abs(root.axes[1].dot(root.axes[2])) > 1e-6) {
      fail(joints[2], "a planar root's slides and hinge must have orthogonal axes");
    }
  } else {
    fail(joints[elements.size() > 1 ? 1 : 0], std::string(kForms));
  }
  // the hinge's point; a slide's own point moves with the root, so any point of it serves
  const JointElement& pivot = elements.back();
  root.anchor_world = pivot.anchor_world;
  for (size_t k = 0; k < elements.size(); ++k) {
    root.names[k] = elements[k].name;
    root.passive[k] = elements[k].spring;
    if (const auto& user = elements[k].user) {
      // write_mjcf's exact anchor and axis (world, at rest)
      const auto& u = *user;
      if (k + 1 == elements.size())
        root.anchor_world = user_anchor(joints[k], u, root.anchor_world);
      const Vector3d axis(u[7], u[8], u[9]);
      if ((axis - root.axes[k]).norm() > 1e-6) {
        fail(joints[k], "its user data (the root joint's axis) disagrees with its axis");
      }
      root.axes[k] = axis;
    }
  }
  return root;
}

}  // namespace puppet::mjcf
