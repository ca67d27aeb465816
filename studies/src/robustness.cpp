#include "puppet/compare/robustness.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "puppet/compare/number.h"
#include "puppet/compare/output.h"
#include "puppet/compare/run.h"
#include "puppet/compare/summary_metrics.h"
#include "puppet/model/text.h"

namespace puppet::compare {
namespace {

// dt as a command line reads it: 1/N when it is one, else the decimal
std::string dt_flag(double dt) {
  const double n = std::round(1.0 / dt);
  if (n >= 1 && std::abs(1.0 / n - dt) <= 1e-8 * dt) return "1/" + std::to_string(int64_t(n));
  return format_dt(dt);
}

// a number as csv_number writes it: empty for NaN, "inf" and "-inf", else a finite decimal (no
// hex, no blanks, no "nan")
double number(const std::string& text, const std::string& where) {
  if (text.empty()) return std::nan("");
  if (text == "inf") return std::numeric_limits<double>::infinity();
  if (text == "-inf") return -std::numeric_limits<double>::infinity();
  const bool decimal = std::all_of(text.begin(), text.end(), [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E';
  });
  double value = 0.0;
  if (!decimal || text.size() > 32 || !parse_finite(text, &value) ||
      text.find('/') != std::string::npos) {
    throw std::runtime_error(where + ": not a number: " + shown(text));
  }
  return value;
}

using ConfigKey = std::tuple<std::string, std::string, std::string, std::string>;
ConfigKey key_of(const RobustnessRow& r) { return {r.scenario, r.solver, r.rule, format_dt(r.dt)}; }

}  // namespace

RunResult run_for_divergence(const SolverConfig& config, const Model& model,
                             const Scenario& scenario, double dt, double duration) {
  auto simulator = make_simulator(config.solver, config.options);
  RunOptions run;
  run.dt = dt;
  run.duration = duration;
  run.timing = false;
  run.sample_hz = 1e-3;  // the first and last poses only: the summary is all it keeps
  return run_scenario(*simulator, model, scenario, run);
}

int64_t robustness_job_count(const RobustnessSpec& spec) {
  return static_cast<int64_t>(spec.scenarios.size() * spec.configs.size() * spec.dts.size()) *
         spec.starts;
}

std::vector<RobustnessRow> run_robustness(const RobustnessSpec& spec) {
  const Model& model = *spec.model;
  const int64_t total = robustness_job_count(spec);
  std::vector<int64_t> jobs;
  for (int64_t j = spec.shard; j < total; j += spec.shards) jobs.push_back(j);
  std::vector<RobustnessRow> rows(jobs.size());
  const int64_t per_dt = spec.starts;
  const int64_t per_config = per_dt * static_cast<int64_t>(spec.dts.size());
  const int64_t per_scenario = per_config * static_cast<int64_t>(spec.configs.size());
  size_t done = 0;
  parallel_for(
      jobs.size(), spec.jobs,
      [&](size_t i) {
        const int64_t job = jobs[i];
        const std::string& name = spec.scenarios[job / per_scenario];
        const SolverConfig& config = spec.configs[(job % per_scenario) / per_config];
        const double dt = spec.dts[(job % per_config) / per_dt];
        const int64_t start_index = job % per_dt;
        ScenarioOptions options = spec.scenario;
        options.start = random_start(model, spec.seed, start_index);
        const Scenario scenario = make_scenario(name, model, options);
        const RunResult result = run_for_divergence(config, model, scenario, dt, spec.duration);

        RobustnessRow& r = rows[i];
        r.job = job;
        r.scenario = name;
        r.solver = config.solver;
        r.rule = rule_of(config);
        r.dt = dt;
        r.seed = spec.seed;
        r.start = start_index;
        const StartInputs& start = *options.start;
        // the tilt is drawn for every start but used only where the figure hangs from a pin
        const bool hanging = !scenario.pins.empty() && scenario.pins[0].path == TargetPath::kFixed;
        r.tilt_deg = hanging ? start.tilt_deg : std::nan("");
        const PinPath* grab = nullptr;
        for (const PinPath& p : scenario.pins) {
          if (p.path != TargetPath::kFixed) grab = &p;
        }
        r.hz = grab ? grab->hz : std::nan("");
        r.phase_deg = grab ? grab->phase * 180.0 / M_PI : std::nan("");
        if (grab) {
          r.grab_segment = model.segments[grab->pin.segment].name;
          r.grab_point = grab->pin.local_point;
        } else {
          r.grab_point.setConstant(std::nan(""));
        }
        r.joint_angle_rms_deg = start.joint_angle_rms_deg();
        r.joint_speed_rms = start.joint_speed_rms();
        r.diverged = result.diverged;
        r.reason = result.diverged_reason;
        r.diverged_at = result.diverged ? result.diverged_at : std::nan("");
        r.peak_speed = result.value(metric::kPeakSpeed, stats::kMax);
        r.joint_gap_max = result.value(metric::kJointGap, stats::kMax);
        r.pin_gap_max = result.value(metric::kPinGap, stats::kMax);
        r.steps = result.steps;
      },
      [&] {
        ++done;
        if (spec.on_progress) spec.on_progress(done, jobs.size());
      });
  return rows;
}

Interval wilson_interval(int64_t k, int64_t n, double z) {
  if (n <= 0) return {0.0, 1.0};
  const double p = static_cast<double>(k) / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

std::string robustness_csv(const std::vector<RobustnessRow>& rows) {
  std::ostringstream out;
  out << kRobustnessHeader << '\n';
  for (const RobustnessRow& r : rows) {
    out << r.job << ',' << r.scenario << ',' << r.solver << ',' << r.rule << ',' << format_dt(r.dt)
        << ',' << r.seed << ',' << r.start << ',' << csv_number(r.tilt_deg) << ','
        << csv_number(r.hz) << ',' << csv_number(r.phase_deg) << ',' << r.grab_segment << ','
        << csv_number(r.grab_point.x()) << ',' << csv_number(r.grab_point.y()) << ','
        << csv_number(r.grab_point.z()) << ',' << csv_number(r.joint_angle_rms_deg) << ','
        << csv_number(r.joint_speed_rms) << ',' << (r.diverged ? "diverged" : "ok") << ','
        << r.reason << ',' << csv_number(r.diverged_at) << ',' << csv_number(r.peak_speed) << ','
        << csv_number(r.joint_gap_max) << ',' << csv_number(r.pin_gap_max) << ',' << r.steps
        << '\n';
  }
  return out.str();
}

std::vector<RobustnessRow> parse_robustness_csv(const std::string& text,
                                                const std::string& source) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kRobustnessHeader) {
    throw std::runtime_error(source + ": not a robustness.csv (unexpected header)");
  }
  std::vector<RobustnessRow> rows;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    const std::string where = source + ":" + std::to_string(line_number);
    const std::vector<std::string> f = split_commas(line);
    if (f.size() != 23) {
      throw std::runtime_error(where + ": expected 23 fields, got " + std::to_string(f.size()));
    }
    RobustnessRow r;
    // plain decimal digits, as robustness_csv writes them
    const auto whole = [&](const std::string& t) -> uint64_t {
      uint64_t value = 0;
      if (!parse_whole(t, &value)) throw std::runtime_error(where + ": not a count: " + shown(t));
      return value;
    };
    r.job = static_cast<int64_t>(whole(f[0]));
    r.scenario = f[1];
    r.solver = f[2];
    r.rule = f[3];
    r.dt = number(f[4], where);
    r.seed = whole(f[5]);
    r.start = static_cast<int64_t>(whole(f[6]));
    r.tilt_deg = number(f[7], where);
    r.hz = number(f[8], where);
    r.phase_deg = number(f[9], where);
    r.grab_segment = f[10];
    r.grab_point = Vector3d(number(f[11], where), number(f[12], where), number(f[13], where));
    r.joint_angle_rms_deg = number(f[14], where);
    r.joint_speed_rms = number(f[15], where);
    if (f[16] != "ok" && f[16] != "diverged") {
      throw std::runtime_error(where + ": status " + shown(f[16]) + " is neither ok nor diverged");
    }
    r.diverged = f[16] == "diverged";
    r.reason = f[17];
    r.diverged_at = number(f[18], where);
    r.peak_speed = number(f[19], where);
    r.joint_gap_max = number(f[20], where);
    r.pin_gap_max = number(f[21], where);
    const uint64_t steps = whole(f[22]);
    if (steps > static_cast<uint64_t>(std::numeric_limits<int>::max())) {
      throw std::runtime_error(where + ": " + std::to_string(steps) + " steps");
    }
    r.steps = static_cast<int>(steps);
    rows.push_back(r);
  }
  return rows;
}

