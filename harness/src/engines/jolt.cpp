// The engine `jolt`: Jolt Physics in its own WebAssembly build (the npm package jolt-physics at
// the version reference/jolt/package.json pins), stepped by Node.js in a driver process
// (reference/jolt/server.mjs; docs/references.md, "The Jolt reference"). The driver steps ahead
// of the calls, on the pin targets the scenario will ask for, so that a run costs a few round
// trips and not one a step; a step whose targets differ from those it guessed sends the driver
// back to that step, by building the world again and replaying what was asked since (Jolt is
// deterministic). Its cost is WebAssembly's: the driver times each step inside Jolt.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "jolt_driver.h"
#include "node_process.h"
#include "puppet/compare/engines.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/joint_springs.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/text.h"

namespace puppet::compare {
namespace {

using nlohmann::json;
using namespace jolt;

constexpr int kStateWidth = 13;   // x, q (x, y, z, w), v, ω
constexpr int kRecordWidth = 19;  // the state and the user's wrench
constexpr int kFirstChunk = 8;    // steps stepped ahead: doubling to kLastChunk
constexpr int kLastChunk = 512;
constexpr double kRunaway = 1e6;  // m/s or rad/s: a divergence, as the driver reads it too

// a quaternion made unit as the driver makes Jolt's (server.mjs, read): the same operations in
// the same order, so that both sides hold the same bits
Quaterniond unit_as_the_driver(const Quaterniond& q) {
  const double n = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w());
  return Quaterniond(q.w() / n, q.x() / n, q.y() / n, q.z() / n);
}

// what Jolt holds of a placed state: each number in single precision (its wasm build's)
std::vector<BodyState> as_jolt_holds(std::span<const BodyState> bodies) {
  std::vector<BodyState> out(bodies.begin(), bodies.end());
  const auto single = [](auto&& v) {
    for (int k = 0; k < v.size(); ++k) v[k] = static_cast<float>(v[k]);
  };
  for (BodyState& b : out) {
    single(b.x);
    single(b.q.coeffs());
    single(b.v);
    single(b.w);
  }
  return out;
}

// Everything that decides the driver's world: what it was built from, and each step asked of
// it since, with its dt and its targets (flat). A snapshot is one: replaying it in a new world
// repeats the same bits.
struct Course {
  std::string build;  // the build request
  std::vector<double> dts;
  std::vector<double> targets;
};

// the simulator's logical state: the course, and what the harness last set or read
struct JoltState {
  Course course;
  bool needs_build = true;        // the state was placed: the next step builds a world from it
  std::vector<BodyState> placed;  // the state placed, as Jolt holds it (the next build's start)
  std::vector<Pin> pins;
  std::vector<Vector3d> targets;  // for the next step
  std::vector<BodyState> bodies;
  std::vector<Wrench> user;
  double time = 0.0;
  double anchor_time = 0.0;  // the clock at the last reset or set_time
  long since_anchor = 0;     // steps taken since
  double own_seconds = -1.0;
  bool diverged = false;
};

class JoltSnapshot : public Snapshot {
 public:
  explicit JoltSnapshot(JoltState s) : state(std::move(s)) {}
  JoltState state;
};

class JoltSimulator : public Simulator {
 public:
  explicit JoltSimulator(const JoltSettings& settings) : settings_(settings) {}
  ~JoltSimulator() override { give_back(std::move(driver_)); }

  std::string name() const override { return "jolt"; }

