// One element of a JSON model file, read field by field (model_loader.cpp): each typed read
// checks the value and fails with a ModelError naming the file, the element and the problem
#pragma once

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "model_builder.h"
#include "puppet/model/model.h"

namespace puppet::detail {

using nlohmann::json;

// reads typed fields of one JSON element and reports problems with its full name
class Element {
 public:
  Element(const json& value, std::string source, std::string where)
      : value_(value), source_(std::move(source)), where_(std::move(where)) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw ModelError(source_ + ": " + where_ + ": " + problem);
  }

  void require_object() const {
    if (!value_.is_object()) fail("must be a JSON object");
  }

  void reject_unknown(std::initializer_list<const char*> known,
                      std::initializer_list<const char*> also = {}) const {
    for (const auto& item : value_.items()) {
      // a named copy: C++20 lambdas may not capture structured bindings (clang refuses)
      const std::string& key = item.key();
      const auto is_key = [&](const char* k) { return key == k; };
      if (std::none_of(known.begin(), known.end(), is_key) &&
          std::none_of(also.begin(), also.end(), is_key)) {
        fail("unknown field " + shown(key));
      }
    }
  }

  bool has(const char* key) const { return value_.contains(key); }

  const json& field(const char* key) const {
    if (!value_.contains(key)) fail(std::string("missing field \"") + key + "\"");
    return value_.at(key);
  }

  std::string string(const char* key) const {
    const json& v = field(key);
    if (!v.is_string()) fail(std::string("field \"") + key + "\" must be a string");
    return v.get<std::string>();
  }

  double number(const char* key) const {
    const json& v = field(key);
    if (!v.is_number()) fail(std::string("field \"") + key + "\" must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(std::string("field \"") + key + "\" must be finite");
    return x;
  }

  double positive(const char* key) const {
    const double x = number(key);
    if (!(x > 0.0))
      fail(std::string("field \"") + key + "\" must be positive (got " + fmt(x) + ")");
    return x;
  }

  double non_negative(const char* key) const {
    const double x = number(key);
    if (x < 0.0)
      fail(std::string("field \"") + key + "\" must not be negative (got " + fmt(x) + ")");
    return x;
  }

  template <int N>
  Eigen::Matrix<double, N, 1> vector(const char* key) const {
    const json& v = field(key);
    if (!v.is_array() || v.size() != N) {
      fail(std::string("field \"") + key + "\" must be an array of " + std::to_string(N) +
           " numbers");
    }
    Eigen::Matrix<double, N, 1> out;
    for (int i = 0; i < N; ++i) {
      if (!v[i].is_number()) {
        fail(std::string("field \"") + key + "\" must be an array of " + std::to_string(N) +
             " numbers");
      }
      out[i] = v[i].get<double>();
      if (!std::isfinite(out[i])) fail(std::string("field \"") + key + "\" must be finite");
    }
    return out;
  }

  // a non-zero vector of N numbers, normalised (its norm within the model's limits)
  template <int N>
  Eigen::Matrix<double, N, 1> direction(const char* key) const {
    const Eigen::Matrix<double, N, 1> v = vector<N>(key);
    if (std::string problem = norm_problem(v); !problem.empty()) {
      fail(std::string("field \"") + key + "\" " + problem);
    }
    return normalized(v);
  }

  Quaterniond quaternion(const char* key) const {
    const Eigen::Vector4d wxyz = direction<4>(key);
    return Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  }

  // a name (of the model, a segment, a joint, or one referred to), within the model's charset
  std::string name(const char* key) const {
    std::string text = string(key);
    if (std::string problem = name_problem(text); !problem.empty()) {
      fail(std::string("field \"") + key + "\": " + problem);
    }
    return text;
  }

  Element child(const char* key, const std::string& name) const {
    return Element(field(key), source_, where_ + " " + name);
  }
  // an element of one of its arrays
  Element item(const json& value, const std::string& name) const {
    return Element(value, source_, where_ + " " + name);
  }

  const std::string& source() const { return source_; }

  static std::string fmt(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
  }

 private:
  const json& value_;
  std::string source_;
  std::string where_;
};

}  // namespace puppet::detail
