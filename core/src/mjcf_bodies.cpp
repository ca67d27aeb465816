// MJCF's bodies (mjcf_reader.h): each body a segment, its geoms (and an <inertial>) composed
// into its mass, inertia and frame as MuJoCo's compiler composes them
#include "mjcf_reader.h"

namespace puppet::mjcf {

void Reader::read_world(const std::vector<const XMLElement*>& worlds) {
  const XMLElement* root = nullptr;
  for (const XMLElement* world : worlds) {
    check_attributes(world, {});
    for (const XMLElement* e : children(world)) {
      const std::string tag = e->Name();
      if (tag == "body") {
        if (root) {
          fail(e, "a second body tree in <worldbody> (the testbed runs one figure, not scenes)");
        }
        root = e;
      } else if (tag == "geom") {
        check_attributes(e, kGeomAttributes);
        const std::string cls = class_of(e, "main");
        if (value(e, "type", cls).value_or("sphere") != "plane") {
          // a rail or a marker that collides with nothing changes nothing: skipped with a note
          const bool inert = contact_off_ || (value(e, "contype", cls).value_or("1") == "0" &&
                                              value(e, "conaffinity", cls).value_or("1") == "0");
          if (!inert) {
            fail(e,
                 "a geom on the world that collides is not supported (only a floor plane, which "
                 "is ignored, and geoms with contype and conaffinity 0)");
          }
          if (options_.strict) fail(e, "is not modelled by the testbed (skipped unless --strict)");
          ++skipped_["<geom> on the world that collides with nothing"];
        }
      } else if (tag == "light" || tag == "camera" || tag == "site") {
        check_ornament(e);
      } else {
        fail(e, "is not supported in <worldbody>");
      }
    }
  }
  if (!root) fail(worlds[0], "has no body");
  collect_body_names(root);
  read_body(root, -1, Vector3d::Zero(), Quaterniond::Identity(), "main");
}

void Reader::collect_body_names(const XMLElement* body) {
  if (const char* n = body->Attribute("name")) body_names_.insert(n);
  for (const XMLElement* c : children(body)) {
    if (std::string(c->Name()) == "body") collect_body_names(c);
  }
}

void Reader::read_body(const XMLElement* e, int parent, const Vector3d& parent_x,
                       const Quaterniond& parent_q, const std::string& inherited_class) {
  check_attributes(e, {"name", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "childclass",
                       "user", "mocap"});
  // an unnamed body is named by its MuJoCo id ("body3": the world is 0, the bodies count in
  // document order), with '_' appended while a named body has that name
  const int index = static_cast<int>(segments_.size());
  const auto given = attribute(e, "name");
  const bool generated = !given || given->empty();
  std::string name = generated ? "body" + std::to_string(index + 1) : *given;
  while (generated && body_names_.count(name)) name += '_';
  if (std::string problem = detail::name_problem(name); !problem.empty()) fail(e, problem);
  if (boolean(e, "mocap").value_or(false)) fail(e, "mocap bodies are not supported");
  std::string child_class = inherited_class;
  if (auto c = attribute(e, "childclass")) {
    if (!class_index_.count(*c)) fail(e, "unknown childclass \"" + one_line(*c) + "\"");
    child_class = *c;
  }
  // the body frame in world (turned below if its hinge's range leaves out the pose as written)
  Vector3d x = parent_x + parent_q * vector3(e, "pos", "", {0, 0, 0});
  Quaterniond q = (parent_q * orientation(e, "")).normalized();

  std::vector<const XMLElement*> geoms, joints, bodies;
  const XMLElement* inertial = nullptr;
  for (const XMLElement* c : children(e)) {
    const std::string tag = c->Name();
    if (tag == "geom") {
      geoms.push_back(c);
    } else if (tag == "joint" || tag == "freejoint") {
      joints.push_back(c);
    } else if (tag == "body") {
      bodies.push_back(c);
    } else if (tag == "inertial") {
      if (inertial) fail(c, "a second <inertial>");
      inertial = c;
    } else if (tag == "site" || tag == "camera" || tag == "light") {
      check_ornament(c);
    } else {
      fail(c, "is not supported in a body");
    }
  }
  segments_.push_back(read_segment(e, geoms, inertial, x, q, child_class));
  segments_.back().name = name;
  segment_where_.push_back(where(e));

  if (parent < 0) {
    root_ = read_root(joints, x, q, child_class);
  } else {
    if (joints.size() == 2 || joints.size() == 3) {
      joints_.push_back(read_box(joints, index, parent, x, q, child_class));
    } else if (joints.size() > 1) {
      fail(joints[3], "a fourth joint in body \"" + name +
                          "\" (one joint per body, or two or three hinges at one point)");
    } else {
      RestTurn turn;
      joints_.push_back(read_joint(e, joints.empty() ? nullptr : joints[0], index, parent, x, q,
                                   child_class, &turn));
      if (turn.why != nullptr) {
        // the body and all below it turned about the hinge into its range
        const detail::RawJoint& hinge = joints_.back();
        const Quaterniond r(Eigen::AngleAxisd(turn.angle, hinge.hinge_axis_world));
        const Vector3d& a = hinge.joint.anchor_world;
        Segment& segment = segments_.back();
        segment.rest_position = a + r * (segment.rest_position - a);
        segment.rest_orientation = (r * segment.rest_orientation).normalized();
        x = a + r * (x - a);
        q = (r * q).normalized();
        ++skipped_[turn.why];
      }
    }
  }
  for (const XMLElement* b : bodies) read_body(b, index, x, q, child_class);
}

Reader::Solid Reader::read_geom(const XMLElement* geom, const std::string& class_name) const {
  const std::string cls = class_of(geom, class_name);
  check_attributes(geom, kGeomAttributes);
  Solid solid;
  Shape& shape = solid.shape;
  if (value(geom, "shellinertia", cls).value_or("false") != "false") {
    fail(geom, "shellinertia is not supported (a segment's shapes are solid)");
  }
  const std::string type = value(geom, "type", cls).value_or("sphere");
  if (type == "mesh" || type == "hfield" || type == "plane" || type == "sdf") {
    fail(geom, "a " + type +
                   " geom on a body is not supported (a segment's shapes are "
                   "spheres, capsules, cylinders, boxes and ellipsoids)");
  }
  if (type != "sphere" && type != "capsule" && type != "cylinder" && type != "box" &&
      type != "ellipsoid") {
    fail(geom, "type \"" + one_line(type) + "\" is not a geom type");
  }
  const auto size_text = value(geom, "size", cls);
  const std::vector<double> size =
      size_text ? numbers(geom, "size", *size_text) : std::vector<double>{};
  Vector3d centre = vector3(geom, "pos", cls, {0, 0, 0});
  Quaterniond frame = orientation(geom, cls);
  // a class's fromto too; it sets the centre, so MuJoCo refuses a pos beside it
  const auto fromto = value(geom, "fromto", cls);
  if (fromto && attribute(geom, "pos")) fail(geom, "gives both pos and fromto");
  auto need = [&](size_t n) {
    if (size.size() < n) {
      fail(geom, "a " + type + " needs " + std::to_string(n) + " size numbers");
    }
    for (size_t k = 0; k < n; ++k) {
      if (!(size[k] > 0.0)) fail(geom, "attribute \"size\" must be positive");
    }
  };
  if (type == "sphere") {
    need(1);
    shape.type = ShapeType::kSphere;
    shape.radius = size[0];
  } else if (type == "capsule" || type == "cylinder") {
    shape.type = type == "capsule" ? ShapeType::kCapsule : ShapeType::kCylinder;
    need(1);
    shape.radius = size[0];
    if (fromto) {
      const auto v = numbers(geom, "fromto", *fromto);
      if (v.size() != 6) fail(geom, "attribute \"fromto\" must have 6 numbers");
      const Vector3d from(v[0], v[1], v[2]), to(v[3], v[4], v[5]);
      if ((to - from).norm() < 1e-9) fail(geom, "fromto's ends coincide");
      centre = 0.5 * (from + to);
      frame = Quaterniond::FromTwoVectors(Vector3d::UnitZ(), (to - from).normalized());
      shape.half_length = 0.5 * (to - from).norm();
    } else {
      need(2);
      shape.half_length = size[1];
    }
  } else {
    need(3);
    shape.type = type == "box" ? ShapeType::kBox : ShapeType::kEllipsoid;
    shape.half_extents = {size[0], size[1], size[2]};
  }
  if (fromto && type != "capsule" && type != "cylinder") {
    fail(geom, "fromto is read for capsules and cylinders only");
  }
  shape.position = centre;
  shape.orientation = frame;
  if (auto m = value(geom, "mass", cls)) {
    solid.mass = single(geom, "mass", *m);
  } else {
    const double density = value(geom, "density", cls)
                               ? single(geom, "density", *value(geom, "density", cls))
                               : 1000.0;  // MuJoCo's default, water's
    solid.mass = density * shape_volume(shape);
  }
  if (!(solid.mass >= 0.0)) fail(geom, "its mass must not be negative");
  // a geom outside the compiler's inertiagrouprange is a shape without mass
  const auto group = value(geom, "group", cls);
  const double g = group ? single(geom, "group", *group) : 0.0;
  if (g < inertia_groups_[0] || g > inertia_groups_[1]) solid.mass = 0.0;
  return solid;
}

Segment Reader::read_segment(const XMLElement* body, const std::vector<const XMLElement*>& geoms,
                             const XMLElement* inertial, const Vector3d& x, const Quaterniond& q,
                             const std::string& class_name) {
  if (geoms.empty()) fail(body, "has no geom (a segment needs a shape)");
  std::vector<Shape> shapes;
  std::vector<double> masses;
  for (const XMLElement* geom : geoms) {
    const Solid solid = read_geom(geom, class_name);
    shapes.push_back(solid.shape);
    masses.push_back(solid.mass);
  }
  const bool use_inertial = inertial && inertia_from_geom_ != "true";
  if (!use_inertial && inertia_from_geom_ == "false") {
    fail(body, "inertiafromgeom is false and the body has no <inertial>");
  }
  Segment s;
  if (use_inertial) {
    // the inertial's frame is the segment's; the shapes are placed in it
    Quaterniond frame;
    Vector3d centre;
    read_inertial(inertial, s, &centre, &frame);
    s.rest_position = x + q * centre;
    s.rest_orientation = (q * frame).normalized();
    for (Shape& shape : shapes) {
      shape.position = frame.conjugate() * (shape.position - centre);
      shape.orientation = (frame.conjugate() * shape.orientation).normalized();
    }
    s.shapes = shapes;
  } else {
    double total = 0.0;
    for (double m : masses) total += m;
    if (!(total > 0.0)) fail(geoms[0], "its body's mass must be positive");
    detail::place_solids(shapes, masses, x, q, s);
  }
  if (auto user = user_data(body, user_body_, kBodyUserSize)) {
    // write_mjcf's exact rest pose, if it still matches the body
    const Vector3d ux((*user)[0], (*user)[1], (*user)[2]);
    const Quaterniond uq((*user)[3], (*user)[4], (*user)[5], (*user)[6]);
    if ((ux - s.rest_position).norm() > 1e-6 ||
        unit_quaternion(uq).angularDistance(s.rest_orientation) > 1e-6) {
      fail(body, "its user data (a rest pose) disagrees with its pos and orientation");
    }
    s.rest_position = ux;
    s.rest_orientation = unit_quaternion(uq);
  }
  derive_mass_terms(s);
  return s;
}

void Reader::read_inertial(const XMLElement* e, Segment& s, Vector3d* centre,
                           Quaterniond* frame) const {
  check_attributes(e, {"pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "mass",
                       "diaginertia", "fullinertia"});
  const auto mass = attribute(e, "mass");
  if (!mass) fail(e, "needs a mass");
  s.mass = single(e, "mass", *mass);
  if (!(s.mass > 0.0)) fail(e, "mass must be positive");
  if (!attribute(e, "pos")) fail(e, "needs a pos");
  *centre = vector3(e, "pos", "", Vector3d::Zero());
  if (attribute(e, "diaginertia") && attribute(e, "fullinertia")) {
    fail(e, "gives both diaginertia and fullinertia");
  }
  if (auto d = attribute(e, "diaginertia")) {
    const auto v = numbers(e, "diaginertia", *d);
    if (v.size() != 3) fail(e, "diaginertia must have 3 numbers");
    *frame = orientation(e, "");
    s.inertia = Vector3d(v[0], v[1], v[2]);
  } else if (auto f = attribute(e, "fullinertia")) {
    for (const char* key : kOrientationAttributes) {
      if (attribute(e, key)) fail(e, "gives an orientation beside fullinertia");
    }
    const auto v = numbers(e, "fullinertia", *f);
    if (v.size() != 6) fail(e, "fullinertia must have 6 numbers");
    Matrix3d in_body;
    in_body << v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2];
    detail::principal_frame(in_body, Quaterniond::Identity(), frame, &s.inertia);
  } else {
    fail(e, "needs diaginertia or fullinertia");
  }
  if ((s.inertia.array() <= 0.0).any()) fail(e, "its moments of inertia must be positive");
}

}  // namespace puppet::mjcf
