// MJCF in: an articulated body written for MuJoCo, read into the same Model the JSON files give
// (docs/mjcf.md lists what is read, what is skipped with a note and what is refused). The
// document's sections in their order (mjcf_reader.h names the other parts): the compiler's,
// the options' and the size's settings; actuators, sensors, tendons without effect and the like
// skipped with one note, or refused under --strict; what changes the dynamics and cannot be
// modelled refused with the element and its line, never dropped.
#include "mjcf_reader.h"

namespace puppet::mjcf {

namespace {

// What the testbed does not model and skips where the passive dynamics stay those MuJoCo
// computes (an actuator with no control, a sensor, a camera...): each kind counted for the note
std::string skipped_note(const std::map<std::string, int>& skipped) {
  std::string note;
  for (const auto& [kind, count] : skipped) {
    // a tag, or a phrase that names its tag itself ("<geom> on the world ...")
    const bool phrase = kind.front() == '<';
    note += (note.empty() ? "" : ", ") + std::to_string(count) +
            (phrase ? " " + kind : " <" + kind + ">");
  }
  return note;
}

}  // namespace

Model Reader::read(const std::string& text, std::string* note) {
  const XMLElement* root = parse_document(text, source_);
  if (std::string(root->Name()) != "mujoco") {
    throw ModelError(source_ + ":" + std::to_string(root->GetLineNum()) + ": <" +
                     one_line(root->Name()) + ">: the root element must be <mujoco>");
  }
  folder_ = std::filesystem::path(source_).parent_path();
  check_attributes(root, {"model"});
  root_line_ = root->GetLineNum();
  name_ = model_name(attribute(root, "model").value_or(""));

  // the sections, in any order and any number (MuJoCo merges repeated ones); the compiler's
  // settings first since everything reads them
  const std::vector<const XMLElement*> sections = children(root);
  for (const XMLElement* e : sections) {
    if (std::string(e->Name()) == "compiler") read_compiler(e);
  }
  std::vector<const XMLElement*> worlds;
  for (const XMLElement* e : sections) {
    const std::string tag = e->Name();
    if (tag == "compiler") continue;
    if (tag == "option") {
      read_option(e);
    } else if (tag == "size") {
      read_size(e);
    } else if (tag == "default") {
      read_default(e, "main", -1);
    } else if (tag == "worldbody") {
      worlds.push_back(e);
    } else if (tag == "visual" || tag == "statistic" || tag == "asset") {
      // what is drawn: nothing that moves the body
    } else if (tag == "contact") {
      for (const XMLElement* c : children(e)) {
        // segments never collide with each other here: an exclusion changes nothing
        if (std::string(c->Name()) != "exclude") {
          fail(c, "is not supported (segments collide only with the ground)");
        }
      }
    } else if (tag == "actuator") {
      for (const XMLElement* c : children(e)) read_actuator(c);
    } else if (tag == "sensor" || tag == "custom" || tag == "keyframe") {
      // what is measured, the user's own data, saved states: skipped
      for (const XMLElement* c : children(e)) skip(c);
    } else if (tag == "tendon") {
      for (const XMLElement* c : children(e)) read_tendon(c);
    } else if (tag == "equality") {
      fail(e, "is not supported: equality constraints change the dynamics");
    } else if (tag == "extension" || tag == "plugin") {
      fail(e, "is not supported: plugins change the dynamics");
    } else {
      fail(e, "is not an MJCF section this reader knows");
    }
  }
  if (worlds.empty()) fail(root, "has no <worldbody>");
  read_world(worlds);
  apply_mass_options();

  auto locate = [this](detail::Part part, int index) {
    switch (part) {
      case detail::Part::kSegment:
        return segment_where_[index] + ": <body name=\"" + one_line(segments_[index].name) + "\">";
      case detail::Part::kJoint:
        return joint_where_[index] + ": <joint name=\"" + one_line(joints_[index].joint.name) +
               "\">";
      case detail::Part::kModel:
        break;
    }
    return source_ + ":" + std::to_string(root_line_) + ": <mujoco>";
  };
  // copies: locate reads the members while assemble consumes its arguments
  Model model = detail::assemble(name_, segments_, joints_, locate, detail::kMjcfAnchorReach);
  model.gravity = gravity_off_ ? Vector3d::Zero() : gravity_;
  model.root = root_;
  const Segment& base = model.segments[0];
  model.root.anchor_in_root =
      base.rest_orientation.conjugate() * (model.root.anchor_world - base.rest_position);
  if (passive_off_) {
    // MuJoCo's passive flag switches the joints' springs and dampers off, not their armature
    for (Joint& joint : model.joints) {
      for (JointPassive& dof : joint.passive) dof.stiffness = dof.damping = 0.0;
    }
    for (JointPassive& dof : model.root.passive) dof.stiffness = dof.damping = 0.0;
  }
  if (note) *note = skipped_note(skipped_);
  return model;
}

std::string Reader::model_name(const std::string& text) {
  std::string name = text.substr(0, detail::kMaxNameLength);
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.' &&
        c != ':') {
      c = '_';
    }
  }
  return name.empty() ? "mjcf" : name;
}