  void reset(const Model& model, const Scenario& scenario) override {
    model_ = &model;
    scenario_ = scenario;
    std::optional<Model> own_model;
    model_json_ = model_json(armature_in_inertia(model, own_model));  // armature as inertia
    environment_json_ = environment_json(scenario.environment);
    s_ = JoltState{};
    s_.pins = scenario.initial_pins();
    place(scenario.initial);
    s_.user.assign(scenario.initial.size(), Wrench{});
    s_.targets.clear();
    for (const Pin& p : s_.pins) s_.targets.push_back(p.target);
    guessing_ = true;
    drop_ahead();
  }
  void set_pins(std::span<const Pin> pins) override {
    s_.pins.assign(pins.begin(), pins.end());
    s_.targets.clear();
    for (const Pin& p : s_.pins) s_.targets.push_back(p.target);
    place(std::vector<BodyState>(s_.bodies));  // a new world from where this one is
    s_.needs_build = true;
    drop_ahead();
  }
  void set_pin_targets(std::span<const Vector3d> targets) override {
    s_.targets.assign(targets.begin(), targets.end());
  }
  void set_time(double time) override {
    s_.time = s_.anchor_time = time;
    s_.since_anchor = 0;
    place(std::vector<BodyState>(s_.bodies));
    s_.needs_build = true;
    drop_ahead();
  }
  void set_state(std::span<const BodyState> bodies) override {
    place(bodies);
    s_.needs_build = true;
    drop_ahead();
  }
  void read_state(std::span<BodyState> out) const override {
    std::copy(s_.bodies.begin(), s_.bodies.end(), out.begin());
  }
  std::span<const Wrench> user_wrenches() const override { return s_.user; }
  bool diverged() const override { return s_.diverged; }
  double own_step_seconds() const override { return s_.own_seconds; }
  std::unique_ptr<Snapshot> snapshot() const override { return std::make_unique<JoltSnapshot>(s_); }
  void restore(const Snapshot& snapshot) override {
    s_ = static_cast<const JoltSnapshot&>(snapshot).state;
    drop_ahead();
    world_steps_ = -1;  // the driver's world is elsewhere: the next step replays the course
  }

  void step(double dt) override {
    if (s_.diverged) return;
    // JSON has no NaN or infinity, and Jolt must never see them: such an input is a divergence
    if (!finite_input(dt)) {
      s_.diverged = true;
      return;
    }
    if (!ahead_matches(dt)) {
      // a guess that was wrong: from here each step is asked for alone, with its own targets
      if (ahead_next_ < ahead_count_) guessing_ = false;
      if (!bring_world_here() || !advance(dt)) {
        s_.diverged = true;  // a driver that fails is never a run that holds
        return;
      }
    }
    consume(dt);
  }

 private:
  size_t pin_width() const { return 3 * s_.targets.size(); }

  // the state Jolt will start from, and what reading it back gives
  void place(std::span<const BodyState> bodies) {
    s_.placed = as_jolt_holds(bodies);
    s_.bodies = s_.placed;
    for (BodyState& b : s_.bodies) b.q = unit_as_the_driver(b.q);
  }

  bool finite_input(double dt) const {
    if (!std::isfinite(dt) || !all_finite(s_.bodies)) return false;
    for (const Vector3d& t : s_.targets) {
      if (!t.allFinite()) return false;
    }
    for (const BodyState& b : s_.bodies) {
      if (b.v.norm() > kRunaway || b.w.norm() > kRunaway) return false;
    }
    return true;
  }

  // forgets the steps stepped ahead, and starts the chunks small again
  void drop_ahead() {
    drop_ahead_keep_chunk();
    chunk_ = kFirstChunk;
  }

  // the next step is stepped already, with this dt and these targets
  bool ahead_matches(double dt) const {
    if (ahead_next_ >= ahead_count_ || dt != ahead_dt_) return false;
    const size_t w = pin_width();
    if (ahead_targets_.size() < (ahead_next_ + 1) * w) return false;
    for (size_t k = 0; k < s_.targets.size(); ++k) {
      for (int a = 0; a < 3; ++a) {
        if (ahead_targets_[ahead_next_ * w + 3 * k + a] != s_.targets[k][a]) return false;
      }
    }
    return true;
  }

  bool fail(const std::string& why) {
    if (!failure_reported_) std::fprintf(stderr, "jolt: %s\n", one_line(why, 390).c_str());
    failure_reported_ = true;
    return false;
  }

  bool ask(const json& request, json& answer) {
    if (!driver_) {
      try {
        driver_ = take_driver();
      } catch (const std::exception& e) {
        return fail(e.what());
      }
    }
    std::string line;
    if (!driver_->request(request.dump(), line, std::chrono::seconds(120))) {
      return fail(driver_->error());
    }
    answer = json::parse(line, nullptr, false);
    if (answer.is_discarded() || !answer.is_object())
      return fail("the driver answered \"" + line.substr(0, 80) + "\"");
    if (const auto e = answer.find("error"); e != answer.end()) {
      return fail(e->is_string() ? e->get<std::string>() : e->dump().substr(0, 200));
    }
    return true;
  }

