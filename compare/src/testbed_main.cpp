// testbed: runs the scenarios in the solvers and writes what it measured.
//
// Bad input (an unknown name, a malformed flag, a bad model file, an unwritable folder) exits
// with status 2 and one line naming the flag or file and the problem, before anything is written.
#include <unistd.h>

#include <csignal>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

#include "puppet/compare/cancel.h"
#include "puppet/compare/frontier.h"
#include "puppet/compare/gate.h"
#include "puppet/compare/number.h"
#include "puppet/compare/output.h"
#include "puppet/compare/output_folder.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/run.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/shard.h"
#include "puppet/compare/simulator.h"
#include "puppet/compare/start.h"
#include "puppet/compare/sweep.h"
#include "puppet/compare/truth_cache.h"
#include "puppet/compare/verdict.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/file.h"
#include "puppet/model/mjcf.h"
#include "puppet/model/model.h"
#include "puppet/model/text.h"
#include "puppet/procedural/solver.h"
#include "puppet/reference/bullet.h"
#include "puppet/reference/mujoco.h"

namespace {

using namespace puppet;
using namespace puppet::compare;

constexpr int kBadInput = 2;
constexpr size_t kMessageLength = 400;  // an error is one line of at most this many characters

// one line of at most kMessageLength characters, the prefix included
void print_error(const char* prefix, const std::string& what) {
  std::cerr << one_line(prefix + what, kMessageLength) << '\n';
}

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Vector3d parse_vector(const std::string& flag, const std::string& text, double bound) {
  std::vector<double> parts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    double value = 0.0;
    if (!parse_finite(item, &value)) break;
    parts.push_back(value);
  }
  if (parts.size() != 3 || std::count(text.begin(), text.end(), ',') != 2) {
    throw UsageError(flag + ": expected three finite numbers X,Y,Z, got " + shown(text));
  }
  for (double part : parts) {
    if (std::abs(part) > bound) {
      std::ostringstream message;
      message << flag << ": " << shown(text) << " has a component beyond " << bound
              << " in magnitude";
      throw UsageError(message.str());
    }
  }
  return {parts[0], parts[1], parts[2]};
}

PointChoice parse_point(const std::string& flag, const std::string& text) {
  PointChoice choice;
  const auto colon = text.find(':');
  choice.segment = text.substr(0, colon);
  if (choice.segment.empty())
    throw UsageError(flag + ": expected SEGMENT[:x,y,z], got " + shown(text));
  // within 100 m of the segment's centre
  if (colon != std::string::npos) {
    choice.local_point = parse_vector(flag, text.substr(colon + 1), 100.0);
  }
  return choice;
}

// a number within [lo, hi] (the flag's stated range, docs in --help and docs/testbed.md)
double parse_in(const std::string& flag, const std::string& text, double lo, double hi,
                const char* unit = "") {
  double value = 0.0;
  if (!parse_finite(text, &value)) throw UsageError(flag + ": not a finite number: " + shown(text));
  if (!(value >= lo && value <= hi)) {
    std::ostringstream range;
    range << flag << ": " << text << " is out of range (from " << lo << " to " << hi << unit << ")";
    throw UsageError(range.str());
  }
  return value;
}

std::vector<std::string> expand(const std::string& flag, const std::string& value,
                                const std::vector<std::string>& all) {
  if (value == "all") return all;
  std::vector<std::string> out;
  std::stringstream in(value);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (std::find(all.begin(), all.end(), item) == all.end()) {
      std::string known;
      for (const auto& a : all) known += (known.empty() ? "" : ", ") + a;
      throw UsageError(flag + ": unknown value " + shown(item) + " (expected all or one of " +
                       known + ")");
    }
    // a repeat would run twice, write its summary rows twice and overwrite its own trace
    if (std::find(out.begin(), out.end(), item) != out.end()) {
      throw UsageError(flag + ": " + shown(item) + " is listed twice");
    }
    out.push_back(item);
  }
  if (out.empty() || value.back() == ',')
    throw UsageError(flag + ": empty item in " + shown(value));
  return out;
}

std::vector<std::string> all_rules() {
  std::vector<std::string> out;
  for (auto rule : procedural::kAllRules) out.emplace_back(procedural::rule_name(rule));
  return out;
}

// what each reference engine refuses of the model (empty when it builds it): MuJoCo's depth,
// arena and compiler (reference::mujoco_model_problem), Bullet's (reference::bullet_model_problem)
std::string engine_problem(const std::string& solver, const Model& model) {
  if (solver == "mujoco") return reference::mujoco_model_problem(model);
  if (solver == "bullet-multibody" || solver == "bullet-rigid") {
    return reference::bullet_model_problem(model);
  }
  return {};
}

int command_list() {
  std::cout << "scenarios:";
  for (const auto& s : scenario_names()) std::cout << ' ' << s;
  std::cout << "\nsolvers:  ";
  for (const auto& s : solver_names()) std::cout << ' ' << s;
  std::cout << "\nrules:    ";
  for (const auto& r : all_rules()) std::cout << ' ' << r;
  std::cout << " (procedural only; default relaxed)\nmodels:    pinocchio (" << builtin_model_path()
            << "), chain:N, or any model file\n";
  return 0;
}

// the model as MJCF (mjcf.h), to a file (written whole or not at all) or to stdout
int command_export_mjcf(const std::string& path, const std::string& out) {
  if (!out.empty() && out != "-") {
    if (std::string problem = output_file_problem(out); !problem.empty()) {
      throw UsageError("-o: " + shown(out) + " " + problem);
    }
  }
  const Model model = load_named_model(path);
  if (std::string problem = mjcf_write_problem(model); !problem.empty()) {
    throw UsageError("MODEL: " + shown(path) + ": " + problem);
  }
  MjcfOptions options;
  options.environment.gravity = model.gravity;
  const std::string xml = write_mjcf(model, options);
  if (out.empty() || out == "-") {
    std::cout << xml;
  } else {
    write_file_atomically(out, xml);
    std::fprintf(stderr, "wrote %s (MJCF of model \"%s\")\n", out.c_str(), model.name.c_str());
  }
  return 0;
}