std::vector<RobustnessRate> robustness_rates(const std::vector<RobustnessRow>& rows) {
  // in the order of the rows' first appearance (the job order)
  std::vector<RobustnessRate> rates;
  std::map<ConfigKey, size_t> index;
  for (const RobustnessRow& r : rows) {
    auto [it, fresh] = index.try_emplace(key_of(r), rates.size());
    if (fresh) {
      RobustnessRate rate;
      rate.scenario = r.scenario;
      rate.solver = r.solver;
      rate.rule = r.rule;
      rate.dt = r.dt;
      rates.push_back(rate);
    }
    RobustnessRate& rate = rates[it->second];
    ++rate.runs;
    rate.diverged += r.diverged ? 1 : 0;
  }
  for (RobustnessRate& rate : rates) rate.ci95 = wilson_interval(rate.diverged, rate.runs);
  return rates;
}

std::string robustness_summary_csv(const std::vector<RobustnessRow>& rows) {
  std::ostringstream out;
  out << kRobustnessSummaryHeader << '\n';
  for (const RobustnessRate& r : robustness_rates(rows)) {
    out << r.scenario << ',' << r.solver << ',' << r.rule << ',' << format_dt(r.dt) << ',' << r.runs
        << ',' << r.diverged << ',' << csv_number(r.rate()) << ',' << csv_number(r.ci95.low) << ','
        << csv_number(r.ci95.high) << '\n';
  }
  return out.str();
}

