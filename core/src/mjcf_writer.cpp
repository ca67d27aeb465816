// write_mjcf (mjcf.h): the model as MJCF in MuJoCo's local coordinates (every body relative to
// its parent, every joint in its body), numbers in their shortest exact decimal form.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include "puppet/model/euler_box.h"
#include "puppet/model/mjcf.h"

namespace puppet {
namespace {

constexpr double kPi = std::numbers::pi;

std::string num(double x) {
  if (x == 0.0) x = 0.0;  // -0 is written as 0: the same number, and a document that reads back
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::string nums(std::initializer_list<double> values) {
  std::string out;
  for (double v : values) {
    if (!out.empty()) out += ' ';
    out += num(v);
  }
  return out;
}

std::string vec(const Vector3d& v) { return nums({v.x(), v.y(), v.z()}); }
std::string quat(const Quaterniond& q) { return nums({q.w(), q.x(), q.y(), q.z()}); }

// "s3": a name by index (GCC 12 warns falsely about "s" + std::to_string(i), -Wrestrict)
std::string indexed(const char* prefix, int index) {
  std::string out(prefix);
  out.append(std::to_string(index));
  return out;
}

// a name as an XML attribute value
std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

const char* integrator_name(MjcfIntegrator integrator) {
  switch (integrator) {
    case MjcfIntegrator::kEuler:
      return "Euler";
    case MjcfIntegrator::kImplicit:
      return "implicit";
    case MjcfIntegrator::kRk4:
      return "RK4";
  }
  return "Euler";
}

std::string geom_attributes(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return "type=\"sphere\" size=\"" + num(shape.radius) + "\"";
    case ShapeType::kCapsule:
      return "type=\"capsule\" size=\"" + nums({shape.radius, shape.half_length}) + "\"";
    case ShapeType::kBox:
      return "type=\"box\" size=\"" + vec(shape.half_extents) + "\"";
    case ShapeType::kCylinder:
      return "type=\"cylinder\" size=\"" + nums({shape.radius, shape.half_length}) + "\"";
    case ShapeType::kEllipsoid:
      return "type=\"ellipsoid\" size=\"" + vec(shape.half_extents) + "\"";
  }
  return {};
}

class Writer {
 public:
  Writer(const Model& model, const MjcfOptions& options) : model_(model), options_(options) {
    const int n = model.segment_count();
    joints_of_.resize(n);
    for (int j = 0; j < model.joint_count(); ++j) {
      joints_of_[model.joints[j].parent].push_back(j);
      joints_of_[model.joints[j].child].push_back(j);
    }
    root_ = options.pinned_segment >= 0 ? options.pinned_segment : 0;
    if (options.pinned_segment >= 0) {
      const Segment& s = model.segments[root_];
      offset_ =
          options.pinned_target - (s.rest_position + s.rest_orientation * options.pinned_point);
    }
  }