  // builds the world the course starts from and replays the course (the driver's world is then
  // at this step); or, when the state was placed, a new course from it
  bool bring_world_here() {
    if (s_.needs_build) {
      std::vector<Pin> pins = s_.pins;
      for (size_t k = 0; k < pins.size() && k < s_.targets.size(); ++k)
        pins[k].target = s_.targets[k];
      json build = {{"op", "build"},
                    {"model", model_json_},
                    {"environment", environment_json_},
                    {"pins", pins_json(pins)},
                    {"settings",
                     {{"velocity_steps", settings_.velocity_steps},
                      {"position_steps", settings_.position_steps},
                      {"baumgarte", settings_.baumgarte}}},
                    {"start", states_json(s_.placed)},
                    {"time", s_.time}};
      s_.course = Course{build.dump(), {}, {}};
      s_.needs_build = false;
      world_steps_ = -1;
    }
    if (world_steps_ == static_cast<long>(s_.course.dts.size())) return true;
    json answer;
    if (!ask(json::parse(s_.course.build), answer)) return false;
    world_steps_ = 0;
    // replay, one request per run of equal dt
    const size_t steps = s_.course.dts.size();
    const size_t w = pin_width();
    size_t k = 0;
    std::vector<char> bytes;
    while (k < steps) {
      size_t end = k;
      while (end < steps && s_.course.dts[end] == s_.course.dts[k]) ++end;
      json request = {{"op", "advance"},
                      {"dt", s_.course.dts[k]},
                      {"steps", end - k},
                      {"targets", std::vector<double>(s_.course.targets.begin() + k * w,
                                                      s_.course.targets.begin() + end * w)}};
      if (!ask(request, answer)) return false;
      size_t replayed = 0;
      bool diverged = false;
      if (!read_records(answer, end - k, bytes, &replayed, &diverged)) return false;
      if (replayed != end - k) return fail("a replay diverged where the run had not");
      k = end;
    }
    world_steps_ = static_cast<long>(steps);
    return true;
  }

  // steps the driver ahead from here: this step with the targets asked, the next ones with the
  // scenario's (while the pins are the scenario's)
  bool advance(double dt) {
    drop_ahead_keep_chunk();
    const bool predictable = guessing_ && s_.pins.size() == scenario_.pins.size();
    const int steps = predictable ? chunk_ : 1;
    chunk_ = std::min(2 * chunk_, kLastChunk);
    std::vector<Vector3d> predicted;
    ahead_targets_.reserve(static_cast<size_t>(steps) * pin_width());
    for (int j = 0; j < steps; ++j) {
      if (j == 0) {
        predicted = s_.targets;
      } else {
        scenario_.targets_at(s_.anchor_time + static_cast<double>(s_.since_anchor + 1 + j) * dt,
                             predicted);
      }
      for (const Vector3d& t : predicted)
        ahead_targets_.insert(ahead_targets_.end(), {t.x(), t.y(), t.z()});
    }
    json request = {{"op", "advance"}, {"dt", dt}, {"steps", steps}, {"targets", ahead_targets_}};
    json answer;
    if (!ask(request, answer)) return false;
    std::vector<char> raw;
    size_t count = 0;
    bool diverged = false;
    if (!read_records(answer, static_cast<size_t>(steps), raw, &count, &diverged)) return false;
    if (count == 0 && !diverged) return fail("the driver stepped nothing and said no divergence");
    ahead_.resize(raw.size() / sizeof(double));
    std::memcpy(ahead_.data(), raw.data(), raw.size());
    ahead_count_ = count;
    ahead_diverged_ = diverged;
    ahead_dt_ = dt;
    ahead_next_ = 0;
    world_steps_ += static_cast<long>(ahead_count_);
    return true;
  }

