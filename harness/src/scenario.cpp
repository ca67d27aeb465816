// The scenarios' shared parts: target paths, pins, what a scenario conserves, the built-in
// model. The scenarios themselves are one file each under scenarios/ (catalogue.cpp lists them).
#include "puppet/compare/scenario.h"

#include "puppet/model/text.h"
#include "puppet/model/user_forces.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

namespace puppet::compare {
namespace {

constexpr double kRampSeconds = 0.5;  // the targets' smoothstep ramp

}  // namespace

void Scenario::targets_at(double t, std::vector<Vector3d>& out) const {
  out.resize(pins.size());
  const double u = std::clamp(t / kRampSeconds, 0.0, 1.0);
  const double ramp = u * u * (3.0 - 2.0 * u);
  for (size_t i = 0; i < pins.size(); ++i) {
    const PinPath& p = pins[i];
    const double angle = p.phase + 2.0 * M_PI * p.hz * t;
    Vector3d offset{0, 0, 0};
    switch (p.path) {
      case TargetPath::kFixed:
        break;
      case TargetPath::kCircle:
        // a circle whose lowest point is the initial point, going forward (+x) first from
        // there; a phase starts the target further round the same circle (the ramp brings it in)
        offset = p.radius * Vector3d(std::sin(angle), 0.0, 1.0 - std::cos(angle));
        break;
      case TargetPath::kShakeX:
        offset = p.radius * Vector3d(std::sin(angle), 0.0, 0.0);
        break;
    }
    out[i] = p.pin.target + ramp * offset;
  }
}

std::vector<Pin> Scenario::initial_pins() const {
  std::vector<Pin> out;
  for (const PinPath& p : pins) out.push_back(p.pin);
  return out;
}

bool Scenario::conserves_energy() const {
  const bool pins_fixed = std::all_of(
      pins.begin(), pins.end(), [](const PinPath& p) { return p.path == TargetPath::kFixed; });
  return pins_fixed && environment.air_drag == 0.0 && !environment.water && !environment.ground &&
         !environment.tremble;
}

bool Scenario::conserves_momentum() const {
  return conserves_energy() && pins.empty() && !root_held && environment.gravity.isZero();
}

GrabSpring grab_spring(const Model& model, const GrabSettings& settings) {
  return {.hz = settings.hz,
          .damping_ratio = settings.damping_ratio,
          .max_force = settings.cap_weights * model.total_mass * kStandardGravity};
}

std::optional<ScenarioError> grab_settings_problem(const GrabSettings& settings) {
  // bounds a user meets only by a slip: a spring faster than any step resolves, a damper past a
  // thousand times critical, a cap of a thousand figures
  if (!(settings.hz > 0.0 && settings.hz <= 1e3)) {
    return ScenarioError("expected a frequency in (0, 1000] Hz", "grab_hz");
  }
  if (!(settings.damping_ratio >= 0.0 && settings.damping_ratio <= 1e3)) {
    return ScenarioError("expected a damping ratio in [0, 1000]", "grab_ratio");
  }
  if (!(settings.cap_weights > 0.0 && settings.cap_weights <= 1e3)) {
    return ScenarioError("expected a force cap in (0, 1000] figure weights", "grab_cap");
  }
  return std::nullopt;
}

namespace {

// a segment's way up the tree: (segment, the joint into it from its parent), from it to the root
std::vector<std::pair<int, int>> way_up(const Model& model, int segment) {
  std::vector<std::pair<int, int>> out;
  for (int s = segment; s >= 0;) {
    int into = -1;
    for (int j = 0; j < model.joint_count(); ++j) {
      if (model.joints[j].child == s) into = j;
    }
    out.emplace_back(s, into);
    s = into >= 0 ? model.joints[into].parent : -1;
  }
  return out;
}

// the span of the chain of segments from pin a's point to pin b's point
double chain_span(const Model& model, const Pin& a, const Pin& b) {
  const auto up_a = way_up(model, a.segment), up_b = way_up(model, b.segment);
  // the lowest common segment
  size_t ia = 0, ib = 0;
  for (; ia < up_a.size(); ++ia) {
    const auto at = std::find_if(up_b.begin(), up_b.end(),
                                 [&](const auto& e) { return e.first == up_a[ia].first; });
    if (at != up_b.end()) {
      ib = static_cast<size_t>(at - up_b.begin());
      break;
    }
  }
  if (ia == up_a.size()) return INFINITY;  // two trees: nothing ties the points
  // the points in each segment along the way, climbing from a, then from b, to the common one
  double span = 0.0;
  auto climb = [&](const std::vector<std::pair<int, int>>& up, size_t top, const Vector3d& start) {
    Vector3d entry = start;  // in up[i]'s frame
    for (size_t i = 0; i < top; ++i) {
      const Joint& joint = model.joints[up[i].second];
      span += (joint.anchor_in_child - entry).norm();
      entry = joint.anchor_in_parent;
    }
    return entry;  // in the common segment's frame
  };
  const Vector3d from_a = climb(up_a, ia, a.local_point);
  const Vector3d from_b = climb(up_b, ib, b.local_point);
  return span + (from_a - from_b).norm();
}

}  // namespace

double reach_shortfall(const Model& model, const Scenario& scenario) {
  std::vector<size_t> hard;
  for (size_t i = 0; i < scenario.pins.size(); ++i) {
    if (scenario.pins[i].pin.is_hard()) hard.push_back(i);
  }
  if (hard.size() < 2) return -INFINITY;
  const double span = chain_span(model, scenario.pins[hard[0]].pin, scenario.pins[hard[1]].pin);
  double farthest = 0.0;
  std::vector<Vector3d> targets;
  const int samples = static_cast<int>(std::lround(scenario.duration * 240.0));
  for (int k = 0; k <= samples; ++k) {
    scenario.targets_at(k / 240.0, targets);
    farthest = std::max(farthest, (targets[hard[0]] - targets[hard[1]]).norm());
  }
  return farthest - span;
}

std::string with_flag(const ScenarioError& error) {
  if (error.option.empty()) return error.what();
  std::string flag = "--" + error.option;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag + ": " + error.what();
}

namespace {
std::mutex builtin_mutex;
std::string& builtin_path() {
  static std::string path = pinocchio_path();
  return path;
}
}  // namespace

std::string builtin_model_path() {
  std::lock_guard lock(builtin_mutex);
  return builtin_path();
}

void set_builtin_model_path(const std::string& path) {
  std::lock_guard lock(builtin_mutex);
  builtin_path() = path;
}

Model load_named_model(const std::string& name, const ReadOptions& options) {
  std::string note;
  Model model = load_model(name == "pinocchio" ? builtin_model_path() : name, options, &note);
  if (!note.empty()) {
    std::fprintf(stderr, "testbed: %s: skipped what the testbed does not model: %s\n",
                 printable(name, 256).c_str(), printable(note, 300).c_str());
  }
  return model;
}

}  // namespace puppet::compare