  std::string document() {
    out_ << "<!-- " << escaped(model_.name)
         << ": an articulated body written by the puppet testbed. Segments are bodies in their\n"
            "     principal frames at their centres of mass; each body's user data holds its rest\n"
            "     pose in world, each joint's its rest anchor, frame and limits. -->\n";
    out_ << "<mujoco model=\"" << escaped(model_.name) << "\">\n";
    out_ << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
    out_ << "  <option timestep=\"" << num(options_.timestep) << "\" gravity=\""
         << vec(options_.environment.gravity) << "\" integrator=\""
         << integrator_name(options_.integrator) << "\"";
    if (options_.stiff_constraints) out_ << " cone=\"elliptic\"";
    out_ << "/>\n";
    out_ << "  <size nconmax=\"" << 4 * model_.segment_count() + 8 << "\" njmax=\""
         << 24 * model_.segment_count() + 3 * static_cast<int>(options_.driven_pins.size()) + 32
         << "\"";
    if (options_.user_data) {
      out_ << " nuser_body=\"" << kBodyUserSize << "\" nuser_jnt=\"" << kJointUserSize << "\"";
    }
    out_ << "/>\n";
    write_defaults();
    out_ << "  <worldbody>\n";
    if (options_.environment.ground) {
      out_ << "    <geom name=\"ground\" type=\"plane\" size=\"0 0 1\" contype=\"0\" "
              "conaffinity=\"1\" friction=\""
           << num(options_.environment.friction) << " 0.005 0.0001\"/>\n";
    }
    write_body(root_, -1, -1, 2);
    for (size_t k = 0; k < options_.driven_pins.size(); ++k) {
      const Pin& pin = options_.driven_pins[k];
      const Segment& s = model_.segments[pin.segment];
      const Vector3d at = s.rest_position + offset_ + s.rest_orientation * pin.local_point;
      out_ << "    <body name=\"pin" << k << "\" mocap=\"true\" pos=\"" << vec(at) << "\"/>\n";
    }
    out_ << "  </worldbody>\n";
    if (!options_.driven_pins.empty()) {
      out_ << "  <equality>\n";
      for (size_t k = 0; k < options_.driven_pins.size(); ++k) {
        const Pin& pin = options_.driven_pins[k];
        out_ << "    <connect name=\"pin" << k << "\" body1=\"" << body_name(pin.segment)
             << "\" body2=\"pin" << k << "\" anchor=\"" << vec(pin.local_point) << "\"/>\n";
      }
      out_ << "  </equality>\n";
    }
    out_ << "</mujoco>\n";
    return out_.str();
  }

 private:
  // Segments collide with the ground only (docs/design.md: no self-collision): a segment's contype
  // meets only the plane's conaffinity. Stiff: MuJoCo's refsafe raises a time constant below
  // 2·timestep to 2·timestep, so 1e-6 asks for the stiffest spring it allows at any timestep;
  // 0.9999 is the largest impedance it accepts (the least constraint force given up as softness)
  //
  // A joint limit is damped at ratio kLimitDampingRatio, not 1: MuJoCo's limit spring acts once an
  // angle is past it and bounces an impact back (mjcf.h), where the other engines' limits are
  // near-inelastic. A larger ratio is a softer spring at the same τ (k = 1/(τζ)²).
  void write_defaults() {
    const std::string tau = options_.constraint_time_constant > 0.0
                                ? num(options_.constraint_time_constant)
                                : std::string("1e-6");
    const std::string solref = tau + " 1";
    const std::string solreflimit = tau + " " + num(kLimitDampingRatio);
    out_ << "  <default>\n";
    out_ << "    <geom contype=\"1\" conaffinity=\"0\" condim=\"3\" friction=\""
         << num(options_.environment.friction) << " 0.005 0.0001\"";
    if (options_.stiff_constraints) {
      out_ << " solref=\"" << solref << "\" solimp=\"0.9999 0.9999 0.001\"";
    }
    out_ << "/>\n";
    out_ << "    <joint armature=\"0\" damping=\"0\" frictionloss=\"0\"";
    if (options_.stiff_constraints) {
      out_ << " solreflimit=\"" << solreflimit << "\" solimplimit=\"0.9999 0.9999 0.001\"";
    }
    out_ << "/>\n";
    if (options_.stiff_constraints) {
      out_ << "    <equality solref=\"" << solref << "\" solimp=\"0.9999 0.9999 0.001\"/>\n";
    }
    out_ << "  </default>\n";
  }

