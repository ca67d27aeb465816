#include <nlohmann/json.hpp>

#include "puppet/model/model.h"

namespace puppet {

// Built through the same JSON path as a file, so a generated model is validated like any other.
Model make_chain(int n) {
  constexpr double kRadius = 0.025, kHalfLength = 0.1, kMass = 1.0;
  constexpr double kLength = 2.0 * (kRadius + kHalfLength);  // tip to tip
  nlohmann::json segments = nlohmann::json::array(), joints = nlohmann::json::array();
  for (int i = 0; i < n; ++i) {
    segments.push_back(
        {{"name", "link" + std::to_string(i)},
         {"mass", kMass},
         {"position", {0.0, 0.0, -0.5 * kLength - kLength * i}},
         {"shape", {{"type", "capsule"}, {"radius", kRadius}, {"half_length", kHalfLength}}}});
    if (i > 0) {
      joints.push_back({{"name", "ball" + std::to_string(i)},
                        {"parent", "link" + std::to_string(i - 1)},
                        {"child", "link" + std::to_string(i)},
                        {"anchor", {0.0, 0.0, -kLength * i}},
                        {"type", "ball"},
                        {"swing_deg", {180.0, 180.0}},
                        {"twist_deg", 180.0}});
    }
  }
  const std::string name = "chain:" + std::to_string(n);
  nlohmann::json model = {{"name", name}, {"segments", segments}, {"joints", joints}};
  return parse_model(model.dump(), name);
}

}  // namespace puppet
