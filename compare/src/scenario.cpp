// The scenarios' shared parts: target paths, pins, what a scenario conserves, the built-in
// model. The scenarios themselves are one file each under scenarios/ (catalogue.cpp lists them).
#include "puppet/compare/scenario.h"

#include "puppet/model/user_forces.h"

#include <algorithm>
#include <cmath>

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
  return conserves_energy() && pins.empty() && environment.gravity.isZero();
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

std::string with_flag(const ScenarioError& error) {
  if (error.option.empty()) return error.what();
  std::string flag = "--" + error.option;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag + ": " + error.what();
}

std::string builtin_model_path() {
  return std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";
}

Model load_named_model(const std::string& name) {
  return load_model(name == "pinocchio" ? builtin_model_path() : name);
}

}  // namespace puppet::compare
