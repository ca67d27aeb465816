// A stop that stops (harness/src/cancel.cpp, through the command): a signal at any moment leaves
// the old results or the new, a long engine step is ended within a second, a second signal ends the
// command at once
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

// SIGINT and SIGTERM stop a run within a second; the folder keeps the old results, whole, and
// nothing else is left behind
TEST(TestbedCli, InterruptedRunsLeaveTheOldResults) {
  for (const int signal : {SIGINT, SIGTERM}) {
    const fs::path out = folder_with_results("interrupted");
    const std::string before = read_all(out / "summary.csv");
    const size_t traces_before = std::distance(fs::directory_iterator(out / "traces"), {});
    const Child child = start(long_run(out));
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // well into the truths
    ::kill(child.pid, signal);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status)) << "still running a second after signal " << signal;
    EXPECT_EQ(status, 128 + signal);
    EXPECT_EQ(read_all(out / "summary.csv"), before);
    EXPECT_EQ(static_cast<size_t>(std::distance(fs::directory_iterator(out / "traces"), {})),
              traces_before);
    EXPECT_TRUE(leftovers(out).empty()) << leftovers(out).front();
    fs::remove_all(out);
  }
}

// a merge that is stopped, reading its shards or writing the merged files, ends within a second
// with 128 + the signal and writes nothing (a shard of 400,000 valid rows takes it seconds)
TEST(TestbedCli, AMergeStopsAtASignalAndWritesNothing) {
  const fs::path root = fresh_folder("merge_signal");
  fs::create_directories(root / "s0");
  const int64_t runs = 400000;
  std::string csv =
      "job,scenario,solver,rule,dt,seed,start,tilt_deg,hz,phase_deg,grab_segment,grab_x,grab_y,"
      "grab_z,joint_angle_rms_deg,joint_speed_rms,status,reason,diverged_at_s,peak_speed_mps,"
      "joint_gap_max_m,pin_gap_max_m,steps\n";
  for (int64_t job = 0; job < runs; ++job) {
    const std::string n = std::to_string(job);
    csv +=
        n + ",hang,bullet-rigid,,0.0166666667,1," + n + ",10,,,,,,,5,0.5,ok,,,1.5,0.001,0.002,30\n";
  }
  write_text(root / "s0" / "robustness.csv", csv);
  write_text(root / "s0" / "shard.txt",
             "puppet robustness shard\nmodel: pinocchio\nscenarios: hang\nconfigs: bullet-rigid\n"
             "dts: 0.0166666667\nstarts: 400000\nseed: 1\nreplay: \ncode: unknown\nshard: 0/1\n"
             "jobs: 400000\nrows: 400000\ncsv: " +
                 std::to_string(csv.size()) + " " + fnv1a(csv) + "\n");
  for (const int signal : {SIGINT, SIGTERM}) {
    const fs::path out = root / "merged";
    const Child child = start({"merge", (root / "s0").string(), "--out", out.string()});
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(child.pid, signal);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status)) << "still running a second after signal " << signal;
    EXPECT_EQ(status, 128 + signal);
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(leftovers(out).empty()) << leftovers(out).front();
  }
  // undisturbed, the same merge succeeds: the signal, not the shard, stopped it
  const Outcome merged =
      testbed("merge " + (root / "s0").string() + " --out " + (root / "merged").string());
  EXPECT_EQ(merged.status, 0) << merged.output;
  fs::remove_all(root);
}

// while a model loads (chain:100000 takes seconds to build and check) nothing has been written:
// a signal ends the command at once with 128 + the signal
TEST(TestbedCli, ACommandLoadingAModelStopsAtASignal) {
  for (const int signal : {SIGINT, SIGTERM}) {
    const Child child = start({"validate", "chain:100000"});
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto sent = std::chrono::steady_clock::now();
    ::kill(child.pid, signal);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status)) << "still loading a second after signal " << signal;
    EXPECT_EQ(status, 128 + signal);
    EXPECT_LT(std::chrono::steady_clock::now() - sent, std::chrono::seconds(1));
  }
}

// A step that does not return (Bullet cannot be asked to stop inside one) is not waited for: the
// process ends within a second of SIGINT or SIGTERM
TEST(TestbedCli, ALongEngineStepStopsWithinASecond) {
  for (const int signal : {SIGINT, SIGTERM}) expect_a_long_step_stopped("long_step", {signal}, 1.0);
}

// A second signal ends the process at once: well inside the grace the first one gives
// (compare::kStopGraceSeconds, 0.5 s)
TEST(TestbedCli, ASecondSignalEndsTheCommandAtOnce) {
  expect_a_long_step_stopped("second_signal", {SIGINT, SIGINT}, 0.3);
}

// A signal at any moment of a run (its truths, its runs, its writing, its swap) leaves the old
// results or the new ones whole, within a second, and nothing beside them
TEST(TestbedCli, ASignalAtAnyMomentLeavesTheOldResultsOrTheNew) {
  const std::vector<std::string> run = {"run",        "--scenario", "spin", "--solver",
                                        "procedural", "--rule",     "xpbd", "--dt",
                                        "1/240",      "--duration", "0.5",  "--no-timing"};
  int old_kept = 0, new_written = 0;
  for (int at_ms = 20; at_ms <= 2000; at_ms += 180) {
    const fs::path out = folder_with_results("any_moment");
    const std::string before = read_all(out / "summary.csv");
    std::vector<std::string> arguments = run;
    arguments.insert(arguments.end(), {"--out", out.string()});
    const Child child = start(arguments);
    std::this_thread::sleep_for(std::chrono::milliseconds(at_ms));
    ::kill(child.pid, at_ms % 360 == 20 ? SIGINT : SIGTERM);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status))
        << "still running a second after the signal, at " << at_ms << " ms";
    const std::string after = read_all(out / "summary.csv");
    if (status == 0) {
      ++new_written;
      EXPECT_NE(after.find("\nspin,"), std::string::npos) << at_ms;
      EXPECT_EQ(after.find("\nhang,"), std::string::npos) << at_ms;
    } else {
      ++old_kept;
      EXPECT_TRUE(status == 128 + SIGINT || status == 128 + SIGTERM) << status;
      EXPECT_EQ(after, before) << at_ms;
    }
    EXPECT_TRUE(leftovers(out).empty()) << at_ms << " ms: " << leftovers(out).front();
    fs::remove_all(out);
  }
  EXPECT_GT(old_kept, 0);  // the signals fell inside runs, not only after them
}

}  // namespace
}  // namespace puppet::cli_test