  void write_body(int s, int parent, int via_joint, int depth) {
    const Segment& seg = model_.segments[s];
    const std::string pad(2 * depth, ' ');
    Vector3d pos;
    Quaterniond q;
    if (parent < 0) {
      pos = seg.rest_position + offset_;
      q = seg.rest_orientation;
    } else {
      const Segment& p = model_.segments[parent];
      pos = p.rest_orientation.conjugate() * (seg.rest_position - p.rest_position);
      q = p.rest_orientation.conjugate() * seg.rest_orientation;
    }
    out_ << pad << "<body name=\"" << body_name(s) << "\" pos=\"" << vec(pos) << "\" quat=\""
         << quat(q) << "\"";
    if (options_.user_data) {
      out_ << " user=\"" << vec(seg.rest_position) << ' ' << quat(seg.rest_orientation) << "\"";
    }
    out_ << ">\n";
    if (parent < 0) {
      if (options_.pinned_segment >= 0) {
        out_ << pad << "  <joint name=\"pin\" type=\"ball\" pos=\"" << vec(options_.pinned_point)
             << "\"/>\n";
      } else {
        write_root(pad + "  ");
      }
    } else {
      write_joint(model_.joints[via_joint], model_.joints[via_joint].child == s, pad + "  ");
    }
    out_ << pad << "  <inertial pos=\"0 0 0\" mass=\"" << num(seg.mass) << "\" diaginertia=\""
         << vec(seg.inertia) << "\"/>\n";
    // a segment's shapes in its frame: the first one named as the segment, the next ones
    // unnamed (no name they could take is sure not to clash); a shape at the origin with the
    // segment's axes gives no pos or quat
    for (size_t k = 0; k < seg.shapes.size(); ++k) {
      const Shape& shape = seg.shapes[k];
      out_ << pad << "  <geom ";
      if (k == 0) {
        out_ << "name=\"" << (options_.model_names ? escaped(seg.name) : indexed("g", s)) << "\" ";
      }
      out_ << geom_attributes(shape);
      if (!shape.position.isZero()) out_ << " pos=\"" << vec(shape.position) << "\"";
      if (shape.orientation.coeffs() != Quaterniond::Identity().coeffs()) {
        out_ << " quat=\"" << quat(shape.orientation) << "\"";
      }
      out_ << "/>\n";
    }
    for (int j : joints_of_[s]) {
      if (j == via_joint) continue;
      const Joint& joint = model_.joints[j];
      write_body(joint.parent == s ? joint.child : joint.parent, s, j, depth + 1);
    }
    out_ << pad << "</body>\n";
  }

  // `forward`: the body is the joint's child, as in the model; else the tree was re-rooted and
  // the body is the joint's parent, which reverses the relative rotation
  void write_joint(const Joint& joint, bool forward, const std::string& pad) {
    if (joint.type == JointType::kFixed) {
      // a body without a joint is welded to its parent; the user data has nowhere to go, and
      // the reader recovers a fixed joint's anchor from the parent's surface
      return;
    }
    if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox) {
      write_box(joint, forward, pad);
      return;
    }
    const Vector3d anchor = forward ? joint.anchor_in_child : joint.anchor_in_parent;
    out_ << pad << "<joint name=\""
         << (options_.model_names ? escaped(joint.name) : indexed("j", joint.child - 1))
         << "\" pos=\"" << vec(anchor) << "\"";
    if (joint.type == JointType::kBall) {
      out_ << " type=\"ball\"";
      const double range = mjcf_ball_range(joint);
      if (range >= 0.0) out_ << " limited=\"true\" range=\"0 " << num(range) << "\"";
    } else {
      // from the parent's side a hinge turns the other way about the same line, a slide moves the
      // other way along it: about (along) minus its axis by the model's coordinate, so the range
      // is the model's
      const bool slide = joint.type == JointType::kSlide;
      const Quaterniond frame = forward ? joint.frame_in_child : joint.frame_in_parent;
      const Vector3d axis = frame * (forward ? joint.hinge_axis : Vector3d(-joint.hinge_axis));
      out_ << " type=\"" << (slide ? "slide" : "hinge") << "\" axis=\"" << vec(axis) << "\"";
      if (slide ? std::isfinite(joint.lower) : joint.lower > -kPi || joint.upper < kPi) {
        out_ << " limited=\"true\" range=\"" << nums({joint.lower, joint.upper}) << "\"";
      }
    }
    write_spring(joint.passive[0], 1.0);
    if (options_.user_data) {
      const Vector3d third = joint.type == JointType::kBall
                                 ? Vector3d(joint.swing_x, joint.swing_y, joint.twist)
                                 : joint.hinge_axis;
      out_ << " user=\"" << vec(joint.anchor_world) << ' ' << quat(joint.frame_world) << ' '
           << vec(third) << "\"";
    }
    out_ << "/>\n";
  }

