// The model's limits (docs/model.md, "Limits"): what every front end checks before a model is
// built, so that every quantity derived from it (inverse masses and inertias, totals, rest
// height, normalised rotations) is a finite number with room to spare.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "model_builder.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/text.h"

namespace puppet {

std::string printable(std::string_view text, size_t max_length) {
  std::string out;
  for (const char c : text) {
    if (out.size() >= max_length) {
      out += "...";
      break;
    }
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte >= 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

namespace detail {

std::string text_problem(std::string_view text) {
  const auto starts = [&](std::string_view mark) { return text.substr(0, mark.size()) == mark; };
  // UTF-32's marks begin as UTF-16's do: looked for first
  if (starts(std::string_view("\xff\xfe\0\0", 4)) || starts(std::string_view("\0\0\xfe\xff", 4))) {
    return "is UTF-32 (a model file is UTF-8 text)";
  }
  if (starts("\xff\xfe") || starts("\xfe\xff")) return "is UTF-16 (a model file is UTF-8 text)";
  if (const size_t nul = text.find('\0'); nul != std::string_view::npos) {
    return "a NUL byte at offset " + std::to_string(nul) + " (a model file is text)";
  }
  return {};
}

}  // namespace detail

std::string one_line(std::string_view text, size_t max_length) {
  // a cut text ends in "...", within max_length
  const bool cut = text.size() > max_length;
  std::string out(text.substr(0, cut ? max_length - std::min<size_t>(3, max_length) : max_length));
  for (char& c : out) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) c = '?';
  }
  if (cut) out += std::string("...").substr(0, std::min<size_t>(3, max_length));
  return out;
}

std::string shown(std::string_view text) {
  std::string out = "\"";
  for (const char c : printable(text, 64)) {
    if (c == '"') {
      out += "\\x22";
    } else {
      out += c;
    }
  }
  return out + "\"";
}

namespace detail {

std::string number(double x) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, x);
  return std::string(text, result.ptr);
}

namespace {

bool within(double x, double lo, double hi) { return x >= lo && x <= hi; }  // false for NaN

std::string vector_problem(const char* what, const Vector3d& v, double bound) {
  for (int i = 0; i < 3; ++i) {
    if (!within(v[i], -bound, bound)) {
      return std::string(what) + " has a coordinate of " + number(v[i]) + " (at most " +
             number(bound) + " in magnitude)";
    }
  }
  return {};
}

std::string length_problem(const char* what, double x) {
  if (within(x, kMinLength, kMaxLength)) return {};
  return std::string(what) + " is " + number(x) + " m (from " + number(kMinLength) + " to " +
         number(kMaxLength) + " m)";
}

std::string rotation_problem(const char* what, const Quaterniond& q) {
  if (!q.coeffs().allFinite() || std::abs(q.squaredNorm() - 1.0) > 1e-9) {
    return std::string(what) + " is not a unit quaternion";
  }
  return {};
}

}  // namespace

std::string name_problem(std::string_view name) {
  if (name.empty()) return "an empty name";
  if (name.size() > kMaxNameLength) {
    return "the name " + shown(name) + " is " + std::to_string(name.size()) + " bytes (at most " +
           std::to_string(kMaxNameLength) + ")";
  }
  for (const char c : name) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                         (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.' || c == ':';
    if (!allowed) {
      return "the name " + shown(name) +
             " has a character other than letters, digits and _ - . : (ASCII)";
    }
  }
  return {};
}

std::string shape_problem(const Shape& shape) {
  std::string problem;
  switch (shape.type) {
    case ShapeType::kSphere:
      problem = length_problem("the radius", shape.radius);
      break;
    case ShapeType::kCapsule:
    case ShapeType::kCylinder:
      problem = length_problem("the radius", shape.radius);
      if (problem.empty()) problem = length_problem("the half length", shape.half_length);
      break;
    case ShapeType::kBox:
    case ShapeType::kEllipsoid:
      for (int i = 0; i < 3 && problem.empty(); ++i) {
        problem = length_problem("a half extent", shape.half_extents[i]);
      }
      break;
  }
  if (problem.empty()) {
    for (int i = 0; i < 3 && problem.empty(); ++i) {
      if (!(std::abs(shape.position[i]) <= kMaxLength)) {
        problem = "a shape's centre is " + number(shape.position[i]) +
                  " m from its segment's (at most " + number(kMaxLength) + " m)";
      }
    }
  }
  return problem;
}

