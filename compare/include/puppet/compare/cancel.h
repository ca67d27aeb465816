// Stopping a command early, for SIGINT and SIGTERM.
#pragma once

#include <atomic>
#include <stdexcept>

namespace puppet::compare {

// Cancellation, for SIGINT and SIGTERM. Until a command has something to tidy (an output
// folder's staging, while a CancelPoint lives), a signal ends the process at once: nothing has
// been written, and reading a model or a shard need not look for it. After that, the handler
// calls request_cancel() (async-signal-safe); every run loop calls throw_if_cancelled() once per
// step, which throws Cancelled, and a folder is never committed after a signal.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};
void request_cancel(int signal);
int cancel_signal();  // the signal that asked, 0 when none
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

}  // namespace puppet::compare
