// testbed: runs the scenarios in the solvers and writes what it measured.
//
// Bad input (an unknown name, a malformed flag, a bad model file, an unwritable folder) exits
// with status 2 and one line naming the flag or file and the problem, before anything is written.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "puppet/compare/output.h"
#include "puppet/compare/run.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/model.h"
#include "puppet/procedural/solver.h"

namespace {

using namespace puppet;
using namespace puppet::compare;

constexpr int kBadInput = 2;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string default_model_path() {
  return std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";
}

// "pinocchio" names the built-in figure; anything else is a file or chain:N
Model load_named_model(const std::string& name) {
  return load_model(name == "pinocchio" ? default_model_path() : name);
}

bool parse_finite(const std::string& text, double* out) {
  std::istringstream in(text);
  double value = 0.0;
  in >> value;
  if (!in || !in.eof() || !std::isfinite(value)) {
    // also accept simple fractions such as 1/240
    const auto slash = text.find('/');
    if (slash == std::string::npos) return false;
    double num = 0.0, den = 0.0;
    if (!parse_finite(text.substr(0, slash), &num) || !parse_finite(text.substr(slash + 1), &den) ||
        den == 0.0) {
      return false;
    }
    value = num / den;
  }
  *out = value;
  return std::isfinite(value);
}

Vector3d parse_vector(const std::string& flag, const std::string& text) {
  std::vector<double> parts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    double value = 0.0;
    if (!parse_finite(item, &value)) break;
    parts.push_back(value);
  }
  if (parts.size() != 3 || std::count(text.begin(), text.end(), ',') != 2) {
    throw UsageError(flag + ": expected three finite numbers X,Y,Z, got \"" + text + "\"");
  }
  return {parts[0], parts[1], parts[2]};
}

PointChoice parse_point(const std::string& flag, const std::string& text) {
  PointChoice choice;
  const auto colon = text.find(':');
  choice.segment = text.substr(0, colon);
  if (choice.segment.empty())
    throw UsageError(flag + ": expected SEGMENT[:x,y,z], got \"" + text + "\"");
  if (colon != std::string::npos) choice.local_point = parse_vector(flag, text.substr(colon + 1));
  return choice;
}

double parse_positive(const std::string& flag, const std::string& text) {
  double value = 0.0;
  if (!parse_finite(text, &value))
    throw UsageError(flag + ": not a finite number: \"" + text + "\"");
  if (!(value > 0.0)) throw UsageError(flag + ": must be positive, got " + text);
  return value;
}

double parse_non_negative(const std::string& flag, const std::string& text) {
  double value = 0.0;
  if (!parse_finite(text, &value))
    throw UsageError(flag + ": not a finite number: \"" + text + "\"");
  if (value < 0.0) throw UsageError(flag + ": must not be negative, got " + text);
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
      throw UsageError(flag + ": unknown value \"" + item + "\" (expected all or one of " + known +
                       ")");
    }
    out.push_back(item);
  }
  if (out.empty()) throw UsageError(flag + ": empty");
  return out;
}

std::vector<std::string> all_rules() {
  std::vector<std::string> out;
  for (auto rule : procedural::kAllRules) out.emplace_back(procedural::rule_name(rule));
  return out;
}

int command_list() {
  std::cout << "scenarios:";
  for (const auto& s : scenario_names()) std::cout << ' ' << s;
  std::cout << "\nsolvers:  ";
  for (const auto& s : solver_names()) std::cout << ' ' << s;
  std::cout << "\nrules:    ";
  for (const auto& r : all_rules()) std::cout << ' ' << r;
  std::cout << " (procedural only; default relaxed)\nmodels:    pinocchio (" << default_model_path()
            << "), chain:N, or any model file\n";
  return 0;
}

