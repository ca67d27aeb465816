// MJCF's XML (mjcf_reader.h): the text's bounds before tinyxml2 reads it, the files and their
// <include>s, each attribute read through the default classes, numbers and orientations
#include "mjcf_reader.h"

namespace puppet::mjcf {

// What a file may hold before tinyxml2 reads it (tinyxml2 checks each attribute against all the
// earlier ones of its element, so a body of 200,000 attributes would take minutes): the most
// attributes an MJCF element has is 33 (a geom), the longest value this reader needs a few
// hundred bytes (user data). Elements nest at most 100 deep (tinyxml2's own limit).
constexpr int kMaxAttributes = 64;
constexpr size_t kMaxAttributeBytes = 4096;
constexpr int kMaxElements = 1000000;

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
      // appended, not "<" + ...: GCC 12 warns of an overlap in that temporary (-Wrestrict, a
      // false positive of its own) once this function is not file-local
      std::string tag = "<";
      tag += detail::printable(text.substr(i, name_end - i), detail::kMaxNameLength);
      tag += ">: ";
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

std::string Reader::where(const XMLElement* e) const {
  return sources_.at(e->GetDocument()) + ":" + std::to_string(e->GetLineNum());
}

[[noreturn]] void Reader::fail(const XMLElement* e, const std::string& problem) const {
  std::string what = "<" + one_line(e->Name());
  if (const char* n = e->Attribute("name")) what += " name=\"" + one_line(n) + "\"";
  // the problem may quote the file (a class name, a value): printable, and bounded
  throw ModelError(where(e) + ": " + what + ">: " + detail::printable(problem, 200));
}

const XMLElement* Reader::parse_document(const std::string& text, const std::string& source) {
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

std::vector<const XMLElement*> Reader::children(const XMLElement* e) {
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

const XMLElement* Reader::included_root(const XMLElement* include) {
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
  // made absolute first: weakly_canonical leaves a relative path to a missing file relative, and
  // it would then read as outside the (absolute) folder
  std::error_code error;
  const fs::path real = fs::weakly_canonical(fs::absolute(path, error), error);
  if (error) fail(include, "cannot resolve \"" + one_line(*file) + "\"");
  if (real != fs::weakly_canonical(fs::absolute(mujocos, error), error)) {
    fail(include, "\"" + one_line(*file) +
                      "\" names another file from the model's folder, where MuJoCo 2.2.2 reads "
                      "it (write it from there)");
  }
  const fs::path top =
      fs::weakly_canonical(fs::absolute(folder_.empty() ? fs::path(".") : folder_, error), error);
  const auto [end, _] = std::mismatch(top.begin(), top.end(), real.begin(), real.end());
  if (end != top.end() && !options_.include_outside) {
    fail(include,
         "\"" + one_line(*file) + "\" is outside the model's folder (--include-outside allows it)");
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

void Reader::check_outside_root(const tinyxml2::XMLDocument& doc, const std::string& source) const {
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

std::string Reader::one_line(const std::string& text) {
  return detail::printable(text, detail::kMaxNameLength);
}

void Reader::check_attributes(const XMLElement* e, Names known) const {
  for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
    if (!among(a->Name(), known)) {
      fail(e, "attribute \"" + one_line(a->Name()) + "\" is not supported");
    }
  }
}

void Reader::check_ornament(const XMLElement* e) {
  check_attributes(e, *default_kind(e->Name()));
  if (e->FirstChildElement()) fail(e->FirstChildElement(), "is not supported here");
  if (std::string(e->Name()) != "site") skip(e);  // a site marks a point; nothing to note
}

std::optional<bool> Reader::boolean(const XMLElement* e, const char* key) const {
  const auto v = attribute(e, key);
  if (!v) return std::nullopt;
  if (*v != "true" && *v != "false") fail(e, std::string(key) + " must be true or false");
  return *v == "true";
}

std::optional<std::string> Reader::attribute(const XMLElement* e, const char* key) {
  const char* v = e->Attribute(key);
  return v ? std::optional<std::string>(v) : std::nullopt;
}

std::optional<std::string> Reader::value(const XMLElement* e, const char* key,
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

std::string Reader::set_by(const XMLElement* e, const char* key,
                           const std::string& class_name) const {
  if (attribute(e, key)) return {};
  const auto c = class_index_.find(class_name);
  for (int k = c == class_index_.end() ? -1 : c->second; k >= 0; k = classes_[k].parent) {
    const auto kind = classes_[k].own.find(e->Name());
    if (kind != classes_[k].own.end() && kind->second.count(key)) {
      return " (set by default class \"" + one_line(classes_[k].name) + "\")";
    }
  }
  return {};
}

double Reader::single(const XMLElement* e, const char* key, const std::string& text) const {
  const std::vector<double> v = numbers(e, key, text);
  if (v.size() != 1) fail(e, std::string("attribute \"") + key + "\" must be one number");
  return v[0];
}

std::vector<double> Reader::numbers(const XMLElement* e, const char* key,
                                    const std::string& text) const {
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

std::vector<double> Reader::numbers(const XMLElement* e, const char* key,
                                    const std::string& class_name, size_t count,
                                    std::vector<double> fallback) const {
  const auto text = value(e, key, class_name);
  if (!text) return fallback;
  std::vector<double> out = numbers(e, key, *text);
  if (out.size() != count) {
    fail(e,
         std::string("attribute \"") + key + "\" must have " + std::to_string(count) + " numbers");
  }
  return out;
}

Vector3d Reader::vector3(const XMLElement* e, const char* key, const std::string& class_name,
                         const Vector3d& fallback) const {
  const auto v = numbers(e, key, class_name, 3, {fallback.x(), fallback.y(), fallback.z()});
  return {v[0], v[1], v[2]};
}

Quaterniond Reader::orientation(const XMLElement* e, const std::string& class_name) const {
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

void Reader::check_one_orientation(const XMLElement* e) const {
  int given = 0;
  for (const char* key : kOrientationAttributes) given += e->Attribute(key) != nullptr;
  if (given > 1) fail(e, "gives its orientation more than once");
}

void Reader::read_default(const XMLElement* e, const std::string& name, int parent) {
  check_attributes(e, {"class"});
  int index = static_cast<int>(classes_.size());
  if (parent < 0 && class_index_.count("main")) {
    index = class_index_.at("main");
  } else {
    if (!class_index_.emplace(name, index).second) {
      fail(e, "a second default class \"" + one_line(name) + "\"");
    }
    classes_.push_back({parent, name, {}});
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

std::string Reader::class_of(const XMLElement* e, const std::string& inherited) const {
  const auto c = attribute(e, "class");
  if (!c) return inherited;
  if (!class_index_.count(*c)) fail(e, "unknown class \"" + one_line(*c) + "\"");
  return *c;
}

}  // namespace puppet::mjcf
