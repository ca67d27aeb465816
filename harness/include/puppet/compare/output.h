// Files the testbed writes (docs/design.md, "Outputs"): the tidy summary.csv, per-run traces
// and poses. Every file is written whole to a temporary name and renamed, so a failure never
// leaves half a file behind.
#pragma once

#include <string>
#include <vector>

#include "puppet/compare/run.h"

namespace puppet::compare {

struct OutputContext {
  std::string model;  // model name
  std::string git_sha;
  std::string machine;
};

// summary.csv's status of a run: finished, or diverged (docs/design.md, "status")
inline constexpr const char* kStatusOk = "ok";
inline constexpr const char* kStatusDiverged = "diverged";
inline constexpr const char* kSummaryHeader =
    "scenario,solver,rule,dt,substeps,metric,stat,value,unit,model,reference,status,git_sha,"
    "machine";

// a number with 9 significant digits, empty for NaN
std::string csv_number(double value);
// text as one CSV field (RFC 4180): as it is, or in double quotes with quotes doubled when it
// holds a comma, a quote or a line break
std::string csv_field(const std::string& text);
// a line's comma-separated fields as csv_number and unquoted csv_field write them ("a,,b," is
// four fields)
std::vector<std::string> split_commas(const std::string& line);
// dt as a decimal with 9 significant digits
std::string format_dt(double dt);
// <model>__<scenario>__<solver>__<rule>__<dt>, safe as a file name ("-" for an empty rule)
std::string trace_stem(const std::string& model, const RunResult& result);

std::string summary_csv(const std::vector<RunResult>& results, const OutputContext& context);
// a trace's columns (traces/<stem>.csv) and its poses' (traces/<stem>__poses.csv)
inline constexpr const char* kTraceHeader =
    "t,joint_gap_max_m,joint_gap_rms_m,pin_gap_max_m,limit_violation_max_deg,energy_drift,"
    "momentum_linear_drift,momentum_angular_drift,penetration_m,peak_speed_mps";
inline constexpr const char* kPosesHeader = "t,segment,x,y,z,qw,qx,qy,qz";
// the metrics of every step; with sample_hz > 0 thinned to that many rows per simulated second
// (the last row always kept)
std::string trace_csv(const RunResult& result, double sample_hz = 0.0);
std::string poses_csv(const Model& model, const RunResult& result);

// What keeps `path` from being written (empty when nothing): it must be a new name in a folder
// that exists and can be written, or a regular file, which is replaced whole. A symbolic link
// (whatever it names), a folder, a device, a FIFO or a socket is never replaced nor written
// through.
std::string output_file_problem(const std::string& path);

// Writes to a new name of its own beside the file (never through a link planted there) and
// renames it into place. Throws OutputError when output_file_problem() objects (checked before
// writing and again before the rename), std::runtime_error naming the file when a write fails.
void write_file_atomically(const std::string& path, const std::string& content);

// the FNV-1a 64-bit hash of a file's bytes, as 16 hex digits: it catches a file cut short or
// edited by accident (a shard's manifest, a truth cache's key); it is no signature
std::string content_checksum(const std::string& bytes);

// the commit the binary runs from ("unknown" outside a git checkout) and a one-line machine id
std::string current_git_sha();
std::string machine_description();

}  // namespace puppet::compare
