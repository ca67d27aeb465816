// The testbed's command line: the error every bad value raises, and the parsers of values that
// CLI11 does not type (fractions such as 1/240, lists checked against a catalogue, lengths with
// units). Each names its flag in its message, which is one line of at most kMessageLength
// characters.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/model/model.h"

namespace puppet::testbed {

inline constexpr int kBadInput = 2;            // the exit status of every bad input
inline constexpr size_t kMessageLength = 400;  // an error is one line of at most this

// a bad flag or value, caught by main and printed as one line; exit status kBadInput
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// one line of at most kMessageLength characters, the prefix included, to standard error
void print_error(const char* prefix, const std::string& what);

// the steps a run may take, from 10 µs to 0.1 s each
inline constexpr double kMinDt = 1e-5, kMaxDt = 0.1;
// at most this many steps per run (the truths' too, at their finest dt)
inline constexpr double kMaxSteps = 1e7;
// that a run of `longest` seconds takes at least one step at the largest of `dts` and at most
// kMaxSteps at the smallest; else a UsageError naming --duration when it was given
// (`duration_given`), else --dt
void check_steps_per_run(double longest, const std::vector<double>& dts, bool duration_given);

// a number within [lo, hi] (the flag's stated range, docs in --help and docs/testbed.md)
double parse_in(const std::string& flag, const std::string& text, double lo, double hi,
                const char* unit = "");
// X,Y,Z, each finite and at most `bound` in magnitude
Vector3d parse_vector(const std::string& flag, const std::string& text, double bound);
// SEGMENT[:x,y,z]
compare::PointChoice parse_point(const std::string& flag, const std::string& text);
// "all" or a comma list of names from `all`, none twice
std::vector<std::string> expand(const std::string& flag, const std::string& value,
                                const std::vector<std::string>& all);
// a comma list of steps (fractions too), none twice as printed
std::vector<double> parse_dts(const std::string& text);
// error budgets: lengths with a unit (50um, 1mm, 1cm, 0.05m) or plain metres, 1 µm to 10 m,
// sorted
std::vector<double> parse_budgets(const std::string& text);
// "I/N" in plain decimal digits (the range is the caller's to check)
bool parse_shard(const std::string& text, uint64_t* index, uint64_t* count);
// a whole number of starts within [1, most]
int64_t parse_starts(const std::string& text, double most);
// a seed of at most 18 digits
uint64_t parse_seed(const std::string& text);
// the model a --model flag names (a file, pinocchio or chain:N)
Model parse_model(const std::string& path, const ReadOptions& reading);

// SIGINT and SIGTERM: before anything is written the process ends at once; after, the runs stop
// at their next step and the output folder is left as it was (cancel.h)
void stop_on_signals();

}  // namespace puppet::testbed
