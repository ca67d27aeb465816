#include "puppet/compare/shard.h"
#include "puppet/compare/engines.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "puppet/compare/number.h"
#include "puppet/compare/output.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/model/file.h"
#include "puppet/model/text.h"
#include "puppet/procedural/rule.h"

namespace puppet::compare {
namespace {

constexpr const char* kHeader = "puppet robustness shard";
constexpr const char* kKeys[] = {"model",  "scenarios", "configs", "dts",  "starts", "seed",
                                 "replay", "code",      "shard",   "jobs", "rows",   "csv"};
constexpr size_t kMaxManifestBytes = 1 << 16;
constexpr size_t kMaxModelName = 1024;
constexpr int64_t kMaxStarts = 1000000;
// the steps of the longest run the testbed takes (an hour at its smallest dt is refused before)
constexpr uint64_t kMaxSteps = 10000001;

std::string config_name(const SolverConfig& config) {
  return has_rules(config.solver)
             ? config.solver + ":" +
                   std::string(procedural::rule_name(config.options.procedural.rule))
             : config.solver;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ",") + item;
  return out;
}

bool known_config(const std::string& config) {
  // ENGINE:RULE for an engine that runs the rules, else the engine's name alone
  const size_t colon = config.find(':');
  if (colon != std::string::npos) {
    return has_rules(config.substr(0, colon)) &&
           procedural::parse_rule(config.substr(colon + 1)).has_value();
  }
  const auto& solvers = solver_names();
  return !has_rules(config) && std::find(solvers.begin(), solvers.end(), config) != solvers.end();
}

// the rows a shard holds: the jobs j < jobs with j mod count = index
int64_t shard_rows(int64_t jobs, int64_t index, int64_t count) {
  return jobs > index ? (jobs - index + count - 1) / count : 0;
}

}  // namespace

std::string shard_model_problem(const std::string& model) {
  const bool printable =
      std::all_of(model.begin(), model.end(), [](char c) { return c >= 0x20 && c < 0x7f; });
  if (model.empty() || model.size() > kMaxModelName || !printable) {
    return "a model's name in shard.txt is 1 to " + std::to_string(kMaxModelName) +
           " characters of printable ASCII";
  }
  return {};
}

std::string shard_manifest(const RobustnessSpec& spec, int64_t rows, const std::string& csv) {
  std::vector<std::string> configs, dts;
  for (const SolverConfig& config : spec.configs) configs.push_back(config_name(config));
  for (double dt : spec.dts) dts.push_back(format_dt(dt));
  std::ostringstream out;
  out << kHeader << "\n"
      << "model: " << spec.model_name << "\n"
      << "scenarios: " << joined(spec.scenarios) << "\n"
      << "configs: " << joined(configs) << "\n"
      << "dts: " << joined(dts) << "\n"
      << "starts: " << spec.starts << "\n"
      << "seed: " << spec.seed << "\n"
      << "replay: " << spec.replay_flags << "\n"
      << "code: " << spec.code << "\n"
      << "shard: " << spec.shard << "/" << spec.shards << "\n"
      << "jobs: " << robustness_job_count(spec) << "\n"
      << "rows: " << rows << "\n"
      << "csv: " << csv.size() << " " << content_checksum(csv) << "\n";
  return out.str();
}

std::string ShardManifest::identity() const {
  return "model=" + model + " scenarios=" + joined(scenarios) + " configs=" + joined(configs) +
         " dts=" + joined(dts) + " starts=" + std::to_string(starts) +
         " seed=" + std::to_string(seed) + " flags=" + replay + " code=" + code +
         " shards=" + std::to_string(count) + " jobs=" + std::to_string(jobs);
}

