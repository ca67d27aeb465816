#include "puppet/compare/cancel.h"

#include <semaphore.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstring>
#include <string>
#include <thread>

namespace puppet::compare {
namespace {

std::atomic<int> g_signal{0};
std::atomic<int> g_signals{0};        // how many signals asked
std::atomic<bool> g_watching{false};  // the watchdog waits on its semaphore

// What the watchdog reads, made once and never destroyed: it may wake while the process exits,
// after static objects are gone. The paths to remove before a forced exit sit in a fixed table,
// so that registering allocates only the path and the watchdog never meets a table resized.
constexpr int kSlots = 256;
struct Watch {
  sem_t wake;  // posted by request_cancel (sem_post is async-signal-safe)
  std::once_flag started;
  std::mutex commit;
  std::mutex tidy_mutex;
  std::array<std::filesystem::path, kSlots> tidy;
  std::array<bool, kSlots> used{};
};
Watch& watch_state() {
  static Watch* const state = new Watch;
  return *state;
}

void tidy_all() {
  Watch& w = watch_state();
  const std::lock_guard<std::mutex> lock(w.tidy_mutex);
  for (size_t i = 0; i < kSlots; ++i) {
    if (!w.used[i]) continue;
    // a folder that a running job may still be filling: tried again until it is gone
    for (int attempt = 0; attempt < 5; ++attempt) {
      std::error_code error;
      std::filesystem::remove_all(w.tidy[i], error);
      if (!error) break;
    }
  }
}

void write_line(const std::string& line) {
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line.data(), line.size());
}

[[noreturn]] void watch(std::string program) {
  while (::sem_wait(&watch_state().wake) != 0) {
  }
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(kStopGraceSeconds);
  while (g_signals.load() < 2 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // the command did not end by itself: a step that does not return, or a second signal
  const std::unique_lock<std::mutex> commit(watch_state().commit);
  tidy_all();
  const int signal = g_signal.load();
  const char* name = signal == SIGTERM ? "SIGTERM" : "SIGINT";
  write_line("\n" + program + ": stopped by " + (g_signals.load() >= 2 ? "a second " : "") + name +
             (g_signals.load() >= 2 ? "" : " (a step had not returned)") +
             "; the output folder is as it was\n");
  ::_exit(128 + signal);
}

}  // namespace

// atomics and sem_post only: safe in a signal handler
void request_cancel(int signal) {
  if (g_signals.fetch_add(1) == 0) g_signal.store(signal);
  cancel_flag().store(true);
  if (g_watching.load()) ::sem_post(&watch_state().wake);
}

int cancel_signal() { return g_signal.load(); }

void clear_cancel() {
  cancel_flag().store(false);
  g_signal.store(0);
  g_signals.store(0);
}

void start_stop_watchdog(const char* program) {
  Watch& w = watch_state();
  std::call_once(w.started, [&w, program] {
    ::sem_init(&w.wake, 0, 0);
    std::thread(watch, std::string(program)).detach();
    g_watching.store(true);
  });
}

std::unique_lock<std::mutex> commit_guard() {
  return std::unique_lock<std::mutex>(watch_state().commit);
}

TidyPath::TidyPath(std::filesystem::path path) {
  Watch& w = watch_state();
  const std::lock_guard<std::mutex> lock(w.tidy_mutex);
  for (size_t i = 0; i < kSlots; ++i) {
    if (w.used[i]) continue;
    w.tidy[i] = std::move(path);
    w.used[i] = true;
    slot_ = static_cast<int>(i);
    return;
  }
  // more than kSlots at once: this one is not tidied by a forced exit (a crash's leftovers,
  // which the next command on the folder removes)
}

void TidyPath::release() {
  if (slot_ < 0) return;
  Watch& w = watch_state();
  const std::lock_guard<std::mutex> lock(w.tidy_mutex);
  w.used[static_cast<size_t>(slot_)] = false;
  w.tidy[static_cast<size_t>(slot_)].clear();
  slot_ = -1;
}

TidyPath::~TidyPath() { release(); }

}  // namespace puppet::compare