  // A box is three hinges in the body, which MuJoCo composes in order: with F the joint frame
  // in the body, R(F·e₀, θ₀) R(F·e₁, θ₁) R(F·e₂, θ₂) = F R_box F⁻¹. Written from the joint's
  // parent (a re-rooted tree) the rotation is inverted: the hinges in reverse order about the
  // parent frame's axes, each angle and range negated. Each hinge's user data is the ball's
  // anchor and frame and its own axis in that frame.
  void write_box(const Joint& joint, bool forward, const std::string& pad) {
    const Vector3d anchor = forward ? joint.anchor_in_child : joint.anchor_in_parent;
    const Quaterniond frame = forward ? joint.frame_in_child : joint.frame_in_parent;
    const std::string name =
        options_.model_names ? escaped(joint.name) : indexed("j", joint.child - 1);
    for (int n = 0; n < 3; ++n) {
      const int k = forward ? n : 2 - n;
      // a third angle held at 0 without a spring is no hinge at all: two hinges are the joint
      if (k == 2 && joint.box_lower[2] == 0.0 && joint.box_upper[2] == 0.0 &&
          joint.passive[2] == JointPassive{}) {
        continue;
      }
      const int axis = joint.box_order.axes[k];
      const Vector3d e = Vector3d::Unit(axis);
      const double lower = forward ? joint.box_lower[k] : -joint.box_upper[k];
      const double upper = forward ? joint.box_upper[k] : -joint.box_lower[k];
      // hinges at different points: each at its own, the first's point carried by the offsets
      Vector3d point_world = joint.anchor_world, at = anchor;
      if (has_box_offsets(joint)) {
        for (int i = 0; i < k; ++i) point_world += joint.box_offsets[static_cast<size_t>(i)];
        const Segment& body = model_.segments[forward ? joint.child : joint.parent];
        at = body.rest_orientation.conjugate() * (point_world - body.rest_position);
      }
      out_ << pad << "<joint name=\"" << name << ':' << "xyz"[axis] << "\" pos=\"" << vec(at)
           << "\" type=\"hinge\" axis=\"" << vec(frame * e) << "\"";
      if (lower > -kPi || upper < kPi) {
        out_ << " limited=\"true\" range=\"" << nums({lower, upper}) << "\"";
      }
      write_spring(joint.passive[static_cast<size_t>(k)], forward ? 1.0 : -1.0);
      if (options_.user_data) {
        out_ << " user=\"" << vec(point_world) << ' ' << quat(joint.frame_world) << ' ' << vec(e)
             << "\"";
      }
      out_ << "/>\n";
    }
  }

  // The world's hold on the root (RootJoint): nothing for a weld, a free joint, or its joints in
  // their order at the anchor, each with its axis in the body frame, its range and its spring; the
  // user data holds the exact anchor and axis in world (a frame of its own it has none)
  void write_root(const std::string& pad) {
    const RootJoint& root = model_.root;
    if (root.hold == RootHold::kWeld) return;
    if (root.hold == RootHold::kFree) {
      out_ << pad << "<joint name=\"root\" type=\"free\"/>\n";
      return;
    }
    const Quaterniond to_body = model_.segments[0].rest_orientation.conjugate();
    const int count = root.hold == RootHold::kPlanar ? 3 : 1;
    for (int k = 0; k < count; ++k) {
      const char* type = root.hold == RootHold::kBall    ? "ball"
                         : root.hold == RootHold::kSlide ? "slide"
                         : root.hold == RootHold::kHinge ? "hinge"
                         : k < 2                         ? "slide"
                                                         : "hinge";
      const size_t dof = static_cast<size_t>(k);
      out_ << pad << "<joint name=\""
           << (options_.model_names ? escaped(root.names[dof]) : indexed("r", k)) << "\" type=\""
           << type << "\" pos=\"" << vec(root.anchor_in_root) << "\"";
      if (root.hold != RootHold::kBall) {
        out_ << " axis=\"" << vec(to_body * root.axes[dof]) << "\"";
      }
      if (root.limited) {
        out_ << " limited=\"true\" range=\"" << nums({root.lower, root.upper}) << "\"";
      }
      write_spring(root.passive[dof], 1.0);
      if (options_.user_data) {
        out_ << " user=\"" << vec(root.anchor_world) << ' ' << quat(Quaterniond::Identity()) << ' '
             << vec(root.axes[dof]) << "\"";
      }
      out_ << "/>\n";
    }
  }