  // the records an "advance" answer announces, read after checking the answer against itself:
  // a whole number of steps, at most those asked, a divergence flag, and exactly the bytes
  // those steps' records take (a driver that answers otherwise is a failed driver, never a
  // read past what came)
  bool read_records(const json& answer, size_t asked, std::vector<char>& raw, size_t* steps,
                    bool* diverged) {
    const auto field = [&](const char* name) -> const json* {
      const auto it = answer.find(name);
      return it == answer.end() ? nullptr : &*it;
    };
    const json* count = field("steps");
    const json* bytes = field("bytes");
    const json* flag = field("diverged");
    if (!count || !count->is_number_unsigned() || !bytes || !bytes->is_number_unsigned() || !flag ||
        !flag->is_boolean()) {
      return fail("the driver's answer lacks its steps, bytes or divergence: " +
                  answer.dump().substr(0, 120));
    }
    *steps = count->get<size_t>();
    *diverged = flag->get<bool>();
    const size_t record = (kRecordWidth * s_.bodies.size() + 1) * sizeof(double);
    if (*steps > asked || bytes->get<size_t>() != *steps * record) {
      return fail("the driver announced " + bytes->dump() + " bytes for " + count->dump() +
                  " steps of " + std::to_string(asked) + " asked (" + std::to_string(record) +
                  " bytes a step)");
    }
    if (!driver_->read_bytes(*steps * record, raw, std::chrono::seconds(120))) {
      return fail(driver_->error());
    }
    return true;
  }

  void drop_ahead_keep_chunk() {
    ahead_.clear();
    ahead_targets_.clear();
    ahead_next_ = 0;
    ahead_count_ = 0;
  }

  void consume(double dt) {
    const size_t n = s_.bodies.size();
    const double* r = ahead_.data() + ahead_next_ * (kRecordWidth * n + 1);
    for (size_t i = 0; i < n; ++i, r += kStateWidth) {
      BodyState& b = s_.bodies[i];
      b.x = Vector3d(r[0], r[1], r[2]);
      b.q = Quaterniond(r[6], r[3], r[4], r[5]);
      b.v = Vector3d(r[7], r[8], r[9]);
      b.w = Vector3d(r[10], r[11], r[12]);
    }
    for (size_t i = 0; i < n; ++i, r += 6) {
      s_.user[i].force = Vector3d(r[0], r[1], r[2]);
      s_.user[i].torque = Vector3d(r[3], r[4], r[5]);
    }
    s_.own_seconds = *r;
    s_.course.dts.push_back(dt);
    for (const Vector3d& t : s_.targets)
      s_.course.targets.insert(s_.course.targets.end(), {t.x(), t.y(), t.z()});
    s_.time += dt;
    ++s_.since_anchor;
    ++ahead_next_;
    if (ahead_diverged_ && ahead_next_ == ahead_count_) s_.diverged = true;
  }

