// What the command line's tests share: running the testbed binary (and a shell), fresh
// folders, shards to merge and edit, children to signal, models whose steps take long.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace puppet::cli_test {

namespace fs = std::filesystem;

struct Outcome {
  int status;
  std::string output;  // stdout and stderr
};

// a shell command line's status and what it printed on standard output
inline Outcome shell(const std::string& command) {
  Outcome outcome{-1, ""};
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return outcome;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) outcome.output += buffer.data();
  const int raw = pclose(pipe);
  outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return outcome;
}

inline Outcome testbed(const std::string& arguments) {
  return shell(std::string(TESTBED_BINARY) + " " + arguments + " 2>&1");
}

inline fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / ("testbed_cli_" + name);
  fs::remove_all(folder);
  return folder;
}

// exit 2 with one line that names the flag or file
inline void expect_bad(const std::string& arguments, const std::string& names) {
  const Outcome o = testbed(arguments);
  EXPECT_EQ(o.status, 2) << arguments << "\n" << o.output;
  EXPECT_NE(o.output.find(names), std::string::npos) << arguments << "\n" << o.output;
  EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << arguments << "\n" << o.output;
  EXPECT_LE(o.output.size(), 401u) << "at most 400 characters, \"testbed: \" included\n"
                                   << o.output;
}

inline std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// "s" + the shard's index, built without operator+ (GCC 12's -Wrestrict misreads it)
inline std::string shard_name(const char* index) {
  std::string name = "s";
  name += index;
  return name;
}

// a small sweep: two scenarios, two solver configurations, two dts, 4 starts (32 runs)
inline const std::string kSweep =
    "robustness --model chain:4 --scenario hang,yank --solver procedural,bullet-rigid "
    "--rule xpbd --dt 1/60,1/120 --starts 4 --duration 0.5 --jobs 2";

// the small sweep as shards 0, 1 and 2 of 3, into FOLDER/s0, s1, s2, run in the order given
inline void run_shards(const fs::path& folder,
                       std::initializer_list<const char*> order = {"0", "1", "2"}) {
  for (const char* shard : order) {
    std::string arguments = kSweep;
    arguments += " --shard ";
    arguments += shard;
    arguments += "/3 --out " + (folder / shard_name(shard)).string();
    const Outcome o = testbed(arguments);
    ASSERT_EQ(o.status, 0) << o.output;
  }
}

