#include "cli.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <iostream>
#include <sstream>

#include "puppet/compare/cancel.h"
#include "puppet/compare/number.h"
#include "puppet/compare/output.h"
#include "puppet/model/text.h"

namespace puppet::testbed {

using compare::format_dt;
using compare::parse_finite;

void check_steps_per_run(double longest, const std::vector<double>& dts, bool duration_given) {
  const double smallest_dt = *std::min_element(dts.begin(), dts.end());
  const double largest_dt = *std::max_element(dts.begin(), dts.end());
  const std::string flag = duration_given ? "--duration" : "--dt";
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
}

void print_error(const char* prefix, const std::string& what) {
  std::cerr << one_line(prefix + what, kMessageLength) << '\n';
}

double parse_in(const std::string& flag, const std::string& text, double lo, double hi,
                const char* unit) {
  double value = 0.0;
  if (!parse_finite(text, &value)) throw UsageError(flag + ": not a finite number: " + shown(text));
  if (!(value >= lo && value <= hi)) {
    std::ostringstream range;
    range << flag << ": " << text << " is out of range (from " << lo << " to " << hi << unit << ")";
    throw UsageError(range.str());
  }
  return value;
}

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

compare::PointChoice parse_point(const std::string& flag, const std::string& text) {
  compare::PointChoice choice;
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

bool parse_shard(const std::string& text, uint64_t* index, uint64_t* count) {
  const size_t slash = text.find('/');
  return slash != std::string::npos && compare::parse_whole(text.substr(0, slash), index) &&
         compare::parse_whole(text.substr(slash + 1), count);
}

int64_t parse_starts(const std::string& text, double most) {
  const int64_t starts = std::llround(parse_in("--starts", text, 1.0, most, ""));
  if (std::to_string(starts) != text) {
    throw UsageError("--starts: expected a whole number, got " + shown(text));
  }
  return starts;
}

uint64_t parse_seed(const std::string& text) {
  uint64_t seed = 0;
  if (!compare::parse_whole(text, &seed)) {
    throw UsageError("--seed: expected a whole number of at most 18 digits, got " + shown(text));
  }
  return seed;
}

Model parse_model(const std::string& path, const ReadOptions& reading) {
  try {
    return compare::load_named_model(path, reading);
  } catch (const ModelError& error) {
    throw UsageError(std::string("--model: ") + error.what());
  }
}

void stop_on_signals() {
  // a step that does not return within compare::kStopGraceSeconds, or a second signal, is not
  // waited for (cancel.h)
  compare::start_stop_watchdog("testbed");
  struct sigaction action {};
  action.sa_handler = [](int signal) {
    if (compare::cancel_points().load() > 0) {
      compare::request_cancel(signal);
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
}

}  // namespace puppet::testbed