int command_validate(const std::string& path) {
  const Model model = load_named_model(path);
  std::printf("model \"%s\": %d segments, %d joints, total mass %.3f kg, rest height %.3f m\n",
              model.name.c_str(), model.segment_count(), model.joint_count(), model.total_mass,
              model.rest_height);
  std::printf("  %-14s %-14s %8s  %s\n", "segment", "parent", "mass kg", "shape");
  for (const Segment& s : model.segments) {
    const char* shape = s.shape.type == ShapeType::kCapsule    ? "capsule"
                        : s.shape.type == ShapeType::kBox      ? "box"
                        : s.shape.type == ShapeType::kCylinder ? "cylinder"
                                                               : "sphere";
    std::printf("  %-14s %-14s %8.3f  %s\n", s.name.c_str(),
                s.parent >= 0 ? model.segments[s.parent].name.c_str() : "-", s.mass, shape);
  }
  std::printf("  %-14s %-6s %-14s %-14s %s\n", "joint", "type", "parent", "child", "limits (deg)");
  for (const Joint& j : model.joints) {
    const double d = 180.0 / M_PI;
    char limits[96];
    if (j.type == JointType::kBall && j.ball_limit == BallLimit::kEulerBox) {
      std::snprintf(limits, sizeof limits, "box %s [%.0f, %.0f] [%.0f, %.0f] [%.0f, %.0f]",
                    euler_order_name(j.box_order).c_str(), j.box_lower[0] * d, j.box_upper[0] * d,
                    j.box_lower[1] * d, j.box_upper[1] * d, j.box_lower[2] * d, j.box_upper[2] * d);
    } else if (j.type == JointType::kBall) {
      std::snprintf(limits, sizeof limits, "swing %.0f x %.0f, twist %.0f", j.swing_x * d,
                    j.swing_y * d, j.twist * d);
    } else if (j.type == JointType::kHinge) {
      std::snprintf(limits, sizeof limits, "range [%.0f, %.0f]", j.lower * d, j.upper * d);
    } else {
      std::snprintf(limits, sizeof limits, "fixed");
    }
    const char* type = j.type == JointType::kBall    ? "ball"
                       : j.type == JointType::kHinge ? "hinge"
                                                     : "fixed";
    std::printf("  %-14s %-6s %-14s %-14s %s\n", j.name.c_str(), type,
                model.segments[j.parent].name.c_str(), model.segments[j.child].name.c_str(),
                limits);
  }
  // what each engine makes of it: the verdict every command applies before it runs
  std::string engines, refusals;
  for (const std::string& solver : solver_names()) {
    const std::string problem = engine_problem(solver, model);
    if (problem.empty()) {
      engines += (engines.empty() ? "" : ", ") + solver;
    } else {
      refusals += "  not " + solver + ": " + one_line(problem, 300) + "\n";
    }
  }
  std::printf("engines: %s\n%s", engines.c_str(), refusals.c_str());
  return 0;
}

struct RunFlags {
  std::string model = "pinocchio", scenario = "all", solver = "all", rule = "all";
  std::string dt = "1/30,1/60,1/120,1/240,1/480", duration, out = "results", pin, grab, gravity,
              air_drag, ground;
  // iterations and substeps empty: the rule's own (relaxed 4 × 1, xpbd 1 × 8)
  // numbers that may be fractions (1/240) are read by parse_finite (CLI11 reads no fractions, and
  // its doubles take hex and leading blanks); counts and choices are CLI11's, typed and checked
  std::string tilt = "30", hz = "0.5", sample_hz = "30", grab_compliance;
  int iterations = procedural::kRuleDefault, substeps = procedural::kRuleDefault;
  int bullet_iterations = 10, jobs = default_jobs();
  std::string mujoco_integrator = "euler";
  bool no_velocities = false, no_tremble = false, no_timing = false, bullet_euler_limits = false;
  bool no_accuracy = false;
  bool first_truth_only = false;
  std::string truth_cache;  // run: a folder of truth trajectories (truth_cache.h)
  std::string start;        // run: SEED:INDEX, a random start (start.h)
  // robustness
  std::string starts = "100", seed = "1", shard;
  // verdict
  std::string budget = "1mm,1cm,5cm", frame_hz = "60", floors_from;

  static int default_jobs() {
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  }
};

// a one-line progress bar on a terminal, a line every tenth of the way otherwise
class Progress {
 public:
  explicit Progress(std::string label)
      : label_(std::move(label)), terminal_(isatty(fileno(stderr))), start_(Clock::now()) {}

  void operator()(size_t done, size_t total) {
    const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    const int tenth = static_cast<int>(10 * done / std::max<size_t>(total, 1));
    if (!terminal_ && tenth == last_tenth_ && done != total) return;
    last_tenth_ = tenth;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done / std::max<size_t>(total, 1));
    std::fprintf(stderr, "%s%s [%s%s] %zu/%zu jobs, %.0f s%s", terminal_ ? "\r" : "",
                 label_.c_str(), std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), done, total, seconds,
                 terminal_ && done != total ? "" : "\n");
    std::fflush(stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  bool terminal_;
  Clock::time_point start_;
  int last_tenth_ = -1;
};

// the steps a run may take, from 10 µs to 0.1 s each
constexpr double kMinDt = 1e-5, kMaxDt = 0.1;

std::vector<double> parse_dts(const std::string& text) {
  std::vector<double> dts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const double dt = parse_in("--dt", item, kMinDt, kMaxDt, " s");
    // two dts that print alike would be one run twice and one trace file
    for (double other : dts) {
      if (format_dt(other) == format_dt(dt)) {
        throw UsageError("--dt: " + shown(item) + " is the step " + format_dt(dt) +
                         " s, listed already");
      }
    }
    dts.push_back(dt);
  }
  if (dts.empty() || text.back() == ',') throw UsageError("--dt: empty item in " + shown(text));
  return dts;
}

ScenarioOptions parse_scenario_options(const RunFlags& f) {
  ScenarioOptions options;
  options.tilt_deg = parse_in("--tilt", f.tilt, -180.0, 180.0, " deg");
  options.hz = parse_in("--hz", f.hz, 1e-3, 50.0, " Hz");
  if (!f.pin.empty()) options.pin = parse_point("--pin", f.pin);
  if (!f.grab.empty()) options.grab = parse_point("--grab", f.grab);
  if (!f.grab_compliance.empty()) {
    options.grab_compliance = parse_in("--grab-compliance", f.grab_compliance, 0.0, 1e3, " m/N");
  }
  // the model's own limit on gravity
  if (!f.gravity.empty()) options.gravity = parse_vector("--gravity", f.gravity, 1e3);
  // drag decays exactly over a step (step_drag_rate): any rate is stable
  if (!f.air_drag.empty()) options.air_drag = parse_in("--air-drag", f.air_drag, 0.0, 1e9, " 1/s");
  if (!f.ground.empty()) options.ground = f.ground == "on";  // CLI11 checked it
  return options;
}

// every solver of --solver, and for procedural every rule of --rule
std::vector<SolverConfig> parse_solver_configs(const RunFlags& f) {
  SolverOptions options;
  options.iterations = f.iterations;  // CLI11 checked the ranges
  options.substeps = f.substeps;
  options.bullet_iterations = f.bullet_iterations;
  options.bullet_euler_limits = f.bullet_euler_limits;
  options.mujoco_integrator = f.mujoco_integrator == "rk4" ? reference::MujocoIntegrator::kRk4
                              : f.mujoco_integrator == "implicit"
                                  ? reference::MujocoIntegrator::kImplicit
                                  : reference::MujocoIntegrator::kEuler;
  options.derive_velocities = !f.no_velocities;
  options.tremble = !f.no_tremble;
  const auto solvers = expand("--solver", f.solver, solver_names());
  const auto rules = expand("--rule", f.rule, all_rules());
  std::vector<SolverConfig> configs;
  for (const auto& solver : solvers) {
    if (solver == "procedural") {
      for (const auto& rule : rules) {
        SolverOptions o = options;
        o.rule = *procedural::parse_rule(rule);  // expand() accepted only rule names
        configs.push_back({solver, o});
      }
    } else {
      configs.push_back({solver, options});
    }
  }
  return configs;
}

Model parse_model(const RunFlags& f) {
  try {
    return load_named_model(f.model);
  } catch (const ModelError& error) {
    throw UsageError(std::string("--model: ") + error.what());
  }
}