void Reader::skip(const XMLElement* e) {
  if (options_.strict) fail(e, "is not modelled by the testbed (skipped unless --strict)");
  ++skipped_[e->Name()];
}

void Reader::read_actuator(const XMLElement* e) {
  const std::string tag = e->Name();
  if (tag == "motor" || tag == "adhesion") return skip(e);
  if (tag == "general") {
    const std::string bias = attribute(e, "biastype").value_or("none");
    if (bias == "none") return skip(e);
  }
  fail(e, "is not supported: this actuator acts as a spring or a damper without a control");
}

void Reader::read_tendon(const XMLElement* e) {
  for (const char* physics : {"stiffness", "damping", "frictionloss"}) {
    if (auto v = attribute(e, physics); v && single(e, physics, *v) != 0.0) {
      fail(e, std::string("a tendon with ") + physics + " is not supported");
    }
  }
  const std::string limited = attribute(e, "limited").value_or("auto");
  if (limited == "true" || (limited == "auto" && attribute(e, "range") && auto_limits_)) {
    fail(e, "a limited tendon is not supported");
  }
  skip(e);
}

void Reader::read_compiler(const XMLElement* e) {
  check_attributes(
      e, {"angle",     "coordinate",   "inertiafromgeom", "eulerseq",       "autolimits",
          "meshdir",   "texturedir",   "assetdir",        "strippath",      "discardvisual",
          "boundmass", "boundinertia", "settotalmass",    "balanceinertia", "inertiagrouprange",
          "fitaabb",   "convexhull",   "usethread",       "fusestatic",     "exactmeshinertia"});
  for (const char* flag :
       {"strippath", "discardvisual", "fitaabb", "convexhull", "usethread", "exactmeshinertia"}) {
    boolean(e, flag);
  }
  if (boolean(e, "fusestatic").value_or(false)) {
    fail(e, "fusestatic is not supported (a body without a joint is a welded segment here)");
  }
  if (auto b = boolean(e, "balanceinertia")) balance_inertia_ = *b;
  if (attribute(e, "boundmass")) bound_mass_ = single(e, "boundmass", *attribute(e, "boundmass"));
  if (attribute(e, "boundinertia")) {
    bound_inertia_ = single(e, "boundinertia", *attribute(e, "boundinertia"));
  }
  if (attribute(e, "settotalmass")) {
    total_mass_ = single(e, "settotalmass", *attribute(e, "settotalmass"));
  }
  if (attribute(e, "inertiagrouprange")) {
    const auto v = numbers(e, "inertiagrouprange", *attribute(e, "inertiagrouprange"));
    if (v.size() != 2 || v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]) ||
        std::abs(v[0]) > 1e6 || std::abs(v[1]) > 1e6) {
      fail(e, "inertiagrouprange must be two integers");
    }
    inertia_groups_ = {static_cast<int>(v[0]), static_cast<int>(v[1])};
  }
  if (auto a = attribute(e, "angle")) {
    if (*a != "degree" && *a != "radian") fail(e, "angle must be degree or radian");
    degrees_ = *a == "degree";
  }
  if (auto c = attribute(e, "coordinate"); c && *c != "local") {
    fail(e, "coordinate=\"" + one_line(*c) + "\" is not supported (local only)");
  }
  if (auto i = attribute(e, "inertiafromgeom")) {
    if (*i != "true" && *i != "false" && *i != "auto") {
      fail(e, "inertiafromgeom must be true, false or auto");
    }
    inertia_from_geom_ = *i;
  }
  if (auto s = attribute(e, "eulerseq")) {
    if (s->size() != 3 || s->find_first_not_of("xyzXYZ") != std::string::npos) {
      fail(e, "eulerseq must be three of x, y, z (or X, Y, Z)");
    }
    euler_sequence_ = *s;
  }
  if (auto a = boolean(e, "autolimits")) auto_limits_ = *a;
  if (e->FirstChildElement()) fail(e->FirstChildElement(), "is not supported in <compiler>");
}

