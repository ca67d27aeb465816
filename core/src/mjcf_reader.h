// The MJCF reader (parse_mjcf, mjcf.h), private to model/. One Reader per file read; its parts,
// by what each reads:
//   mjcf_reader.cpp    the document's sections in their order; the compiler's, the options' and
//                      the size's settings; what is skipped with a note or refused; the compiler's
//                      mass options once every body is read
//   mjcf_document.cpp  the XML: the text's bounds, the files and their includes, every attribute
//                      through the default classes, numbers, orientations
//   mjcf_bodies.cpp    the bodies and their geoms and inertials into segments
//   mjcf_joints.cpp    each body's joints into the model's joint to its parent (free root, weld,
//                      hinge, ball, several hinges as an Euler box)
#pragma once

#include <tinyxml2.h>

#include <charconv>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "model_builder.h"
#include "puppet/model/file.h"
#include "puppet/model/mjcf.h"

namespace puppet::mjcf {

using tinyxml2::XMLElement;

inline constexpr double kPi = 3.14159265358979323846;

// The attributes each element this reader reads may carry: MuJoCo 2.2.2's own lists
// (xml_native_reader.cc), less what a body's physics here cannot hold (those are read and
// refused with a reason where they matter). In a <default> class the same lists hold without
// name and class.
using Names = std::initializer_list<const char*>;
inline constexpr Names kGeomAttributes = {
    "name",      "class",    "type",       "size",        "fromto",      "pos",      "quat",
    "axisangle", "euler",    "xyaxes",     "zaxis",       "mass",        "density",  "rgba",
    "material",  "group",    "contype",    "conaffinity", "condim",      "friction", "solref",
    "solimp",    "solmix",   "margin",     "gap",         "priority",    "user",     "mesh",
    "hfield",    "fitscale", "fluidshape", "fluidcoef",   "shellinertia"};
inline constexpr Names kJointAttributes = {
    "name",         "class", "type",      "pos",         "axis",        "range",
    "limited",      "ref",   "stiffness", "springref",   "damping",     "armature",
    "frictionloss", "group", "user",      "solreflimit", "solimplimit", "margin"};
inline constexpr Names kSiteAttributes = {"name",   "class",    "type",  "group",  "pos",
                                          "quat",   "material", "size",  "fromto", "axisangle",
                                          "xyaxes", "zaxis",    "euler", "rgba",   "user"};
inline constexpr Names kCameraAttributes = {"name", "class",     "fovy",   "ipd",   "pos",
                                            "quat", "axisangle", "xyaxes", "zaxis", "euler",
                                            "mode", "target",    "user"};
inline constexpr Names kLightAttributes = {
    "name",   "class",    "directional", "castshadow", "active",   "pos",  "dir",   "attenuation",
    "cutoff", "exponent", "ambient",     "diffuse",    "specular", "mode", "target"};
inline constexpr Names kMaterialAttributes = {"name",        "class",    "texture",  "texrepeat",
                                              "texuniform",  "emission", "specular", "shininess",
                                              "reflectance", "rgba"};
// what a <default> may also set: defaults of what this reader skips or refuses
inline constexpr Names kDefaultKindsElsewhere = {
    "mesh",     "pair",        "equality", "tendon",   "general", "motor",   "position",
    "velocity", "intvelocity", "damper",   "cylinder", "muscle",  "adhesion"};
inline constexpr Names kOrientationAttributes = {"quat", "axisangle", "xyaxes", "zaxis", "euler"};
inline constexpr Names kSizeAttributes = {
    "njmax",        "nconmax",        "nstack",      "nuserdata",  "nkey",
    "nuser_body",   "nuser_jnt",      "nuser_geom",  "nuser_site", "nuser_cam",
    "nuser_tendon", "nuser_actuator", "nuser_sensor"};

// the attributes an element kind may carry, for the kinds a <default> class may set (null for
// any other kind)
inline const Names* default_kind(const std::string& tag) {
  if (tag == "geom") return &kGeomAttributes;
  if (tag == "joint") return &kJointAttributes;
  if (tag == "site") return &kSiteAttributes;
  if (tag == "camera") return &kCameraAttributes;
  if (tag == "light") return &kLightAttributes;
  if (tag == "material") return &kMaterialAttributes;
  return nullptr;
}

inline bool among(const char* name, const Names& names) {
  for (const char* n : names) {
    if (std::strcmp(n, name) == 0) return true;
  }
  return false;
}

// One linear pass over the text before tinyxml2 sees it: every element's attribute count and
// value lengths within bounds, the element count too, and no character reference to a control
// character (tinyxml2 turns "a&#0;b" into "a", silently). Returns the line and the problem of
// the first breach (line 0: none). What is not well-formed is left to tinyxml2 to name.
std::pair<int, std::string> xml_shape_problem(const std::string& text);

// A <default> class: what it sets itself, by element kind, and the class it inherits from. A
// value is looked up along the chain of parents (at most 100 deep, as elements nest), so no class
// copies its parent's attributes.
struct DefaultClass {
  int parent = -1;
  std::string name;
  std::map<std::string, std::map<std::string, std::string>> own;
};

// <include> files: at most this deep, and this many in one model (each file once, as MuJoCo)
inline constexpr int kMaxIncludeDepth = 8;
inline constexpr int kMaxIncludedFiles = 64;

class Reader {
 public:
  Reader(std::string source, const ReadOptions& options)
      : source_(std::move(source)), options_(options) {}

