// The model, the checks every binding shares, the environment and a pin as Python sees them.
#include <pybind11/stl.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.h"
#include "puppet/compare/scenario.h"
#include "puppet/model/environment.h"
#include "puppet/model/text.h"

namespace puppet::python {

void refuse(const std::string& name, const std::string& problem) {
  throw py::value_error(bounded(name + ": " + problem));
}

double finite(const char* name, double value) {
  if (!std::isfinite(value)) refuse(name, "not a finite number");
  return value;
}

Vector3d vector3(const char* name, const py::handle& value) {
  // the length first: a huge sequence (a broadcast array of zero strides) is never copied
  if (py::isinstance<py::array>(value)) {
    const auto a = py::reinterpret_borrow<py::array>(value);
    check_kind(name, a);
    if (a.ndim() != 1 || a.shape(0) != 3) refuse(name, "expected three numbers");
  } else if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value) ||
             py::len(value) != 3) {
    refuse(name, "expected three numbers");
  }
  std::vector<double> v;
  try {
    v = value.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    refuse(name, "expected three numbers");
  }
  if (v.size() != 3) refuse(name, "expected three numbers, got " + std::to_string(v.size()));
  for (double x : v) finite(name, x);
  return {v[0], v[1], v[2]};
}

void check_kind(const char* name, const py::array& a) {
  // NumPy's kinds: b bool, i and u whole numbers, f floating point, c complex, O objects, ...
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    refuse(name, std::string("expected real numbers, got an array of dtype ") +
                     py::str(a.dtype()).cast<std::string>());
  }
}

py::array_t<double, py::array::c_style> real_array(const char* name, const py::handle& value,
                                                   ssize_t rows, ssize_t width) {
  const std::string shape = "(" + std::to_string(rows) + ", " + std::to_string(width) + ")";
  const bool sequence = py::isinstance<py::sequence>(value) && !py::isinstance<py::str>(value) &&
                        !py::isinstance<py::bytes>(value);
  if (!py::isinstance<py::array>(value) && !sequence) {
    refuse(name, "expected an array of shape " + shape);
  }
  // a sequence becomes an array as NumPy reads it (a list of lists); an array is looked at as it
  // is: its kind and shape are checked before any of it is copied or converted
  const py::array a = py::isinstance<py::array>(value)
                          ? py::reinterpret_borrow<py::array>(value)
                          : py::array(py::module_::import("numpy").attr("asarray")(value));
  check_kind(name, a);
  if (a.ndim() != 2 || a.shape(0) != rows || a.shape(1) != width) {
    refuse(name, "expected shape " + shape);
  }
  auto out = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!out) refuse(name, "expected real numbers");
  for (ssize_t k = 0; k < out.size(); ++k) {
    if (!std::isfinite(out.data()[k])) refuse(name, "a value is not finite");
  }
  return out;
}

long long whole(const char* name, const py::handle& value, long long lo, long long hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!py::isinstance<py::int_>(value) || py::isinstance<py::bool_>(value)) {
    refuse(name, "expected a whole number in " + range);
  }
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow != 0 || v < lo || v > hi) refuse(name, "must be in " + range);
  return v;
}

std::string bounded(const std::string& message) {
  std::string line = one_line(message, 400);
  // a cut may end inside a character, which Python would not decode: drop its first bytes
  // (a line the command line cut already ends in "..." at the bound)
  const bool cut =
      message.size() >= 400 && line.size() >= 3 && line.compare(line.size() - 3, 3, "...") == 0;
  size_t end = line.size() - (cut ? 3 : 0);
  size_t lead = end;
  while (lead > 0 && lead + 4 > end &&
         (static_cast<unsigned char>(line[lead - 1]) & 0xC0) == 0x80) {
    --lead;
  }
  if (lead > 0) {
    const auto byte = static_cast<unsigned char>(line[lead - 1]);
    const size_t length = byte >= 0xF0 ? 4 : byte >= 0xE0 ? 3 : byte >= 0xC0 ? 2 : 1;
    if (length > 1 && lead - 1 + length > end) end = lead - 1;
  }
  return line.substr(0, end) + (cut ? "..." : "");
}

