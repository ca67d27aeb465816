// The jolt engine's driver (reference/jolt/server.mjs) as the testbed reaches it: where Node.js
// and the package are, a pool of running drivers, and the requests' JSON (jolt_driver.h).
#include "jolt_driver.h"

#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <mutex>
#include <sstream>

#include "jolt_box.h"
#include "puppet/model/root_joint.h"

namespace puppet::compare {
namespace jolt {

using nlohmann::json;
namespace {

constexpr const char* kPackageVersion = "1.1.0";  // as reference/jolt/package.json pins it

std::string node_path() { return PUPPET_NODE; }
std::string driver_dir() { return PUPPET_JOLT_DIR; }

// Drivers kept between simulators (starting Node and Jolt costs about 0.2 s)
class DriverPool {
 public:
  std::unique_ptr<NodeProcess> take() {
    {
      std::lock_guard lock(mutex_);
      if (!idle_.empty()) {
        std::unique_ptr<NodeProcess> out = std::move(idle_.back());
        idle_.pop_back();
        return out;
      }
    }
    return std::make_unique<NodeProcess>(node_path(), driver_dir() + "/server.mjs");
  }
  void give_back(std::unique_ptr<NodeProcess> process) {
    if (!process || !process->healthy()) return;
    std::lock_guard lock(mutex_);
    idle_.push_back(std::move(process));
  }

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<NodeProcess>> idle_;
};

// outlives every simulator; its idle drivers end with the process (node_process.h)
DriverPool* g_pool = nullptr;

DriverPool& pool() {
  static std::once_flag once;
  std::call_once(once, [] {
    g_pool = new DriverPool;
    // a process forked from this one starts with no drivers: the parent's stay the parent's
    // (forgotten in the child, neither ended nor reused; their locks may be held)
    pthread_atfork(nullptr, nullptr, [] { g_pool = new DriverPool; });
  });
  return *g_pool;
}
json vec(const Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json quat(const Quaterniond& q) { return json::array({q.x(), q.y(), q.z(), q.w()}); }
// a limit angle as Jolt takes it: within [−π, π], where ±π means free
double angle(double a) { return std::clamp(a, -M_PI, M_PI); }

json shape_json(const Shape& shape) {
  return {{"type", shape_type_name(shape.type)}, {"radius", shape.radius},
          {"half_length", shape.half_length},    {"half_extents", vec(shape.half_extents)},
          {"position", vec(shape.position)},     {"orientation", quat(shape.orientation)}};
}

}  // namespace

// why the engine cannot run here (empty when it can): Node.js and the pinned package
std::string absent_reason() {
  if (node_path().empty() || access(node_path().c_str(), X_OK) != 0) {
    return "Node.js is missing (Debian: nodejs; scripts/setup.sh installs it)";
  }
  std::ifstream file(driver_dir() + "/node_modules/jolt-physics/package.json");
  std::stringstream text;
  text << file.rdbuf();
  if (!file || text.str().find(std::string("\"version\": \"") + kPackageVersion + "\"") ==
                   std::string::npos) {
    return std::string("the npm package jolt-physics ") + kPackageVersion +
           " is missing from reference/jolt (scripts/setup.sh installs it)";
  }
  return {};
}

bool available() {
  static const bool yes = absent_reason().empty();
  return yes;
}

std::unique_ptr<NodeProcess> take_driver() { return pool().take(); }

std::string driver_problem() {
  std::unique_ptr<NodeProcess> driver;
  try {
    driver = take_driver();
  } catch (const std::exception& e) {
    return e.what();
  }
  std::string line;
  if (!driver->request(R"({"op":"version"})", line, std::chrono::seconds(60))) {
    return "its driver does not answer here: " + driver->error();
  }
  const json answer = json::parse(line, nullptr, false);
  if (!answer.is_object() || answer.value("jolt", std::string()) != kPackageVersion) {
    return "its driver answered \"" + line.substr(0, 80) + "\" to a version request";
  }
  give_back(std::move(driver));
  return {};
}
void give_back(std::unique_ptr<NodeProcess> driver) { pool().give_back(std::move(driver)); }

json model_json(const Model& model) {
  json segments = json::array();
  for (const Segment& s : model.segments) {
    json shapes = json::array();
    for (const Shape& shape : s.shapes) shapes.push_back(shape_json(shape));
    segments.push_back({{"mass", s.mass},
                        {"inertia", vec(s.inertia)},
                        {"inv_mass", s.inv_mass},
                        {"inv_inertia", vec(s.inv_inertia)},
                        {"volume", segment_volume(s)},
                        {"lone_shape", lone_shape(s)},
                        {"shapes", shapes}});
  }
  json joints = json::array();
  for (const Joint& j : model.joints) {
    const char* type = joint_type_name(j.type);
    const bool slide = j.type == JointType::kSlide;
    json pyramid;
    if (j.type == JointType::kBall && j.ball_limit == BallLimit::kEulerBox) {
      const JoltPyramid p = nearest_jolt_pyramid(j);
      pyramid = {{"twist_first", p.twist_first},
                 {"x", p.x},
                 {"y", p.y},
                 {"z", p.z},
                 {"y_sign", p.y_sign},
                 {"lower", {angle(p.lower[0]), angle(p.lower[1]), angle(p.lower[2])}},
                 {"upper", {angle(p.upper[0]), angle(p.upper[1]), angle(p.upper[2])}}};
    }
    json passive = json::array();
    for (const JointPassive& spring : j.passive) {
      passive.push_back({{"stiffness", spring.stiffness},
                         {"damping", spring.damping},
                         {"spring_ref", spring.spring_ref}});
    }
    joints.push_back({{"type", type},
                      {"parent", j.parent},
                      {"child", j.child},
                      {"anchor_in_parent", vec(j.anchor_in_parent)},
                      {"anchor_in_child", vec(j.anchor_in_child)},
                      {"frame_in_parent", quat(j.frame_in_parent)},
                      {"frame_in_child", quat(j.frame_in_child)},
                      {"ball_limit", j.ball_limit == BallLimit::kEulerBox ? "box" : "swing-twist"},
                      {"swing_x", std::min(j.swing_x, M_PI)},
                      {"swing_y", std::min(j.swing_y, M_PI)},
                      {"twist", std::min(j.twist, M_PI)},
                      {"pyramid", pyramid},
                      {"hinge_axis", vec(j.hinge_axis)},
                      // a hinge's angles; a slide's distances, when limited
                      {"limited", std::isfinite(j.lower)},
                      {"lower", slide ? (std::isfinite(j.lower) ? j.lower : 0.0) : angle(j.lower)},
                      {"upper", slide ? (std::isfinite(j.upper) ? j.upper : 0.0) : angle(j.upper)},
                      {"box_order", j.box_order.axes},
                      {"passive", passive}});
  }
  // the world's joint on the root: its hold, anchor, axes and range, a spring per coordinate
  const RootJoint& r = model.root;
  const int coordinates = root_coordinate_count(r.hold);
  json root_passive = json::array();
  for (int k = 0; k < coordinates; ++k) {
    const JointPassive& spring = r.passive[static_cast<size_t>(k)];
    root_passive.push_back({{"stiffness", spring.stiffness},
                            {"damping", spring.damping},
                            {"spring_ref", spring.spring_ref}});
  }
  const json root = {{"hold", root_hold_name(r.hold)},
                     {"anchor_world", vec(r.anchor_world)},
                     {"anchor_in_root", vec(r.anchor_in_root)},
                     {"axes", {vec(r.axes[0]), vec(r.axes[1]), vec(r.axes[2])}},
                     {"slides", root_slide_count(r.hold)},
                     {"limited", r.limited},
                     {"lower", r.lower},
                     {"upper", r.upper},
                     {"rest_orientation", quat(model.segments[0].rest_orientation)},
                     {"passive", root_passive}};
  return {{"segments", segments}, {"joints", joints}, {"root", root}};
}

json environment_json(const Environment& e) {
  return {{"gravity", vec(e.gravity)},
          {"tremble", e.tremble},
          {"tremble_seed", std::to_string(e.tremble_seed)},
          {"air_drag", e.air_drag},
          {"water", e.water},
          {"water_level", e.water_level},
          {"water_density", e.water_density},
          {"water_drag", e.water_drag},
          {"ground", e.ground},
          {"friction", e.friction}};
}

json pins_json(std::span<const Pin> pins) {
  json out = json::array();
  for (const Pin& p : pins) {
    out.push_back({{"segment", p.segment},
                   {"local_point", vec(p.local_point)},
                   {"target", vec(p.target)},
                   {"compliance", p.compliance},
                   {"grab",
                    {{"hz", p.grab.hz},
                     {"damping_ratio", p.grab.damping_ratio},
                     {"max_force", p.grab.max_force}}}});
  }
  return out;
}

json states_json(std::span<const BodyState> bodies) {
  json out = json::array();
  for (const BodyState& b : bodies) {
    for (double v : {b.x.x(), b.x.y(), b.x.z(), b.q.x(), b.q.y(), b.q.z(), b.q.w(), b.v.x(),
                     b.v.y(), b.v.z(), b.w.x(), b.w.y(), b.w.z()}) {
      out.push_back(v);
    }
  }
  return out;
}

}  // namespace jolt

using namespace jolt;

bool jolt_driver_forces(const Model& model, const Environment& environment,
                        std::span<const Pin> pins, std::span<const BodyState> bodies, double time,
                        double h, std::vector<Wrench>& applied, std::vector<Wrench>& user,
                        std::string& error) {
  std::unique_ptr<NodeProcess> driver;
  try {
    driver = take_driver();
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  const json request = {{"op", "forces"},
                        {"model", model_json(model)},
                        {"environment", environment_json(environment)},
                        {"pins", pins_json(pins)},
                        {"states", states_json(bodies)},
                        {"time", time},
                        {"h", h}};
  std::string line;
  if (!driver->request(request.dump(), line, std::chrono::seconds(60))) {
    error = driver->error();
    return false;
  }
  const json answer = json::parse(line, nullptr, false);
  // six numbers a segment, or the answer is not used
  const auto wrenches = [&](const char* name) -> const json* {
    const auto it = answer.is_object() ? answer.find(name) : answer.end();
    if (it == answer.end() || !it->is_array() || it->size() != 6 * bodies.size()) return nullptr;
    for (const json& v : *it) {
      if (!v.is_number()) return nullptr;
    }
    return &*it;
  };
  const json* applied_json = answer.is_discarded() ? nullptr : wrenches("applied");
  const json* user_json = answer.is_discarded() ? nullptr : wrenches("user");
  if (!applied_json || !user_json) {
    error = line.substr(0, 200);
    return false;
  }
  const auto unpack = [](const json& flat, std::vector<Wrench>& out) {
    out.resize(flat.size() / 6);
    for (size_t i = 0; i < out.size(); ++i) {
      const auto at = [&](size_t k) { return flat[6 * i + k].get<double>(); };
      out[i].force = Vector3d(at(0), at(1), at(2));
      out[i].torque = Vector3d(at(3), at(4), at(5));
    }
  };
  unpack(*applied_json, applied);
  unpack(*user_json, user);
  give_back(std::move(driver));
  return true;
}

bool jolt_driver_heap_after_builds(const Model& model, int builds, std::vector<double>& used,
                                   std::string& error) {
  NodeProcess driver(node_path(), driver_dir() + "/server.mjs");
  const json build = {
      {"op", "build"},
      {"model", model_json(model)},
      {"environment", environment_json(Environment{.ground = true})},
      {"pins", pins_json({})},
      {"settings", {{"velocity_steps", 10}, {"position_steps", 2}, {"baumgarte", 0.2}}},
      {"start", states_json(rest_pose(model))},
      {"time", 0.0}};
  const std::string line = build.dump();
  std::string answer;
  for (int k = 0; k < builds; ++k) {
    if (!driver.request(line, answer, std::chrono::seconds(60)) ||
        !driver.request(R"({"op":"memory"})", answer, std::chrono::seconds(60))) {
      error = driver.error();
      return false;
    }
    const json memory = json::parse(answer, nullptr, false);
    if (memory.is_discarded() || !memory.is_object() || !memory.contains("used") ||
        !memory["used"].is_number()) {
      error = answer.substr(0, 200);
      return false;
    }
    used.push_back(memory["used"].get<double>());
  }
  return true;
}

}  // namespace puppet::compare
