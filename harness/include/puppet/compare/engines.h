// The engine catalogue: one row per engine the testbed can run (docs/design.md, "The
// references"). Every client that lists, makes or checks engines reads it: the testbed's
// commands and flags, the sweeps and the truths, the viewer, the benchmarks. An engine is its
// file under harness/src/engines/ (its Simulator, its flags, its row), its row in
// engines/catalogue.cpp, its settings in SolverOptions, its CMake lines and its test.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "puppet/compare/simulator.h"
#include "puppet/model/model.h"

namespace CLI {  // CLI11's: the rows add their flags to a command
class App;
class Validator;
}  // namespace CLI

namespace puppet::compare {

// one configuration a verdict searches besides dt (docs/verdict.md): the flags that set it, as
// candidates.csv names it ("--substeps 8"; empty: the defaults), a few words for tables ("8
// substeps", "RK4"), and the options it makes
struct Setting {
  std::string flags;
  std::string label;
  SolverOptions options;
};

struct Engine {
  std::string_view name;     // as --solver, the CSVs and the plots spell it
  std::string_view summary;  // one line: what it is (testbed list)
  // how it holds joints, limits, pins and contacts, in a sentence the report quotes where two
  // engines' answers differ
  std::string_view constraints;
  bool built = true;  // false: this build lacks the library (MuJoCo without libmujoco-dev)
  // why it is not built and how to get it, in one line (null: it always is)
  std::string (*missing)() = nullptr;
  bool has_rules = false;  // true: a sweep runs it once per --rule (procedural)
  // false: its cost is measured in WebAssembly (jolt), reported in a column of its own and never
  // ranked against native code's
  bool native = true;
  // true: its state is single precision (jolt): what it reads back is rounded to float, and the
  // tests that compare two of its runs allow for it
  bool single_precision = false;
  // true: it builds joint armature exactly (MuJoCo, in generalized coordinates); false: it runs
  // armature_in_inertia's model (joint_springs.h) and says so (engine_model_note)
  bool exact_armature = false;
  // why it cannot run the model (empty when it can), decided before anything runs
  std::string (*model_problem)(const Model& model) = nullptr;
  // an estimate of the CPU seconds it takes to step one simulated second of the model at
  // kBudgetDt with `options` (its solver's order in joints, limit rows and sweeps, calibrated on
  // this project's reference machine; docs/reliability.md): engine_model_problem refuses a model
  // whose estimate exceeds its budget
  double (*second_cost)(const Model& model, const SolverOptions& options) = nullptr;
  // a simulator with these options; throws ScenarioError for invalid settings
  std::unique_ptr<Simulator> (*make)(const SolverOptions& options) = nullptr;
  // its own flags, bound to its part of `options` (null: none, or a sibling row adds them)
  void (*add_flags)(CLI::App& command, SolverOptions& options) = nullptr;
  // the flags add_flags would read back as `options`, for those that differ from SolverOptions'
  // defaults, each as " --flag value" (a robustness run's replay command)
  void (*replay_flags)(const SolverOptions& options, std::string& out) = nullptr;
  // what a verdict searches besides dt, from `base` (its rule's row for procedural), appended
  // to `out` (null: dt alone)
  void (*search)(const SolverOptions& base, std::vector<Setting>& out) = nullptr;
};

// the check of a count flag: plain decimal digits (CLI11's integers would also take 0x10, " 3"
// and 010, as 8)
const CLI::Validator& whole_number_check();

// the check of a number flag CLI11 reads as a double: a finite number (CLI11's Range lets NaN
// through, since every comparison with it is false), to be followed by the flag's Range
const CLI::Validator& finite_number_check();

// every engine, built or not, in the order the tables list them
std::span<const Engine> engines();
// the row named `name` that this build has, or null
const Engine* find_engine(std::string_view name);
// the names of the engines this build has
const std::vector<std::string>& solver_names();
// the check of a --solver list against the catalogue: an engine this build lacks is named with
// why (its row's missing), in one line; empty when every name is built or unknown
std::string unbuilt_engine_problem(const std::vector<std::string>& names);
// --substeps' help, from the rule catalogue: "procedural substeps per step (default: the rule's:
// xpbd 8, tree 8, the others 1)" (the testbed's flag and the viewer's)
std::string procedural_substeps_help();
// the engine whose row runs the procedural rules, one configuration per rule
inline constexpr std::string_view kProceduralEngine = "procedural";
// whether the engine named runs once per procedural rule (its row's has_rules)
bool has_rules(std::string_view solver);
// what a verdict searches for one solver besides dt: its row's search from `base`, or `base`
// alone
std::vector<Setting> settings_searched(std::string_view solver, const SolverOptions& base);
// The budget: how many CPU seconds stepping one simulated second of a model at kBudgetDt may
// take an engine (--engine-budget, which each command hands down with its options; nothing of
// it is kept between calls). A model past it is refused before anything runs, in one line
// naming the engine and its estimate.
inline constexpr double kBudgetDt = 1.0 / 240.0;
inline constexpr double kDefaultEngineBudget = 60.0;

// why the engine cannot run the model (empty when it can): its row's model_problem, or an
// estimated cost per simulated second above `budget` (finite and positive); an unknown name says
// so
// what the engine approximates in the model, in one line (empty when nothing): a command prints
// it as a note before it runs the engine
std::string engine_model_note(std::string_view name, const Model& model);

std::string engine_model_problem(std::string_view name, const Model& model,
                                 const SolverOptions& options = {},
                                 double budget = kDefaultEngineBudget);

// what an engine's cost grows with, counted from the model, at its worst (every limit acting,
// every shape on the ground): degrees of freedom (a free root's six among them), the deepest
// chain of joints, the limit rows (a box three, a swing–twist limit two, a hinge's range one),
// the rows that hold the joints in maximal coordinates (a ball three, a hinge five, a fixed joint
// six), the box limits among the limits, and the points where the shapes touch a plane they lie
// on (a sphere or an ellipsoid one, a capsule two, a box or a cylinder four): three rows each,
// the normal and two of friction
struct ModelSize {
  int segments = 0;
  int dofs = 0;
  int depth = 0;
  int limit_rows = 0;
  int joint_rows = 0;
  int box_limits = 0;
  int contact_points = 0;
};
ModelSize model_size(const Model& model);

}  // namespace puppet::compare