// What the flags imply, checked before anything runs: every run takes at least one step and at
// most kMaxSteps (the truths too, at their 1/15360 s), what the sweep holds in memory at once
// stays under kMaxMemory, and every trace's file name fits a file system's 255 bytes.
constexpr double kMaxSteps = 1e7;
constexpr double kMaxMemory = 2.0 * (1u << 30);  // bytes

void check_run_size(const SweepSpec& spec, const Model& model) {
  const double n = model.segment_count();
  double longest = 0.0;
  for (const Scenario& scenario : spec.scenarios) {
    longest = std::max(longest, spec.run.duration >= 0.0 ? spec.run.duration : scenario.duration);
  }
  const double smallest_dt = *std::min_element(spec.dts.begin(), spec.dts.end());
  const double largest_dt = *std::max_element(spec.dts.begin(), spec.dts.end());
  const std::string flag = spec.run.duration >= 0.0 ? "--duration" : "--dt";
  if (std::llround(longest / largest_dt) < 1) {
    throw UsageError(flag + ": a run of " + format_dt(longest) + " s at dt " +
                     format_dt(largest_dt) + " s takes no step");
  }
  const double steps = longest / smallest_dt;
  if (steps > kMaxSteps) {
    std::ostringstream message;
    message << flag << ": " << format_dt(longest) << " s at dt " << format_dt(smallest_dt)
            << " s is " << steps << " steps per run (at most " << kMaxSteps << ")";
    throw UsageError(message.str());
  }
  const double truth_steps = longest * 15360.0;
  if (spec.accuracy && truth_steps > kMaxSteps) {
    std::ostringstream message;
    message << "--duration: the truths would take " << truth_steps
            << " steps of 1/15360 s (at most " << kMaxSteps
            << "); shorten it or pass --no-accuracy";
    throw UsageError(message.str());
  }
  // in flight per job: the trace, the poses kept and the trajectory for accuracy; held for the
  // whole sweep: six truth trajectories per scenario (two truths at three dts) and
  // bullet-multibody's at every dt
  const double samples = longest / kAccuracySampleInterval + 1;
  const double kept_poses = spec.run.sample_hz > 0.0 ? longest * spec.run.sample_hz + 1 : steps;
  const double per_job = steps * sizeof(StepMetrics) + kept_poses * n * sizeof(PoseSample) +
                         samples * n * sizeof(BodyState);
  const double held = spec.accuracy ? (6.0 + spec.dts.size()) * spec.scenarios.size() * samples *
                                          n * sizeof(BodyState)
                                    : 0.0;
  const double memory = spec.jobs * per_job + held;
  if (memory > kMaxMemory) {
    std::ostringstream message;
    message << "--model, --duration, --sample-hz, --jobs: the sweep would hold "
            << std::lround(memory / (1 << 20)) << " MiB at once (at most "
            << std::lround(kMaxMemory / (1 << 20))
            << "); use a smaller model, a shorter run, fewer poses kept or fewer jobs";
    throw UsageError(message.str());
  }
  for (const Scenario& scenario : spec.scenarios) {
    for (const SolverConfig& config : spec.configs) {
      for (double dt : spec.dts) {
        RunResult r;
        r.scenario = scenario.name;
        r.solver = config.solver;
        r.rule = rule_of(config);
        r.dt = dt;
        const std::string name = trace_stem(model.name, r) + "__poses.csv";
        if (name.size() > 255) {
          throw UsageError("--model: the trace file name " + shown(name) + " is " +
                           std::to_string(name.size()) + " bytes (at most 255)");
        }
      }
    }
  }
}

// One verdict per model, before anything runs: an engine that cannot build the model is refused
// when --solver names it, and left out with a note when --solver is all
void apply_engine_verdicts(std::vector<SolverConfig>& configs, const Model& model,
                           const RunFlags& f) {
  std::vector<std::string> refused;
  for (const SolverConfig& config : configs) {
    if (std::find(refused.begin(), refused.end(), config.solver) != refused.end()) continue;
    const std::string problem = engine_problem(config.solver, model);
    if (problem.empty()) continue;
    if (f.solver != "all") {
      throw UsageError("--solver: " + config.solver + " cannot run " + shown(f.model) + ": " +
                       problem);
    }
    print_error("testbed: ", "note: " + config.solver + " left out, it cannot run " +
                                 shown(f.model) + ": " + problem);
    refused.push_back(config.solver);
  }
  std::erase_if(configs, [&](const SolverConfig& c) {
    return std::find(refused.begin(), refused.end(), c.solver) != refused.end();
  });
}

// the dt of the sweep shown in the table: the one nearest 1/240 s
double table_dt(const std::vector<double>& dts) {
  return *std::min_element(dts.begin(), dts.end(), [](double a, double b) {
    return std::abs(std::log(a * 240)) < std::abs(std::log(b * 240));
  });
}

void print_table(const std::vector<RunResult>& results, double dt) {
  std::printf("\ndt = %s s (every dt is in summary.csv)\n", format_dt(dt).c_str());
  std::printf("%-8s %-16s %-9s %-8s %11s %11s %11s %9s %9s %11s\n", "scenario", "solver", "rule",
              "status", "joint gap m", "pin gap m", "E drift", "limit deg", "us/step",
              "reseeded m");
  for (const RunResult& r : results) {
    if (r.dt != dt) continue;
    auto show = [&](const char* metric, const char* stat, const char* format,
                    const char* reference = "") {
      double v = std::numeric_limits<double>::quiet_NaN();
      for (const SummaryRow& row : r.summary) {
        if (row.metric == metric && row.stat == stat && row.reference == reference) v = row.value;
      }
      if (std::isnan(v)) return std::string("-");
      char cell[32];
      std::snprintf(cell, sizeof cell, format, v);
      return std::string(cell);
    };
    const std::string status =
        r.diverged ? "div@" + show("diverged_at_s", "value", "%.2f") : std::string("ok");
    std::printf("%-8s %-16s %-9s %-8s %11s %11s %11s %9s %9s %11s\n", r.scenario.c_str(),
                r.solver.c_str(), r.rule.empty() ? "-" : r.rule.c_str(), status.c_str(),
                show("joint_gap_m", "max", "%.2e").c_str(),
                show("pin_gap_m", "max", "%.2e").c_str(),
                show("energy_drift", "final", "%+.2e").c_str(),
                show("limit_violation_deg", "max", "%.1e").c_str(),
                show("step_us", "median", "%.1f").c_str(),
                show("pose_err_m", "reseeded_mean", "%.2e", "truth").c_str());
  }
}

