#include "puppet/compare/output.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "puppet/compare/output_folder.h"

namespace puppet::compare {

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string csv_number(double value) {
  if (std::isnan(value)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

namespace {

std::string sanitise(const std::string& text) {
  std::string out = text;
  for (char& c : out) {
    const bool safe =
        std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
    if (!safe) c = '-';
  }
  return out;
}

}  // namespace

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  // RFC 4180: in double quotes, a quote inside doubled
  std::string out = "\"";
  for (const char c : text) {
    out += c;
    if (c == '"') out += '"';
  }
  return out + "\"";
}

std::string format_dt(double dt) { return csv_number(dt); }

std::string trace_stem(const std::string& model, const RunResult& r) {
  return sanitise(model) + "__" + sanitise(r.scenario) + "__" + sanitise(r.solver) + "__" +
         (r.rule.empty() ? std::string("-") : sanitise(r.rule)) + "__" + format_dt(r.dt);
}

std::string summary_csv(const std::vector<RunResult>& results, const OutputContext& context) {
  std::ostringstream out;
  out << kSummaryHeader << '\n';
  for (const RunResult& r : results) {
    const char* status = r.diverged ? kStatusDiverged : kStatusOk;
    for (const SummaryRow& row : r.summary) {
      out << csv_field(r.scenario) << ',' << csv_field(r.solver) << ',' << csv_field(r.rule) << ','
          << format_dt(r.dt) << ',' << r.substeps << ',' << csv_field(row.metric) << ','
          << csv_field(row.stat) << ',' << csv_number(row.value) << ',' << csv_field(row.unit)
          << ',' << csv_field(context.model) << ',' << csv_field(row.reference) << ',' << status
          << ',' << csv_field(context.git_sha) << ',' << csv_field(context.machine) << '\n';
    }
  }
  return out.str();
}

std::string trace_csv(const RunResult& r, double sample_hz) {
  const size_t stride =
      sample_hz > 0.0
          ? std::max<size_t>(1, static_cast<size_t>(std::lround(1.0 / (sample_hz * r.dt))))
          : 1;
  std::ostringstream out;
  out << kTraceHeader << '\n';
  for (size_t k = 0; k < r.trace.size(); ++k) {
    if (k % stride != 0 && k + 1 != r.trace.size()) continue;
    const StepMetrics& m = r.trace[k];
    out << csv_number(m.t) << ',' << csv_number(m.joint_gap_max) << ','
        << csv_number(m.joint_gap_rms) << ',' << csv_number(m.pin_gap_max) << ','
        << csv_number(m.limit_violation_max_deg) << ',' << csv_number(m.energy_drift) << ','
        << csv_number(m.linear_momentum_drift) << ',' << csv_number(m.angular_momentum_drift) << ','
        << csv_number(m.penetration) << ',' << csv_number(m.peak_speed) << '\n';
  }
  return out.str();
}

std::string poses_csv(const Model& model, const RunResult& r) {
  std::ostringstream out;
  out << kPosesHeader << '\n';
  for (const PoseSample& p : r.poses) {
    const BodyState& b = p.body;
    out << csv_number(p.t) << ',' << csv_field(model.segments[p.segment].name) << ','
        << csv_number(b.x.x()) << ',' << csv_number(b.x.y()) << ',' << csv_number(b.x.z()) << ','
        << csv_number(b.q.w()) << ',' << csv_number(b.q.x()) << ',' << csv_number(b.q.y()) << ','
        << csv_number(b.q.z()) << '\n';
  }
  return out.str();
}

std::string output_file_problem(const std::string& path) {
  if (path.empty()) return "is an empty path";
  struct stat link {};
  if (::lstat(path.c_str(), &link) != 0) {
    if (errno != ENOENT) return std::string("cannot be examined (") + std::strerror(errno) + ")";
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    std::error_code error;
    if (!folder.empty() && !std::filesystem::is_directory(folder, error)) {
      return "is in a folder that does not exist";
    }
    return {};
  }
  struct stat target = link;
  const bool is_link = S_ISLNK(link.st_mode);
  if (is_link && ::stat(path.c_str(), &target) != 0) {
    return "is a symbolic link to nothing (it is not followed to make a file)";
  }
  if (S_ISREG(target.st_mode)) return {};
  const char* what = S_ISDIR(target.st_mode)    ? "a folder"
                     : S_ISCHR(target.st_mode)  ? "a character device"
                     : S_ISBLK(target.st_mode)  ? "a block device"
                     : S_ISFIFO(target.st_mode) ? "a FIFO"
                     : S_ISSOCK(target.st_mode) ? "a socket"
                                                : "not a regular file";
  return std::string(is_link ? "is a symbolic link to " : "is ") + what +
         ", which is never replaced (name a new or a regular file)";
}

void write_file_atomically(const std::string& path, const std::string& content) {
  auto check = [&](const std::string& file) {
    if (std::string problem = output_file_problem(file); !problem.empty()) {
      throw OutputError(path + " " + problem);
    }
  };
  check(path);
  // through a symbolic link: the file it names is the one replaced, the link stays
  std::error_code error;
  const bool is_link = std::filesystem::is_symlink(std::filesystem::symlink_status(path, error));
  error.clear();  // a new name has no status
  const std::string file = is_link ? std::filesystem::canonical(path, error).string() : path;
  if (error) throw OutputError(path + " cannot be resolved (" + error.message() + ")");
  // a name of this writer's own: two writers of one path (two threads, two processes) never
  // share a temporary, and the last rename wins whole
  static std::atomic<unsigned> counter{0};
  const std::string temporary =
      file + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write");
    out << content;
    out.flush();
    if (!out) {
      const std::string reason = std::strerror(errno);
      std::remove(temporary.c_str());
      throw std::runtime_error(path + ": write failed (" + reason + ")");
    }
  }
  try {
    check(file);  // what may have appeared at the name while the file was written
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  std::filesystem::rename(temporary, file, error);
  if (error) {
    std::remove(temporary.c_str());
    throw std::runtime_error(path + ": cannot write (" + error.message() + ")");
  }
}

std::string current_git_sha() {
  std::string sha;
  if (FILE* pipe = popen("git rev-parse --short=12 HEAD 2>/dev/null", "r")) {
    std::array<char, 64> buffer{};
    if (std::fgets(buffer.data(), buffer.size(), pipe)) sha = buffer.data();
    pclose(pipe);
  }
  while (!sha.empty() && (sha.back() == '\n' || sha.back() == '\r')) sha.pop_back();
  return sha.empty() ? "unknown" : sha;
}

std::string machine_description() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line, model = "unknown cpu";
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) model = line.substr(colon + 2);
      break;
    }
  }
  return model + " x" + std::to_string(std::thread::hardware_concurrency());
}

}  // namespace puppet::compare