// FNV-1a 64 of a file's bytes, as shard.txt's csv line gives it (written here again, to edit a
// shard as one who also rewrites its manifest would)
inline std::string fnv1a(const std::string& bytes) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : bytes) hash = (hash ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// shard.txt's line KEY set to VALUE
inline void edit_manifest(const fs::path& shard, const std::string& key, const std::string& value) {
  std::string text = slurp(shard / "shard.txt");
  const size_t at = text.find("\n" + key + ": ") + 1;
  const size_t end = text.find('\n', at);
  text.replace(at, end - at, key + ": " + value);
  write_text(shard / "shard.txt", text);
}

// robustness.csv's data row ROW (0 first), field FIELD set to VALUE, and the manifest's size and
// checksum made to match
inline void edit_row(const fs::path& shard, int row, int field, const std::string& value) {
  std::string text = slurp(shard / "robustness.csv");
  size_t at = text.find('\n') + 1;
  for (int k = 0; k < row; ++k) at = text.find('\n', at) + 1;
  for (int k = 0; k < field; ++k) at = text.find(',', at) + 1;
  const size_t end = text.find_first_of(",\n", at);
  text.replace(at, end - at, value);
  write_text(shard / "robustness.csv", text);
  edit_manifest(shard, "csv", std::to_string(text.size()) + " " + fnv1a(text));
}

// A testbed started in the background: its pid, and its exit status once it ends.
struct Child {
  pid_t pid = -1;
  // ends within `seconds` (true) or not; status is the exit code, or 128 + the signal
  bool wait(double seconds, int* status) const {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until) {
      int raw = 0;
      if (::waitpid(pid, &raw, WNOHANG) == pid) {
        *status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
};

// `file_limit` > 0: the child may write no file larger than that (a full disk, as it meets it)
inline Child start(const std::vector<std::string>& arguments, long file_limit = 0) {
  Child child;
  child.pid = ::fork();
  if (child.pid == 0) {
    if (file_limit > 0) {
      const rlimit limit{static_cast<rlim_t>(file_limit), static_cast<rlim_t>(file_limit)};
      ::setrlimit(RLIMIT_FSIZE, &limit);
      ::signal(SIGXFSZ, SIG_IGN);  // a write past it fails with EFBIG instead
    }
    std::vector<char*> argv{const_cast<char*>(TESTBED_BINARY)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(TESTBED_BINARY, argv.data());
    ::_exit(127);
  }
  return child;
}

inline std::string read_all(const fs::path& path) {
  std::ifstream file(path);
  return std::string((std::istreambuf_iterator<char>(file)), {});
}

// what a folder's parent holds beside the folder: the staging folders and locks of its commands
inline std::vector<std::string> leftovers(const fs::path& folder) {
  std::string prefix = ".";  // appended, not "." + name + ".": GCC 12's -Wrestrict misfires
  prefix += folder.filename().string();
  prefix += '.';
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(folder.parent_path())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0) out.push_back(name);
  }
  return out;
}

// a long run on a folder that already holds a short run's results
inline std::vector<std::string> long_run(const fs::path& out) {
  return {"run",  "--scenario", "all",   "--solver",    "procedural", "--rule",
          "tree", "--dt",       "1/480", "--no-timing", "--out",      out.string()};
}

inline fs::path folder_with_results(const std::string& name) {
  const fs::path out = fresh_folder(name);
  const Outcome first = testbed(
      "run --scenario hang --solver procedural --rule literal --duration 0.1 "
      "--no-accuracy --no-timing --out " +
      out.string());
  EXPECT_EQ(first.status, 0) << first.output;
  return out;
}

// a JSON chain of n spheres joined by ball joints, each limited to ±limit_deg about every axis of
// a box: at 1° every limit acts at once in shake, and one btMultiBody step of 300 links takes
// seconds (its rows span the whole tree)
inline fs::path limited_chain(const fs::path& folder, int n, double limit_deg) {
  std::string json = "{\"name\": \"limited\", \"segments\": [";
  for (int i = 0; i < n; ++i) {
    json += (i ? ", " : "") + std::string("{\"name\": \"s") + std::to_string(i) +
            "\", \"mass\": 1, \"position\": [0, 0, " + std::to_string(-0.1 * i) +
            "], \"orientation\": [1, 0, 0, 0], \"shape\": {\"type\": \"sphere\", "
            "\"radius\": 0.04}}";
  }
  json += "], \"joints\": [";
  const std::string d = std::to_string(limit_deg);
  for (int i = 1; i < n; ++i) {
    json += (i > 1 ? ", " : "") + std::string("{\"name\": \"j") + std::to_string(i) +
            "\", \"parent\": \"s" + std::to_string(i - 1) + "\", \"child\": \"s" +
            std::to_string(i) + "\", \"anchor\": [0, 0, " + std::to_string(-0.1 * i + 0.05) +
            "], \"type\": \"ball\", \"box_deg\": {\"order\": \"yxz\", \"lower\": [-" + d + ", -" +
            d + ", -" + d + "], \"upper\": [" + d + ", " + d + ", " + d + "]}}";
  }
  json += "]}";
  fs::create_directories(folder);
  const fs::path path = folder / ("limited" + std::to_string(n) + ".json");
  write_text(path, json);
  return path;
}

// a run of bullet-multibody on a 300-link chain whose limits all act: each step takes seconds,
// so a signal arrives inside one (--engine-budget lifts the engine's own refusal)
inline std::vector<std::string> long_step_run(const fs::path& model, const fs::path& out) {
  return {"run",      "--model",          model.string(), "--scenario",      "shake",
          "--solver", "bullet-multibody", "--dt",         "1/240",           "--duration",
          "1",        "--no-accuracy",    "--no-timing",  "--engine-budget", "1e9",
          "--out",    out.string()};
}

// A run inside a step that takes seconds, sent `signals` 20 ms apart: it ends within `seconds` of
// the last with 128 + the first, the old results whole and nothing left beside them
// (`name`: the test's own folders, since tests run side by side)
inline void expect_a_long_step_stopped(const std::string& name, const std::vector<int>& signals,
                                       double seconds) {
  const fs::path model = limited_chain(fresh_folder(name + "_model"), 300, 1.0);
  const fs::path out = folder_with_results(name);
  const std::string before = read_all(out / "summary.csv");
  const Child child = start(long_step_run(model, out));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // inside a step
  for (size_t k = 0; k < signals.size(); ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ::kill(child.pid, signals[k]);
  }
  int status = 0;
  ASSERT_TRUE(child.wait(seconds, &status))
      << "still running " << seconds << " s after " << signals.size() << " signal(s)";
  EXPECT_EQ(status, 128 + signals.front());
  EXPECT_EQ(read_all(out / "summary.csv"), before);
  EXPECT_TRUE(leftovers(out).empty()) << leftovers(out).front();
  fs::remove_all(out);
  fs::remove_all(model.parent_path());
}

}  // namespace puppet::cli_test
