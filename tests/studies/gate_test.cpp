#include "puppet/compare/gate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace puppet::compare {
namespace {

// a file in a fresh temporary folder
std::string write_temp(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "puppet_gate_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

// Google Benchmark JSON with one median aggregate per (name, items per second)
std::string bench_json(const std::vector<std::pair<std::string, double>>& medians,
                       int repetitions = 9) {
  std::string json = R"({"context": {}, "benchmarks": [)";
  for (size_t i = 0; i < medians.size(); ++i) {
    const auto& [name, rate] = medians[i];
    if (i) json += ",";
    // the mean differs from the median: the gate must read the median
    json += R"({"name": ")" + name + R"(/manual_time_mean", "run_name": ")" + name +
            R"(/manual_time", "run_type": "aggregate", "aggregate_name": "mean", "repetitions": )" +
            std::to_string(repetitions) + R"(, "items_per_second": )" + std::to_string(rate / 2) +
            "},";
    json +=
        R"({"name": ")" + name + R"(/manual_time_median", "run_name": ")" + name +
        R"(/manual_time", "run_type": "aggregate", "aggregate_name": "median", "repetitions": )" +
        std::to_string(repetitions) + R"(, "items_per_second": )" + std::to_string(rate) + "}";
  }
  return json + "]}";
}

TEST(Gate, RatiosOfMediansPerItemAgainstThresholds) {
  const auto times = read_bench_times(write_temp("b.json", bench_json({{"step/hang/slow", 1000.0},
                                                                       {"step/hang/fast", 25000.0},
                                                                       {"chain/1024", 100.0},
                                                                       {"chain/16", 5000.0}})));
  ASSERT_EQ(times.size(), 4u);
  EXPECT_EQ(times[0].name, "step/hang/slow");  // "/manual_time" is dropped
  EXPECT_DOUBLE_EQ(times[0].seconds, 1e-3);

  const auto specs = read_gate_specs(write_temp("g.json", R"({"gates": [
      {"name": "speedup", "numerator": "step/hang/slow", "denominator": "step/hang/fast",
       "min": 20, "floor": 10, "measured": 31.5, "measured_on": "machine-a"},
      {"name": "too slow", "numerator": "step/hang/slow", "denominator": "step/hang/fast",
       "min": 30, "floor": 10},
      {"name": "per segment", "numerator": "chain/1024", "numerator_per": 1024,
       "denominator": "chain/16", "denominator_per": 16, "max": 1.5},
      {"name": "known", "numerator": "step/hang/slow", "denominator": "step/hang/fast",
       "min": 40, "known_failure": "not yet"},
      {"name": "gone", "numerator": "step/hang/none", "denominator": "step/hang/fast", "min": 1},
      {"name": "skipped", "numerator": "step/hang/slow", "denominator": "step/drop/diverged",
       "min": 30, "floor": 30, "known_failure": "diverges in the warm-up"}
    ]})"));
  const auto results = evaluate_gates(specs, times);
  ASSERT_EQ(results.size(), 6u);
  EXPECT_DOUBLE_EQ(results[0].ratio, 25.0);
  EXPECT_EQ(results[0].status, GateStatus::kPass);
  EXPECT_EQ(results[1].status, GateStatus::kFail);
  // (1/100 s / 1024) / (1/5000 s / 16) = 50·16/1024
  EXPECT_DOUBLE_EQ(results[2].ratio, 50.0 * 16.0 / 1024.0);
  EXPECT_EQ(results[2].status, GateStatus::kPass);
  EXPECT_EQ(results[3].status, GateStatus::kKnownFailure);
  EXPECT_TRUE(std::isnan(results[4].ratio));
  EXPECT_EQ(results[4].status, GateStatus::kMissing);
  // a benchmark skipped because its run diverged: known, when the gate says so
  EXPECT_TRUE(std::isnan(results[5].ratio));
  EXPECT_EQ(results[5].status, GateStatus::kKnownFailure);
  EXPECT_TRUE(gate_passed({results[5]}));
  EXPECT_FALSE(gate_passed(results));
  EXPECT_TRUE(gate_passed({results[0], results[2], results[3]}));
  EXPECT_NE(gate_table(results).find("FAIL"), std::string::npos);
  // the missing benchmark is named; the skipped one is explained by its reason instead
  EXPECT_NE(gate_table(results).find("missing benchmark: step/hang/none"), std::string::npos);
  EXPECT_EQ(gate_table(results).find("missing benchmark: step/hang/slow"), std::string::npos);
  EXPECT_NE(gate_table(results).find("known: diverges in the warm-up"), std::string::npos);
  // the machine a threshold was measured on is named under the table
  EXPECT_EQ(specs[0].measured_on, "machine-a");
  EXPECT_NE(gate_table(results).find("31.50^1"), std::string::npos);
  EXPECT_NE(gate_table(results).find("^1 measured on machine-a"), std::string::npos);
}

