// Stopping a command early, for SIGINT and SIGTERM.
#pragma once

#include <atomic>
#include <stdexcept>

namespace puppet::compare {

// Cancellation, for SIGINT and SIGTERM: the handler calls request_cancel() (async-signal-safe);
// every run loop calls throw_if_cancelled() once per step, which throws Cancelled.
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

}  // namespace puppet::compare