ShardManifest read_shard_manifest(
    const std::string& folder,
    const std::function<std::string(const std::string& replay)>& canonical_replay) {
  const std::string path = folder + "/shard.txt";
  const std::string where = shown(path);
  auto fail = [&](const std::string& problem) -> void { throw ShardError(where + ": " + problem); };
  std::string text, problem;
  if (!read_regular_file(path, kMaxManifestBytes, &text, &problem)) fail(problem);
  for (const char c : text) {
    if (c != '\n' && (c < 0x20 || c >= 0x7f)) fail("holds a byte that is not printable ASCII");
  }
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kHeader) fail("not a robustness shard's manifest");
  std::map<std::string, std::string> fields;
  while (std::getline(in, line)) {
    const size_t colon = line.find(": ");
    const std::string key = line.substr(0, colon);
    if (colon == std::string::npos ||
        std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
      fail("an unknown line " + shown(line));
    }
    if (!fields.emplace(key, line.substr(colon + 2)).second) fail("a second " + key + " line");
  }
  for (const char* key : kKeys) {
    if (!fields.count(key)) fail(std::string("no ") + key + " line");
  }
  auto whole = [&](const char* key, uint64_t lo, uint64_t hi) {
    uint64_t value = 0;
    if (!parse_whole(fields[key], &value) || value < lo || value > hi) {
      fail(std::string(key) + ": " + shown(fields[key]) + " is not a whole number from " +
           std::to_string(lo) + " to " + std::to_string(hi));
    }
    return value;
  };
  auto list = [&](const char* key, size_t most, const auto& known) {
    std::vector<std::string> items = split_commas(fields[key]);
    if (items.empty() || items.size() > most)
      fail(std::string(key) + ": from 1 to " + std::to_string(most) + " items expected");
    std::set<std::string> seen;
    for (const std::string& item : items) {
      if (!known(item)) fail(std::string(key) + ": " + shown(item) + " is not known");
      if (!seen.insert(item).second) fail(std::string(key) + ": " + shown(item) + " twice");
    }
    return items;
  };

  ShardManifest m;
  m.folder = folder;
  m.model = fields["model"];
  if (std::string name_problem = shard_model_problem(m.model); !name_problem.empty()) {
    fail("model: " + name_problem);
  }
  const auto& scenarios = scenario_names();
  m.scenarios = list("scenarios", scenarios.size(), [&](const std::string& s) {
    return std::find(scenarios.begin(), scenarios.end(), s) != scenarios.end();
  });
  m.configs = list("configs", 64, known_config);
  m.dts = list("dts", 64, [](const std::string& t) {
    double dt = 0.0;
    return parse_finite(t, &dt) && dt >= 1e-5 && dt <= 0.1 && format_dt(dt) == t;
  });
  m.starts = static_cast<int64_t>(whole("starts", 1, kMaxStarts));
  m.seed = whole("seed", 0, 999999999999999999ull);
  m.code = fields["code"];
  const bool hex = !m.code.empty() && m.code.size() <= 40 &&
                   m.code.find_first_not_of("0123456789abcdef") == std::string::npos;
  if (!hex && m.code != "unknown") fail("code: " + shown(m.code) + " is not a commit");
  m.replay = fields["replay"];
  if (canonical_replay(m.replay) != m.replay) {
    fail("replay: " + shown(m.replay) + " is not the flags the testbed writes");
  }
  uint64_t index = 0, count = 0;
  const std::string& place = fields["shard"];
  const size_t slash = place.find('/');
  if (slash == std::string::npos || !parse_whole(place.substr(0, slash), &index) ||
      !parse_whole(place.substr(slash + 1), &count) || count < 1 ||
      count > static_cast<uint64_t>(kMaxShards) || index >= count) {
    fail("shard: " + shown(place) + " is not I/N with 0 <= I < N <= " + std::to_string(kMaxShards));
  }
  m.index = static_cast<int64_t>(index);
  m.count = static_cast<int64_t>(count);
  m.jobs = static_cast<int64_t>(whole("jobs", 1, kMaxSweepRuns));
  // the sweep's size from its parts (each part bounded above, so no product overflows)
  const int64_t expected_jobs =
      static_cast<int64_t>(m.scenarios.size() * m.configs.size() * m.dts.size()) * m.starts;
  if (m.jobs != expected_jobs) {
    fail("jobs: " + std::to_string(m.jobs) + ", but its scenarios, configs, dts and starts make " +
         std::to_string(expected_jobs));
  }
  m.rows = static_cast<int64_t>(whole("rows", 0, kMaxShardRuns));
  if (m.rows != shard_rows(m.jobs, m.index, m.count)) {
    fail("rows: " + std::to_string(m.rows) + ", but shard " + place + " of " +
         std::to_string(m.jobs) + " runs has " +
         std::to_string(shard_rows(m.jobs, m.index, m.count)));
  }
  const std::string& csv = fields["csv"];
  const size_t space = csv.find(' ');
  uint64_t bytes = 0;
  if (space == std::string::npos || !parse_whole(csv.substr(0, space), &bytes) ||
      bytes > (uint64_t{1} << 32) || csv.size() - space - 1 != 16 ||
      csv.find_first_not_of("0123456789abcdef", space + 1) != std::string::npos) {
    fail("csv: " + shown(csv) + " is not BYTES CHECKSUM");
  }
  m.csv_bytes = static_cast<int64_t>(bytes);
  m.csv_checksum = csv.substr(space + 1);
  return m;
}