// A paired benchmark's sides (counters "s_per_item/<side>") are read as benchmarks of their own,
// beside the pair's own time; a side that is not a positive time is refused
TEST(Gate, APairedBenchmarksSidesAreReadAsBenchmarks) {
  const std::string entry =
      R"({"run_type": "aggregate", "aggregate_name": "median", "run_name": "py/step/manual_time", )"
      R"("repetitions": 9, "items_per_second": 1000, )";
  const auto times = read_bench_times(
      write_temp("paired.json", R"({"benchmarks": [)" + entry +
                                    R"("s_per_item/cpp": 0.0009, "s_per_item/python": 0.0011}]})"));
  ASSERT_EQ(times.size(), 3u);
  EXPECT_EQ(times[0].name, "py/step");
  EXPECT_EQ(times[1].name, "py/step/cpp");
  EXPECT_DOUBLE_EQ(times[1].seconds, 0.0009);
  EXPECT_EQ(times[2].name, "py/step/python");
  EXPECT_EQ(times[2].repetitions, 9);
  const auto specs = read_gate_specs(write_temp("paired_gate.json", R"({"gates": [
      {"name": "python", "numerator": "py/step/python", "denominator": "py/step/cpp", "max": 1.1}
    ]})"));
  const auto results = evaluate_gates(specs, times);
  EXPECT_NEAR(results[0].ratio, 11.0 / 9.0, 1e-12);
  EXPECT_EQ(results[0].status, GateStatus::kFail);
  for (const std::string bad :
       {R"("s_per_item/cpp": 0)", R"("s_per_item/cpp": "fast")", R"("s_per_item/": 0.001)"}) {
    std::string message;
    try {
      read_bench_times(write_temp("paired_bad.json", R"({"benchmarks": [)" + entry + bad + "}]}"));
    } catch (const GateError& e) {
      message = e.what();
    }
    EXPECT_NE(message.find("must be a positive number of seconds"), std::string::npos) << bad;
    EXPECT_NE(message.find("paired_bad.json: py/step"), std::string::npos) << message;
  }
}

// A floor not reached yet is a known failure, and its threshold guards what was measured: the
// gate still fails when the ratio falls past it, and says so when the floor is reached.
TEST(Gate, AKnownFailureStillFailsWhenItRegressesPastItsGuard) {
  const auto specs = read_gate_specs(write_temp("guard.json", R"({"gates": [
      {"name": "guard", "numerator": "slow", "denominator": "fast", "min": 4.5, "floor": 12,
       "measured": 7.5, "known_failure": "not reached yet"},
      {"name": "ceiling", "numerator": "fast", "denominator": "floor", "max": 4.8, "floor": 3,
       "measured": 3.4, "known_failure": "not reached yet"}
    ]})"));
  auto status_at = [&](size_t gate, double numerator_per_s, double denominator_per_s) {
    const std::string file =
        write_temp("guard_b.json", bench_json({{gate == 0 ? "slow" : "fast", numerator_per_s},
                                               {gate == 0 ? "fast" : "floor", denominator_per_s}}));
    return evaluate_gates({specs[gate]}, read_bench_times(file))[0].status;
  };
  // ratio = denominator's rate / numerator's rate
  EXPECT_EQ(status_at(0, 1000, 7000), GateStatus::kKnownFailure);     // 7: under the floor
  EXPECT_EQ(status_at(0, 1000, 4000), GateStatus::kFail);             // 4: past the guard
  EXPECT_EQ(status_at(0, 1000, 13000), GateStatus::kUnexpectedPass);  // 13: the floor reached
  EXPECT_EQ(status_at(1, 1000, 3500), GateStatus::kKnownFailure);     // 3.5
  EXPECT_EQ(status_at(1, 1000, 5000), GateStatus::kFail);             // 5
  EXPECT_EQ(status_at(1, 1000, 2900), GateStatus::kUnexpectedPass);   // 2.9
}

