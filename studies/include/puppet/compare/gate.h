// The performance gate: ratios of Google Benchmark results measured in the same run, checked
// against results/gate.json. Absolute times are never compared: a noisy shared machine slows
// both sides of a ratio alike.
//
// gate.json:
//   {"gates": [{"name": "...", "numerator": "step/hang/bullet-multibody",
//               "denominator": "step/hang/literal", "min": 20, "floor": 10, "measured": 27.1},
//              {"name": "...", "numerator": "scaling/literal/1024", "numerator_per": 1024,
//               "denominator": "scaling/literal/16", "denominator_per": 16, "max": 1.5, ...}]}
// A benchmark's time is one item's (1 / the median of items_per_second over its repetitions),
// divided by its `_per` count (segments, say). A gate has `min` or `max`; `floor` is the
// weakest threshold the project accepts (a `min` may not be below it, a `max` not above it);
// `measured` records the ratio the threshold was set from. `known_failure` (a reason) marks a
// floor that the solver does not reach yet: its failure is shown but does not fail the gate,
// and its passing is reported so that the mark is removed. It also marks a floor that the full
// run reached by less than a quick run's noise (its `measured` meets the floor): the guard then
// holds the measured value, and a pass is reported as such, not as a mark to remove.
// A paired benchmark (two sides timed in turn within each iteration, so that a machine slowed
// for a while slows both alike) gives each side's median seconds per item as a counter
// "s_per_item/<side>", read as the benchmark "<name>/<side>".
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace puppet::compare {

struct GateSpec {
  std::string name;
  std::string numerator, denominator;
  double numerator_per = 1.0, denominator_per = 1.0;
  std::optional<double> min, max;
  std::optional<double> floor, measured;
  std::string measured_on;    // the machine whose full run gave `measured` (may be empty)
  std::string known_failure;  // empty: a failure fails the gate
};

// median seconds per item of each benchmark, from Google Benchmark JSON
struct BenchTime {
  std::string name;
  double seconds = 0.0;  // per item
  int repetitions = 0;
};

// kNarrowPass: a known failure whose own `measured` met its floor (reached narrowly) passing
enum class GateStatus { kPass, kFail, kKnownFailure, kUnexpectedPass, kNarrowPass, kMissing };

struct GateResult {
  GateSpec spec;
  double ratio = 0.0;  // NaN when a benchmark is missing
  GateStatus status = GateStatus::kMissing;
};

// minimum repetitions the gate accepts per benchmark
inline constexpr int kGateRepetitions = 9;

// Both throw GateError naming the file and the problem (bad JSON, a missing field, a threshold
// looser than its floor, too few repetitions).
class GateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
std::vector<GateSpec> read_gate_specs(const std::string& path);
std::vector<BenchTime> read_bench_times(const std::string& path);

std::vector<GateResult> evaluate_gates(const std::vector<GateSpec>& specs,
                                       const std::vector<BenchTime>& times);
// the table printed by `testbed gate`
std::string gate_table(const std::vector<GateResult>& results);
// true when nothing failed (known failures excepted) and nothing was missing
bool gate_passed(const std::vector<GateResult>& results);
// one row per benchmark: name, repetitions, median time per item (s), items per second
std::string bench_csv(const std::vector<BenchTime>& times);

}  // namespace puppet::compare