std::vector<RobustnessRow> read_shard_rows(const ShardManifest& shard) {
  const std::string path = shard.folder + "/robustness.csv";
  std::string text, problem;
  if (!read_regular_file(path, static_cast<size_t>(shard.csv_bytes), &text, &problem)) {
    throw ShardError(shown(path) + ": " + problem + " (shard.txt says " +
                     std::to_string(shard.csv_bytes) + " bytes)");
  }
  if (static_cast<int64_t>(text.size()) != shard.csv_bytes ||
      content_checksum(text) != shard.csv_checksum) {
    throw ShardError(shown(path) + ": " + std::to_string(text.size()) + " bytes, checksum " +
                     content_checksum(text) + "; shard.txt says " +
                     std::to_string(shard.csv_bytes) + " bytes, " + shard.csv_checksum +
                     " (the file was changed or cut)");
  }
  std::vector<RobustnessRow> rows;
  try {
    rows = parse_robustness_csv(text, shown(path));
  } catch (const std::runtime_error& e) {
    throw ShardError(e.what());
  }
  if (static_cast<int64_t>(rows.size()) != shard.rows) {
    throw ShardError(shown(path) + ": " + std::to_string(rows.size()) + " rows, shard " +
                     std::to_string(shard.index) + "/" + std::to_string(shard.count) + " has " +
                     std::to_string(shard.rows));
  }
  const int64_t per_dt = shard.starts;
  const int64_t per_config = per_dt * static_cast<int64_t>(shard.dts.size());
  const int64_t per_scenario = per_config * static_cast<int64_t>(shard.configs.size());
  for (size_t k = 0; k < rows.size(); ++k) {
    const RobustnessRow& r = rows[k];
    const std::string where = shown(path) + ":" + std::to_string(k + 2);
    auto fail = [&](const std::string& what) -> void { throw ShardError(where + ": " + what); };
    const int64_t job = shard.index + static_cast<int64_t>(k) * shard.count;
    if (r.job != job) {
      fail("job " + std::to_string(r.job) + " where shard " + std::to_string(shard.index) + "/" +
           std::to_string(shard.count) + " has job " + std::to_string(job));
    }
    const std::string config = r.rule.empty() ? r.solver : r.solver + ":" + r.rule;
    if (r.scenario != shard.scenarios[job / per_scenario] ||
        config != shard.configs[(job % per_scenario) / per_config] ||
        format_dt(r.dt) != shard.dts[(job % per_config) / per_dt] || r.seed != shard.seed ||
        r.start != job % per_dt) {
      fail("job " + std::to_string(job) + " is not the run its sweep numbers so (scenario " +
           shown(r.scenario) + ", " + shown(config) + ", dt " + format_dt(r.dt) + ", seed " +
           std::to_string(r.seed) + ", start " + std::to_string(r.start) + ")");
    }
    const double inputs[] = {r.tilt_deg,
                             r.hz,
                             r.phase_deg,
                             r.grab_point.x(),
                             r.grab_point.y(),
                             r.grab_point.z(),
                             r.joint_angle_rms_deg,
                             r.joint_speed_rms};
    for (double v : inputs) {
      if (std::isinf(v)) fail("an infinite start input");
    }
    if (static_cast<uint64_t>(r.steps) > kMaxSteps) fail("more steps than any run takes");
    const bool plain_reason = std::all_of(r.reason.begin(), r.reason.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || c == ' ' || c == '-';
    });
    if (r.diverged) {
      if (r.reason.empty() || !plain_reason || !std::isfinite(r.diverged_at) ||
          r.diverged_at < 0.0) {
        fail("a diverged run without a reason and a finite time");
      }
    } else {
      if (!r.reason.empty() || !std::isnan(r.diverged_at) || r.steps < 1 ||
          !std::isfinite(r.peak_speed) || !std::isfinite(r.joint_gap_max) ||
          !std::isfinite(r.pin_gap_max)) {
        fail("an ok run needs finite metrics, a step and no divergence");
      }
    }
  }
  return rows;
}