int command_run(const RunFlags& f) {
  // every flag checked before anything runs or is written
  SweepSpec spec;
  spec.dts = parse_dts(f.dt);
  if (!f.duration.empty())
    spec.run.duration = parse_in("--duration", f.duration, 0.0, 3600.0, " s");
  spec.run.sample_hz = parse_in("--sample-hz", f.sample_hz, 0.0, 1e4, " Hz");
  spec.run.timing = !f.no_timing;
  spec.accuracy = !f.no_accuracy;
  spec.first_truth_only = f.first_truth_only;
  spec.jobs = f.jobs;
  const ScenarioOptions scenario_options = parse_scenario_options(f);
  spec.configs = parse_solver_configs(f);
  const auto scenarios = expand("--scenario", f.scenario, scenario_names());
  const Model model = parse_model(f);
  spec.model = &model;
  ScenarioOptions options = scenario_options;
  if (!f.start.empty()) {
    uint64_t seed = 0;
    int64_t index = 0;
    try {
      parse_start(f.start, &seed, &index);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--start: ") + e.what());
    }
    options.start = random_start(model, seed, index);
  }
  for (const auto& name : scenarios) {
    spec.scenarios.push_back(make_scenario(name, model, options));
  }
  check_run_size(spec, model);
  apply_engine_verdicts(spec.configs, model, f);
  // the truths this model has (sweep.h): none, no accuracy rows; one, judged by it alone
  if (spec.accuracy) {
    const std::vector<Truth> truths = truths_for(model);
    if (truths.empty()) {
      print_error("testbed: ",
                  "note: no truth for this model (neither MuJoCo nor bullet-multibody "
                  "can run it); no accuracy rows");
      spec.accuracy = false;
    } else if (truths.size() == 1) {
      print_error("testbed: ", "note: one truth for this model (" + truths[0].solver +
                                   "): the other cannot run it");
    }
  }
  // made if missing: the last flag checked, so that a bad one before it leaves nothing behind
  try {
    spec.truth_cache = TruthCache(f.truth_cache).folder();
  } catch (const std::runtime_error& e) {
    throw UsageError(std::string("--truth-cache: ") + e.what());
  }
  OutputFolder folder("--out", f.out, {"summary.csv", "traces"});
  const std::filesystem::path traces = folder.staging() / "traces";
  std::filesystem::create_directory(traces);

  for (double dt : spec.dts) {
    if (spec.accuracy && !divides_sample_interval(dt)) {
      std::fprintf(stderr, "testbed: dt %s s does not divide 1/30 s: no accuracy rows for it\n",
                   format_dt(dt).c_str());
    }
  }
  const double sample_hz = spec.run.sample_hz;
  spec.on_run = [&](const RunResult& r) {
    const std::string stem = (traces / trace_stem(model.name, r)).string();
    write_file_atomically(stem + ".csv", trace_csv(r, sample_hz));
    write_file_atomically(stem + "__poses.csv", poses_csv(model, r));
  };
  spec.on_progress = Progress("run");
  const std::vector<RunResult> results = run_sweep(spec);

  const OutputContext context{model.name, current_git_sha(), machine_description()};
  write_file_atomically((folder.staging() / "summary.csv").string(), summary_csv(results, context));
  folder.commit();
  print_table(results, table_dt(spec.dts));
  const size_t runs = spec.scenarios.size() * spec.configs.size() * spec.dts.size();
  std::printf("\nwrote %s: summary.csv and %zu traces\n", folder.path().c_str(), 2 * runs);
  return 0;
}

int command_frontier(const RunFlags& f) {
  FrontierSpec spec;
  spec.scenario = parse_scenario_options(f);
  spec.configs = parse_solver_configs(f);
  spec.jobs = f.jobs;
  const Model model = parse_model(f);
  spec.model = &model;
  apply_engine_verdicts(spec.configs, model, f);
  make_scenario("yank", model, spec.scenario);  // a bad --grab fails here, before any run
  OutputFolder folder("--out", f.out, {"frontier.csv"});
  spec.on_progress = Progress("frontier");
  const std::vector<FrontierRow> rows = find_frontier(spec);

  const OutputContext context{model.name, current_git_sha(), machine_description()};
  write_file_atomically((folder.staging() / "frontier.csv").string(), frontier_csv(rows, context));
  folder.commit();
  std::printf(
      "\nyank, no air drag: the largest circle frequency (at dt = %s s) and the largest dt "
      "(at %s Hz) that stay ok\n",
      format_dt(spec.hz_dt).c_str(), format_dt(spec.scenario.hz).c_str());
  std::printf("%-16s %-9s %-9s %12s %14s %10s  %s\n", "solver", "rule", "quantity", "largest ok",
              "first diverged", "pin gap m", "reason");
  for (const FrontierRow& r : rows) {
    auto cell = [](const std::optional<double>& v, bool inverse) {
      if (!v) return std::string("-");
      char text[32];
      std::snprintf(text, sizeof text, inverse ? "1/%.0f" : "%.3g", inverse ? 1.0 / *v : *v);
      return std::string(text);
    };
    const bool dt = r.quantity == "dt";
    char pin_gap[32] = "-";
    if (r.largest_ok) std::snprintf(pin_gap, sizeof pin_gap, "%.3f", r.pin_gap_at_largest_ok);
    std::printf("%-16s %-9s %-9s %12s %14s %10s  %s\n", r.solver.c_str(),
                r.rule.empty() ? "-" : r.rule.c_str(), r.quantity.c_str(),
                cell(r.largest_ok, dt).c_str(), cell(r.first_diverged, dt).c_str(), pin_gap,
                r.reason.c_str());
  }
  std::printf("\nwrote %s/frontier.csv\n", folder.path().c_str());
  return 0;
}

// error budgets: lengths with a unit (50um, 1mm, 1cm, 0.05m) or plain metres, from 1 µm to 10 m
std::vector<double> parse_budgets(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    double scale = 1.0;
    std::string number = item;
    for (const auto& [unit, factor] :
         {std::pair{"um", 1e-6}, {"mm", 1e-3}, {"cm", 1e-2}, {"m", 1.0}}) {
      const std::string u = unit;
      if (number.size() > u.size() && number.ends_with(u)) {
        number.resize(number.size() - u.size());
        scale = factor;
        break;
      }
    }
    double value = 0.0;
    if (!parse_finite(number, &value) || number.find_first_of(" \t") != std::string::npos) {
      throw UsageError("--budget: expected a length such as 1mm, 1cm or 0.05m, got " + shown(item));
    }
    value *= scale;
    if (!(value >= 1e-6 && value <= 10.0)) {
      throw UsageError("--budget: " + shown(item) + " is out of range (from 1 um to 10 m)");
    }
    for (double other : out) {
      if (std::abs(other - value) <= 1e-12 * value) {
        throw UsageError("--budget: " + shown(item) + " is listed already");
      }
    }
    out.push_back(value);
  }
  if (out.empty() || text.back() == ',') throw UsageError("--budget: empty item in " + shown(text));
  std::sort(out.begin(), out.end());
  return out;
}

