#include "puppet/compare/scenario.h"

#include <algorithm>
#include <cmath>

#include "puppet/model/text.h"

namespace puppet::compare {
namespace {

constexpr double kRampSeconds = 0.5;
constexpr double kCircleRadius = 0.3;  // m
constexpr double kShakeAmplitude = 0.1;
constexpr double kShakeHz = 3.0;

// rotate every body rigidly by `rotation` about `centre`
void rotate_about(std::vector<BodyState>& bodies, const Quaterniond& rotation,
                  const Vector3d& centre) {
  for (BodyState& body : bodies) {
    body.x = centre + rotation * (body.x - centre);
    body.q = (rotation * body.q).normalized();
    body.v = rotation * body.v;
    body.w = rotation * body.w;
  }
}

// the shape's extreme point along a world direction, at rest, in the segment frame
Vector3d rest_extreme_point(const Segment& segment, const Vector3d& world_direction) {
  return support_point(segment.shape, segment.rest_orientation.conjugate() * world_direction);
}

double rest_lowest_z(const Segment& segment) {
  return (segment.rest_position +
          segment.rest_orientation * rest_extreme_point(segment, -Vector3d::UnitZ()))
      .z();
}

Pin choose_point(const Model& model, const std::optional<PointChoice>& choice, int default_segment,
                 const Vector3d& extreme_direction, const char* option) {
  Pin pin;
  pin.segment = default_segment;
  if (choice) {
    pin.segment = model.find_segment(choice->segment);
    if (pin.segment < 0) {
      throw ScenarioError(
          "unknown segment " + shown(choice->segment) + " in model " + shown(model.name), option);
    }
  }
  const Segment& segment = model.segments[pin.segment];
  pin.local_point = choice && choice->local_point ? *choice->local_point
                                                  : rest_extreme_point(segment, extreme_direction);
  return pin;
}

Vector3d world_of(const std::vector<BodyState>& bodies, const Pin& pin) {
  return bodies[pin.segment].x + bodies[pin.segment].q * pin.local_point;
}

}  // namespace

const std::vector<std::string>& scenario_names() {
  static const std::vector<std::string> names = {"hang", "drag",  "shake",   "spin",
                                                 "drop", "water", "tremble", "yank"};
  return names;
}

int default_pin_segment(const Model& model) {
  const int head = model.find_segment("head");
  return head >= 0 ? head : 0;
}

int default_grab_segment(const Model& model, const std::string& scenario) {
  const int hand = model.find_segment(scenario == "shake" ? "l_forearm" : "r_forearm");
  if (hand >= 0) return hand;
  int lowest = 0;
  for (int i = 1; i < model.segment_count(); ++i) {
    if (rest_lowest_z(model.segments[i]) < rest_lowest_z(model.segments[lowest]) - 1e-12)
      lowest = i;
  }
  return lowest;
}

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
         !tremble;
}

bool Scenario::conserves_momentum() const {
  return conserves_energy() && pins.empty() && environment.gravity.isZero();
}

std::string with_flag(const ScenarioError& error) {
  if (error.option.empty()) return error.what();
  std::string flag = "--" + error.option;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag + ": " + error.what();
}

