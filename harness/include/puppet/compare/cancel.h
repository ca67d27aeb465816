// Stopping a command early, for SIGINT and SIGTERM.
#pragma once

#include <atomic>
#include <filesystem>
#include <mutex>
#include <stdexcept>

namespace puppet::compare {

// Cancellation, for SIGINT and SIGTERM. Until a command has something to tidy (an output
// folder's staging, while a CancelPoint lives), a signal ends the process at once: nothing has
// been written, and reading a model or a shard need not look for it. After that, the handler
// calls request_cancel() (async-signal-safe); every run loop calls throw_if_cancelled() once per
// step, which throws Cancelled, and a folder is never committed after a signal.
//
// A step that does not return (one btMultiBody step of a large model can take seconds, and
// Bullet's solver cannot be asked to stop inside one) is not waited for: the stop watchdog, a
// thread started by start_stop_watchdog(), ends the process kStopGrace after the first signal,
// or at once after a second one. Before it does, it takes commit_guard() (so a folder is either
// swapped whole or not at all) and removes every path a TidyPath names (staging folders, locks,
// temporary files): the old results or the new, never a mix, and nothing left behind.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};
void request_cancel(int signal);  // async-signal-safe; the second call asks for the exit at once
int cancel_signal();              // the signal that asked, 0 when none
// forgets a request, for a host that runs commands one after another in one process (the Python
// package) and turns a stop into its own exception; never while a command runs
void clear_cancel();
inline std::atomic<bool>& cancel_flag() {
  static std::atomic<bool> flag{false};
  return flag;
}
inline void throw_if_cancelled() {
  if (cancel_flag().load(std::memory_order_relaxed)) throw Cancelled();
}

// whether a signal must be turned into Cancelled (something to tidy lives) rather than end the
// process at once; read by the signal handler, so a lock-free atomic count
inline std::atomic<int>& cancel_points() {
  static std::atomic<int> count{0};
  return count;
}
// while one lives, a signal is a request to stop (request_cancel), not the process's end
class CancelPoint {
 public:
  CancelPoint() { cancel_points().fetch_add(1); }
  ~CancelPoint() { cancel_points().fetch_sub(1); }
  CancelPoint(const CancelPoint&) = delete;
  CancelPoint& operator=(const CancelPoint&) = delete;
};

// how long after the first signal the watchdog waits for the command to stop by itself
inline constexpr double kStopGraceSeconds = 0.5;

// Starts the watchdog (once; later calls do nothing). `program` prefixes its one line, e.g.
// "testbed".
void start_stop_watchdog(const char* program);

// Held across anything that must not be cut in half by the watchdog's exit (a folder's swap).
std::unique_lock<std::mutex> commit_guard();

// While one lives, the watchdog removes `path` (a file, a link or a folder, whole) before it
// ends the process. release() forgets it early (the path was committed or removed).
class TidyPath {
 public:
  explicit TidyPath(std::filesystem::path path);
  ~TidyPath();
  void release();
  TidyPath(const TidyPath&) = delete;
  TidyPath& operator=(const TidyPath&) = delete;

 private:
  int slot_ = -1;
};

}  // namespace puppet::compare