int command_verdict(const RunFlags& f) {
  VerdictSpec spec;
  spec.scenarios = expand("--scenario", f.scenario, scenario_names());
  spec.scenario = parse_scenario_options(f);
  spec.solvers = parse_solver_configs(f);
  spec.dts = parse_dts(f.dt);
  for (double dt : spec.dts) {
    if (!divides_sample_interval(dt)) {
      throw UsageError("--dt: " + format_dt(dt) +
                       " s does not divide the error's sample "
                       "interval of 1/30 s");
    }
  }
  spec.budgets_m = parse_budgets(f.budget);
  spec.frame_hz = parse_in("--frame-hz", f.frame_hz, 1.0, 1000.0, " Hz");
  spec.starts = std::llround(parse_in("--starts", f.starts, 1.0, 10000.0, ""));
  if (std::to_string(spec.starts) != f.starts) {
    throw UsageError("--starts: expected a whole number, got " + shown(f.starts));
  }
  if (!parse_whole(f.seed, &spec.seed)) {
    throw UsageError("--seed: expected a whole number of at most 18 digits, got " + shown(f.seed));
  }
  spec.jobs = f.jobs;
  const Model model = parse_model(f);
  spec.model = &model;
  apply_engine_verdicts(spec.solvers, model, f);
  if (truths_for(model).empty()) {
    throw UsageError("--model: " + shown(f.model) +
                     ": no truth can run it (neither MuJoCo nor bullet-multibody)");
  }
  if (!f.floors_from.empty()) {
    // a regular file of a sweep's size: /dev/zero or a FIFO would never end
    std::error_code error;
    const auto status = std::filesystem::status(f.floors_from, error);
    if (error || !std::filesystem::is_regular_file(status)) {
      throw UsageError("--floors-from: " + shown(f.floors_from) + ": not a readable file");
    }
    if (std::filesystem::file_size(f.floors_from, error) > (size_t{256} << 20) || error) {
      throw UsageError("--floors-from: " + shown(f.floors_from) + ": larger than 256 MiB");
    }
    std::ifstream in(f.floors_from, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (!in || in.bad()) {
      throw UsageError("--floors-from: " + shown(f.floors_from) + ": cannot read");
    }
    try {
      spec.floors =
          floors_from_summary(text.str(), f.floors_from, model, spec.scenarios, current_git_sha());
    } catch (const std::runtime_error& e) {
      throw UsageError(std::string("--floors-from: ") + e.what());
    }
  }
  for (const std::string& name : spec.scenarios) {
    ScenarioOptions options = spec.scenario;
    make_scenario(name, model, options);  // a bad --grab or --pin fails here, before any run
    options.start = random_start(model, spec.seed, 0);
    make_scenario(name, model, options);
  }
  OutputFolder folder("--out", f.out, {"candidates.csv", "verdict.csv"});
  Progress bar("verdict");
  std::string shown_phase;
  spec.on_progress = [&](const char* phase, size_t done, size_t total) {
    if (shown_phase != phase) {
      shown_phase = phase;
      bar = Progress(std::string("verdict: ") + phase);
    }
    bar(done, total);
  };
  const VerdictResult result = run_verdict(spec);
  const OutputContext context{model.name, current_git_sha(), machine_description()};
  write_file_atomically((folder.staging() / "candidates.csv").string(),
                        verdict_candidates_csv(result, context));
  write_file_atomically((folder.staging() / "verdict.csv").string(),
                        verdict_csv(result, spec, context));
  folder.commit();

  std::printf(
      "\nthe cheapest configuration within each budget that survives %lld random starts: "
      "CPU us per simulated second (any dt)\n",
      static_cast<long long>(spec.starts));
  std::printf("%-8s %-16s %-9s", "scenario", "solver", "rule");
  for (double b : spec.budgets_m) std::printf(" %14s", budget_text(b).c_str());
  std::printf("\n");
  for (size_t i = 0; i < result.rows.size();) {
    const VerdictRow& first = result.rows[i];
    if (first.view != "second") {
      i += spec.budgets_m.size();
      continue;
    }
    std::printf("%-8s %-16s %-9s", first.scenario.c_str(), first.solver.c_str(),
                first.rule.empty() ? "-" : first.rule.c_str());
    for (size_t b = 0; b < spec.budgets_m.size(); ++b, ++i) {
      const VerdictRow& r = result.rows[i];
      char cell[32];
      if (r.chosen >= 0) {
        std::snprintf(cell, sizeof cell, "%.0f", result.candidates[r.chosen].cost_us_per_s);
      } else {
        std::snprintf(cell, sizeof cell, "%s", r.verdict.c_str());
      }
      std::printf(" %14s", cell);
    }
    std::printf("\n");
  }
  std::printf("\nwrote %s: candidates.csv, verdict.csv\n", folder.path().c_str());
  return 0;
}

// the flags a replay of one robustness run repeats: every one given that changes the run
std::string replay_flags(const RunFlags& f) {
  std::string out;
  auto add = [&](const char* flag, const std::string& value) {
    if (!value.empty()) out += std::string(" ") + flag + " " + shell_word(value);
  };
  add("--duration", f.duration);
  if (f.iterations != procedural::kRuleDefault) add("--iterations", std::to_string(f.iterations));
  if (f.substeps != procedural::kRuleDefault) add("--substeps", std::to_string(f.substeps));
  if (f.bullet_iterations != 10) add("--bullet-iterations", std::to_string(f.bullet_iterations));
  if (f.mujoco_integrator != "euler") add("--mujoco-integrator", f.mujoco_integrator);
  add("--grab-compliance", f.grab_compliance);
  add("--pin", f.pin);
  add("--grab", f.grab);
  add("--gravity", f.gravity);
  add("--air-drag", f.air_drag);
  add("--ground", f.ground);
  if (f.bullet_euler_limits) out += " --bullet-euler-limits";
  if (f.no_velocities) out += " --no-velocities";
  if (f.no_tremble) out += " --no-tremble";
  return out;
}

// the three files of a run or a merge, from its rows in job order: the summary and the worst
// starts are read from the rows as written, so that a merge of shards, which reads them back,
// writes the same bytes
std::string write_robustness(const OutputFolder& folder, const std::vector<RobustnessRow>& rows,
                             const RobustnessSpec& spec) {
  const std::string csv = robustness_csv(rows);
  const std::vector<RobustnessRow> written = parse_robustness_csv(csv, "robustness.csv");
  write_file_atomically((folder.staging() / "robustness.csv").string(), csv);
  write_file_atomically((folder.staging() / "robustness_summary.csv").string(),
                        robustness_summary_csv(written));
  write_file_atomically((folder.staging() / "worst.csv").string(), worst_csv(written, spec));
  return csv;
}

void print_rates(const std::vector<RobustnessRow>& rows) {
  // from the rows as written, as robustness_summary.csv is
  const std::vector<RobustnessRow> written =
      parse_robustness_csv(robustness_csv(rows), "robustness.csv");
  std::printf("\n%-8s %-16s %-9s %-12s %6s %9s %8s %s\n", "scenario", "solver", "rule", "dt",
              "runs", "diverged", "rate", "95 % interval");
  for (const RobustnessRate& r : robustness_rates(written)) {
    std::printf("%-8s %-16s %-9s %-12s %6lld %9lld %8.3f [%.3f, %.3f]\n", r.scenario.c_str(),
                r.solver.c_str(), r.rule.empty() ? "-" : r.rule.c_str(), format_dt(r.dt).c_str(),
                static_cast<long long>(r.runs), static_cast<long long>(r.diverged), r.rate(),
                r.ci95.low, r.ci95.high);
  }
}

// "I/N" in plain decimal digits (the range is the caller's to check)
bool parse_shard(const std::string& text, uint64_t* index, uint64_t* count) {
  const size_t slash = text.find('/');
  return slash != std::string::npos && parse_whole(text.substr(0, slash), index) &&
         parse_whole(text.substr(slash + 1), count);
}

int command_robustness(const RunFlags& f) {
  RobustnessSpec spec;
  spec.dts = parse_dts(f.dt);
  if (!f.duration.empty()) spec.duration = parse_in("--duration", f.duration, 0.0, 3600.0, " s");
  spec.scenario = parse_scenario_options(f);
  spec.configs = parse_solver_configs(f);
  spec.scenarios = expand("--scenario", f.scenario, scenario_names());
  spec.starts = std::llround(parse_in("--starts", f.starts, 1.0, 1e6, ""));
  if (std::to_string(spec.starts) != f.starts) {
    throw UsageError("--starts: expected a whole number, got " + shown(f.starts));
  }
  if (!parse_whole(f.seed, &spec.seed)) {
    throw UsageError("--seed: expected a whole number of at most 18 digits, got " + shown(f.seed));
  }
  if (!f.shard.empty()) {
    uint64_t i = 0, n = 0;
    if (!parse_shard(f.shard, &i, &n)) {
      throw UsageError("--shard: expected I/N, got " + shown(f.shard));
    }
    if (n < 1 || n > static_cast<uint64_t>(kMaxShards) || i >= n) {
      throw UsageError("--shard: expected I/N with 0 <= I < N <= " + std::to_string(kMaxShards) +
                       ", got " + shown(f.shard));
    }
    spec.shard = static_cast<int>(i);
    spec.shards = static_cast<int>(n);
  }
  spec.jobs = f.jobs;
  // what a shard's manifest carries, merge reads back: its model's name too
  if (std::string problem = shard_model_problem(f.model); spec.shards > 1 && !problem.empty()) {
    throw UsageError("--model: " + shown(f.model) + ": " + problem);
  }
  const Model model = parse_model(f);
  spec.model = &model;
  spec.model_name = f.model;
  apply_engine_verdicts(spec.configs, model, f);
  // the bounds merge reads a shard within (shard.h)
  const int64_t jobs = robustness_job_count(spec);
  const int64_t per_shard = (jobs + spec.shards - 1) / spec.shards;
  if (jobs > kMaxSweepRuns || per_shard > kMaxShardRuns) {
    throw UsageError("--starts: " + std::to_string(jobs) + " runs in all, " +
                     std::to_string(per_shard) + " in this shard (at most " +
                     std::to_string(kMaxShardRuns) + " per shard, " +
                     std::to_string(kMaxSweepRuns) + " in all): use more shards");
  }
  // every scenario builds with a start, and no run is longer than a sweep's
  double longest = 0.0;
  for (const std::string& name : spec.scenarios) {
    ScenarioOptions options = spec.scenario;
    options.start = random_start(model, spec.seed, 0);
    const Scenario scenario = make_scenario(name, model, options);
    longest = std::max(longest, spec.duration >= 0.0 ? spec.duration : scenario.duration);
  }
  const double smallest_dt = *std::min_element(spec.dts.begin(), spec.dts.end());
  if (longest / smallest_dt > kMaxSteps) {
    throw UsageError("--dt: " + format_dt(longest) + " s at dt " + format_dt(smallest_dt) +
                     " s is more than 1e7 steps per run");
  }
  if (std::llround(longest / *std::max_element(spec.dts.begin(), spec.dts.end())) < 1) {
    throw UsageError("--duration: a run takes no step");
  }
  spec.replay_flags = replay_flags(f);
  spec.code = current_git_sha();
  OutputFolder folder("--out", f.out,
                      {"robustness.csv", "robustness_summary.csv", "worst.csv", "shard.txt"});
  spec.on_progress = Progress("robustness");
  const auto begin = std::chrono::steady_clock::now();
  const std::vector<RobustnessRow> rows = run_robustness(spec);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  const std::string csv = write_robustness(folder, rows, spec);
  if (spec.shards > 1) {
    write_file_atomically((folder.staging() / "shard.txt").string(),
                          shard_manifest(spec, static_cast<int64_t>(rows.size()), csv));
  }
  folder.commit();
  print_rates(rows);
  std::printf("\n%zu runs in %.1f s on %d threads: %.1f runs/s, %.1f per thread\n", rows.size(),
              seconds, spec.jobs, rows.size() / seconds, rows.size() / seconds / spec.jobs);
  std::printf("wrote %s: robustness.csv, robustness_summary.csv, worst.csv%s\n",
              folder.path().c_str(), spec.shards > 1 ? ", shard.txt" : "");
  return 0;
}

void add_robustness_flags(CLI::App* robustness, RunFlags& rf);

// the replay flags of a shard's manifest as the testbed writes them, from what its own flag
// parsers make of them (ShardError when they do not parse): shard.h's canonical_replay
std::string canonical_replay(const std::string& replay) {
  std::vector<std::string> words;
  if (!split_shell_words(replay, &words)) {
    throw ShardError("not words a shell reads as they are written");
  }
  CLI::App app;
  RunFlags f;
  add_robustness_flags(&app, f);
  std::reverse(words.begin(), words.end());  // CLI11 reads its argument vector from the back
  try {
    app.parse(words);
    if (!f.duration.empty()) parse_in("--duration", f.duration, 0.0, 3600.0, " s");
    parse_scenario_options(f);
  } catch (const CLI::ParseError& e) {
    throw ShardError(e.what());
  } catch (const UsageError& e) {
    throw ShardError(e.what());
  }
  return replay_flags(f);
}

int command_merge(const std::vector<std::string>& folders, const std::string& out) {
  // nothing is written before every shard and every row is checked; a signal meanwhile ends the
  // command at once (cancel.h)
  std::vector<ShardManifest> shards;
  for (const std::string& folder : folders) {
    shards.push_back(read_shard_manifest(folder, [](const std::string& replay) {
      try {
        return canonical_replay(replay);
      } catch (const ShardError& e) {
        throw ShardError("replay: " + shown(replay) + ": " + e.what());
      }
    }));
  }
  check_shard_set(shards);
  std::sort(shards.begin(), shards.end(),
            [](const ShardManifest& a, const ShardManifest& b) { return a.index < b.index; });
  std::vector<RobustnessRow> rows;
  rows.reserve(static_cast<size_t>(std::min<int64_t>(shards.front().jobs, kMaxShardRuns)));
  for (const ShardManifest& shard : shards) {
    const std::vector<RobustnessRow> part = read_shard_rows(shard);
    rows.insert(rows.end(), part.begin(), part.end());
  }
  // each row was its shard's job, each shard there once: every job is here once
  std::sort(rows.begin(), rows.end(),
            [](const RobustnessRow& a, const RobustnessRow& b) { return a.job < b.job; });
  RobustnessSpec spec;
  spec.model_name = shards.front().model;
  spec.replay_flags = shards.front().replay;
  OutputFolder folder("--out", out, {"robustness.csv", "robustness_summary.csv", "worst.csv"});
  write_robustness(folder, rows, spec);
  folder.commit();
  print_rates(rows);
  std::printf("\nmerged %zu shards, %zu runs into %s\n", shards.size(), rows.size(),
              folder.path().c_str());
  return 0;
}

// a count as plain decimal digits: CLI11's integers would also take 0x10, " 3" and 010 (as 8)
const CLI::Validator kWholeNumber(
    [](std::string& text) {
      const bool digits =
          !text.empty() && text.size() <= 9 && (text.size() == 1 || text[0] != '0') &&
          std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
      return digits ? std::string() : "expected a whole number, got " + shown(text);
    },
    "N");

void add_solver_flags(CLI::App* command, RunFlags& f) {
  command->add_option("--model", f.model, "model file, pinocchio, or chain:N")
      ->capture_default_str();
  command->add_option("--solver", f.solver, "solver name, comma list, or all")
      ->capture_default_str();
  command->add_option("--rule", f.rule, "adjust rule (procedural), comma list, or all")
      ->capture_default_str();
  command->add_option("--out", f.out, "output folder")->capture_default_str();
  command->add_option("--jobs", f.jobs, "worker threads")
      ->check(kWholeNumber)
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  command->add_option("--grab", f.grab, "dragged point SEGMENT[:x,y,z] (segment frame)");
  command->add_option("--gravity", f.gravity, "gravity X,Y,Z (m/s^2)");
  command
      ->add_option("--iterations", f.iterations,
                   "relaxed, xpbd: two-sided sweeps per substep; tree: Newton iterations "
                   "(default: the rule's, 4, 1, 1)")
      ->check(kWholeNumber)
      ->check(CLI::Range(0, procedural::kMaxIterations));
  command->add_option("--grab-compliance", f.grab_compliance,
                      "the grab's compliance C (m/N): 0 holds the hand on its target (default), "
                      "C > 0 pulls it with a spring of stiffness 1/C");
  command
      ->add_option("--bullet-iterations", f.bullet_iterations,
                   "Bullet: sequential-impulse sweeps per step")
      ->check(kWholeNumber)
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command->add_flag("--bullet-euler-limits", f.bullet_euler_limits,
                    "bullet-multibody: Bullet's own ball limits (a box of Euler angles)");
  command
      ->add_option("--mujoco-integrator", f.mujoco_integrator,
                   "mujoco: euler (MuJoCo's semi-implicit Euler), implicit or rk4")
      ->check(CLI::IsMember({"euler", "implicit", "rk4"}))
      ->capture_default_str();
  command
      ->add_option(
          "--substeps", f.substeps,
          "procedural substeps per step (default: the rule's, 8 for xpbd and tree, else 1)")
      ->check(kWholeNumber)
      ->check(CLI::Range(1, procedural::kMaxSubsteps));
  command->add_flag("--no-velocities", f.no_velocities,
                    "procedural: do not derive velocities from poses");
}

// robustness's flags and their defaults (the command line's, and merge's reading of a shard's
// replay flags)
void add_robustness_flags(CLI::App* robustness, RunFlags& rf) {
  rf.dt = "1/240";
  rf.out = "results/robustness";
  rf.solver = "procedural";
  add_solver_flags(robustness, rf);
  robustness->add_option("--scenario", rf.scenario, "scenario name, comma list, or all")
      ->capture_default_str();
  robustness->add_option("--dt", rf.dt, "time steps in seconds, comma list")->capture_default_str();
  robustness->add_option("--duration", rf.duration,
                         "seconds to simulate (default: the scenario's)");
  robustness->add_option("--starts", rf.starts, "random starts per scenario, solver, rule and dt")
      ->capture_default_str();
  robustness->add_option("--seed", rf.seed, "the starts' seed")->capture_default_str();
  robustness->add_option("--shard", rf.shard,
                         "run only shard I of N (jobs j with j mod N = I); merge the shards with "
                         "testbed merge");
  robustness->add_option("--pin", rf.pin, "hanging point SEGMENT[:x,y,z] (segment frame)");
  robustness->add_option("--air-drag", rf.air_drag, "air drag k_air (1/s)");
  robustness->add_option("--ground", rf.ground, "ground plane on|off")
      ->check(CLI::IsMember({"on", "off"}));
  robustness->add_flag("--no-tremble", rf.no_tremble, "procedural: no tremble");
}

}  // namespace