Scenario make_scenario(const std::string& name, const Model& model,
                       const ScenarioOptions& options) {
  if (std::find(scenario_names().begin(), scenario_names().end(), name) == scenario_names().end()) {
    throw ScenarioError("unknown scenario " + shown(name), "scenario");
  }
  Scenario s;
  s.name = name;
  s.environment.gravity = model.gravity;
  const bool hanging =
      name == "hang" || name == "drag" || name == "shake" || name == "water" || name == "tremble";
  const bool circling = name == "drag" || name == "water" || name == "tremble" || name == "yank";
  const std::optional<StartInputs>& start = options.start;
  // the pins, chosen on the rest pose
  Pin head, hand;
  if (hanging) {
    head = choose_point(model, options.pin, default_pin_segment(model), Vector3d::UnitZ(), "pin");
  }
  if (circling || name == "shake") {
    hand = choose_point(model, options.grab, default_grab_segment(model, name), -Vector3d::UnitZ(),
                        "grab");
    if (start && !(options.grab && options.grab->local_point)) {
      hand.local_point = support_point(model.segments[hand.segment].shape, start->grab_direction);
    }
  }
  // a random start poses the figure from the segment held first (it stays at rest, so a held
  // point starts still), else from the root
  const int anchor = hanging ? head.segment : circling ? hand.segment : 0;
  s.initial = start ? posed_start(model, *start, anchor) : rest_pose(model);

  if (hanging) {
    // a marionette: the pin point fixed, the figure tilted about world x through it
    const Vector3d pivot = world_of(s.initial, head);
    const double tilt_deg = start ? start->tilt_deg : options.tilt_deg;
    rotate_about(s.initial,
                 Quaterniond(Eigen::AngleAxisd(tilt_deg * M_PI / 180.0, Vector3d::UnitX())), pivot);
    PinPath fixed;
    fixed.pin = head;
    fixed.pin.target = pivot;
    s.pins.push_back(fixed);
    s.environment.air_drag = name == "hang" ? 0.0 : 0.1;
  }
  if (circling || name == "shake") {
    PinPath grab;
    grab.pin = hand;
    grab.pin.target = world_of(s.initial, hand);
    grab.pin.compliance = options.grab_compliance;
    if (name == "shake") {
      grab.path = TargetPath::kShakeX;
      grab.radius = kShakeAmplitude;
      // a start's frequency scaled from the circle's default (0.5 Hz) to the shake's (3 Hz)
      grab.hz = start ? kShakeHz * start->hz / 0.5 : kShakeHz;
    } else {
      grab.path = TargetPath::kCircle;
      grab.radius = kCircleRadius;
      grab.hz = start ? start->hz : options.hz;
    }
    if (start) grab.phase = start->phase;
    s.pins.push_back(grab);
  }
  if (name == "water") {
    s.environment.water = true;
    s.environment.water_level = 3.0;
    s.environment.water_density = 1000.0;
    s.environment.water_drag = 2.0;
  }
  if (name == "tremble") s.tremble = true;
  if (name == "yank") s.environment.air_drag = 0.0;

  if (name == "spin") {
    // rigid rotation about the centre of mass, no gravity
    s.environment.gravity.setZero();
    Vector3d com{0, 0, 0};
    for (int i = 0; i < model.segment_count(); ++i) com += model.segments[i].mass * s.initial[i].x;
    com /= model.total_mass;
    const Vector3d omega(0.3, 0.0, 2.0);
    for (BodyState& body : s.initial) {
      body.w += omega;
      body.v += omega.cross(body.x - com);
    }
  }
  if (name == "drop") {
    // tilted 20° about x through the centre of mass, lowest point 1 m above the ground
    s.duration = 3.0;
    s.environment.air_drag = 0.05;
    s.environment.ground = true;
    s.environment.friction = 0.8;
    Vector3d com{0, 0, 0};
    for (int i = 0; i < model.segment_count(); ++i) com += model.segments[i].mass * s.initial[i].x;
    com /= model.total_mass;
    rotate_about(s.initial, Quaterniond(Eigen::AngleAxisd(20.0 * M_PI / 180.0, Vector3d::UnitX())),
                 com);
    double lowest = INFINITY;
    for (int i = 0; i < model.segment_count(); ++i) {
      double low = 0.0, high = 0.0;
      vertical_extent(model.segments[i], s.initial[i].q, s.initial[i].x, &low, &high);
      lowest = std::min(lowest, low);
    }
    for (BodyState& body : s.initial) body.x.z() += 1.0 - lowest;
  }

  // command-line overrides of the environment
  if (options.gravity) s.environment.gravity = *options.gravity;
  if (options.air_drag) s.environment.air_drag = *options.air_drag;
  if (options.ground) s.environment.ground = *options.ground;
  return s;
}

std::string builtin_model_path() {
  return std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";
}

Model load_named_model(const std::string& name) {
  return load_model(name == "pinocchio" ? builtin_model_path() : name);
}

}  // namespace puppet::compare