  Model read(const std::string& text, std::string* note);

 private:
  // MuJoCo takes any text as the model's name ("planar walker"); the model's names are within
  // a charset (detail::name_problem), so every other byte becomes '_' and the name is cut to
  // its longest (an empty name is "mjcf")
  static std::string model_name(const std::string& text);

  // where an element is: its file and line
  std::string where(const XMLElement* e) const;

  [[noreturn]] void fail(const XMLElement* e, const std::string& problem) const;

  // One file's text checked and parsed: its root element. The documents live as long as the
  // reader, each with the name it is reported by
  const XMLElement* parse_document(const std::string& text, const std::string& source);

  // An element's child elements, each <include> replaced by the children of its file's root, as
  // MuJoCo splices them in (recursively: an included file may include)
  std::vector<const XMLElement*> children(const XMLElement* e);

  // The file an <include> names: resolved from the including file's folder, checked to lie in
  // the model's folder (unless the options allow more), read once (an element is read once
  // however often its parent's children are listed), and not a file read before
  const XMLElement* included_root(const XMLElement* include);

  // An element the testbed does not model, whose absence leaves the passive dynamics MuJoCo's:
  // counted for the note, or refused when reading strictly
  void skip(const XMLElement* e);

  // An actuator with no control applies no force when nothing but its control drives it (a
  // motor; a general actuator without bias; an adhesion); one with a bias (a position or
  // velocity servo, a damper, a muscle) is a spring or a damper even at rest
  void read_actuator(const XMLElement* e);

  // A tendon without stiffness, damping, friction loss or limit does nothing by itself
  void read_tendon(const XMLElement* e);

  // Outside its one root element an XML document holds only comments, whitespace and, first, a
  // declaration. tinyxml2 also keeps text before the root, CDATA and a closing tag after it, a
  // second byte-order mark and a DOCTYPE there; MuJoCo's reader takes some of those. None is
  // MJCF, and a DOCTYPE's entities would be read unexpanded, so each is refused.
  void check_outside_root(const tinyxml2::XMLDocument& doc, const std::string& source) const;

  // bounded, single-line text from the file for messages
  static std::string one_line(const std::string& text);

  // that v's norm is within the model's limits (a rotation or an axis as given)
  template <typename V>
  void check_norm(const XMLElement* e, const char* what, const V& v) const {
    if (std::string problem = detail::norm_problem(v); !problem.empty()) {
      fail(e, std::string(what) + " " + problem);
    }
  }
  // v normalised, when its norm is within the model's limits
  template <typename V>
  V unit(const XMLElement* e, const char* what, const V& v) const {
    check_norm(e, what, v);
    return detail::normalized(v);
  }

  void check_attributes(const XMLElement* e, Names known) const;

  // a site, camera or light: nothing that moves the body, but what it says is MJCF
  void check_ornament(const XMLElement* e);

  // a boolean attribute: "true" or "false" (MJCF's spelling), else refused
  std::optional<bool> boolean(const XMLElement* e, const char* key) const;

  static std::optional<std::string> attribute(const XMLElement* e, const char* key);

  // an attribute of a body element, else its class's default
  std::optional<std::string> value(const XMLElement* e, const char* key,
                                   const std::string& class_name) const;

  // where a value value() finds came from, for a refusal: " (set by default class \"limb\")"
  // when a class gave it, empty when the element itself did (or nothing)
  std::string set_by(const XMLElement* e, const char* key, const std::string& class_name) const;

  // exactly one number (an empty attribute, or two numbers, is refused)
  double single(const XMLElement* e, const char* key, const std::string& text) const;

  std::vector<double> numbers(const XMLElement* e, const char* key, const std::string& text) const;

  std::vector<double> numbers(const XMLElement* e, const char* key, const std::string& class_name,
                              size_t count, std::vector<double> fallback) const;

  Vector3d vector3(const XMLElement* e, const char* key, const std::string& class_name,
                   const Vector3d& fallback) const;