std::string segment_problem(const Segment& s) {
  if (std::string p = name_problem(s.name); !p.empty()) return p;
  if (s.shapes.empty()) return "the segment has no shape";
  for (const Shape& shape : s.shapes) {
    if (std::string p = shape_problem(shape); !p.empty()) return p;
  }
  if (!within(s.mass, kMinMass, kMaxMass)) {
    return "the mass is " + number(s.mass) + " kg (from " + number(kMinMass) + " to " +
           number(kMaxMass) + " kg)";
  }
  const Vector3d& i = s.inertia;
  for (int k = 0; k < 3; ++k) {
    if (!within(i[k], kMinInertia, kMaxInertia)) {
      return "a moment of inertia is " + number(i[k]) + " kg m^2 (from " + number(kMinInertia) +
             " to " + number(kMaxInertia) + ")";
    }
  }
  // a real body's principal moments obey the triangle inequality: I_a = ∫(r_b² + r_c²) dm
  // ≤ I_b + I_c, with equality only for a flat body
  for (int k = 0; k < 3; ++k) {
    const double others = i[(k + 1) % 3] + i[(k + 2) % 3];
    if (i[k] > others * (1.0 + 1e-9)) {
      return "the moments of inertia (" + number(i.x()) + ", " + number(i.y()) + ", " +
             number(i.z()) + ") break the triangle inequality (no real body has them)";
    }
  }
  if (std::string p = vector_problem("the position", s.rest_position, kMaxCoordinate); !p.empty())
    return p;
  return rotation_problem("the orientation", s.rest_orientation);
}

std::string joint_problem(const Joint& j) {
  if (std::string p = name_problem(j.name); !p.empty()) return p;
  if (std::string p = vector_problem("the anchor", j.anchor_world, kMaxCoordinate); !p.empty())
    return p;
  if (std::string p = rotation_problem("the frame", j.frame_world); !p.empty()) return p;
  for (const Vector3d& offset : j.box_offsets) {
    if (std::string p = vector_problem("a box's hinge offset", offset, 1.0); !p.empty()) return p;
  }
  if (has_box_offsets(j) && (j.type != JointType::kBall || j.ball_limit != BallLimit::kEulerBox)) {
    return "hinges at different points make a box (a ball joint with Euler-angle limits) only";
  }
  if ((j.type == JointType::kHinge || j.type == JointType::kSlide) &&
      (!j.hinge_axis.allFinite() || std::abs(j.hinge_axis.squaredNorm() - 1.0) > 1e-9)) {
    return j.type == JointType::kHinge ? "the hinge axis is not a unit vector"
                                       : "the slide's direction is not a unit vector";
  }
  // the limits, whichever file gave them (JSON's fields, MJCF's range or its user data)
  constexpr double kPi = 3.14159265358979323846;
  if (j.type == JointType::kBall && j.ball_limit == BallLimit::kEulerBox) {
    const auto& a = j.box_order.axes;
    for (int k = 0; k < 3; ++k) {
      if (a[k] < 0 || a[k] > 2 || a[k] == a[(k + 1) % 3]) return "the box's axes are not an order";
      const double bound = k == 1 ? kMaxBoxMiddle : kPi;
      if (!within(j.box_lower[k], -bound, 0.0) || !within(j.box_upper[k], 0.0, bound)) {
        return "the box's angle " + std::to_string(k) + " range [" + number(j.box_lower[k]) + ", " +
               number(j.box_upper[k]) + "] rad must contain 0 and lie within [" + number(-bound) +
               ", " + number(bound) + "]" +
               (k == 1 ? " (the middle angle: Euler angles lose an axis at 90 degrees)" : "");
      }
    }
  } else if (j.type == JointType::kBall) {
    const std::pair<const char*, double> limits[] = {
        {"swing x", j.swing_x}, {"swing y", j.swing_y}, {"twist", j.twist}};
    for (const auto& [what, value] : limits) {
      if (!within(value, 0.0, kPi)) {
        return std::string("the ") + what + " limit is " + number(value) + " rad (from 0 to pi)";
      }
    }
  } else if (j.type == JointType::kHinge) {
    if (!within(j.lower, -kPi, 0.0) || !within(j.upper, 0.0, kPi)) {
      return "the hinge range [" + number(j.lower) + ", " + number(j.upper) +
             "] rad must contain 0, the rest angle, and lie within [-pi, pi]";
    }
  } else if (j.type == JointType::kSlide) {
    // not limited: both ends infinite
    const bool open = j.lower == -INFINITY && j.upper == INFINITY;
    if (!open && (!within(j.lower, -kMaxCoordinate, 0.0) || !within(j.upper, 0.0, kMaxCoordinate) ||
                  j.lower == j.upper)) {
      return "the slide's range [" + number(j.lower) + ", " + number(j.upper) +
             "] m must contain 0, the rest place, be wider than a point and lie within " +
             number(kMaxCoordinate) + " m of it (or be infinite at both ends: not limited)";
    }
  }
  return {};
}

std::string gravity_problem(const Vector3d& gravity) {
  return vector_problem("gravity", gravity, kMaxGravity);
}

std::string norm_problem(const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (!v.allFinite()) return "is not finite";
  // stableNorm: [1e200, 0, 0, 0] has a norm, although its squared norm overflows
  const double n = v.stableNorm();
  if (!within(n, kMinNorm, kMaxNorm)) {
    return "has a norm of " + number(n) + " (from " + number(kMinNorm) + " to " + number(kMaxNorm) +
           ")";
  }
  return {};
}

}  // namespace detail
}  // namespace puppet
