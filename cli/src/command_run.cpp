// testbed run: scenarios × solvers × rules × dts, the main job; writes summary.csv and a trace and
// a poses file per run.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "flags.h"
#include "progress.h"
#include "puppet/compare/output.h"
#include "puppet/compare/output_folder.h"
#include "puppet/compare/start.h"
#include "puppet/compare/sweep.h"
#include "puppet/compare/truth_cache.h"
#include "puppet/model/text.h"
#include "tables.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

// What the flags imply, checked before anything runs: every run takes at least one step and at
// most kMaxSteps (the truths too, at their 1/15360 s), what the sweep holds in memory at once
// stays under kMaxMemory, and every trace's file name fits a file system's 255 bytes.
constexpr double kMaxMemory = 2.0 * (1u << 30);  // bytes

void check_run_size(const SweepSpec& spec, const Model& model) {
  const double n = model.segment_count();
  double longest = 0.0;
  for (const Scenario& scenario : spec.scenarios) {
    longest = std::max(longest, spec.run.duration >= 0.0 ? spec.run.duration : scenario.duration);
  }
  check_steps_per_run(longest, spec.dts, spec.run.duration >= 0.0);
  const double steps = longest / *std::min_element(spec.dts.begin(), spec.dts.end());
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

int run(const Flags& f) {
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
  spec.engine_budget = f.engine_budget;
  const ScenarioOptions scenario_options = parse_scenario_options(f);
  spec.configs = parse_solver_configs(f);
  const auto scenarios = expand("--scenario", f.scenario, scenario_names());
  const Model model = parse_model(f.model, f.reading);
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
    const std::vector<Truth> truths = truths_for(model, spec.engine_budget);
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
  print_run_table(results, table_dt(spec.dts));
  const size_t runs = spec.scenarios.size() * spec.configs.size() * spec.dts.size();
  std::printf("\nwrote %s: summary.csv and %zu traces\n", folder.path().c_str(), 2 * runs);
  return 0;
}

}  // namespace

Command add_run_command(CLI::App& app) {
  auto f = std::make_shared<Flags>();
  CLI::App* command = app.add_subcommand(
      "run",
      "run scenarios x solvers x rules x dts (default: all of them, the main job) and write "
      "summary.csv and traces");
  add_solver_flags(command, *f);
  add_sweep_flags(command, *f);
  command->add_option("--tilt", f->tilt, "initial tilt of hang and the scenarios built on it (deg)")
      ->capture_default_str();
  command->add_option("--hz", f->hz, "circle frequency of drag and yank (Hz)")
      ->capture_default_str();
  command
      ->add_option("--sample-hz", f->sample_hz,
                   "trace rows and poses kept per simulated second (0: every step)")
      ->capture_default_str();
  command->add_flag("--no-timing", f->no_timing, "skip the separate timing pass");
  command->add_option("--start", f->start,
                      "SEED:INDEX: the random start of testbed robustness (pose, velocities, "
                      "tilt, grab point, circle frequency and phase)");
  command->add_flag("--first-truth-only", f->first_truth_only,
                    "judge against the first truth alone, at its dt: no error bars, no second "
                    "truth (quicker, to compare configurations)");
  command->add_option("--truth-cache", f->truth_cache,
                      "FOLDER: keep the truths' trajectories there and read them back in later "
                      "runs of this build on the same model and scenario (made if missing)");
  command->add_flag("--no-accuracy", f->no_accuracy,
                    "skip the truths (mujoco RK4 at 1/7680 s, bullet-multibody at 1/3840 s, each "
                    "at half and twice that too) and the accuracy rows");
  return {command, [f] { return run(*f); }};
}

}  // namespace puppet::testbed