  double angle(double x) const { return degrees_ ? x * kPi / 180.0 : x; }

  // The element's orientation in its parent's frame, as MuJoCo 2.2.2 compiles it
  // (mjCAlternative::Set): where the element gives none of quat, axisangle, xyaxes, zaxis and
  // euler, it takes its class's; the quat is the base, and each alternative that is set, in that
  // order, replaces it. So a class's euler outranks an element's own quat, as in MuJoCo. One
  // element (or one class's element) gives at most one of them.
  Quaterniond orientation(const XMLElement* e, const std::string& class_name) const;

  // at most one orientation on one element, a default class's among them (MuJoCo refuses more)
  void check_one_orientation(const XMLElement* e) const;

  void read_compiler(const XMLElement* e);

  void read_option(const XMLElement* e);

  // MuJoCo's switches: gravity off is a model without gravity; limits off (or every constraint
  // off) are joints without limits. Contacts are the scenarios' (they decide the ground), and the
  // switches of what the testbed does not model (equality, friction loss, passive forces,
  // actuation, sensors) or that change nothing here (energy, warm start...) are taken as they
  // are
  void read_flags(const XMLElement* e);

  void read_size(const XMLElement* e);

  // A <default> class. The top-level ones are all "main" (MuJoCo merges them), and a kind given
  // twice in one class is merged too, the later value of an attribute replacing the earlier. The
  // kinds that only set up what this reader skips or refuses (actuators, tendons, meshes...) are
  // taken as they are
  void read_default(const XMLElement* e, const std::string& name, int parent);

  std::string class_of(const XMLElement* e, const std::string& inherited) const;

  // The <worldbody> sections, merged: one body tree (its root on a free joint), and what the
  // world holds besides: a floor plane (the scenarios decide whether there is ground), lights,
  // cameras and sites
  void read_world(const std::vector<const XMLElement*>& worlds);

  // every name a body of the tree gives itself: the names generated for the others avoid them
  void collect_body_names(const XMLElement* body);

  void read_body(const XMLElement* e, int parent, const Vector3d& parent_x,
                 const Quaterniond& parent_q, const std::string& inherited_class);

  bool is_free(const XMLElement* joint, const std::string& class_name) const;

  // A free root: whatever MuJoCo reads on it that leaves its six degrees of freedom free.
  // <freejoint> takes no class; a <joint type="free"> takes its class's values, and its damping,
  // armature, stiffness and friction loss must be zero, and it must not be limited (its range and
  // margin mean nothing to MuJoCo on a free joint)
  void check_free(const XMLElement* joint, const std::string& class_name) const;

  // A geom as a solid of its body: its shape placed in the body frame, and its mass (its own,
  // or its density times its volume, as MuJoCo's compiler takes it)
  struct Solid {
    Shape shape;
    double mass = 0.0;
  };

  Solid read_geom(const XMLElement* geom, const std::string& class_name) const;

  // The segment of a body in world (x, q): its shapes, and its mass and inertia from its
  // <inertial>, else composed from its geoms as MuJoCo composes them (detail::place_solids: one
  // geom gives its own frame, several their principal frame at their centre of mass)
  Segment read_segment(const XMLElement* body, const std::vector<const XMLElement*>& geoms,
                       const XMLElement* inertial, const Vector3d& x, const Quaterniond& q,
                       const std::string& class_name);

  // The compiler's options on mass and inertia, as MuJoCo 2.2.2 applies them: each body's mass
  // and moments raised to boundmass and boundinertia, moments that break the triangle inequality
  // set to their mean with balanceinertia (A + B < C is refused otherwise, by the model's
  // checks), then every mass and moment scaled so that the total is settotalmass
  void apply_mass_options();

  // the inertial's mass, its frame in the body (centre and axes) and its principal moments: a
  // diaginertia is about its own axes, a fullinertia (in the body's axes) is diagonalised
  void read_inertial(const XMLElement* e, Segment& s, Vector3d* centre, Quaterniond* frame) const;

  // A quaternion from user data: taken as it is when it is a unit quaternion to rounding (as
  // write_mjcf writes them: normalising again would change its last bits, and an exported file
  // read back and exported again would differ), normalised otherwise
  static Quaterniond unit_quaternion(const Quaterniond& q);

  // an element's user data when the file declares at least `size` numbers per element (size's
  // nuser_body, nuser_jnt) and the element gives them
  std::optional<std::vector<double>> user_data(const XMLElement* e, int declared, int size,
                                               const std::string& class_name = "") const;