  JoltSettings settings_;
  const Model* model_ = nullptr;
  Scenario scenario_;
  json model_json_, environment_json_;
  JoltState s_;
  std::unique_ptr<NodeProcess> driver_;
  long world_steps_ = -1;  // steps the driver's world has taken along s_.course (−1: none built)
  // the steps stepped ahead: records (kRecordWidth per segment, then the seconds), their targets
  std::vector<double> ahead_, ahead_targets_;
  size_t ahead_next_ = 0, ahead_count_ = 0;
  double ahead_dt_ = 0.0;
  bool ahead_diverged_ = false;
  int chunk_ = kFirstChunk;
  bool guessing_ = true;  // steps ahead on the scenario's targets (until a guess is wrong)
  bool failure_reported_ = false;
};

std::string jolt_model_problem(const Model& model) {
  if (std::string problem = slide_armature_problem(model); !problem.empty()) return problem;
  if (std::string problem = box_offsets_problem(model); !problem.empty()) return problem;
  // the ground and a handle per hard pin besides the segments
  if (model.segment_count() + 1 + procedural::kMaxPins > kMaxBodies) {
    return std::to_string(model.segment_count()) + " segments are too many: a Jolt world holds " +
           std::to_string(kMaxBodies) + " bodies, the ground and " +
           std::to_string(procedural::kMaxPins) + " pins' handles among them";
  }
  for (const Segment& segment : model.segments) {
    for (const Shape& shape : segment.shapes) {
      if (shape.type == ShapeType::kEllipsoid) {
        return "segment \"" + segment.name + "\" has an ellipsoid, for which Jolt has no shape";
      }
    }
  }
  for (const Joint& joint : model.joints) {
    if (joint.type == JointType::kHinge && (joint.lower > 0.0 || joint.upper < 0.0)) {
      return "joint \"" + joint.name + "\": Jolt's hinge limits must hold the rest angle 0";
    }
  }
  // last, as it starts a driver when none is pooled
  return driver_problem();
}

std::string validate(const JoltSettings& s) {
  if (s.velocity_steps < 1 || s.velocity_steps > 1000) return "must be 1 to 1000";
  if (s.position_steps < 0 || s.position_steps > 1000) return "must be 0 to 1000";
  if (!(s.baumgarte >= 0.0 && s.baumgarte <= 1.0)) return "must be 0 to 1";
  return {};
}

std::unique_ptr<Simulator> make(const SolverOptions& options) {
  const std::string problem = validate(options.jolt);
  if (!problem.empty()) throw ScenarioError(problem, "jolt_velocity_steps");
  return std::make_unique<JoltSimulator>(options.jolt);
}

void add_flags(CLI::App& command, SolverOptions& options) {
  command
      .add_option("--jolt-velocity-steps", options.jolt.velocity_steps,
                  "jolt: velocity sweeps per step (Jolt's default 10)")
      ->check(whole_number_check())
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command
      .add_option("--jolt-position-steps", options.jolt.position_steps,
                  "jolt: position sweeps per step (Jolt's default 2)")
      ->check(whole_number_check())
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
}

void replay_flags(const SolverOptions& options, std::string& out) {
  const SolverOptions defaults;
  if (options.jolt.velocity_steps != defaults.jolt.velocity_steps) {
    out += " --jolt-velocity-steps " + std::to_string(options.jolt.velocity_steps);
  }
  if (options.jolt.position_steps != defaults.jolt.position_steps) {
    out += " --jolt-position-steps " + std::to_string(options.jolt.position_steps);
  }
}

// Jolt's defaults, as a game ships them, and sweeps enough for its limits to converge further
void search(const SolverOptions& base, std::vector<Setting>& out) {
  out.push_back({"", "", base});  // Jolt's defaults: 10 + 2 sweeps
  Setting more{"--jolt-velocity-steps 40 --jolt-position-steps 8", "40 + 8 sweeps", base};
  more.options.jolt.velocity_steps = 40;
  more.options.jolt.position_steps = 8;
  out.push_back(std::move(more));
}

// Jolt's sweeps are linear in the constraints' rows, in WebAssembly. Figures folded onto the ground
// (bench_budget: chains of capsules, boxes and box-limited boxes, four rods of many boxes,
// Pinocchio and humanoid.xml, each let go curled and timed 1.5 s later; scripts/budget_table.py
// results/bench/budget.json --fit gives the terms, docs/reliability.md the ratios): at its default
// twelve sweeps, 2.6 µs a body or joint row, 1.9 µs a limit row and 0.15 µs a contact point (within
// 0.6–2.9×, laid flat too)
double jolt_cost(const Model& model, const SolverOptions& options) {
  const ModelSize n = model_size(model);
  const double sweeps = options.jolt.velocity_steps + options.jolt.position_steps;
  const double step =
      2.6e-6 * (n.segments + n.joint_rows) + 1.9e-6 * n.limit_rows + 0.15e-6 * n.contact_points;
  return step * sweeps / 12.0 / kBudgetDt;
}

}  // namespace

Engine jolt_engine() {
  return {.name = "jolt",
          .summary =
              "Jolt Physics (its WebAssembly build, single precision, in Node.js): a game "
              "engine's ragdoll",
          .constraints =
              "each joint is rows between two free bodies solved by sequential impulses on "
              "velocities, then on positions (Baumgarte 0.2); a swing–twist limit is Jolt's "
              "elliptic cone in quaternion space, a box limit its swing–twist pyramid (not the "
              "Euler box); contact allows 2 cm of penetration",
          .built = available(),
          .missing = absent_reason,
          .native = false,
          .single_precision = true,
          .model_problem = jolt_model_problem,
          .second_cost = jolt_cost,
          .make = make,
          .add_flags = add_flags,
          .replay_flags = replay_flags,
          .search = search};
}

}  // namespace puppet::compare
