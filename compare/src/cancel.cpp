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
std::atomic<int> g_signals{0};  // how many signals asked

// posted by request_cancel (sem_post is async-signal-safe), waited for by the watchdog
sem_t g_wake;
std::once_flag g_started;

std::mutex g_commit;

// the paths to remove before a forced exit; a fixed table, so that registering never allocates
// more than the path itself and the watchdog never meets a table being resized
constexpr int kSlots = 256;
std::mutex g_tidy_mutex;
std::array<std::filesystem::path, kSlots> g_tidy;
std::array<bool, kSlots> g_tidy_used{};

void tidy_all() {
  const std::lock_guard<std::mutex> lock(g_tidy_mutex);
  for (int i = 0; i < kSlots; ++i) {
    if (!g_tidy_used[static_cast<size_t>(i)]) continue;
    // a folder that a running job may still be filling: tried again until it is gone
    for (int attempt = 0; attempt < 5; ++attempt) {
      std::error_code error;
      std::filesystem::remove_all(g_tidy[static_cast<size_t>(i)], error);
      if (!error) break;
    }
  }
}

void write_line(const std::string& line) {
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line.data(), line.size());
}

[[noreturn]] void watch(std::string program) {
  while (::sem_wait(&g_wake) != 0) {
  }
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(kStopGraceSeconds);
  while (g_signals.load() < 2 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // the command did not end by itself: a step that does not return, or a second signal
  const std::unique_lock<std::mutex> commit(g_commit);
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
  ::sem_post(&g_wake);
}

int cancel_signal() { return g_signal.load(); }

void start_stop_watchdog(const char* program) {
  std::call_once(g_started, [program] {
    ::sem_init(&g_wake, 0, 0);
    std::thread(watch, std::string(program)).detach();
  });
}

std::unique_lock<std::mutex> commit_guard() { return std::unique_lock<std::mutex>(g_commit); }

TidyPath::TidyPath(std::filesystem::path path) {
  const std::lock_guard<std::mutex> lock(g_tidy_mutex);
  for (int i = 0; i < kSlots; ++i) {
    if (g_tidy_used[static_cast<size_t>(i)]) continue;
    g_tidy[static_cast<size_t>(i)] = std::move(path);
    g_tidy_used[static_cast<size_t>(i)] = true;
    slot_ = i;
    return;
  }
  // more than kSlots at once: this one is not tidied by a forced exit (a crash's leftovers,
  // which the next command on the folder removes)
}

void TidyPath::release() {
  if (slot_ < 0) return;
  const std::lock_guard<std::mutex> lock(g_tidy_mutex);
  g_tidy_used[static_cast<size_t>(slot_)] = false;
  g_tidy[static_cast<size_t>(slot_)].clear();
  slot_ = -1;
}

TidyPath::~TidyPath() { release(); }

}  // namespace puppet::compare
