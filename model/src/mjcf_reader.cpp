// MJCF in: an articulated body written for MuJoCo, read into the same Model the JSON files give
// (docs/mjcf.md lists what is read and what is refused). Every body is a segment with one geom;
// its joint (free on the root; one hinge or ball, or none for a weld, elsewhere) ties it to its
// parent. What the model cannot hold (actuators, tendons, equality constraints, several joints
// or geoms on one body, joint springs and damping...) is refused with the element and its line,
// never dropped. User data written by write_mjcf gives back the exact rest values.
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
#include <vector>

#include "model_builder.h"
#include "puppet/model/file.h"
#include "puppet/model/mjcf.h"

namespace puppet {
namespace {

using tinyxml2::XMLElement;

constexpr double kPi = 3.14159265358979323846;

// What a file may hold before tinyxml2 reads it (tinyxml2 checks each attribute against all the
// earlier ones of its element, so a body of 200,000 attributes would take minutes): the most
// attributes an MJCF element has is 33 (a geom), the longest value this reader needs a few
// hundred bytes (user data). Elements nest at most 100 deep (tinyxml2's own limit).
constexpr int kMaxAttributes = 64;
constexpr size_t kMaxAttributeBytes = 4096;
constexpr int kMaxElements = 1000000;

// The attributes each element this reader reads may carry: MuJoCo 2.2.2's own lists
// (xml_native_reader.cc), less what a body's physics here cannot hold (those are read and
// refused with a reason where they matter). In a <default> class the same lists hold without
// name and class.
using Names = std::initializer_list<const char*>;
constexpr Names kGeomAttributes = {
    "name",      "class",    "type",       "size",        "fromto",      "pos",      "quat",
    "axisangle", "euler",    "xyaxes",     "zaxis",       "mass",        "density",  "rgba",
    "material",  "group",    "contype",    "conaffinity", "condim",      "friction", "solref",
    "solimp",    "solmix",   "margin",     "gap",         "priority",    "user",     "mesh",
    "hfield",    "fitscale", "fluidshape", "fluidcoef",   "shellinertia"};
constexpr Names kJointAttributes = {
    "name",         "class", "type",      "pos",         "axis",        "range",
    "limited",      "ref",   "stiffness", "springref",   "damping",     "armature",
    "frictionloss", "group", "user",      "solreflimit", "solimplimit", "margin"};
constexpr Names kSiteAttributes = {"name",   "class",    "type",  "group",  "pos",
                                   "quat",   "material", "size",  "fromto", "axisangle",
                                   "xyaxes", "zaxis",    "euler", "rgba",   "user"};
constexpr Names kCameraAttributes = {"name", "class",     "fovy",   "ipd",   "pos",
                                     "quat", "axisangle", "xyaxes", "zaxis", "euler",
                                     "mode", "target",    "user"};
constexpr Names kLightAttributes = {"name",    "class",   "directional", "castshadow", "active",
                                    "pos",     "dir",     "attenuation", "cutoff",     "exponent",
                                    "ambient", "diffuse", "specular",    "mode",       "target"};
constexpr Names kMaterialAttributes = {"name",        "class",    "texture",  "texrepeat",
                                       "texuniform",  "emission", "specular", "shininess",
                                       "reflectance", "rgba"};
// what a <default> may also set: defaults of what this reader skips or refuses
constexpr Names kDefaultKindsElsewhere = {
    "mesh",     "pair",        "equality", "tendon",   "general", "motor",   "position",
    "velocity", "intvelocity", "damper",   "cylinder", "muscle",  "adhesion"};
constexpr Names kOrientationAttributes = {"quat", "axisangle", "xyaxes", "zaxis", "euler"};
constexpr Names kSizeAttributes = {"njmax",       "nconmax",    "nstack",       "nuserdata",
                                   "nkey",        "nuser_body", "nuser_jnt",    "nuser_geom",
                                   "nuser_site",  "nuser_cam",  "nuser_tendon", "nuser_actuator",
                                   "nuser_sensor"};

// the attributes an element kind may carry, for the kinds a <default> class may set (null for
// any other kind)
const Names* default_kind(const std::string& tag) {
  if (tag == "geom") return &kGeomAttributes;
  if (tag == "joint") return &kJointAttributes;
  if (tag == "site") return &kSiteAttributes;
  if (tag == "camera") return &kCameraAttributes;
  if (tag == "light") return &kLightAttributes;
  if (tag == "material") return &kMaterialAttributes;
  return nullptr;
}

bool among(const char* name, const Names& names) {
  for (const char* n : names) {
    if (std::strcmp(n, name) == 0) return true;
  }
  return false;
}

// One linear pass over the text before tinyxml2 sees it: every element's attribute count and
// value lengths within bounds, the element count too, and no character reference to a control
// character (tinyxml2 turns "a&#0;b" into "a", silently). Returns the line and the problem of
// the first breach (line 0: none). What is not well-formed is left to tinyxml2 to name.
std::pair<int, std::string> xml_shape_problem(const std::string& text) {
  int line = 1, elements = 0;
  const size_t n = text.size();
  auto skip_to = [&](size_t from, const char* end) {
    const size_t at = text.find(end, from);
    const size_t stop = at == std::string::npos ? n : at + std::strlen(end);
    line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(from),
                                        text.begin() + static_cast<std::ptrdiff_t>(stop), '\n'));
    return stop;
  };
  // a reference at i ("&...;"): one of XML's five entities (no DOCTYPE declares others, and
  // tinyxml2 would keep an unknown one as text), or a character reference to a character that
  // is not a control character, however many zeros pad it
  auto reference_problem = [&](size_t i) -> std::string {
    const size_t semicolon = text.find(';', i);
    const std::string shown =
        detail::printable(text.substr(i, semicolon == std::string::npos ? 12 : semicolon + 1 - i),
                          detail::kMaxNameLength);
    if (text.compare(i, 2, "&#") != 0) {
      for (const char* entity : {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"}) {
        if (text.compare(i, std::strlen(entity), entity) == 0) return {};
      }
      return "an entity reference XML does not define (" + shown + ")";
    }
    const bool hex = i + 2 < n && (text[i + 2] == 'x' || text[i + 2] == 'X');
    unsigned long code = 0;
    size_t k = i + (hex ? 3 : 2);
    for (; k < n && std::isxdigit(static_cast<unsigned char>(text[k])); ++k) {
      const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(text[k])));
      if (!hex && !std::isdigit(static_cast<unsigned char>(c))) break;
      const unsigned long digit = static_cast<unsigned long>(c <= '9' ? c - '0' : c - 'a' + 10);
      code = std::min(code * (hex ? 16 : 10) + digit, 0x110000UL);  // past Unicode: saturated
    }
    if (k < n && text[k] == ';' && (code < 0x20 || (code >= 0x7f && code <= 0x9f))) {
      return "a character reference to a control character (" + shown + ")";
    }
    return {};
  };
  int depth = 0;  // elements open
  size_t i = 0;
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '&') {
      if (std::string problem = reference_problem(i); !problem.empty()) return {line, problem};
      ++i;
    } else if (c != '<') {
      ++i;
    } else if (text.compare(i, 4, "<!--") == 0) {
      i = skip_to(i + 4, "-->");
    } else if (text.compare(i, 9, "<![CDATA[") == 0) {
      i = skip_to(i + 9, "]]>");
    } else if (text.compare(i, 2, "</") == 0) {
      // tinyxml2 drops a closing tag that closes nothing
      if (depth-- == 0) return {line, "a closing tag with no element open"};
      i = skip_to(i + 1, ">");
    } else if (text.compare(i, 2, "<?") == 0 || text.compare(i, 2, "<!") == 0) {
      i = skip_to(i + 1, ">");
    } else {
      // an element's start tag: its attributes are its '=' outside quoted values
      if (++elements > kMaxElements) {
        return {line, "more than " + std::to_string(kMaxElements) + " elements"};
      }
      const int tag_line = line;
      int attributes = 0;
      ++i;
      size_t name_end = i;
      while (name_end < n && name_end - i < detail::kMaxNameLength &&
             !std::isspace(static_cast<unsigned char>(text[name_end])) && text[name_end] != '>' &&
             text[name_end] != '/') {
        ++name_end;
      }
      const std::string tag =
          "<" + detail::printable(text.substr(i, name_end - i), detail::kMaxNameLength) + ">: ";
      while (i < n && text[i] != '>') {
        const char t = text[i];
        if (t == '\n') ++line;
        if (t == '=' && ++attributes > kMaxAttributes) {
          return {tag_line, tag + "more than " + std::to_string(kMaxAttributes) +
                                " attributes (an MJCF element has at most 33)"};
        }
        if (t == '"' || t == '\'') {
          const size_t close = text.find(t, i + 1);
          if (close == std::string::npos) return {0, {}};  // tinyxml2 names it
          if (close - i - 1 > kMaxAttributeBytes) {
            return {line, tag + "an attribute value of more than " +
                              std::to_string(kMaxAttributeBytes) + " bytes"};
          }
          for (size_t k = i + 1; k < close; ++k) {
            if (text[k] == '\n') ++line;
            if (text[k] == '&') {
              if (std::string problem = reference_problem(k); !problem.empty()) {
                return {line, tag + problem};
              }
            }
          }
          i = close;
        }
        ++i;
      }
      if (i < n && text[i - 1] != '/') ++depth;  // not an empty element ("<a/>")
    }
  }
  return {0, {}};
}

