#include "puppet/viewer/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "puppet/compare/metrics.h"
#include "puppet/model/text.h"

namespace puppet::viewer {
namespace {

bool is_one_of(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// throws ScenarioError for an unknown solver or rule
Run make_run(const std::string& solver, const compare::SolverOptions& options, const Model& model) {
  Run run;
  run.simulator = compare::make_simulator(solver, options);
  run.label = solver;
  if (const std::string rule = run.simulator->rule(); !rule.empty()) run.label += " (" + rule + ")";
  run.bodies.resize(model.segment_count());
  run.joint_gaps.resize(model.joint_count());
  return run;
}

}  // namespace

void History::push(float value) {
  values_[next_] = value;
  next_ = (next_ + 1) % static_cast<int>(values_.size());
}

float History::latest() const {
  const int n = static_cast<int>(values_.size());
  return values_[(next_ + n - 1) % n];
}

float History::max() const { return *std::max_element(values_.begin(), values_.end()); }

std::optional<compare::ScenarioError> validate(const SessionConfig& config) {
  using compare::ScenarioError;
  if (!std::isfinite(config.dt) || config.dt <= 0.0) {
    return ScenarioError("must be a positive number of seconds", "dt");
  }
  if (!is_one_of(compare::scenario_names(), config.scenario)) {
    return ScenarioError("unknown scenario " + shown(config.scenario), "scenario");
  }
  if (!is_one_of(compare::solver_names(), config.solver)) {
    return ScenarioError("unknown solver " + shown(config.solver), "solver");
  }
  if (!(config.grab_compliance >= 0.0 && config.grab_compliance <= 1.0)) {
    return ScenarioError("expected a compliance in [0, 1] m/N", "grab_compliance");
  }
  if (auto problem = compare::grab_settings_problem(config.grab_spring)) return problem;
  if (config.anchor != "auto" && config.anchor != "grab" && config.anchor != "scenario") {
    return ScenarioError("expected auto, grab or scenario, got " + shown(config.anchor), "anchor");
  }
  if (!config.start.empty()) {
    try {
      uint64_t seed = 0;
      int64_t index = 0;
      compare::parse_start(config.start, &seed, &index);
    } catch (const std::invalid_argument& e) {
      return ScenarioError(e.what(), "start");
    }
  }
  if (!config.ghost.empty() && !is_one_of(compare::solver_names(), config.ghost)) {
    return ScenarioError("unknown solver " + shown(config.ghost), "ghost");
  }
  if (!std::isfinite(config.shake_amplitude) || config.shake_amplitude < 0.0 ||
      !std::isfinite(config.shake_hz) || config.shake_hz <= 0.0) {
    return ScenarioError("the amplitude must be at least 0 and the frequency above 0", "shake");
  }
  return std::nullopt;
}

namespace {

// the scenario, from its random start when the configuration names one
compare::Scenario scenario_of(const SessionConfig& config, const Model& model) {
  compare::ScenarioOptions options;
  if (!config.start.empty()) {
    uint64_t seed = 0;
    int64_t index = 0;
    compare::parse_start(config.start, &seed, &index);  // validate() checked it
    options.start = compare::random_start(model, seed, index);
  }
  return compare::make_scenario(config.scenario, model, options);
}

}  // namespace

Session::Session(const SessionConfig& config) : config_(config) {
  if (auto problem = validate(config)) throw *problem;
  model_ = std::make_unique<Model>(compare::load_named_model(config.model));
  scenario_ = scenario_of(config, *model_);
  start_over();
}

void Session::start_over() {
  // everything that can throw comes first
  std::vector<Run> runs;
  runs.push_back(make_run(config_.solver, config_.options, *model_));
  if (!config_.ghost.empty()) runs.push_back(make_run(config_.ghost, config_.options, *model_));
  runs_ = std::move(runs);
  time_ = 0.0;
  leftover_ = 0.0;
  grab_segment_ = -1;
  released_pin_ = -1;
  compute_targets(0.0);
  collect_pins();
  for (Run& run : runs_) rebuild(run, scenario_.initial);
}

void Session::configure(const SessionConfig& config) {
  if (auto problem = validate(config)) throw *problem;
  if (config.model != config_.model || config.scenario != config_.scenario ||
      config.start != config_.start) {
    auto model = std::make_unique<Model>(compare::load_named_model(config.model));
    compare::Scenario scenario = scenario_of(config, *model);
    // the solvers are checked before anything is replaced
    make_run(config.solver, config.options, *model);
    if (!config.ghost.empty()) make_run(config.ghost, config.options, *model);
    config_ = config;
    model_ = std::move(model);
    scenario_ = std::move(scenario);
    start_over();
    return;
  }
  std::vector<Run> runs;
  runs.push_back(make_run(config.solver, config.options, *model_));
  if (!config.ghost.empty()) runs.push_back(make_run(config.ghost, config.options, *model_));
  config_ = config;
  // each run continues from its predecessor's state, a new ghost from the solver's; a diverged
  // state is no place to continue from
  auto source = [&](size_t i) -> std::span<const BodyState> {
    if (i < runs_.size() && !runs_[i].diverged) return runs_[i].bodies;
    if (!runs_.empty() && !runs_[0].diverged) return runs_[0].bodies;
    return scenario_.initial;
  };
  // the anchor may have changed with the rule
  compute_targets(time_);
  collect_pins();
  for (size_t i = 0; i < runs.size(); ++i) rebuild(runs[i], source(i));
  runs_ = std::move(runs);
}

void Session::set_environment(const Environment& environment) {
  scenario_.environment = environment;
  for (Run& run : runs_) {
    if (!run.diverged) rebuild(run, std::vector<BodyState>(run.bodies));
  }
}

void Session::reset() { start_over(); }

void Session::rebuild(Run& run, std::span<const BodyState> bodies) const {
  run.simulator->reset(*model_, scenario_);
  run.simulator->set_pins(pins_);
  run.simulator->set_pin_targets(targets_);
  run.simulator->set_state(bodies);
  run.simulator->read_state(run.bodies);
  compare::joint_gaps(*model_, run.bodies, run.joint_gaps);
  run.energy_start = compare::mechanical_energy(*model_, scenario_.environment, run.bodies);
  run.energy_reference = compare::energy_reference(*model_, scenario_.environment, run.bodies);
  run.diverged = false;
}

int Session::advance(double seconds, int max_steps) {
  leftover_ += seconds;
  int steps = static_cast<int>(std::floor(leftover_ / config_.dt + 1e-9));
  if (steps > max_steps) {
    // too slow for real time: drop the backlog rather than fall further behind
    steps = max_steps;
    leftover_ = 0.0;
  } else {
    leftover_ = std::max(0.0, leftover_ - steps * config_.dt);
  }
  if (steps > 0) step_frame(steps);
  return steps;
}

void Session::step_frame(int steps) {
  using Clock = std::chrono::steady_clock;
  std::vector<double> seconds(runs_.size(), 0.0), own(runs_.size(), -1.0);
  // a move of the mouse is spread over the frame's steps, as a hand moves, not taken in one
  for (int k = 0; k < steps; ++k) {
    compute_targets(time_ + config_.dt, static_cast<double>(k + 1) / steps);
    for (size_t i = 0; i < runs_.size(); ++i) {
      Run& run = runs_[i];
      if (run.diverged) continue;
      run.simulator->set_pin_targets(targets_);
      const auto start = Clock::now();
      run.simulator->step(config_.dt);
      seconds[i] += std::chrono::duration<double>(Clock::now() - start).count();
      const double own_seconds = run.simulator->own_step_seconds();
      if (own_seconds >= 0.0) own[i] = std::max(own[i], 0.0) + own_seconds;
      judge(run, time_ + config_.dt);
    }
    time_ += config_.dt;
  }
  grab_from_ = grab_target_;
  for (size_t i = 0; i < runs_.size(); ++i) {
    Run& run = runs_[i];
    if (run.diverged) continue;
    const double gap = run.joint_gaps.empty()
                           ? 0.0
                           : *std::max_element(run.joint_gaps.begin(), run.joint_gaps.end());
    run.gap_mm.push(static_cast<float>(gap * 1e3));
    run.step_us.push(static_cast<float>(seconds[i] / steps * 1e6));
    run.own_step_us = own[i] >= 0.0 ? static_cast<float>(own[i] / steps * 1e6) : -1.0f;
  }
}

void Session::judge(Run& run, double t) {
  run.simulator->read_state(run.bodies);
  compare::joint_gaps(*model_, run.bodies, run.joint_gaps);
  pin_gaps_.resize(pins_.size());
  compare::pin_gaps(pins_, targets_, run.bodies, pin_gaps_);
  run.pin_gap_max = pin_gaps_.empty() ? 0.0 : *std::max_element(pin_gaps_.begin(), pin_gaps_.end());
  // the testbed's criteria after every step, as the testbed applies them: non-finite, a joint gap
  // over 0.5 m, or energy above 10 E_ref (a user does work, but nowhere near that much)
  compare::StepMetrics m;
  m.finite = !run.simulator->diverged() && all_finite(run.bodies);
  m.joint_gap_max = run.joint_gaps.empty()
                        ? 0.0
                        : *std::max_element(run.joint_gaps.begin(), run.joint_gaps.end());
  m.energy_drift =
      (compare::mechanical_energy(*model_, scenario_.environment, run.bodies) - run.energy_start) /
      run.energy_reference;
  const char* reason = compare::divergence_reason(m);
  // NaN passes every comparison
  if (reason == nullptr && !std::isfinite(m.joint_gap_max + m.energy_drift)) reason = "non-finite";
  if (reason != nullptr) {
    run.diverged = true;
    run.diverged_at = t;
    run.diverged_reason = reason;
  }
}

bool Session::grab_anchors() const {
  return config_.anchor == "grab" ||
         (config_.anchor == "auto" &&
          procedural::rule_info(config_.options.procedural.rule).grab_anchors);
}

int Session::grab_index() const {
  if (!grabbing()) return -1;
  const int kept = static_cast<int>(scenario_.pins.size()) - (released_pin_ >= 0 ? 1 : 0);
  return grab_anchors() ? 0 : kept;
}

void Session::compute_targets(double t, double along) {
  scenario_.targets_at(t, targets_);
  if (!grabbing()) return;
  if (released_pin_ >= 0) targets_.erase(targets_.begin() + released_pin_);
  Vector3d target = grab_from_ + along * (grab_target_ - grab_from_);
  if (shake_) {
    const double phase = 2.0 * M_PI * config_.shake_hz * (t - shake_start_);
    target += config_.shake_amplitude * std::sin(phase) * shake_axis_;
  }
  targets_.insert(targets_.begin() + grab_index(), target);
}

void Session::collect_pins() {
  pins_ = scenario_.initial_pins();
  if (grabbing()) {
    if (released_pin_ >= 0) pins_.erase(pins_.begin() + released_pin_);
    Pin grab;
    grab.segment = grab_segment_;
    grab.local_point = grab_local_;
    grab.target = grab_target_;
    if (config_.grab_pin) {
      grab.compliance = config_.grab_compliance;
    } else {
      grab.grab = compare::grab_spring(*model_, config_.grab_spring);
    }
    pins_.insert(pins_.begin() + grab_index(), grab);
  }
  for (size_t i = 0; i < pins_.size(); ++i) pins_[i].target = targets_[i];
}

void Session::pins_changed() {
  collect_pins();
  for (Run& run : runs_) {
    if (!run.diverged) run.simulator->set_pins(pins_);
  }
}

void Session::grab(int segment, const Vector3d& local_point, const Vector3d& target) {
  grab_segment_ = segment;
  released_pin_ = -1;
  for (size_t i = 0; i < scenario_.pins.size(); ++i) {
    if (scenario_.pins[i].pin.segment == segment) released_pin_ = static_cast<int>(i);
  }
  grab_local_ = local_point;
  grab_target_ = target;
  grab_from_ = target;
  shake_start_ = time_;
  compute_targets(time_);
  pins_changed();
}

void Session::move_grab(const Vector3d& target) { grab_target_ = target; }

void Session::release() {
  if (!grabbing()) return;
  grab_segment_ = -1;
  released_pin_ = -1;
  compute_targets(time_);
  pins_changed();
}

void Session::set_shake(bool on, const Vector3d& axis) {
  shake_ = on;
  shake_axis_ = axis;
  shake_start_ = time_;
}

}  // namespace puppet::viewer