int command_validate(const std::string& path) {
  const Model model = load_named_model(path);
  std::printf("model \"%s\": %d segments, %d joints, total mass %.3f kg, rest height %.3f m\n",
              model.name.c_str(), model.segment_count(), model.joint_count(), model.total_mass,
              model.rest_height);
  std::printf("  %-14s %-14s %8s  %s\n", "segment", "parent", "mass kg", "shape");
  for (const Segment& s : model.segments) {
    const char* shape = s.shape.type == ShapeType::kCapsule ? "capsule"
                        : s.shape.type == ShapeType::kBox   ? "box"
                                                            : "sphere";
    std::printf("  %-14s %-14s %8.3f  %s\n", s.name.c_str(),
                s.parent >= 0 ? model.segments[s.parent].name.c_str() : "-", s.mass, shape);
  }
  std::printf("  %-14s %-6s %-14s %-14s %s\n", "joint", "type", "parent", "child", "limits (deg)");
  for (const Joint& j : model.joints) {
    const double d = 180.0 / M_PI;
    char limits[96];
    if (j.type == JointType::kBall) {
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
  return 0;
}

struct RunFlags {
  std::string model = "pinocchio", scenario = "all", solver = "all", rule = "all";
  std::string dt = "1/240", duration, out = "results", pin, grab, gravity, air_drag, ground;
  std::string tilt = "30", hz = "0.5", sample_hz = "0", iterations = "4", substeps = "1";
  std::string bullet_iterations = "10";
  bool no_velocities = false, no_tremble = false, no_timing = false, bullet_euler_limits = false;
};

void print_table(const std::vector<RunResult>& results) {
  std::printf("\n%-8s %-11s %-9s %-8s %11s %11s %11s %9s %9s\n", "scenario", "solver", "rule",
              "status", "joint gap m", "pin gap m", "E drift", "limit deg", "us/step");
  for (const RunResult& r : results) {
    auto show = [&](const char* metric, const char* stat, const char* format) {
      const double v = r.value(metric, stat);
      if (std::isnan(v)) return std::string("-");
      char cell[32];
      std::snprintf(cell, sizeof cell, format, v);
      return std::string(cell);
    };
    const std::string status =
        r.diverged ? "div@" + show("diverged_at_s", "value", "%.2f") : std::string("ok");
    std::printf("%-8s %-11s %-9s %-8s %11s %11s %11s %9s %9s\n", r.scenario.c_str(),
                r.solver.c_str(), r.rule.empty() ? "-" : r.rule.c_str(), status.c_str(),
                show("joint_gap_m", "max", "%.2e").c_str(),
                show("pin_gap_m", "max", "%.2e").c_str(),
                show("energy_drift", "final", "%+.2e").c_str(),
                show("limit_violation_deg", "max", "%.1e").c_str(),
                show("step_us", "median", "%.1f").c_str());
  }
}

int command_run(const RunFlags& f) {
  // every flag checked before anything runs or is written
  RunOptions options;
  options.dt = parse_positive("--dt", f.dt);
  if (!f.duration.empty()) options.duration = parse_non_negative("--duration", f.duration);
  options.sample_hz = parse_non_negative("--sample-hz", f.sample_hz);
  options.timing = !f.no_timing;
  ScenarioOptions scenario_options;
  double tilt = 0.0;
  if (!parse_finite(f.tilt, &tilt))
    throw UsageError("--tilt: not a finite number: \"" + f.tilt + "\"");
  scenario_options.tilt_deg = tilt;
  scenario_options.hz = parse_positive("--hz", f.hz);
  if (!f.pin.empty()) scenario_options.pin = parse_point("--pin", f.pin);
  if (!f.grab.empty()) scenario_options.grab = parse_point("--grab", f.grab);
  if (!f.gravity.empty()) scenario_options.gravity = parse_vector("--gravity", f.gravity);
  if (!f.air_drag.empty()) scenario_options.air_drag = parse_non_negative("--air-drag", f.air_drag);
  if (!f.ground.empty()) {
    if (f.ground != "on" && f.ground != "off") {
      throw UsageError("--ground: expected on or off, got \"" + f.ground + "\"");
    }
    scenario_options.ground = f.ground == "on";
  }
  SolverOptions solver_options;
  double iterations = 0.0, substeps = 0.0;
  if (!parse_finite(f.iterations, &iterations) || iterations < 0 ||
      iterations != std::floor(iterations)) {
    throw UsageError("--iterations: expected a non-negative integer, got \"" + f.iterations + "\"");
  }
  double bullet_iterations = 0.0;
  if (!parse_finite(f.bullet_iterations, &bullet_iterations) || bullet_iterations < 1 ||
      bullet_iterations != std::floor(bullet_iterations)) {
    throw UsageError("--bullet-iterations: expected a positive integer, got \"" +
                     f.bullet_iterations + "\"");
  }
  if (!parse_finite(f.substeps, &substeps) || substeps < 1 || substeps != std::floor(substeps)) {
    throw UsageError("--substeps: expected a positive integer, got \"" + f.substeps + "\"");
  }
  solver_options.iterations = static_cast<int>(iterations);
  solver_options.substeps = static_cast<int>(substeps);
  solver_options.bullet_iterations = static_cast<int>(bullet_iterations);
  solver_options.bullet_euler_limits = f.bullet_euler_limits;
  solver_options.derive_velocities = !f.no_velocities;
  solver_options.tremble = !f.no_tremble;

  const auto scenarios = expand("--scenario", f.scenario, scenario_names());
  const auto solvers = expand("--solver", f.solver, solver_names());
  const auto rules = expand("--rule", f.rule, all_rules());

  Model model;
  try {
    model = load_named_model(f.model);
  } catch (const ModelError& error) {
    throw UsageError(std::string("--model: ") + error.what());
  }
  std::vector<Scenario> built;
  for (const auto& name : scenarios) built.push_back(make_scenario(name, model, scenario_options));
  std::vector<std::unique_ptr<Simulator>> simulators;
  for (const auto& solver : solvers) {
    if (solver == "procedural") {
      for (const auto& rule : rules) {
        SolverOptions o = solver_options;
        o.rule = rule;
        simulators.push_back(make_simulator(solver, o));
      }
    } else {
      simulators.push_back(make_simulator(solver, solver_options));
    }
  }

  // the output folder must be writable before any run starts
  namespace fs = std::filesystem;
  const fs::path out(f.out), traces = out / "traces";
  std::error_code error;
  fs::create_directories(traces, error);
  const fs::path probe = traces / ".write-test";
  if (error || !std::ofstream(probe)) {
    throw UsageError("--out: cannot write to \"" + f.out + "\"");
  }
  fs::remove(probe, error);

  std::vector<RunResult> results;
  const size_t total = built.size() * simulators.size();
  for (const Scenario& scenario : built) {
    for (auto& simulator : simulators) {
      std::fprintf(stderr, "[%zu/%zu] %s %s %s dt=%s\n", results.size() + 1, total,
                   scenario.name.c_str(), simulator->name().c_str(), simulator->rule().c_str(),
                   format_dt(options.dt).c_str());
      results.push_back(run_scenario(*simulator, model, scenario, options));
      RunResult& r = results.back();
      const std::string stem = (traces / trace_stem(model.name, r)).string();
      write_file_atomically(stem + ".csv", trace_csv(r));
      write_file_atomically(stem + "__poses.csv", poses_csv(model, r));
      r.trace = {};
      r.poses = {};
    }
  }
  const OutputContext context{model.name, current_git_sha(), machine_description()};
  write_file_atomically((out / "summary.csv").string(), summary_csv(results, context));
  print_table(results);
  std::printf("\nwrote %s and %zu traces under %s\n", (out / "summary.csv").c_str(),
              2 * results.size(), traces.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"testbed: the seed's procedural solver for articulated bodies, measured"};
  app.require_subcommand(1);
  app.fallthrough(false);

  app.add_subcommand("list", "list scenarios, solvers, rules and models");
  std::string validate_path;
  auto* validate = app.add_subcommand("validate", "load a model and print it, or its error");
  validate->add_option("MODEL", validate_path, "model file, pinocchio, or chain:N")->required();

  RunFlags f;
  auto* run = app.add_subcommand("run", "run scenarios and write summary.csv and traces");
  run->add_option("--model", f.model, "model file, pinocchio, or chain:N")->capture_default_str();
  run->add_option("--scenario", f.scenario, "scenario name, comma list, or all")
      ->capture_default_str();
  run->add_option("--solver", f.solver, "solver name, comma list, or all")->capture_default_str();
  run->add_option("--rule", f.rule, "adjust rule (procedural), comma list, or all")
      ->capture_default_str();
  run->add_option("--dt", f.dt, "time step in seconds (a fraction such as 1/240 is accepted)")
      ->capture_default_str();
  run->add_option("--duration", f.duration, "seconds to simulate (default: the scenario's)");
  run->add_option("--out", f.out, "output folder")->capture_default_str();
  run->add_option("--pin", f.pin, "hanging point SEGMENT[:x,y,z] (segment frame)");
  run->add_option("--grab", f.grab, "dragged point SEGMENT[:x,y,z] (segment frame)");
  run->add_option("--gravity", f.gravity, "gravity X,Y,Z (m/s^2)");
  run->add_option("--air-drag", f.air_drag, "air drag k_air (1/s)");
  run->add_option("--ground", f.ground, "ground plane on|off");
  run->add_option("--tilt", f.tilt, "initial tilt of hang and the scenarios built on it (deg)")
      ->capture_default_str();
  run->add_option("--hz", f.hz, "circle frequency of drag and yank (Hz)")->capture_default_str();
  run->add_option("--sample-hz", f.sample_hz, "poses kept per simulated second (0: every step)")
      ->capture_default_str();
  run->add_option("--iterations", f.iterations, "relaxed: two-sided sweeps")->capture_default_str();
  run->add_option("--bullet-iterations", f.bullet_iterations,
                  "Bullet: sequential-impulse sweeps per step")
      ->capture_default_str();
  run->add_flag("--bullet-euler-limits", f.bullet_euler_limits,
                "bullet-multibody: Bullet's own ball limits (a box of Euler angles)");
  run->add_option("--substeps", f.substeps, "procedural substeps per step")->capture_default_str();
  run->add_flag("--no-velocities", f.no_velocities,
                "procedural: do not derive velocities from poses");
  run->add_flag("--no-tremble", f.no_tremble,
                "procedural: no tremble even in the tremble scenario");
  run->add_flag("--no-timing", f.no_timing, "skip the separate timing pass");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "testbed: " << e.what() << '\n';
    return kBadInput;
  }

  try {
    if (app.got_subcommand("list")) return command_list();
    if (app.got_subcommand("validate")) return command_validate(validate_path);
    return command_run(f);
  } catch (const UsageError& e) {
    std::cerr << "testbed: " << e.what() << '\n';
  } catch (const ModelError& e) {
    std::cerr << "testbed: " << e.what() << '\n';
  } catch (const ScenarioError& e) {
    std::cerr << "testbed: " << e.what() << '\n';
  } catch (const std::exception& e) {
    std::cerr << "testbed: " << e.what() << '\n';
    return 1;
  }
  return kBadInput;
}