// exit 0 when every gate passes, 1 when one fails, 2 on bad input
int command_gate(const std::vector<std::string>& bench_files, const std::string& thresholds,
                 const std::string& csv) {
  if (!csv.empty()) {
    if (std::string problem = output_file_problem(csv); !problem.empty()) {
      throw UsageError("--csv: " + shown(csv) + " " + problem);
    }
  }
  const std::vector<GateSpec> specs = read_gate_specs(thresholds);
  std::vector<BenchTime> times;
  for (const std::string& file : bench_files) {
    for (const BenchTime& time : read_bench_times(file)) times.push_back(time);
  }
  const std::vector<GateResult> results = evaluate_gates(specs, times);
  std::cout << gate_table(results);
  if (!csv.empty()) {
    write_file_atomically(csv, bench_csv(times));
    std::cout << "wrote " << csv << '\n';
  }
  const bool passed = gate_passed(results);
  std::cout << (passed ? "gate: pass\n" : "gate: FAIL\n");
  return passed ? 0 : 1;
}

int run_command(int argc, char** argv) {
  CLI::App app{"testbed: the seed's procedural solver for articulated bodies, measured"};
  app.require_subcommand(1);
  app.fallthrough(false);

  app.add_subcommand("list", "list scenarios, solvers, rules and models");
  std::string validate_path;
  auto* validate = app.add_subcommand("validate", "load a model and print it, or its error");
  validate->add_option("MODEL", validate_path, "model file, pinocchio, or chain:N")->required();

  std::string export_path, export_out;
  auto* export_mjcf = app.add_subcommand(
      "export-mjcf", "write a model as MJCF, MuJoCo's XML format, to stdout or a file");
  export_mjcf->add_option("MODEL", export_path, "model file, pinocchio, or chain:N")->required();
  export_mjcf->add_option("-o,--out", export_out, "output file (default: stdout)");

  RunFlags f;
  auto* run = app.add_subcommand(
      "run",
      "run scenarios x solvers x rules x dts (default: all of them, the main job) and write "
      "summary.csv and traces");
  add_solver_flags(run, f);
  run->add_option("--scenario", f.scenario, "scenario name, comma list, or all")
      ->capture_default_str();
  run->add_option("--dt", f.dt, "time steps in seconds, comma list (fractions such as 1/240 too)")
      ->capture_default_str();
  run->add_option("--duration", f.duration, "seconds to simulate (default: the scenario's)");
  run->add_option("--pin", f.pin, "hanging point SEGMENT[:x,y,z] (segment frame)");
  run->add_option("--air-drag", f.air_drag, "air drag k_air (1/s)");
  run->add_option("--ground", f.ground, "ground plane on|off")->check(CLI::IsMember({"on", "off"}));
  run->add_option("--tilt", f.tilt, "initial tilt of hang and the scenarios built on it (deg)")
      ->capture_default_str();
  run->add_option("--hz", f.hz, "circle frequency of drag and yank (Hz)")->capture_default_str();
  run->add_option("--sample-hz", f.sample_hz,
                  "trace rows and poses kept per simulated second (0: every step)")
      ->capture_default_str();
  run->add_flag("--no-tremble", f.no_tremble,
                "procedural: no tremble even in the tremble scenario");
  run->add_flag("--no-timing", f.no_timing, "skip the separate timing pass");
  run->add_option("--start", f.start,
                  "SEED:INDEX: the random start of testbed robustness (pose, velocities, tilt, "
                  "grab point, circle frequency and phase)");
  run->add_flag("--first-truth-only", f.first_truth_only,
                "judge against the first truth alone, at its dt: no error bars, no second truth "
                "(quicker, to compare configurations)");
  run->add_option("--truth-cache", f.truth_cache,
                  "FOLDER: keep the truths' trajectories there and read them back in later runs "
                  "of this build on the same model and scenario (made if missing)");
  run->add_flag("--no-accuracy", f.no_accuracy,
                "skip the truths (mujoco RK4 at 1/7680 s, bullet-multibody at 1/3840 s, each at "
                "half and twice that too) and the accuracy rows");

  auto* frontier = app.add_subcommand(
      "frontier",
      "bisect, per solver and rule, the largest circle frequency and dt at which yank stays ok; "
      "write frontier.csv");
  add_solver_flags(frontier, f);
  frontier->add_option("--hz", f.hz, "circle frequency held during the dt search (Hz)")
      ->capture_default_str();

  RunFlags rf;
  auto* robustness = app.add_subcommand(
      "robustness",
      "run every scenario x solver x rule x dt from N random starts (--seed); write "
      "robustness.csv, "
      "the divergence rates with 95 % Wilson intervals and the worst starts as replay commands");
  add_robustness_flags(robustness, rf);

  RunFlags vf;
  vf.dt = "1/30,1/60,1/120,1/240,1/480,1/960";
  vf.out = "results/verdict";
  vf.starts = "32";
  auto* verdict = app.add_subcommand(
      "verdict",
      "per solver and scenario, the cheapest configuration (dt, substeps, sweeps) within each "
      "error budget against the truth that survives N random starts; write candidates.csv and "
      "verdict.csv");
  verdict->add_option("--model", vf.model, "model file, pinocchio, or chain:N")
      ->capture_default_str();
  verdict->add_option("--scenario", vf.scenario, "scenario name, comma list, or all")
      ->capture_default_str();
  verdict->add_option("--solver", vf.solver, "solver name, comma list, or all")
      ->capture_default_str();
  verdict->add_option("--rule", vf.rule, "adjust rule (procedural), comma list, or all")
      ->capture_default_str();
  verdict->add_option("--dt", vf.dt, "time steps searched, comma list (each divides 1/30 s)")
      ->capture_default_str();
  verdict->add_option("--budget", vf.budget, "error budgets, comma list (1mm, 1cm, 0.05m)")
      ->capture_default_str();
  verdict
      ->add_option("--starts", vf.starts,
                   "random starts a chosen configuration must survive without diverging")
      ->capture_default_str();
  verdict->add_option("--seed", vf.seed, "the starts' seed")->capture_default_str();
  verdict
      ->add_option("--frame-hz", vf.frame_hz,
                   "the frame rate of the per-frame view (a whole number of steps per frame)")
      ->capture_default_str();
  verdict->add_option("--floors-from", vf.floors_from,
                      "the truths' floors from this summary.csv of testbed run (the same model "
                      "and commit, both truths at three dts) instead of measuring them");
  verdict->add_option("--out", vf.out, "output folder")->capture_default_str();
  verdict->add_option("--jobs", vf.jobs, "worker threads (the timing runs alone)")
      ->check(kWholeNumber)
      ->check(CLI::Range(1, 256))
      ->capture_default_str();

  std::vector<std::string> merge_folders;
  std::string merge_out = "results/robustness";
  auto* merge = app.add_subcommand(
      "merge",
      "merge the shards of one testbed robustness sweep into what one unsharded run writes");
  merge->add_option("DIR", merge_folders, "the shards' output folders")->required();
  merge->add_option("--out", merge_out, "output folder")->capture_default_str();

  std::vector<std::string> gate_files;
  std::string gate_thresholds = "results/gate.json", gate_csv;
  auto* gate = app.add_subcommand(
      "gate",
      "check speed ratios from Google Benchmark JSON (>= 9 repetitions, medians) against "
      "thresholds; exit 1 when one fails");
  gate->add_option("BENCH.json", gate_files, "Google Benchmark JSON output(s)")->required();
  gate->add_option("--thresholds", gate_thresholds, "the gates (JSON)")->capture_default_str();
  gate->add_option("--csv", gate_csv, "also write every benchmark's median to this CSV");

  // CLI11 says "A subcommand is required" of a mistyped one: name it
  std::string known;
  bool is_command = false;
  for (const CLI::App* command : app.get_subcommands({})) {
    known += (known.empty() ? "" : ", ") + command->get_name();
    is_command = is_command || (argc > 1 && command->get_name() == argv[1]);
  }
  if (argc > 1 && argv[1][0] != '-' && !is_command) {
    std::cerr << "testbed: unknown command " << shown(argv[1]) << " (expected " << known << ")\n";
    return kBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    print_error("testbed: ", e.what());
    return kBadInput;
  }

  // SIGINT and SIGTERM: before anything is written, the process ends at once; after, the runs
  // stop at their next step and the output folder is left as it was (cancel.h)
  struct sigaction action {};
  action.sa_handler = [](int signal) {
    if (cancel_points().load() > 0) {
      request_cancel(signal);
      return;
    }
    // nothing written yet (a model or the shards being read): stop at once
    static const char kInt[] = "\ntestbed: stopped by SIGINT; nothing was written\n";
    static const char kTerm[] = "\ntestbed: stopped by SIGTERM; nothing was written\n";
    const bool term = signal == SIGTERM;
    [[maybe_unused]] const ssize_t written =
        ::write(STDERR_FILENO, term ? kTerm : kInt, term ? sizeof kTerm - 1 : sizeof kInt - 1);
    ::_exit(128 + signal);
  };
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  try {
    if (app.got_subcommand("list")) return command_list();
    if (app.got_subcommand("validate")) return command_validate(validate_path);
    if (app.got_subcommand("export-mjcf")) return command_export_mjcf(export_path, export_out);
    if (app.got_subcommand("frontier")) return command_frontier(f);
    if (app.got_subcommand("gate")) return command_gate(gate_files, gate_thresholds, gate_csv);
    if (app.got_subcommand("robustness")) return command_robustness(rf);
    if (app.got_subcommand("merge")) return command_merge(merge_folders, merge_out);
    if (app.got_subcommand("verdict")) return command_verdict(vf);
    return command_run(f);
  } catch (const Cancelled&) {
    const int signal = cancel_signal();
    std::fprintf(stderr, "\ntestbed: stopped by %s; the output folder is as it was\n",
                 signal == SIGTERM ? "SIGTERM" : "SIGINT");
    return 128 + signal;
  } catch (const OutputError& e) {
    print_error("testbed: ", e.what());
  } catch (const UsageError& e) {
    print_error("testbed: ", e.what());
  } catch (const ModelError& e) {
    print_error("testbed: ", e.what());
  } catch (const ScenarioError& e) {
    // the library names the option; the command line adds its flag
    print_error("testbed: ", with_flag(e));
  } catch (const ShardError& e) {
    print_error("testbed merge: ", e.what());
  } catch (const GateError& e) {
    print_error("testbed gate: ", e.what());
  } catch (const std::exception& e) {
    print_error("testbed: ", e.what());
    return 1;
  }
  return kBadInput;
}

// what a command printed reached standard output, or the command fails: a full disk or a closed
// file there is not success
int main(int argc, char** argv) {
  const int status = run_command(argc, argv);
  std::cout.flush();
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
    const int error = errno;
    print_error("testbed: ", std::string("cannot write to standard output (") +
                                 (error ? std::strerror(error) : "write failed") + ")");
    return status == 0 ? 1 : status;
  }
  return status;
}
