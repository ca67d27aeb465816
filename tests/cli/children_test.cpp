// No child outlives its command by more than a second (docs/reliability.md, "No orphan"): the
// jolt engine's node drivers end with the testbed however it ends (SIGINT, SIGTERM, SIGKILL),
// whether the driver is computing steps ahead, stopped, or killed. This process adopts what the
// testbed leaves behind (PR_SET_CHILD_SUBREAPER), so an orphan is one of its children to count.
#include <sys/prctl.h>

#include <cstring>
#include <sstream>

#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

// the live (not zombie) processes whose parent is `parent` and whose command line holds `what`
std::vector<pid_t> children_of(pid_t parent, const std::string& what) {
  std::vector<pid_t> out;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = read_all(entry.path() / "stat");
    const auto close = stat.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream fields(stat.substr(close + 2));
    char state = 0;
    pid_t ppid = 0;
    fields >> state >> ppid;
    if (ppid != parent || state == 'Z') continue;
    if (read_all(entry.path() / "cmdline").find(what) != std::string::npos) {
      out.push_back(std::stoi(name));
    }
  }
  return out;
}

// reaps what this process adopted, and says whether `pid` still lives
bool alive(pid_t pid) {
  int status = 0;
  if (::waitpid(pid, &status, WNOHANG) == pid) return false;
  const std::string stat = read_all(fs::path("/proc") / std::to_string(pid) / "stat");
  const auto close = stat.rfind(')');
  return close != std::string::npos && stat[close + 2] != 'Z';
}

class Children : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(::prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0), 0) << std::strerror(errno);
    const Outcome jolt = testbed("validate pinocchio");
    if (jolt.output.find("not jolt") != std::string::npos ||
        jolt.output.find(", jolt") == std::string::npos) {
      GTEST_SKIP() << "jolt is not built here";
    }
  }

  // a long jolt run, its driver stepping ahead (the command has made its staging folder, so the
  // driver is the run's, not the one that answered the engine's check); the driver's pid
  pid_t start_long_run(const fs::path& out, Child* testbed_child) {
    *testbed_child =
        start({"run", "--model", "chain:60", "--solver", "jolt", "--scenario", "shake", "--dt",
               "1/960", "--duration", "60", "--no-accuracy", "--no-timing", "--out", out.string()});
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < until) {
      const std::vector<pid_t> drivers = children_of(testbed_child->pid, "server.mjs");
      if (!drivers.empty() && !leftovers(out).empty()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));  // stepping by now
        return drivers.front();
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }

  // the testbed ends on `signals` (sent in turn) and its driver is gone within a second of it
  void expect_no_orphan(const std::string& name, const std::vector<int>& signals,
                        bool stop_driver_first) {
    const fs::path out = fresh_folder("children_" + name);
    Child child;
    const pid_t driver = start_long_run(out, &child);
    ASSERT_GT(driver, 0) << name << ": no driver started";
    if (stop_driver_first) ::kill(driver, SIGSTOP);
    for (int signal : signals) ::kill(child.pid, signal);
    int status = 0;
    ASSERT_TRUE(child.wait(5.0, &status)) << name;
    EXPECT_EQ(status, 128 + signals.front()) << name;
    const auto ended = std::chrono::steady_clock::now();
    while (alive(driver) && std::chrono::steady_clock::now() - ended < std::chrono::seconds(1)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const bool left = alive(driver);
    if (left) ::kill(driver, SIGKILL);
    EXPECT_FALSE(left) << name << ": the driver outlived the testbed by more than 1 s";
    // (SIGKILL leaves its staging folder, which the next command on the folder removes)
    if (signals.front() != SIGKILL) {
      EXPECT_TRUE(leftovers(out).empty()) << name;
    }
    fs::remove_all(out);
  }
};

TEST_F(Children, NoDriverOutlivesAnInterruptedRun) {
  expect_no_orphan("sigint", {SIGINT}, false);
  expect_no_orphan("sigterm", {SIGTERM}, false);
}

TEST_F(Children, NoDriverOutlivesAKilledTestbed) { expect_no_orphan("sigkill", {SIGKILL}, false); }

// a stopped driver never answers: the stop watchdog ends the testbed, and the driver with it
TEST_F(Children, NoStoppedDriverOutlivesItsTestbed) { expect_no_orphan("stopped", {SIGINT}, true); }

// a driver killed under a run is that run's divergence; the command goes on and writes its results
TEST_F(Children, AKilledDriverIsThatRunsDivergence) {
  const fs::path out = fresh_folder("children_killed_driver");
  Child child;
  const pid_t driver = start_long_run(out, &child);
  ASSERT_GT(driver, 0);
  ::kill(driver, SIGKILL);
  int status = 0;
  ASSERT_TRUE(child.wait(60.0, &status));
  EXPECT_EQ(status, 0);
  EXPECT_NE(read_all(out / "summary.csv").find("shake,jolt,,0.00104166667,1,diverged_at_s"),
            std::string::npos);
  fs::remove_all(out);
}

}  // namespace
}  // namespace puppet::cli_test