// A <default> class: what it sets itself, by element kind, and the class it inherits from. A
// value is looked up along the chain of parents (at most 100 deep, as elements nest), so no class
// copies its parent's attributes.
struct DefaultClass {
  int parent = -1;
  std::map<std::string, std::map<std::string, std::string>> own;
};

// <include> files: at most this deep, and this many in one model (each file once, as MuJoCo)
constexpr int kMaxIncludeDepth = 8;
constexpr int kMaxIncludedFiles = 64;

// What the testbed does not model and skips where the passive dynamics stay those MuJoCo
// computes (an actuator with no control, a sensor, a camera...): each kind counted for the note
std::string skipped_note(const std::map<std::string, int>& skipped) {
  std::string note;
  for (const auto& [kind, count] : skipped) {
    note += (note.empty() ? "" : ", ") + std::to_string(count) + " <" + kind + ">";
  }
  return note;
}

class Reader {
 public:
  Reader(std::string source, const ReadOptions& options)
      : source_(std::move(source)), options_(options) {}

  Model read(const std::string& text, std::string* note) {
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
          return segment_where_[index] + ": <body name=\"" + one_line(segments_[index].name) +
                 "\">";
        case detail::Part::kJoint:
          return joint_where_[index] + ": <joint name=\"" + one_line(joints_[index].joint.name) +
                 "\">";
        case detail::Part::kModel:
          break;
      }
      return source_ + ":" + std::to_string(root_line_) + ": <mujoco>";
    };
    // copies: locate reads the members while assemble consumes its arguments
    Model model = detail::assemble(name_, segments_, joints_, locate);
    model.gravity = gravity_off_ ? Vector3d::Zero() : gravity_;
    if (note) *note = skipped_note(skipped_);
    return model;
  }

 private:
  // MuJoCo takes any text as the model's name ("planar walker"); the model's names are within
  // a charset (detail::name_problem), so every other byte becomes '_' and the name is cut to
  // its longest (an empty name is "mjcf")
  static std::string model_name(const std::string& text) {
    std::string name = text.substr(0, detail::kMaxNameLength);
    for (char& c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.' &&
          c != ':') {
        c = '_';
      }
    }
    return name.empty() ? "mjcf" : name;
  }

  // where an element is: its file and line
  std::string where(const XMLElement* e) const {
    return sources_.at(e->GetDocument()) + ":" + std::to_string(e->GetLineNum());
  }

  [[noreturn]] void fail(const XMLElement* e, const std::string& problem) const {
    std::string what = "<" + one_line(e->Name());
    if (const char* n = e->Attribute("name")) what += " name=\"" + one_line(n) + "\"";
    // the problem may quote the file (a class name, a value): printable, and bounded
    throw ModelError(where(e) + ": " + what + ">: " + detail::printable(problem, 200));
  }

  // One file's text checked and parsed: its root element. The documents live as long as the
  // reader, each with the name it is reported by
  const XMLElement* parse_document(const std::string& text, const std::string& source) {
    if (std::string problem = detail::text_problem(text); !problem.empty()) {
      throw ModelError(source + ": " + problem);
    }
    if (const auto [line, problem] = xml_shape_problem(text); line > 0) {
      throw ModelError(source + ":" + std::to_string(line) + ": " + problem);
    }
    auto doc = std::make_unique<tinyxml2::XMLDocument>();
    if (doc->Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
      // "XML_ERROR_MISMATCHED_ELEMENT" → "mismatched element"
      std::string what = doc->ErrorName();
      if (what.rfind("XML_ERROR_", 0) == 0) what = what.substr(10);
      for (char& c : what) c = c == '_' ? ' ' : static_cast<char>(std::tolower(c));
      throw ModelError(source + ":" + std::to_string(doc->ErrorLineNum()) +
                       ": malformed XML: " + what);
    }
    const XMLElement* root = doc->RootElement();
    if (root == nullptr) throw ModelError(source + ":1: malformed XML: no element");
    check_outside_root(*doc, source);
    sources_[doc.get()] = source;
    documents_.push_back(std::move(doc));
    if (const XMLElement* second = root->NextSiblingElement()) {
      fail(second, "a second root element (a file holds one <mujoco>)");
    }
    return root;
  }

  // An element's child elements, each <include> replaced by the children of its file's root, as
  // MuJoCo splices them in (recursively: an included file may include)
  std::vector<const XMLElement*> children(const XMLElement* e) {
    std::vector<const XMLElement*> out;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::string(c->Name()) != "include") {
        out.push_back(c);
        continue;
      }
      for (const XMLElement* k : children(included_root(c))) out.push_back(k);
    }
    return out;
  }

  // The file an <include> names: resolved from the including file's folder, checked to lie in
  // the model's folder (unless the options allow more), read once (an element is read once
  // however often its parent's children are listed), and not a file read before
  const XMLElement* included_root(const XMLElement* include) {
    if (auto known = includes_.find(include); known != includes_.end()) return known->second;
    check_attributes(include, {"file"});
    if (include->FirstChild()) fail(include, "an <include> has no content");
    const auto file = attribute(include, "file");
    if (!file || file->empty()) fail(include, "needs a file");
    const std::string& from = sources_.at(include->GetDocument());
    const int depth = depths_[include->GetDocument()] + 1;
    if (depth > kMaxIncludeDepth) {
      fail(include, "includes nest more than " + std::to_string(kMaxIncludeDepth) + " deep");
    }
    if (static_cast<int>(includes_.size()) >= kMaxIncludedFiles) {
      fail(include, "more than " + std::to_string(kMaxIncludedFiles) + " included files");
    }
    namespace fs = std::filesystem;
    const fs::path path = (fs::path(from).parent_path() / *file).lexically_normal();
    // MuJoCo 2.2.2 reads every include's path from the top file's folder: where the two
    // readings name different files the model means one thing to MuJoCo and another here
    const fs::path mujocos = (folder_ / *file).lexically_normal();
    std::error_code error;
    const fs::path real = fs::weakly_canonical(path, error);
    if (error) fail(include, "cannot resolve \"" + one_line(*file) + "\"");
    if (real != fs::weakly_canonical(mujocos, error)) {
      fail(include, "\"" + one_line(*file) +
                        "\" names another file from the model's folder, where MuJoCo 2.2.2 reads "
                        "it (write it from there)");
    }
    const fs::path top = fs::weakly_canonical(folder_.empty() ? fs::path(".") : folder_, error);
    const auto [end, _] = std::mismatch(top.begin(), top.end(), real.begin(), real.end());
    if (end != top.end() && !options_.include_outside) {
      fail(include, "\"" + one_line(*file) +
                        "\" is outside the model's folder (--include-outside allows it)");
    }
    if (!included_files_.insert(real.string()).second) {
      fail(include, "\"" + one_line(*file) + "\" is included a second time");
    }
    std::string text, problem;
    if (!read_regular_file(path.string(), detail::kMaxFileBytes, &text, &problem)) {
      fail(include, "cannot read \"" + one_line(*file) + "\": " + problem);
    }
    const XMLElement* root = parse_document(text, path.string());
    depths_[root->GetDocument()] = depth;
    if (!root->FirstChildElement()) fail(include, "\"" + one_line(*file) + "\" is empty");
    includes_[include] = root;
    return root;
  }

  // An element the testbed does not model, whose absence leaves the passive dynamics MuJoCo's:
  // counted for the note, or refused when reading strictly
  void skip(const XMLElement* e) {
    if (options_.strict) fail(e, "is not modelled by the testbed (skipped unless --strict)");
    ++skipped_[e->Name()];
  }

  // An actuator with no control applies no force when nothing but its control drives it (a
  // motor; a general actuator without bias; an adhesion); one with a bias (a position or
  // velocity servo, a damper, a muscle) is a spring or a damper even at rest
  void read_actuator(const XMLElement* e) {
    const std::string tag = e->Name();
    if (tag == "motor" || tag == "adhesion") return skip(e);
    if (tag == "general") {
      const std::string bias = attribute(e, "biastype").value_or("none");
      if (bias == "none") return skip(e);
    }
    fail(e, "is not supported: this actuator acts as a spring or a damper without a control");
  }

  // A tendon without stiffness, damping, friction loss or limit does nothing by itself
  void read_tendon(const XMLElement* e) {
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

  // Outside its one root element an XML document holds only comments, whitespace and, first, a
  // declaration. tinyxml2 also keeps text before the root, CDATA and a closing tag after it, a
  // second byte-order mark and a DOCTYPE there; MuJoCo's reader takes some of those. None is
  // MJCF, and a DOCTYPE's entities would be read unexpanded, so each is refused.
  void check_outside_root(const tinyxml2::XMLDocument& doc, const std::string& source) const {
    for (const tinyxml2::XMLNode* node = doc.FirstChild(); node; node = node->NextSibling()) {
      if (node->ToElement() || node->ToComment()) continue;
      if (node->ToDeclaration() && node == doc.FirstChild()) continue;
      std::string what = node->ToDeclaration() ? "a declaration after the first node"
                         : node->ToUnknown()   ? "a DOCTYPE or other markup declaration"
                         : node->ToText() && node->ToText()->CData() ? "CDATA"
                                                                     : "text";
      throw ModelError(source + ":" + std::to_string(node->GetLineNum()) +
                       ": malformed XML: " + what + " outside the root element");
    }
  }

  // bounded, single-line text from the file for messages
  static std::string one_line(const std::string& text) {
    return detail::printable(text, detail::kMaxNameLength);
  }

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

  void check_attributes(const XMLElement* e, Names known) const {
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      if (!among(a->Name(), known)) {
        fail(e, "attribute \"" + one_line(a->Name()) + "\" is not supported");
      }
    }
  }

  // a site, camera or light: nothing that moves the body, but what it says is MJCF
  void check_ornament(const XMLElement* e) {
    check_attributes(e, *default_kind(e->Name()));
    if (e->FirstChildElement()) fail(e->FirstChildElement(), "is not supported here");
    if (std::string(e->Name()) != "site") skip(e);  // a site marks a point; nothing to note
  }

  // a boolean attribute: "true" or "false" (MJCF's spelling), else refused
  std::optional<bool> boolean(const XMLElement* e, const char* key) const {
    const auto v = attribute(e, key);
    if (!v) return std::nullopt;
    if (*v != "true" && *v != "false") fail(e, std::string(key) + " must be true or false");
    return *v == "true";
  }

  static std::optional<std::string> attribute(const XMLElement* e, const char* key) {
    const char* v = e->Attribute(key);
    return v ? std::optional<std::string>(v) : std::nullopt;
  }

  // an attribute of a body element, else its class's default
  std::optional<std::string> value(const XMLElement* e, const char* key,
                                   const std::string& class_name) const {
    if (auto v = attribute(e, key)) return v;
    const auto c = class_index_.find(class_name);
    for (int k = c == class_index_.end() ? -1 : c->second; k >= 0; k = classes_[k].parent) {
      const auto kind = classes_[k].own.find(e->Name());
      if (kind == classes_[k].own.end()) continue;
      const auto v = kind->second.find(key);
      if (v != kind->second.end()) return v->second;
    }
    return std::nullopt;
  }

  // exactly one number (an empty attribute, or two numbers, is refused)
  double single(const XMLElement* e, const char* key, const std::string& text) const {
    const std::vector<double> v = numbers(e, key, text);
    if (v.size() != 1) fail(e, std::string("attribute \"") + key + "\" must be one number");
    return v[0];
  }

  std::vector<double> numbers(const XMLElement* e, const char* key, const std::string& text) const {
    std::vector<double> out;
    const char* p = text.c_str();
    while (true) {
      while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
      if (*p == '\0') break;
      // decimal numbers only, whatever the locale: from_chars reads no hex ("0x10"), and inf
      // and nan are refused (a leading '+', which from_chars does not take, is skipped)
      if (*p == '+') ++p;
      double x = 0.0;
      const char* stop = p + std::strlen(p);
      const auto [end, error] = std::from_chars(p, stop, x);
      const bool separated =
          end == stop || *end == ' ' || *end == '\t' || *end == '\n' || *end == '\r';
      if (error == std::errc::result_out_of_range || (error == std::errc() && !std::isfinite(x))) {
        fail(e,
             std::string("attribute \"") + key + "\" must be finite (and within a double's range)");
      }
      if (error != std::errc() || !separated) {
        fail(e, std::string("attribute \"") + key + "\" must be numbers");
      }
      out.push_back(x);
      p = end;
    }
    return out;
  }

  std::vector<double> numbers(const XMLElement* e, const char* key, const std::string& class_name,
                              size_t count, std::vector<double> fallback) const {
    const auto text = value(e, key, class_name);
    if (!text) return fallback;
    std::vector<double> out = numbers(e, key, *text);
    if (out.size() != count) {
      fail(e, std::string("attribute \"") + key + "\" must have " + std::to_string(count) +
                  " numbers");
    }
    return out;
  }

  Vector3d vector3(const XMLElement* e, const char* key, const std::string& class_name,
                   const Vector3d& fallback) const {
    const auto v = numbers(e, key, class_name, 3, {fallback.x(), fallback.y(), fallback.z()});
    return {v[0], v[1], v[2]};
  }

  double angle(double x) const { return degrees_ ? x * kPi / 180.0 : x; }

  // The element's orientation in its parent's frame, as MuJoCo 2.2.2 compiles it
  // (mjCAlternative::Set): where the element gives none of quat, axisangle, xyaxes, zaxis and
  // euler, it takes its class's; the quat is the base, and each alternative that is set, in that
  // order, replaces it. So a class's euler outranks an element's own quat, as in MuJoCo. One
  // element (or one class's element) gives at most one of them.
  Quaterniond orientation(const XMLElement* e, const std::string& class_name) const {
    check_one_orientation(e);
    const auto quat = numbers(e, "quat", class_name, 4, {1, 0, 0, 0});
    check_norm(e, "quat", Eigen::Vector4d(quat[0], quat[1], quat[2], quat[3]));
    Quaterniond q(quat[0], quat[1], quat[2], quat[3]);
    if (value(e, "axisangle", class_name)) {
      const auto v = numbers(e, "axisangle", class_name, 4, {});
      const Vector3d axis = unit(e, "axisangle's axis", Vector3d(v[0], v[1], v[2]));
      q = Quaterniond(Eigen::AngleAxisd(angle(v[3]), axis));
    }
    if (value(e, "xyaxes", class_name)) {
      const auto v = numbers(e, "xyaxes", class_name, 6, {});
      const Vector3d x = unit(e, "xyaxes' x", Vector3d(v[0], v[1], v[2]));
      Vector3d y(v[3], v[4], v[5]);
      check_norm(e, "xyaxes' y", y);
      y -= x * x.dot(y);
      if (y.norm() < 1e-9) fail(e, "attribute \"xyaxes\": y is parallel to x");
      y.normalize();
      Matrix3d r;
      r << x, y, x.cross(y);
      q = Quaterniond(r);
    }
    if (value(e, "zaxis", class_name)) {
      const Vector3d z = unit(e, "zaxis", vector3(e, "zaxis", class_name, Vector3d::Zero()));
      q = Quaterniond::FromTwoVectors(Vector3d::UnitZ(), z);
    }
    if (value(e, "euler", class_name)) {
      const auto v = numbers(e, "euler", class_name, 3, {});
      q = Quaterniond::Identity();
      for (int i = 0; i < 3; ++i) {
        const char axis_name = euler_sequence_[i];
        const Vector3d axis = std::tolower(axis_name) == 'x'   ? Vector3d::UnitX()
                              : std::tolower(axis_name) == 'y' ? Vector3d::UnitY()
                                                               : Vector3d::UnitZ();
        const Quaterniond turn(Eigen::AngleAxisd(angle(v[i]), axis));
        // lower case: about the rotating axes; upper case: about the fixed ones
        q = std::islower(axis_name) ? Quaterniond(q * turn) : Quaterniond(turn * q);
      }
    }
    const Eigen::Vector4d unit_coeffs = detail::normalized(Eigen::Vector4d(q.coeffs()));
    return Quaterniond(unit_coeffs[3], unit_coeffs[0], unit_coeffs[1], unit_coeffs[2]);
  }

  // at most one orientation on one element, a default class's among them (MuJoCo refuses more)
  void check_one_orientation(const XMLElement* e) const {
    int given = 0;
    for (const char* key : kOrientationAttributes) given += e->Attribute(key) != nullptr;
    if (given > 1) fail(e, "gives its orientation more than once");
  }

  void read_compiler(const XMLElement* e) {
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

  void read_option(const XMLElement* e) {
    // the solver's own settings are each engine's; what the model is made of is read
    check_attributes(e, {"timestep",          "gravity",          "integrator",    "cone",
                         "jacobian",          "solver",           "iterations",    "tolerance",
                         "noslip_iterations", "mpr_iterations",   "collision",     "impratio",
                         "density",           "viscosity",        "wind",          "magnetic",
                         "apirate",           "noslip_tolerance", "mpr_tolerance", "o_margin",
                         "o_solref",          "o_solimp"});
    if (attribute(e, "gravity")) {
      gravity_ = vector3(e, "gravity", "", gravity_);
      if (std::string problem = detail::gravity_problem(gravity_); !problem.empty())
        fail(e, problem);
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

  // MuJoCo's switches: gravity off is a model without gravity; limits off (or every constraint
  // off) are joints without limits. Contacts are the scenarios' (they decide the ground), and the
  // switches of what the testbed does not model (equality, friction loss, passive forces,
  // actuation, sensors) or that change nothing here (energy, warm start...) are taken as they
  // are
  void read_flags(const XMLElement* e) {
    check_attributes(
        e, {"constraint", "equality", "frictionloss", "limit", "contact", "passive", "gravity",
            "clampctrl", "warmstart", "filterparent", "actuation", "refsafe", "sensor", "override",
            "energy", "fwdinv", "sensornoise", "multiccd"});
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
  }

  void read_size(const XMLElement* e) {
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

  // A <default> class. The top-level ones are all "main" (MuJoCo merges them), and a kind given
  // twice in one class is merged too, the later value of an attribute replacing the earlier. The
  // kinds that only set up what this reader skips or refuses (actuators, tendons, meshes...) are
  // taken as they are
  void read_default(const XMLElement* e, const std::string& name, int parent) {
    check_attributes(e, {"class"});
    int index = static_cast<int>(classes_.size());
    if (parent < 0 && class_index_.count("main")) {
      index = class_index_.at("main");
    } else {
      if (!class_index_.emplace(name, index).second) {
        fail(e, "a second default class \"" + one_line(name) + "\"");
      }
      classes_.push_back({parent, {}});
    }
    const std::vector<const XMLElement*> kinds = children(e);
    for (const XMLElement* c : kinds) {
      const std::string tag = c->Name();
      if (tag == "default") continue;
      const Names* known = default_kind(tag);
      if (!known) {
        if (among(tag.c_str(), kDefaultKindsElsewhere)) continue;
        fail(c, "is not an element a <default> sets");
      }
      if (c->FirstChildElement()) fail(c->FirstChildElement(), "is not supported here");
      auto& own = classes_[index].own[tag];
      check_one_orientation(c);
      for (const tinyxml2::XMLAttribute* a = c->FirstAttribute(); a; a = a->Next()) {
        if (!among(a->Name(), *known) || std::strcmp(a->Name(), "name") == 0 ||
            std::strcmp(a->Name(), "class") == 0) {
          fail(c, "attribute \"" + one_line(a->Name()) + "\" is not supported in a default");
        }
        own[a->Name()] = a->Value();
      }
    }
    for (const XMLElement* c : kinds) {
      if (std::string(c->Name()) != "default") continue;
      const auto child = attribute(c, "class");
      if (!child) fail(c, "a nested default needs a class");
      read_default(c, *child, index);
    }
  }

  std::string class_of(const XMLElement* e, const std::string& inherited) const {
    const auto c = attribute(e, "class");
    if (!c) return inherited;
    if (!class_index_.count(*c)) fail(e, "unknown class \"" + one_line(*c) + "\"");
    return *c;
  }

  // The <worldbody> sections, merged: one body tree (its root on a free joint), and what the
  // world holds besides: a floor plane (the scenarios decide whether there is ground), lights,
  // cameras and sites
  void read_world(const std::vector<const XMLElement*>& worlds) {
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
          if (value(e, "type", class_of(e, "main")).value_or("sphere") != "plane") {
            fail(e, "a geom on the world is not supported (only a floor plane, which is ignored)");
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

  // every name a body of the tree gives itself: the names generated for the others avoid them
  void collect_body_names(const XMLElement* body) {
    if (const char* n = body->Attribute("name")) body_names_.insert(n);
    for (const XMLElement* c : children(body)) {
      if (std::string(c->Name()) == "body") collect_body_names(c);
    }
  }

  void read_body(const XMLElement* e, int parent, const Vector3d& parent_x,
                 const Quaterniond& parent_q, const std::string& inherited_class) {
    check_attributes(e, {"name", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis",
                         "childclass", "user", "mocap"});
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
    // the body frame in world
    const Vector3d x = parent_x + parent_q * vector3(e, "pos", "", {0, 0, 0});
    const Quaterniond q = (parent_q * orientation(e, "")).normalized();

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
      if (joints.size() != 1 || !is_free(joints[0], child_class)) {
        fail(e, "the root body needs exactly one free joint (the scenarios hold it or let it go)");
      }
      check_free(joints[0], child_class);
    } else {
      if (joints.size() == 3) {
        joints_.push_back(read_box(joints, index, parent, x, q, child_class));
      } else if (joints.size() > 1) {
        fail(joints[1], "a second joint in body \"" + name +
                            "\" (one joint per body, or three hinges at one point for a box)");
      } else {
        joints_.push_back(
            read_joint(e, joints.empty() ? nullptr : joints[0], index, parent, x, q, child_class));
      }
    }
    for (const XMLElement* b : bodies) read_body(b, index, x, q, child_class);
  }

  bool is_free(const XMLElement* joint, const std::string& class_name) const {
    if (std::string(joint->Name()) == "freejoint") return true;
    return value(joint, "type", class_of(joint, class_name)).value_or("hinge") == "free";
  }

  // A free root: whatever MuJoCo reads on it that leaves its six degrees of freedom free.
  // <freejoint> takes no class; a <joint type="free"> takes its class's values, and its damping,
  // armature, stiffness and friction loss must be zero, and it must not be limited (its range and
  // margin mean nothing to MuJoCo on a free joint)
  void check_free(const XMLElement* joint, const std::string& class_name) const {
    if (std::string(joint->Name()) == "freejoint") {
      check_attributes(joint, {"name", "group"});
      return;
    }
    check_attributes(joint, kJointAttributes);
    const std::string cls = class_of(joint, class_name);
    for (const char* physics : {"damping", "armature", "stiffness", "frictionloss"}) {
      const auto v = value(joint, physics, cls);
      if (v && single(joint, physics, *v) != 0.0) {
        fail(joint, std::string(physics) + " on the free root is not supported");
      }
    }
    if (value(joint, "limited", cls).value_or("false") == "true") {
      fail(joint, "a limited free joint (MuJoCo refuses it too)");
    }
  }

  // A geom as a solid of its body: its shape placed in the body frame, and its mass (its own,
  // or its density times its volume, as MuJoCo's compiler takes it)
  struct Solid {
    Shape shape;
    double mass = 0.0;
  };

  Solid read_geom(const XMLElement* geom, const std::string& class_name) const {
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

  // The segment of a body in world (x, q): its shapes, and its mass and inertia from its
  // <inertial>, else composed from its geoms as MuJoCo composes them (detail::place_solids: one
  // geom gives its own frame, several their principal frame at their centre of mass)
  Segment read_segment(const XMLElement* body, const std::vector<const XMLElement*>& geoms,
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

  // The compiler's options on mass and inertia, as MuJoCo 2.2.2 applies them: each body's mass
  // and moments raised to boundmass and boundinertia, moments that break the triangle inequality
  // set to their mean with balanceinertia (A + B < C is refused otherwise, by the model's
  // checks), then every mass and moment scaled so that the total is settotalmass
  void apply_mass_options() {
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

  // the inertial's mass, its frame in the body (centre and axes) and its principal moments: a
  // diaginertia is about its own axes, a fullinertia (in the body's axes) is diagonalised
  void read_inertial(const XMLElement* e, Segment& s, Vector3d* centre, Quaterniond* frame) const {
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

  // A quaternion from user data: taken as it is when it is a unit quaternion to rounding (as
  // write_mjcf writes them: normalising again would change its last bits, and an exported file
  // read back and exported again would differ), normalised otherwise
  static Quaterniond unit_quaternion(const Quaterniond& q) {
    return std::abs(q.squaredNorm() - 1.0) <= 8.0 * std::numeric_limits<double>::epsilon()
               ? q
               : q.normalized();
  }

  // an element's user data when the file declares at least `size` numbers per element (size's
  // nuser_body, nuser_jnt) and the element gives them
  std::optional<std::vector<double>> user_data(const XMLElement* e, int declared, int size,
                                               const std::string& class_name = "") const {
    const auto text = value(e, "user", class_name);
    if (!text || declared < size) return std::nullopt;
    auto v = numbers(e, "user", *text);
    if (v.size() < static_cast<size_t>(size)) return std::nullopt;
    return v;
  }

  // What a <joint> below the root says before its type is read: its name, point, range (rad)
  // and user data; for a hinge its axis in world and its range checked (±π when unlimited)
  struct JointElement {
    std::string name, type;
    Vector3d anchor_world{0, 0, 0};
    bool limited = false;
    std::vector<double> range;
    std::optional<std::vector<double>> user;
    Vector3d axis_world{0, 0, 1};
    double lower = -kPi, upper = kPi;
  };

  JointElement read_joint_element(const XMLElement* e, int child, const Vector3d& x,
                                  const Quaterniond& q, const std::string& class_name) const {
    if (std::string(e->Name()) == "freejoint") fail(e, "a free joint below the root");
    const std::string cls = class_of(e, class_name);
    check_attributes(e, kJointAttributes);
    JointElement out;
    out.name = attribute(e, "name").value_or(segments_[child].name);
    if (std::string problem = detail::name_problem(out.name); !problem.empty()) fail(e, problem);
    for (const char* physics : {"stiffness", "damping", "armature", "frictionloss", "ref"}) {
      const auto v = value(e, physics, cls);
      if (v && single(e, physics, *v) != 0.0) {
        fail(e, std::string(physics) + " is not supported (the model's joints are ideal)");
      }
    }
    out.type = value(e, "type", cls).value_or("hinge");
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
    out.limited =
        !limits_off_ && (limited_text == "true" || (limited_text == "auto" && range_text));
    if (out.limited) {
      if (!range_text) fail(e, "limited but has no range");
      out.range = numbers(e, "range", *range_text);
      if (out.range.size() != 2) fail(e, "attribute \"range\" must have 2 numbers");
      out.range = {angle(out.range[0]), angle(out.range[1])};
    }
    out.user = user_data(e, user_joint_, kJointUserSize, cls);
    if (out.type == "hinge") {
      const Vector3d axis = vector3(e, "axis", cls, {0, 0, 1});
      check_norm(e, "axis", axis);
      out.axis_world = detail::normalized(Vector3d(q * axis));
      if (out.limited) {
        if (out.range[0] > out.range[1]) fail(e, "its range has lo > hi");
        if (out.range[0] > 0.0 || out.range[1] < 0.0) {
          fail(e, "its range must contain 0, the rest angle");
        }
        out.lower = std::max(out.range[0], -kPi);
        out.upper = std::min(out.range[1], kPi);
      }
    }
    return out;
  }

  // write_mjcf's exact rest anchor, if it still matches the joint's pos
  Vector3d user_anchor(const XMLElement* e, const std::vector<double>& u,
                       const Vector3d& anchor_world) const {
    const Vector3d anchor(u[0], u[1], u[2]);
    if ((anchor - anchor_world).norm() > 1e-6) {
      fail(e, "its user data (a rest anchor) disagrees with its pos");
    }
    return anchor;
  }

  // Three hinges in one body, at one point, about orthogonal axes: MuJoCo turns the body by
  // R(a₀, θ₀) R(a₁, θ₁) R(a₂, θ₂), a ball joint with a box limit (euler_box.h) whose frame has
  // the axes as its columns in the order x, y, z (the third negated, with its range, if they
  // are left-handed). With user data on all three (as export-mjcf writes it) the frame, the
  // order and the anchor are the exact ones; a name "<joint>:x" ... gives the joint's name.
  detail::RawJoint read_box(const std::vector<const XMLElement*>& hinges, int child, int parent,
                            const Vector3d& x, const Quaterniond& q,
                            const std::string& class_name) {
    detail::RawJoint raw;
    Joint& j = raw.joint;
    raw.parent_name = segments_[parent].name;
    raw.child_name = segments_[child].name;
    joint_where_.push_back(where(hinges[0]));
    std::array<JointElement, 3> h;
    for (int k = 0; k < 3; ++k) {
      h[k] = read_joint_element(hinges[k], child, x, q, class_name);
      if (h[k].type != "hinge") {
        fail(hinges[k], "several joints in one body are read only as three hinges (a box limit)");
      }
      if ((h[k].anchor_world - h[0].anchor_world).norm() > 1e-9) {
        fail(hinges[k], "a box limit's three hinges must share one pos");
      }
      for (int m = 0; m < k; ++m) {
        if (std::abs(h[k].axis_world.dot(h[m].axis_world)) > 1e-6) {
          fail(hinges[k], "a box limit's three hinges must have orthogonal axes");
        }
      }
    }
    j.type = JointType::kBall;
    j.ball_limit = BallLimit::kEulerBox;
    j.swing_x = j.swing_y = j.twist = kPi;
    j.anchor_world = h[0].anchor_world;
    for (int k = 0; k < 3; ++k) {
      j.box_lower[k] = h[k].lower;
      j.box_upper[k] = h[k].upper;
    }
    const std::string stem = h[0].name.substr(0, h[0].name.rfind(':'));
    j.name = h[0].name;
    for (int k = 0; k < 3; ++k) {
      const std::string& name = h[k].name;
      if (stem.empty() || name.size() != stem.size() + 2 || name.compare(0, stem.size(), stem) ||
          name[stem.size()] != ':') {
        break;
      }
      if (k == 2) j.name = stem;
    }
    if (h[0].user && h[1].user && h[2].user) {
      const auto& u = *h[0].user;
      j.anchor_world = user_anchor(hinges[0], u, j.anchor_world);
      j.frame_world = unit_quaternion(Quaterniond(u[3], u[4], u[5], u[6]));
      for (int k = 0; k < 3; ++k) {
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
      if (j.box_order.axes[0] == j.box_order.axes[1] ||
          j.box_order.axes[1] == j.box_order.axes[2] ||
          j.box_order.axes[2] == j.box_order.axes[0]) {
        fail(hinges[2], "its user data names a box frame's axis twice");
      }
    } else {
      Eigen::Matrix3d frame;
      frame << h[0].axis_world, h[1].axis_world, h[2].axis_world;
      if (frame.determinant() < 0.0) {
        frame.col(2) = -frame.col(2);
        j.box_lower[2] = -h[2].upper;
        j.box_upper[2] = -h[2].lower;
      }
      j.frame_world = Quaterniond(frame).normalized();
    }
    derive_limit_terms(j);
    return raw;
  }

  detail::RawJoint read_joint(const XMLElement* body, const XMLElement* e, int child, int parent,
                              const Vector3d& x, const Quaterniond& q,
                              const std::string& class_name) {
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
    const JointElement element = read_joint_element(e, child, x, q, class_name);
    j.name = element.name;
    j.anchor_world = element.anchor_world;
    const auto& user = element.user;
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
    } else {
      fail(e, "type \"" + one_line(element.type) +
                  "\" is not supported below the root (hinge or ball)");
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
  std::array<int, 2> inertia_groups_{0, 5};
};

}  // namespace

Model parse_mjcf(const std::string& xml_text, const std::string& source, const ReadOptions& options,
                 std::string* note) {
  return Reader(source, options).read(xml_text, note);
}

}  // namespace puppet