void Reader::read_option(const XMLElement* e) {
  // the solver's own settings are each engine's; what the model is made of is read
  check_attributes(e, {"timestep",          "gravity",          "integrator",    "cone",
                       "jacobian",          "solver",           "iterations",    "tolerance",
                       "noslip_iterations", "mpr_iterations",   "collision",     "impratio",
                       "density",           "viscosity",        "wind",          "magnetic",
                       "apirate",           "noslip_tolerance", "mpr_tolerance", "o_margin",
                       "o_solref",          "o_solimp"});
  if (attribute(e, "gravity")) {
    gravity_ = vector3(e, "gravity", "", gravity_);
    if (std::string problem = detail::gravity_problem(gravity_); !problem.empty()) fail(e, problem);
  }
  for (const char* fluid : {"density", "viscosity"}) {
    if (attribute(e, fluid) && numbers(e, fluid, "", 1, {})[0] != 0.0) {
      fail(e, std::string(fluid) +
                  " is not supported: air and water are the scenarios' (--air-drag, water)");
    }
  }
  if (attribute(e, "wind") && !vector3(e, "wind", "", Vector3d::Zero()).isZero()) {
    fail(e, "wind is not supported");
  }
  for (const XMLElement* c : children(e)) {
    if (std::string(c->Name()) != "flag") fail(c, "is not supported in <option>");
    read_flags(c);
  }
}

void Reader::read_flags(const XMLElement* e) {
  check_attributes(e, {"constraint", "equality", "frictionloss", "limit", "contact", "passive",
                       "gravity", "clampctrl", "warmstart", "filterparent", "actuation", "refsafe",
                       "sensor", "override", "energy", "fwdinv", "sensornoise", "multiccd"});
  for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
    const std::string v = a->Value();
    if (v != "enable" && v != "disable") {
      fail(e, "attribute \"" + one_line(a->Name()) + "\" must be enable or disable");
    }
  }
  const auto off = [&](const char* flag) {
    return attribute(e, flag).value_or("enable") == "disable";
  };
  if (off("gravity")) gravity_off_ = true;
  if (off("limit") || off("constraint")) limits_off_ = true;
  if (off("passive")) passive_off_ = true;
  // contact switched off, or its parameters overridden, change what the scenarios decide (the
  // ground and its contact): named in the note, never dropped unsaid
  const auto contact_flag = [&](const char* flag, const char* changed) {
    if (attribute(e, flag).value_or("") != changed) return;
    const std::string what = std::string("flag ") + flag + "=\"" + changed + "\"";
    if (options_.strict) {
      fail(e, what +
                  " is not modelled by the testbed: the scenarios decide the ground and its "
                  "contact (skipped unless --strict)");
    }
    ++skipped_[what];
  };
  if (off("contact")) contact_off_ = true;
  contact_flag("contact", "disable");
  contact_flag("override", "enable");
}

void Reader::read_size(const XMLElement* e) {
  check_attributes(e, kSizeAttributes);
  if (e->FirstChildElement()) fail(e->FirstChildElement(), "is not supported in <size>");
  auto count = [&](const char* key) {
    const std::vector<double> v = numbers(e, key, *attribute(e, key));
    if (v.size() != 1 || v[0] < -1 || v[0] > 1000 || v[0] != std::floor(v[0])) {
      fail(e, std::string(key) + " must be an integer from -1 to 1000");
    }
    return static_cast<int>(v[0]);
  };
  if (attribute(e, "nuser_body")) user_body_ = count("nuser_body");
  if (attribute(e, "nuser_jnt")) user_joint_ = count("nuser_jnt");
}

void Reader::apply_mass_options() {
  double total = 0.0;
  for (Segment& s : segments_) {
    s.mass = std::max(s.mass, bound_mass_);
    s.inertia = s.inertia.cwiseMax(bound_inertia_);
    const Vector3d& i = s.inertia;
    if (balance_inertia_ && (i[0] + i[1] < i[2] || i[0] + i[2] < i[1] || i[1] + i[2] < i[0])) {
      s.inertia.setConstant((i[0] + i[1] + i[2]) / 3.0);
    }
    total += s.mass;
  }
  if (total_mass_ > 0.0) {
    const double scale = std::max(1e-15, total_mass_ / std::max(1e-15, total));  // mjMINVAL
    for (Segment& s : segments_) {
      s.mass *= scale;
      s.inertia *= scale;
    }
  }
  for (Segment& s : segments_) derive_mass_terms(s);
}

}  // namespace puppet::mjcf

namespace puppet {

Model parse_mjcf(const std::string& xml_text, const std::string& source, const ReadOptions& options,
                 std::string* note) {
  return mjcf::Reader(source, options).read(xml_text, note);
}

}  // namespace puppet