void check_shard_set(const std::vector<ShardManifest>& shards) {
  if (shards.empty()) throw ShardError("no shards");
  const ShardManifest& first = shards.front();
  std::map<int64_t, const ShardManifest*> by_index;
  for (const ShardManifest& shard : shards) {
    if (shard.identity() != first.identity()) {
      throw ShardError(shown(shard.folder) + " is a shard of another sweep than " +
                       shown(first.folder) + " (their shard.txt identities differ)");
    }
    if (!by_index.emplace(shard.index, &shard).second) {
      throw ShardError(shown(shard.folder) + " and " + shown(by_index[shard.index]->folder) +
                       " are both shard " + std::to_string(shard.index) + "/" +
                       std::to_string(shard.count));
    }
  }
  // count is at most kMaxShards: the loop is bounded
  std::string missing;
  int64_t missing_count = 0;
  for (int64_t i = 0; i < first.count; ++i) {
    if (by_index.count(i)) continue;
    if (++missing_count <= 10) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
  }
  if (missing_count > 0) {
    throw ShardError(std::to_string(missing_count) + " of " + std::to_string(first.count) +
                     " shards missing: " + missing + (missing_count > 10 ? ", ..." : ""));
  }
}

bool split_shell_words(const std::string& text, std::vector<std::string>* words) {
  words->clear();
  size_t i = 0;
  while (i < text.size()) {
    if (text[i] == ' ') {
      ++i;
      continue;
    }
    std::string word;
    bool quoted = false;
    while (i < text.size() && text[i] != ' ') {
      if (text.compare(i, 2, "\\'") == 0) {  // '\'' puts a quote inside a quoted word
        word += '\'';
        i += 2;
        quoted = true;
      } else if (text[i] == '\'') {
        const size_t close = text.find('\'', i + 1);
        if (close == std::string::npos) return false;
        word += text.substr(i + 1, close - i - 1);
        i = close + 1;
        quoted = true;
      } else {
        const char c = text[i];
        if (!(std::isalnum(static_cast<unsigned char>(c)) ||
              std::string("_./:=,+-").find(c) != std::string::npos)) {
          return false;  // what a shell would read otherwise: $, `, ;, \, ", ...
        }
        word += c;
        ++i;
      }
    }
    if (word.empty() && !quoted) return false;
    words->push_back(word);
  }
  return true;
}

}  // namespace puppet::compare