namespace {

ModelPtr load(const std::string& name, bool strict, bool include_outside) {
  try {
    return std::make_shared<Model>(compare::load_named_model(
        name, ReadOptions{.strict = strict, .include_outside = include_outside}));
  } catch (const std::exception& e) {
    throw py::value_error(bounded(e.what()));
  }
}

double in_range(const char* name, double value, double lo, double hi) {
  if (!(finite(name, value) >= lo && value <= hi)) {
    std::ostringstream message;
    message << value << " is out of range (from " << lo << " to " << hi << ")";
    refuse(name, message.str());
  }
  return value;
}

// the command line's ranges where it has the flag (--gravity, --air-drag), else wide ones that
// keep every force finite
Environment make_environment(const py::handle& gravity, double air_drag, bool water,
                             double water_level, double water_density, double water_drag,
                             bool ground, double friction, bool tremble,
                             const py::object& tremble_seed) {
  Environment e;
  e.gravity = vector3("gravity", gravity);
  if (e.gravity.norm() > 1e3) refuse("gravity", "larger than 1000 m/s^2");
  e.air_drag = in_range("air_drag", air_drag, 0.0, 1e9);
  e.water = water;
  e.water_level = in_range("water_level", water_level, -1e3, 1e3);
  e.water_density = in_range("water_density", water_density, 0.0, 1e5);
  e.water_drag = in_range("water_drag", water_drag, 0.0, 1e9);
  e.ground = ground;
  e.friction = in_range("friction", friction, 0.0, 1e3);
  e.tremble = tremble;
  // the command line's seeds have at most 18 digits
  e.tremble_seed =
      static_cast<uint64_t>(whole("tremble_seed", tremble_seed, 0, 999'999'999'999'999'999LL));
  return e;
}

std::string vector_text(const Vector3d& v) {
  return "(" + py::repr(py::float_(v.x())).cast<std::string>() + ", " +
         py::repr(py::float_(v.y())).cast<std::string>() + ", " +
         py::repr(py::float_(v.z())).cast<std::string>() + ")";
}

py::tuple xyz(const Vector3d& v) { return py::make_tuple(v.x(), v.y(), v.z()); }
// quaternions as the package's arrays hold them: x, y, z, w (named so in every key)
py::tuple xyzw(const Quaterniond& q) { return py::make_tuple(q.x(), q.y(), q.z(), q.w()); }

// a segment by index or name
int segment_of(const Model& model, const py::handle& which) {
  if (py::isinstance<py::str>(which)) {
    const std::string name = which.cast<std::string>();
    const int index = model.find_segment(name);
    if (index < 0) refuse("segment", "no segment \"" + one_line(name, 64) + "\" in " + model.name);
    return index;
  }
  if (!py::isinstance<py::int_>(which) || py::isinstance<py::bool_>(which)) {
    refuse("segment", "a segment is an index or a name");
  }
  const long long index = which.cast<long long>();
  if (index < 0 || index >= model.segment_count()) {
    refuse("segment", "index " + std::to_string(index) + " is not one of the " +
                          std::to_string(model.segment_count()) + " segments");
  }
  return static_cast<int>(index);
}

py::dict shape_dict(const Shape& shape) {
  py::dict d;
  d["type"] = shape_type_name(shape.type);
  d["radius"] = shape.radius;
  d["half_length"] = shape.half_length;
  d["half_extents"] = xyz(shape.half_extents);
  d["position"] = xyz(shape.position);
  d["orientation_xyzw"] = xyzw(shape.orientation);
  return d;
}

py::dict segment_dict(const Model& model, int s) {
  const Segment& segment = model.segments[static_cast<size_t>(s)];
  py::dict d;
  d["index"] = s;
  d["name"] = segment.name;
  d["parent"] = segment.parent < 0 ? py::object(py::none())
                                   : py::object(py::str(model.segments[segment.parent].name));
  d["mass"] = segment.mass;
  d["inertia"] = xyz(segment.inertia);
  d["rest_position"] = xyz(segment.rest_position);
  d["rest_orientation_xyzw"] = xyzw(segment.rest_orientation);
  py::list shapes;
  for (const Shape& shape : segment.shapes) shapes.append(shape_dict(shape));
  d["shapes"] = shapes;
  return d;
}

// a joint as its model says it (docs/model-format.md): kind, segments, anchor and frame at rest
// in world, and its limits in the units the JSON format gives them
py::dict joint_dict(const Model& model, const Joint& joint) {
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  py::dict d;
  d["name"] = joint.name;
  d["type"] = joint_type_name(joint.type);
  d["parent"] = model.segments[joint.parent].name;
  d["child"] = model.segments[joint.child].name;
  d["anchor"] = xyz(joint.anchor_world);
  d["frame_xyzw"] = xyzw(joint.frame_world);
  switch (joint.type) {
    case JointType::kHinge:
      d["axis"] = xyz(joint.frame_world * joint.hinge_axis);
      d["range_deg"] = py::make_tuple(joint.lower * kDeg, joint.upper * kDeg);
      break;
    case JointType::kSlide:
      d["axis"] = xyz(joint.frame_world * joint.hinge_axis);
      d["range_m"] = std::isfinite(joint.lower)
                         ? py::object(py::make_tuple(joint.lower, joint.upper))
                         : py::object(py::none());
      break;
    case JointType::kBall:
      if (joint.ball_limit == BallLimit::kEulerBox) {
        d["box_order"] = std::string{"xyz"[joint.box_order.axes[0]], "xyz"[joint.box_order.axes[1]],
                                     "xyz"[joint.box_order.axes[2]]};
        d["box_lower_deg"] = xyz(joint.box_lower * kDeg);
        d["box_upper_deg"] = xyz(joint.box_upper * kDeg);
      } else {
        d["swing_deg"] = py::make_tuple(joint.swing_x * kDeg, joint.swing_y * kDeg);
        d["twist_deg"] = joint.twist * kDeg;
      }
      break;
    case JointType::kFixed:
      break;
  }
  py::list passive;
  for (const JointPassive& p : joint.passive) {
    py::dict spring;
    spring["stiffness"] = p.stiffness;
    spring["damping"] = p.damping;
    spring["spring_ref"] = p.spring_ref;
    spring["armature"] = p.armature;
    passive.append(spring);
  }
  d["passive"] = passive;
  return d;
}

// the Model class: its names, masses, segments and joints
void bind_model_class(py::module_& m) {
  py::class_<Model, ModelPtr>(m, "Model", "an articulated figure: segments joined in a tree")
      .def_property_readonly("name", [](const Model& model) { return model.name; })
      .def_property_readonly("segment_count", &Model::segment_count)
      .def_property_readonly("segments",
                             [](const Model& model) {
                               std::vector<std::string> names;
                               for (const Segment& s : model.segments) names.push_back(s.name);
                               return names;
                             })
      .def_property_readonly(
          "masses",
          [](const Model& model) {
            std::vector<double> masses;
            for (const Segment& s : model.segments) masses.push_back(s.mass);
            return masses;
          },
          "each segment's mass (kg), in the order of `segments`")
      .def(
          "segment_index",
          [](const Model& model, const std::string& name) {
            const int index = model.find_segment(name);
            if (index < 0) refuse("segment", "no segment \"" + name + "\" in " + model.name);
            return index;
          },
          py::arg("name"))
      .def(
          "segment",
          [](const Model& model, const py::handle& which) {
            return segment_dict(model, segment_of(model, which));
          },
          py::arg("which"),
          "a segment, by index or name, as a dict: name, parent (a name, None for the root), "
          "mass, inertia (diagonal, segment frame), rest_position, rest_orientation_xyzw and its "
          "shapes (type, sizes, place in the segment frame)")
      .def_property_readonly(
          "joints",
          [](const Model& model) {
            py::list joints;
            for (const Joint& joint : model.joints) joints.append(joint_dict(model, joint));
            return joints;
          },
          "each joint as a dict: name, type (ball, hinge, slide, fixed), parent and child "
          "(names), anchor and frame_xyzw at rest in world, a hinge's or slide's axis and "
          "range (range_deg, range_m: None when not limited), a ball's swing and twist or box "
          "(deg), and passive: per degree of freedom its stiffness, damping, spring_ref, "
          "armature")
      .def(
          "joint",
          [](const Model& model, const py::handle& which) {
            if (py::isinstance<py::str>(which)) {
              const std::string name = which.cast<std::string>();
              for (const Joint& joint : model.joints) {
                if (joint.name == name) return joint_dict(model, joint);
              }
              refuse("joint", "no joint \"" + one_line(name, 64) + "\" in " + model.name);
            }
            if (!py::isinstance<py::int_>(which) || py::isinstance<py::bool_>(which)) {
              refuse("joint", "a joint is an index or a name");
            }
            const long long index = which.cast<long long>();
            if (index < 0 || index >= model.joint_count()) {
              refuse("joint", "index " + std::to_string(index) + " is not one of the " +
                                  std::to_string(model.joint_count()) + " joints");
            }
            return joint_dict(model, model.joints[static_cast<size_t>(index)]);
          },
          py::arg("which"), "a joint, by index or name, as in `joints`")
      .def("__repr__", [](const Model& model) {
        return "<puppet.Model " + model.name + ": " + std::to_string(model.segment_count()) +
               " segments>";
      });
}

}  // namespace

void bind_model(py::module_& m) {
  bind_model_class(m);
  m.def("_use_builtin_model", &compare::set_builtin_model_path, py::arg("path"),
        "where \"pinocchio\" is read from: the package's own copy");
  m.def("load_model", &load, py::arg("name"), py::kw_only(), py::arg("strict") = false,
        py::arg("include_outside") = false,
        "pinocchio, chain:N, or a model file (JSON or MJCF), read as the command line's --strict "
        "and --include-outside say (for this call only); ValueError when it does not load");

  py::class_<Environment>(m, "Environment",
                          "the world: gravity, air drag, water, the ground and the tremble")
      .def(py::init(&make_environment), py::kw_only(),
           py::arg("gravity") = py::make_tuple(0.0, 0.0, -9.81), py::arg("air_drag") = 0.0,
           py::arg("water") = false, py::arg("water_level") = 0.0,
           py::arg("water_density") = 1000.0, py::arg("water_drag") = 0.0,
           py::arg("ground") = false, py::arg("friction") = 0.8, py::arg("tremble") = false,
           py::arg("tremble_seed") = py::int_(2001))
      .def_property_readonly("gravity",
                             [](const Environment& e) {
                               return py::make_tuple(e.gravity.x(), e.gravity.y(), e.gravity.z());
                             })
      .def_readonly("air_drag", &Environment::air_drag)
      .def_readonly("water", &Environment::water)
      .def_readonly("water_level", &Environment::water_level)
      .def_readonly("water_density", &Environment::water_density)
      .def_readonly("water_drag", &Environment::water_drag)
      .def_readonly("ground", &Environment::ground)
      .def_readonly("friction", &Environment::friction)
      .def_readonly("tremble", &Environment::tremble)
      .def_readonly("tremble_seed", &Environment::tremble_seed)
      .def("__repr__", [](const Environment& e) {
        return "puppet.Environment(gravity=" + vector_text(e.gravity) +
               ", air_drag=" + py::repr(py::float_(e.air_drag)).cast<std::string>() +
               ", water=" + (e.water ? "True" : "False") +
               ", ground=" + (e.ground ? "True" : "False") +
               ", tremble=" + (e.tremble ? "True" : "False") + ")";
      });

  py::class_<GrabSpring>(m, "GrabSpring",
                         "a user's grab: F = M (w^2 (t - p) - 2 zeta w v), w = 2 pi hz, |F| <= "
                         "max_force (docs/design.md, \"The grab\")")
      .def(py::init([](double hz, double damping_ratio, double max_force) {
             if (!(finite("hz", hz) > 0.0)) refuse("hz", "must be positive");
             if (!(finite("damping_ratio", damping_ratio) >= 0.0)) {
               refuse("damping_ratio", "must not be negative");
             }
             if (!(finite("max_force", max_force) > 0.0)) refuse("max_force", "must be positive");
             return GrabSpring{hz, damping_ratio, max_force};
           }),
           py::arg("hz"), py::arg("damping_ratio") = 1.0, py::arg("max_force"))
      .def_readonly("hz", &GrabSpring::hz)
      .def_readonly("damping_ratio", &GrabSpring::damping_ratio)
      .def_readonly("max_force", &GrabSpring::max_force);
  m.def(
      "grab_spring",
      [](const Model& model) { return compare::grab_spring(model, compare::GrabSettings{}); },
      py::arg("model"),
      "the testbed's grab for a model: 2 Hz, damping ratio 1, capped at the figure's weight");
}

}  // namespace puppet::python
