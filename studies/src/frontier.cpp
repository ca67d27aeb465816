#include "puppet/compare/frontier.h"

#include <cmath>
#include <sstream>

#include "puppet/compare/summary_metrics.h"

namespace puppet::compare {
namespace {

struct Outcome {
  bool ok = false;
  std::string reason;
  double diverged_at = 0.0;
  double pin_gap = 0.0;  // m, max
};

// one run of the frontier's scenario (yank) with no air drag at circle frequency hz and step dt
Outcome run_yank(const FrontierSpec& spec, const SolverConfig& config, double hz, double dt) {
  ScenarioOptions options = spec.scenario;
  options.hz = hz;
  options.air_drag = 0.0;
  const Scenario yank = make_scenario(kFrontierScenario, *spec.model, options);
  RunOptions run;
  run.dt = dt;
  run.timing = false;
  run.sample_hz = 1.0;  // the poses are not used
  auto simulator = make_simulator(config.solver, config.options);
  const RunResult result = run_scenario(*simulator, *spec.model, yank, run);
  return {!result.diverged, result.diverged_reason, result.diverged_at,
          result.value(metric::kPinGap, stats::kMax)};
}

// bisection in log space for the largest x in [low, high] where ok(x), assuming one boundary
FrontierRow bisect(const std::string& quantity, const std::string& unit, double low, double high,
                   double resolution, const std::function<Outcome(double)>& ok) {
  FrontierRow row;
  row.quantity = quantity;
  row.unit = unit;
  auto fail = [&](double x, const Outcome& outcome) {
    row.first_diverged = x;
    row.reason = outcome.reason;
    row.diverged_at = outcome.diverged_at;
  };
  ++row.runs;
  const Outcome at_low = ok(low);
  if (!at_low.ok) {
    fail(low, at_low);
    return row;
  }
  row.pin_gap_at_largest_ok = at_low.pin_gap;
  ++row.runs;
  const Outcome at_high = ok(high);
  if (at_high.ok) {
    row.largest_ok = high;
    row.pin_gap_at_largest_ok = at_high.pin_gap;
    return row;
  }
  fail(high, at_high);
  while (high / low > resolution) {
    const double middle = std::sqrt(low * high);
    ++row.runs;
    const Outcome outcome = ok(middle);
    if (outcome.ok) {
      low = middle;
      row.pin_gap_at_largest_ok = outcome.pin_gap;
    } else {
      high = middle;
      fail(high, outcome);
    }
  }
  row.largest_ok = low;
  return row;
}

}  // namespace

std::vector<FrontierRow> find_frontier(const FrontierSpec& spec) {
  const size_t count = 2 * spec.configs.size();
  std::vector<FrontierRow> rows(count);
  size_t done = 0;
  parallel_for(
      count, spec.jobs,
      [&](size_t i) {
        const SolverConfig& config = spec.configs[i / 2];
        FrontierRow row;
        if (i % 2 == 0) {
          row = bisect(kQuantityHz, "Hz", spec.hz_low, spec.hz_high, spec.resolution,
                       [&](double hz) { return run_yank(spec, config, hz, spec.hz_dt); });
          row.held = spec.hz_dt;
        } else {
          row = bisect(kQuantityDt, "s", spec.dt_low, spec.dt_high, spec.resolution,
                       [&](double dt) { return run_yank(spec, config, spec.scenario.hz, dt); });
          row.held = spec.scenario.hz;
        }
        row.solver = config.solver;
        row.rule = rule_of(config);
        rows[i] = std::move(row);
      },
      [&] {
        if (spec.on_progress) spec.on_progress(++done, count);
      });
  return rows;
}

std::string frontier_csv(const std::vector<FrontierRow>& rows, const OutputContext& context) {
  std::ostringstream out;
  out << kFrontierHeader << '\n';
  auto optional = [](const std::optional<double>& v) { return v ? csv_number(*v) : ""; };
  for (const FrontierRow& r : rows) {
    out << csv_field(r.solver) << ',' << csv_field(r.rule) << ',' << csv_field(r.quantity) << ','
        << csv_field(r.unit) << ',' << csv_number(r.held) << ',' << optional(r.largest_ok) << ','
        << optional(r.first_diverged) << ','
        << (r.largest_ok ? csv_number(r.pin_gap_at_largest_ok) : "") << ',' << csv_field(r.reason)
        << ',' << (r.first_diverged ? csv_number(r.diverged_at) : "") << ',' << r.runs << ','
        << csv_field(context.model) << ',' << csv_field(context.git_sha) << ','
        << csv_field(context.machine) << '\n';
  }
  return out.str();
}

}  // namespace puppet::compare