  // What a <joint> below the root says before its type is read: its name, point, range (rad)
  // and user data; for a hinge its axis in world and its range checked (±π when unlimited)
  // a lone hinge's rest pose turned into its range: by what angle (rad), and the note that says why
  struct RestTurn {
    double angle = 0.0;
    const char* why = nullptr;
  };
  struct JointElement {
    std::string name, type;
    Vector3d anchor_world{0, 0, 0};
    bool limited = false;
    std::vector<double> range;
    std::optional<std::vector<double>> user;
    Vector3d axis_world{0, 0, 1};
    double lower = -kPi, upper = kPi;
    // stiffness, damping and (a hinge's) springref less ref: the testbed's angles start at 0 in
    // the body's pose as written, MuJoCo's hinge at ref
    JointPassive spring;
    // a lone hinge whose range leaves out the pose as written (dm_control's hopper: its knee's
    // [5°, 150°]) or passes half a turn (dm_control's cheetah: its back foot's [-230°, 50°]):
    // the angle its rest pose turns it by, and by which the range and springref above were
    // moved (the rest is the testbed's angle 0)
    RestTurn rest_turn;
  };

  // may_turn: a hinge whose range leaves out the pose as written, or passes half a turn, gets a
  // rest_turn instead of a refusal (a lone hinge below the root; a box's and the root's ranges
  // must hold the pose, within half a turn)
  JointElement read_joint_element(const XMLElement* e, int child, const Vector3d& x,
                                  const Quaterniond& q, const std::string& class_name,
                                  bool may_turn = false) const;

  // write_mjcf's exact rest anchor, if it still matches the joint's pos
  Vector3d user_anchor(const XMLElement* e, const std::vector<double>& u,
                       const Vector3d& anchor_world) const;

  // Three hinges in one body, at one point, about orthogonal axes: MuJoCo turns the body by
  // R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂), a ball joint with a box limit (euler_box.h) whose frame has
  // the axes as its columns in the order x, y, z (the third negated, with its range, if they
  // are left-handed). Two hinges are such a box whose third angle, about a₀ × a₁, is held at 0.
  // With user data on each (as export-mjcf writes it) the frame, the order and the anchor are
  // the exact ones; a name "<joint>:x" ... gives the joint's name.
  detail::RawJoint read_box(const std::vector<const XMLElement*>& hinges, int child, int parent,
                            const Vector3d& x, const Quaterniond& q, const std::string& class_name);

  // The root body's joints as the world's hold on it (RootJoint, model.h): one free joint (checked
  // by check_free), none (a weld), one hinge, slide or unlimited ball, or slide, slide, hinge about
  // orthogonal axes (a planar root). Its anchor in the root's frame is set once the root is placed.
  RootJoint read_root(const std::vector<const XMLElement*>& joints, const Vector3d& x,
                      const Quaterniond& q, const std::string& class_name);

  // one joint, or none (a weld); *rest_turn is its JointElement's (no angle but for a turned hinge)
  detail::RawJoint read_joint(const XMLElement* body, const XMLElement* e, int child, int parent,
                              const Vector3d& x, const Quaterniond& q,
                              const std::string& class_name, RestTurn* rest_turn);

  std::string source_;
  std::string name_;
  int root_line_ = 1;
  bool degrees_ = true;  // MuJoCo's default
  std::string inertia_from_geom_ = "auto";
  std::string euler_sequence_ = "xyz";
  bool auto_limits_ = false;  // MuJoCo 2.2's default
  Vector3d gravity_{0.0, 0.0, -9.81};
  int user_body_ = 0, user_joint_ = 0;
  std::vector<DefaultClass> classes_;
  std::map<std::string, int> class_index_;
  std::vector<Segment> segments_;
  std::set<std::string> body_names_;
  std::vector<detail::RawJoint> joints_;
  RootJoint root_;            // the world's hold on the root body
  bool contact_off_ = false;  // <flag contact="disable">: no geom collides with anything
  std::vector<std::string> segment_where_, joint_where_;  // file:line
  ReadOptions options_;
  std::filesystem::path folder_;  // the model file's
  std::vector<std::unique_ptr<tinyxml2::XMLDocument>> documents_;
  std::map<const tinyxml2::XMLDocument*, std::string> sources_;
  std::map<const tinyxml2::XMLDocument*, int> depths_;       // of includes
  std::map<const XMLElement*, const XMLElement*> includes_;  // <include> → its file's root
  std::set<std::string> included_files_;
  std::map<std::string, int> skipped_;
  // compiler options on mass and inertia (MuJoCo's names; negative: not set)
  double bound_mass_ = 0.0, bound_inertia_ = 0.0, total_mass_ = -1.0;
  bool balance_inertia_ = false;
  bool gravity_off_ = false, limits_off_ = false;  // <option><flag>
  bool passive_off_ = false;  // <flag passive="disable">: no joint springs or dampers
  std::array<int, 2> inertia_groups_{0, 5};
};

}  // namespace puppet::mjcf