// A floor the full run reached by less than the noise margin is guarded at the measured value:
// above the floor it passes as such (the mark is not to be removed), past the guard it fails
TEST(Gate, ANarrowlyReachedFloorPassesWithItsGuardAndStillFails) {
  const auto specs = read_gate_specs(write_temp("narrow.json", R"({"gates": [
      {"name": "narrow", "numerator": "slow", "denominator": "fast", "min": 0.7, "floor": 1,
       "measured": 1.2, "known_failure": "reached by less than the margin"}
    ]})"));
  auto status_at = [&](double slow_per_s, double fast_per_s) {
    const std::string file =
        write_temp("narrow_b.json", bench_json({{"slow", slow_per_s}, {"fast", fast_per_s}}));
    return evaluate_gates(specs, read_bench_times(file))[0].status;
  };
  EXPECT_EQ(status_at(1000, 1100), GateStatus::kNarrowPass);   // 1.1: at its floor
  EXPECT_EQ(status_at(1000, 900), GateStatus::kKnownFailure);  // 0.9: under it, within the guard
  EXPECT_EQ(status_at(1000, 600), GateStatus::kFail);          // 0.6: past the guard
  const auto results = evaluate_gates(
      specs,
      read_bench_times(write_temp("narrow_c.json", bench_json({{"slow", 1000}, {"fast", 1100}}))));
  EXPECT_NE(gate_table(results).find("pass (narrowly: the guard stays)"), std::string::npos);
}

TEST(Gate, BadInputNamesTheFileAndTheProblem) {
  auto error_of = [](auto read, const std::string& file) -> std::string {
    try {
      read(file);
    } catch (const GateError& e) {
      return e.what();
    }
    return "";
  };
  const std::string few = write_temp("few.json", bench_json({{"a", 1.0}}, 3));
  EXPECT_NE(error_of(read_bench_times, few).find("3 repetitions"), std::string::npos);
  const std::string broken = write_temp("broken.json", "{\"benchmarks\": [");
  EXPECT_NE(error_of(read_bench_times, broken).find("broken.json: not JSON"), std::string::npos);
  EXPECT_NE(error_of(read_bench_times, "/nonexistent.json").find("cannot open"), std::string::npos);
  const std::string loose = write_temp(
      "loose.json",
      R"({"gates": [{"name": "x", "numerator": "a", "denominator": "b", "min": 5, "floor": 10}]})");
  EXPECT_NE(error_of(read_gate_specs, loose).find("below its floor"), std::string::npos);
  const std::string both = write_temp(
      "both.json",
      R"({"gates": [{"name": "x", "numerator": "a", "denominator": "b", "min": 5, "max": 6}]})");
  EXPECT_NE(error_of(read_gate_specs, both).find("exactly one"), std::string::npos);
}

// Hostile benchmark JSON: every malformed entry is a GateError naming the file and the problem in
// one bounded line, never a JSON library's exception
TEST(Gate, MalformedBenchmarkJsonIsAGateErrorNeverALibrarysException) {
  const std::string median =
      R"({"run_type": "aggregate", "aggregate_name": "median", "run_name": "a", )";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"benchmarks": [5]})", "benchmarks[0]: expected an object"},
      {R"({"benchmarks": [[{"run_type": "aggregate"}]]})", "benchmarks[0]: expected an object"},
      {R"({"benchmarks": [{"run_type": 7}]})", "\"run_type\" must be a string"},
      {R"({"benchmarks": [)" + median + R"("items_per_second": 1, "repetitions": "5"}]})",
       "\"repetitions\" must be a whole number"},
      {R"({"benchmarks": [)" + median + R"("items_per_second": 1, "repetitions": -5}]})",
       "\"repetitions\" must be a whole number"},
      {R"({"benchmarks": [)" + median + R"("items_per_second": 0, "repetitions": 5}]})",
       "a rate must be positive"},
      {R"({"benchmarks": [)" + median + R"("items_per_second": -3, "repetitions": 5}]})",
       "a rate must be positive"},
      {R"({"benchmarks": [)" + median + R"("error_occurred": "yes"}]})",
       "\"error_occurred\" must be true or false"},
      {R"({"benchmarks": [{"run_type": "aggregate", "aggregate_name": "median", "run_name": ")" +
           std::string(5000, 'n') + R"(", "repetitions": 5}]})",
       "has no items_per_second"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string file = write_temp("hostile" + std::to_string(i) + ".json", cases[i].first);
    std::string message;
    try {
      read_bench_times(file);
    } catch (const GateError& e) {
      message = e.what();
    }
    EXPECT_NE(message.find(cases[i].second), std::string::npos) << i << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << i;
    EXPECT_LE(message.size(), 500u) << i;
  }
  const std::string unnamed =
      write_temp("unnamed.json",
                 R"({"gates": [{"name": 3, "numerator": "a", "denominator": "b", "min": 1}]})");
  std::string message;
  try {
    read_gate_specs(unnamed);
  } catch (const GateError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("\"name\" (a string) is required"), std::string::npos) << message;
}

}  // namespace
}  // namespace puppet::compare
