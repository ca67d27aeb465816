#include "puppet/compare/output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
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
  // the temporary name write_file_atomically gives it adds ".tmp.<pid>.<n>", at most 26 bytes
  constexpr size_t kNameMax = 255, kTemporaryExtra = 26;
  if (const size_t name = std::filesystem::path(path).filename().string().size();
      name + kTemporaryExtra > kNameMax) {
    return "has a name of " + std::to_string(name) + " bytes; at most " +
           std::to_string(kNameMax - kTemporaryExtra) + " (its temporary name is longer)";
  }
  struct stat link {};
  if (::lstat(path.c_str(), &link) != 0) {
    if (errno == ENAMETOOLONG) return "has a name longer than the file system allows";
    if (errno != ENOENT) return std::string("cannot be examined (") + std::strerror(errno) + ")";
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    std::error_code error;
    if (!folder.empty() && !std::filesystem::is_directory(folder, error)) {
      return "is in a folder that does not exist";
    }
    if (std::filesystem::path(path).is_relative()) {
      const std::filesystem::path working = std::filesystem::current_path(error);
      if (error || working.empty()) {
        return "is relative to a working folder that no longer exists";
      }
    }
    if (::access(folder.empty() ? "." : folder.c_str(), W_OK | X_OK) != 0) {
      return std::string("is in a folder that cannot be written (") + std::strerror(errno) + ")";
    }
    return {};
  }
  if (S_ISREG(link.st_mode)) return {};
  const char* what = S_ISLNK(link.st_mode)    ? "a symbolic link, which is never written through"
                     : S_ISDIR(link.st_mode)  ? "a folder"
                     : S_ISCHR(link.st_mode)  ? "a character device"
                     : S_ISBLK(link.st_mode)  ? "a block device"
                     : S_ISFIFO(link.st_mode) ? "a FIFO"
                     : S_ISSOCK(link.st_mode) ? "a socket"
                                              : "not a regular file";
  return std::string("is ") + what + " (name a new or a regular file)";
}

std::string content_checksum(const std::string& bytes) {
  uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a 64: offset basis and prime
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

void write_file_atomically(const std::string& path, const std::string& content) {
  auto check = [&] {
    if (std::string problem = output_file_problem(path); !problem.empty()) {
      throw OutputError(path + " " + problem);
    }
  };
  check();
  // a name of this writer's own, made new (O_EXCL, and O_NOFOLLOW: a link planted at that name
  // is never followed): two writers of one path (two threads, two processes) never share a
  // temporary, and the last rename wins whole
  static std::atomic<unsigned> counter{0};
  const std::string temporary =
      path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  const int fd =
      ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error(path + ": cannot write (" + std::strerror(errno) + ")");
  }
  TidyPath tidy(temporary);  // removed if the process is stopped while it exists
  const char* p = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t wrote = ::write(fd, p, left);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) {
      const std::string reason = wrote < 0 ? std::strerror(errno) : "nothing written";
      ::close(fd);
      ::unlink(temporary.c_str());
      throw std::runtime_error(path + ": write failed (" + reason + ")");
    }
    p += wrote;
    left -= static_cast<size_t>(wrote);
  }
  if (::close(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temporary.c_str());
    throw std::runtime_error(path + ": write failed (" + reason + ")");
  }
  try {
    check();  // what may have appeared at the name while the file was written
  } catch (...) {
    ::unlink(temporary.c_str());
    throw;
  }
  // rename replaces the name itself: a link that appeared there since is replaced, never followed
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temporary.c_str());
    throw std::runtime_error(path + ": cannot write (" + reason + ")");
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
