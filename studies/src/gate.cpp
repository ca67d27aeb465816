#include "puppet/compare/gate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>

#include "puppet/compare/output.h"
#include "puppet/model/file.h"
#include "puppet/model/text.h"

namespace puppet::compare {
namespace {

using nlohmann::json;

constexpr std::string_view kSidePrefix = "s_per_item/";

// a regular file, as a model is read (a FIFO would block, /dev/zero never end): Google
// Benchmark's JSON of a full run is a few MB
json read_json(const std::string& path) {
  std::string text, problem;
  if (!read_regular_file(path, size_t{256} << 20, &text, &problem)) {
    throw GateError(printable(path, 256) + ": " + problem);
  }
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw GateError(printable(path, 256) + ": not JSON (" + printable(e.what(), 200) + ")");
  }
}

std::optional<double> optional_number(const json& gate, const char* key, const std::string& where) {
  if (!gate.contains(key)) return std::nullopt;
  if (!gate[key].is_number()) throw GateError(where + ": \"" + key + "\" must be a number");
  const double value = gate[key].get<double>();
  if (!std::isfinite(value)) throw GateError(where + ": \"" + key + "\" must be finite");
  return value;
}

std::string required_string(const json& gate, const char* key, const std::string& where) {
  if (!gate.contains(key) || !gate[key].is_string() || gate[key].get<std::string>().empty()) {
    throw GateError(where + ": \"" + key + "\" (a benchmark name) is required");
  }
  return gate[key].get<std::string>();
}

std::string status_text(GateStatus status) {
  switch (status) {
    case GateStatus::kPass:
      return "pass";
    case GateStatus::kFail:
      return "FAIL";
    case GateStatus::kKnownFailure:
      return "known failure";
    case GateStatus::kUnexpectedPass:
      return "pass (remove known_failure)";
    case GateStatus::kNarrowPass:
      return "pass (narrowly: the guard stays)";
    case GateStatus::kMissing:
      return "MISSING";
  }
  return "?";
}

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

}  // namespace

std::vector<GateSpec> read_gate_specs(const std::string& path) {
  const json root = read_json(path);
  const std::string file = printable(path, 256);
  if (!root.is_object() || !root.contains("gates") || !root["gates"].is_array()) {
    throw GateError(file + ": expected an object with a \"gates\" array");
  }
  std::vector<GateSpec> specs;
  for (size_t i = 0; i < root["gates"].size(); ++i) {
    const json& gate = root["gates"][i];
    const std::string where = file + ": gates[" + std::to_string(i) + "]";
    if (!gate.is_object()) throw GateError(where + ": expected an object");
    GateSpec spec;
    if (!gate.contains("name") || !gate["name"].is_string() ||
        gate["name"].get<std::string>().empty()) {
      throw GateError(where + ": \"name\" (a string) is required");
    }
    spec.name = printable(gate["name"].get<std::string>(), 120);
    spec.numerator = required_string(gate, "numerator", where);
    spec.denominator = required_string(gate, "denominator", where);
    spec.numerator_per = optional_number(gate, "numerator_per", where).value_or(1.0);
    spec.denominator_per = optional_number(gate, "denominator_per", where).value_or(1.0);
    if (!(spec.numerator_per > 0.0) || !(spec.denominator_per > 0.0)) {
      throw GateError(where + ": \"_per\" counts must be > 0");
    }
    spec.min = optional_number(gate, "min", where);
    spec.max = optional_number(gate, "max", where);
    spec.floor = optional_number(gate, "floor", where);
    spec.measured = optional_number(gate, "measured", where);
    if (gate.contains("measured_on")) {
      if (!gate["measured_on"].is_string()) {
        throw GateError(where + ": \"measured_on\" must be a string (a machine)");
      }
      spec.measured_on = gate["measured_on"].get<std::string>();
    }
    if (spec.min.has_value() == spec.max.has_value()) {
      throw GateError(where + " (" + spec.name + "): exactly one of \"min\" and \"max\"");
    }
    if (gate.contains("known_failure")) {
      if (!gate["known_failure"].is_string()) {
        throw GateError(where + ": \"known_failure\" must be a string (the reason)");
      }
      spec.known_failure = gate["known_failure"].get<std::string>();
    }
    // only a known failure's threshold may be looser than its floor: it guards what was measured
    const bool guard = !spec.known_failure.empty();
    if (!guard && spec.floor && spec.min && *spec.min < *spec.floor) {
      throw GateError(where + " (" + spec.name + "): min " + format("%g", *spec.min) +
                      " is below its floor " + format("%g", *spec.floor));
    }
    if (!guard && spec.floor && spec.max && *spec.max > *spec.floor) {
      throw GateError(where + " (" + spec.name + "): max " + format("%g", *spec.max) +
                      " is above its floor " + format("%g", *spec.floor));
    }
    specs.push_back(spec);
  }
  return specs;
}