std::string shell_word(const std::string& text) {
  const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) ||
           (c != '\0' && std::strchr("_./:=,+-", c) != nullptr);
  });
  if (plain) return text;
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string worst_csv(const std::vector<RobustnessRow>& rows, const RobustnessSpec& spec,
                      int worst) {
  std::vector<ConfigKey> order;
  std::map<ConfigKey, std::vector<const RobustnessRow*>> by_config;
  for (const RobustnessRow& r : rows) {
    auto [it, fresh] = by_config.try_emplace(key_of(r));
    if (fresh) order.push_back(key_of(r));
    it->second.push_back(&r);
  }
  // diverged first, earliest first; then the widest joint gap, the fastest segment; then the job
  const auto worse = [](const RobustnessRow* a, const RobustnessRow* b) {
    if (a->diverged != b->diverged) return a->diverged;
    if (a->diverged && a->diverged_at != b->diverged_at) return a->diverged_at < b->diverged_at;
    if (!a->diverged && a->joint_gap_max != b->joint_gap_max) {
      return a->joint_gap_max > b->joint_gap_max;
    }
    if (!a->diverged && a->peak_speed != b->peak_speed) return a->peak_speed > b->peak_speed;
    return a->job < b->job;
  };
  std::ostringstream out;
  out << kWorstHeader << '\n';
  for (const ConfigKey& key : order) {
    std::vector<const RobustnessRow*>& list = by_config[key];
    std::sort(list.begin(), list.end(), worse);
    for (int k = 0; k < worst && k < static_cast<int>(list.size()); ++k) {
      const RobustnessRow& r = *list[k];
      const std::string start = std::to_string(r.seed) + ":" + std::to_string(r.start);
      const std::string which = "--scenario " + r.scenario + " --solver " + r.solver +
                                (r.rule.empty() ? "" : " --rule " + r.rule) + " --dt " +
                                dt_flag(r.dt) + " --start " + start;
      const std::string model = shell_word(spec.model_name);
      const std::string testbed = "build/release/testbed run --model " + model + " " + which +
                                  spec.replay_flags + " --no-accuracy --out results/replay";
      const std::string viewer = "build/release/viewer/viewer --model " + model + " " + which;
      out << r.scenario << ',' << r.solver << ',' << r.rule << ',' << format_dt(r.dt) << ','
          << r.seed << ',' << r.start << ',' << (r.diverged ? "diverged" : "ok") << ','
          << csv_number(r.diverged_at) << ',' << csv_number(r.joint_gap_max) << ','
          << csv_number(r.peak_speed) << ',' << csv_field(testbed) << ',' << csv_field(viewer)
          << '\n';
    }
  }
  return out.str();
}

}  // namespace puppet::compare