  // a joint's spring, damper and armature as MuJoCo's attributes (its angle turned by `sign`, -1
  // when the joint is written from its child's side)
  void write_spring(const JointPassive& spring, double sign) {
    if (spring.stiffness != 0.0) out_ << " stiffness=\"" << num(spring.stiffness) << "\"";
    if (spring.damping != 0.0) out_ << " damping=\"" << num(spring.damping) << "\"";
    if (spring.spring_ref != 0.0) out_ << " springref=\"" << num(sign * spring.spring_ref) << "\"";
    if (spring.armature != 0.0) out_ << " armature=\"" << num(spring.armature) << "\"";
  }

  std::string body_name(int s) const {
    return options_.model_names ? escaped(model_.segments[s].name) : indexed("s", s);
  }

  const Model& model_;
  const MjcfOptions& options_;
  std::vector<std::vector<int>> joints_of_;
  int root_ = 0;
  Vector3d offset_{0, 0, 0};
  std::ostringstream out_;
};

}  // namespace

std::string mjcf_write_problem(const Model& model) {
  // a box's hinges are named "<joint>:x" and so on: no other joint may have such a name
  std::set<std::string> names;
  for (const Joint& joint : model.joints) {
    if (joint.type == JointType::kFixed) continue;
    const bool box = joint.type == JointType::kBall && joint.ball_limit == BallLimit::kEulerBox;
    for (int k = 0; k < (box ? 3 : 1); ++k) {
      std::string name = joint.name;
      if (box) name.append({':', "xyz"[joint.box_order.axes[k]]});
      if (!names.insert(name).second) {
        return "two joints would be written as \"" + name +
               "\" (a box limit's hinges are named <joint>:x, :y and :z)";
      }
    }
  }
  std::vector<int> depth(model.segment_count(), 1);
  int deepest = 0;
  for (int i = 0; i < model.segment_count(); ++i) {
    if (model.segments[i].parent >= 0) depth[i] = depth[model.segments[i].parent] + 1;
    deepest = std::max(deepest, depth[i]);
  }
  if (deepest <= kMjcfMaxDepth) return {};
  return "the model's tree is " + std::to_string(deepest) + " segments deep; MJCF (read with " +
         "tinyxml2, by MuJoCo and by this project) nests at most " + std::to_string(kMjcfMaxDepth);
}

std::string mjcf_inexact_joint(const Model& model) {
  for (const Joint& joint : model.joints) {
    if (joint.type == JointType::kBall && joint.ball_limit == BallLimit::kSwingTwist &&
        std::min({joint.swing_x, joint.swing_y, joint.twist}) < kPi) {
      return joint.name;
    }
  }
  return {};
}

double mjcf_ball_range(const Joint& joint) {
  const double largest = std::max({joint.swing_x, joint.swing_y, joint.twist});
  return largest < kPi ? largest : -1.0;
}

std::string mjcf_segment_body(int segment) { return indexed("s", segment); }

std::string write_mjcf(const Model& model, const MjcfOptions& options) {
  return Writer(model, options).document();
}

}  // namespace puppet