std::vector<BenchTime> read_bench_times(const std::string& path) {
  const json root = read_json(path);
  const std::string file = printable(path, 256);
  if (!root.is_object() || !root.contains("benchmarks") || !root["benchmarks"].is_array()) {
    throw GateError(file + ": not Google Benchmark JSON (no \"benchmarks\" array)");
  }
  std::vector<BenchTime> times;
  const json& entries = root["benchmarks"];
  for (size_t i = 0; i < entries.size(); ++i) {
    const json& entry = entries[i];
    const std::string where = file + ": benchmarks[" + std::to_string(i) + "]";
    if (!entry.is_object()) throw GateError(where + ": expected an object");
    // a field Google Benchmark writes as a string: absent reads as empty, any other type is
    // not its JSON
    auto text = [&](const char* key) -> std::string {
      if (!entry.contains(key)) return {};
      if (!entry[key].is_string()) throw GateError(where + ": \"" + key + "\" must be a string");
      return entry[key].get<std::string>();
    };
    if (text("run_type") != "aggregate" || text("aggregate_name") != "median") continue;
    if (entry.contains("error_occurred")) {
      if (!entry["error_occurred"].is_boolean()) {
        throw GateError(where + ": \"error_occurred\" must be true or false");
      }
      if (entry["error_occurred"].get<bool>()) continue;
    }
    // "/manual_time" and "/real_time" say how a benchmark is timed, not what it is
    std::string name = text("run_name");
    for (const std::string suffix : {"/manual_time", "/real_time"}) {
      if (name.size() > suffix.size() && name.ends_with(suffix)) {
        name.resize(name.size() - suffix.size());
      }
    }
    const std::string shown_name = printable(name, 120);
    if (!entry.contains("items_per_second") || !entry["items_per_second"].is_number()) {
      throw GateError(file + ": " + shown_name + " has no items_per_second");
    }
    const double rate = entry["items_per_second"].get<double>();
    if (!std::isfinite(rate) || rate <= 0.0) {
      throw GateError(file + ": " + shown_name + " has items_per_second " + format("%g", rate) +
                      " (a rate must be positive)");
    }
    BenchTime time;
    time.name = name;
    time.seconds = 1.0 / rate;
    if (entry.contains("repetitions") && !entry["repetitions"].is_number_unsigned()) {
      throw GateError(where + ": \"repetitions\" must be a whole number");
    }
    time.repetitions = static_cast<int>(
        std::min<uint64_t>(entry.value("repetitions", uint64_t{0}), uint64_t{1} << 30));
    if (time.repetitions < kGateRepetitions) {
      throw GateError(file + ": " + shown_name + " has " + std::to_string(time.repetitions) +
                      " repetitions; the gate needs at least " + std::to_string(kGateRepetitions) +
                      " (--benchmark_repetitions)");
    }
    times.push_back(time);
    // a paired benchmark times its sides in turn within each iteration, so that whatever slows
    // the machine slows both alike (bench_python): each side's seconds per item is a counter
    // "s_per_item/<side>", read as the benchmark <name>/<side>
    for (const auto& [key, value] : entry.items()) {
      if (!key.starts_with(kSidePrefix)) continue;
      const std::string side = printable(key.substr(kSidePrefix.size()), 60);
      if (side.empty() || !value.is_number() || !std::isfinite(value.get<double>()) ||
          !(value.get<double>() > 0.0)) {
        throw GateError(file + ": " + shown_name + ": \"" + printable(key, 80) +
                        "\" must be a positive number of seconds (a side's time per item)");
      }
      times.push_back({name + "/" + side, value.get<double>(), time.repetitions});
    }
  }
  if (times.empty()) {
    throw GateError(file + ": no median aggregates (run with --benchmark_repetitions=" +
                    std::to_string(kGateRepetitions) + ")");
  }
  return times;
}

