#include "tables.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>

#include "puppet/compare/output.h"
#include "puppet/compare/summary_metrics.h"
#include "puppet/compare/sweep.h"

namespace puppet::testbed {

using namespace puppet::compare;

double table_dt(const std::vector<double>& dts) {
  return *std::min_element(dts.begin(), dts.end(), [](double a, double b) {
    return std::abs(std::log(a * 240)) < std::abs(std::log(b * 240));
  });
}

void print_run_table(const std::vector<RunResult>& results, double dt) {
  std::printf("\ndt = %s s (every dt is in summary.csv)\n", format_dt(dt).c_str());
  std::printf("%-8s %-16s %-9s %-8s %11s %11s %11s %9s %9s %11s\n", "scenario", "solver", "rule",
              "status", "joint gap m", "pin gap m", "E drift", "limit deg", "us/step",
              "reseeded m");
  for (const RunResult& r : results) {
    if (r.dt != dt) continue;
    auto show = [&](const MetricInfo& metric, const StatInfo& stat, const char* format,
                    std::string_view reference = "") {
      double v = std::numeric_limits<double>::quiet_NaN();
      for (const SummaryRow& row : r.summary) {
        if (row.metric == metric.name && row.stat == stat.name && row.reference == reference) {
          v = row.value;
        }
      }
      if (std::isnan(v)) return std::string("-");
      char cell[32];
      std::snprintf(cell, sizeof cell, format, v);
      return std::string(cell);
    };
    const std::string status =
        r.diverged ? "div@" + show(metric::kDivergedAt, stats::kValue, "%.2f") : std::string("ok");
    std::printf("%-8s %-16s %-9s %-8s %11s %11s %11s %9s %9s %11s\n", r.scenario.c_str(),
                r.solver.c_str(), r.rule.empty() ? "-" : r.rule.c_str(), status.c_str(),
                show(metric::kJointGap, stats::kMax, "%.2e").c_str(),
                show(metric::kPinGap, stats::kMax, "%.2e").c_str(),
                show(metric::kEnergyDrift, stats::kFinal, "%+.2e").c_str(),
                show(metric::kLimitViolation, stats::kMax, "%.1e").c_str(),
                show(metric::kStepTime, stats::kMedian, "%.1f").c_str(),
                show(metric::kPoseError, stats::kReseededMean, "%.2e", kTruthReference).c_str());
  }
}

void print_frontier_table(const FrontierSpec& spec, const std::vector<FrontierRow>& rows) {
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
}

void print_verdict_table(const VerdictSpec& spec, const VerdictResult& result) {
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

}  // namespace puppet::testbed
