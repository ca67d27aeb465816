#include "puppet/compare/output.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace puppet::compare {
namespace {

std::string number(double value) {
  if (std::isnan(value)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

std::string sanitise(const std::string& text) {
  std::string out = text;
  for (char& c : out) {
    const bool safe =
        std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
    if (!safe) c = '-';
  }
  return out;
}

// CSV fields here never need quoting except free text; keep commas and quotes out of it
std::string field(const std::string& text) {
  std::string out = text;
  for (char& c : out) {
    if (c == ',' || c == '"' || c == '\n') c = ' ';
  }
  return out;
}

}  // namespace

std::string format_dt(double dt) { return number(dt); }

std::string trace_stem(const std::string& model, const RunResult& r) {
  return sanitise(model) + "__" + sanitise(r.scenario) + "__" + sanitise(r.solver) + "__" +
         (r.rule.empty() ? std::string("-") : sanitise(r.rule)) + "__" + format_dt(r.dt);
}

std::string summary_csv(const std::vector<RunResult>& results, const OutputContext& context) {
  std::ostringstream out;
  out << kSummaryHeader << '\n';
  for (const RunResult& r : results) {
    const char* status = r.diverged ? "diverged" : "ok";
    for (const SummaryRow& row : r.summary) {
      out << r.scenario << ',' << r.solver << ',' << r.rule << ',' << format_dt(r.dt) << ','
          << r.substeps << ',' << row.metric << ',' << row.stat << ',' << number(row.value) << ','
          << row.unit << ',' << field(context.model) << ",," << status << ','
          << field(context.git_sha) << ',' << field(context.machine) << '\n';
    }
  }
  return out.str();
}

std::string trace_csv(const RunResult& r) {
  std::ostringstream out;
  out << "t,joint_gap_max_m,joint_gap_rms_m,pin_gap_max_m,limit_violation_max_deg,energy_drift,"
         "momentum_linear_drift,momentum_angular_drift,penetration_m,peak_speed_mps\n";
  for (const StepMetrics& m : r.trace) {
    out << number(m.t) << ',' << number(m.joint_gap_max) << ',' << number(m.joint_gap_rms) << ','
        << number(m.pin_gap_max) << ',' << number(m.limit_violation_max_deg) << ','
        << number(m.energy_drift) << ',' << number(m.linear_momentum_drift) << ','
        << number(m.angular_momentum_drift) << ',' << number(m.penetration) << ','
        << number(m.peak_speed) << '\n';
  }
  return out.str();
}

std::string poses_csv(const Model& model, const RunResult& r) {
  std::ostringstream out;
  out << "t,segment,x,y,z,qw,qx,qy,qz\n";
  for (const PoseSample& p : r.poses) {
    const BodyState& b = p.body;
    out << number(p.t) << ',' << model.segments[p.segment].name << ',' << number(b.x.x()) << ','
        << number(b.x.y()) << ',' << number(b.x.z()) << ',' << number(b.q.w()) << ','
        << number(b.q.x()) << ',' << number(b.q.y()) << ',' << number(b.q.z()) << '\n';
  }
  return out.str();
}

void write_file_atomically(const std::string& path, const std::string& content) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    if (!file) throw std::runtime_error(path + ": cannot write");
    file << content;
    file.flush();
    if (!file) {
      std::remove(temporary.c_str());
      throw std::runtime_error(path + ": write failed");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
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
  return field(model) + " x" + std::to_string(std::thread::hardware_concurrency());
}

}  // namespace puppet::compare