std::vector<GateResult> evaluate_gates(const std::vector<GateSpec>& specs,
                                       const std::vector<BenchTime>& times) {
  std::map<std::string, double> seconds;
  for (const BenchTime& time : times) seconds[time.name] = time.seconds;
  std::vector<GateResult> results;
  for (const GateSpec& spec : specs) {
    GateResult result{spec, std::nan(""), GateStatus::kMissing};
    const auto numerator = seconds.find(spec.numerator);
    const auto denominator = seconds.find(spec.denominator);
    if (numerator != seconds.end() && denominator != seconds.end()) {
      result.ratio =
          (numerator->second / spec.numerator_per) / (denominator->second / spec.denominator_per);
      const double ratio = result.ratio;
      auto meets = [&](double limit) { return spec.min ? ratio >= limit : ratio <= limit; };
      const double threshold = spec.min ? *spec.min : *spec.max;
      if (spec.known_failure.empty()) {
        result.status = meets(threshold) ? GateStatus::kPass : GateStatus::kFail;
      } else if (meets(spec.floor.value_or(threshold))) {
        // the full run had reached it too: a floor within the noise, not a mark to remove
        const bool narrow =
            spec.floor && spec.measured &&
            (spec.min ? *spec.measured >= *spec.floor : *spec.measured <= *spec.floor);
        result.status = narrow ? GateStatus::kNarrowPass : GateStatus::kUnexpectedPass;
      } else if (const bool guarded = spec.floor && threshold != *spec.floor;
                 !guarded || meets(threshold)) {
        // below the floor, as known; a threshold looser than the floor guards the measured
        // value, and only falling past it fails
        result.status = GateStatus::kKnownFailure;
      } else {
        result.status = GateStatus::kFail;
      }
    } else if (!spec.known_failure.empty()) {
      // a benchmark skips a run the testbed calls diverged: a known failure has no time
      result.status = GateStatus::kKnownFailure;
    }
    results.push_back(result);
  }
  return results;
}

std::string gate_table(const std::vector<GateResult>& results) {
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof line, "%-52s %9s %11s %9s %9s  %s\n", "gate", "ratio", "threshold",
                "floor", "measured", "status");
  out << line;
  std::vector<std::string> machines;  // where the measured values come from, in order of use
  for (const GateResult& r : results) {
    const std::string threshold =
        r.spec.min ? format(">= %.2f", *r.spec.min) : format("<= %.2f", *r.spec.max);
    const std::string floor = r.spec.floor ? format("%.2f", *r.spec.floor) : "-";
    std::string measured = r.spec.measured ? format("%.2f", *r.spec.measured) : "-";
    if (r.spec.measured && !r.spec.measured_on.empty()) {
      auto at = std::find(machines.begin(), machines.end(), r.spec.measured_on);
      if (at == machines.end()) at = machines.insert(machines.end(), r.spec.measured_on);
      measured.append(1, '^').append(std::to_string(at - machines.begin() + 1));
    }
    const std::string ratio = std::isnan(r.ratio) ? "-" : format("%.2f", r.ratio);
    std::snprintf(line, sizeof line, "%-52s %9s %11s %9s %9s  %s\n", r.spec.name.c_str(),
                  ratio.c_str(), threshold.c_str(), floor.c_str(), measured.c_str(),
                  status_text(r.status).c_str());
    out << line;
    // a known failure without a ratio is a run skipped as diverged: its reason says so
    if (r.status == GateStatus::kMissing) {
      out << "    missing benchmark: " << r.spec.numerator << " or " << r.spec.denominator << '\n';
    }
    if (r.status == GateStatus::kKnownFailure) out << "    known: " << r.spec.known_failure << '\n';
  }
  for (size_t i = 0; i < machines.size(); ++i) {
    out << "^" << i + 1 << " measured on " << machines[i] << '\n';
  }
  return out.str();
}

bool gate_passed(const std::vector<GateResult>& results) {
  for (const GateResult& r : results) {
    if (r.status == GateStatus::kFail || r.status == GateStatus::kMissing) return false;
  }
  return true;
}

std::string bench_csv(const std::vector<BenchTime>& times) {
  std::string csv = "benchmark,repetitions,median_s_per_item,items_per_second\n";
  for (const BenchTime& time : times) {
    csv += csv_field(time.name) + "," + std::to_string(time.repetitions) + "," +
           csv_number(time.seconds) + "," + csv_number(1.0 / time.seconds) + "\n";
  }
  return csv;
}

}  // namespace puppet::compare
