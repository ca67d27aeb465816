#include "node_process.h"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace puppet::compare {
namespace {

// the most of node's error stream kept for its log (a stack trace is a few kB)
constexpr size_t kMaxErrorBytes = 64 << 10;

// a write to a pipe whose reader is gone raises SIGPIPE, which would end the testbed: it is
// blocked on this thread for the write, and one it raised is taken before unblocking
class SigpipeBlocked {
 public:
  SigpipeBlocked() {
    sigemptyset(&pipe_);
    sigaddset(&pipe_, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_, &old_);
  }
  ~SigpipeBlocked() {
    const timespec zero{0, 0};
    while (sigtimedwait(&pipe_, nullptr, &zero) > 0) {
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }

 private:
  sigset_t pipe_{}, old_{};
};

// What a child is started with: every string and descriptor is ready before the fork, so that
// the child calls nothing but async-signal-safe functions until it executes node.
struct Launch {
  char* const* argv = nullptr;
  int in = -1, out = -1, err = -1;  // the child's stdin, stdout and stderr
  pid_t parent = -1;
  pid_t pid = -1;
  int error = 0;  // errno of a failed fork
  bool done = false;
};

[[noreturn]] void become_driver(const Launch& launch) {
  // killed when the spawner thread ends, which is when the process ends
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != launch.parent) _exit(127);  // the process ended before the line above
  setpgid(0, 0);  // its own group: a terminal's Ctrl-C reaches the testbed alone
  // signals the testbed blocks or handles are the defaults again in the driver
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  signal(SIGPIPE, SIG_DFL);
  if (dup2(launch.in, 0) < 0 || dup2(launch.out, 1) < 0 || dup2(launch.err, 2) < 0) _exit(127);
  execve(launch.argv[0], launch.argv, environ);
  _exit(127);
}

// One thread for the life of the process starts every driver: PR_SET_PDEATHSIG fires when the
// thread that forked the child ends, and the testbed's worker threads come and go. A process
// forked from this one (Python's os.fork) has no such thread: its first launch makes its own.
class Spawner {
 public:
  Spawner() : thread_([this] { serve(); }) { thread_.detach(); }

  void launch(Launch& job) {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [&] { return job_ == nullptr; });
    job_ = &job;
    wake_.notify_all();
    idle_.wait(lock, [&] { return job.done; });
  }

 private:
  void serve() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return job_ != nullptr; });
      Launch& job = *job_;
      job.pid = fork();
      if (job.pid == 0) become_driver(job);
      if (job.pid < 0) job.error = errno;
      job.done = true;
      job_ = nullptr;
      idle_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, idle_;
  Launch* job_ = nullptr;
  std::thread thread_;
};

Spawner* g_spawner = nullptr;
std::mutex g_spawner_mutex;

Spawner& spawner() {
  static std::once_flag registered;
  // in a forked child the parent's spawner thread does not exist and its locks may be held:
  // the child forgets it (leaked, not destroyed) and makes its own when it first needs one
  std::call_once(registered, [] {
    pthread_atfork(nullptr, nullptr, [] {
      g_spawner = nullptr;
      new (&g_spawner_mutex) std::mutex;
    });
  });
  std::lock_guard lock(g_spawner_mutex);
  if (g_spawner == nullptr) g_spawner = new Spawner;
  return *g_spawner;
}

void close_pair(int fds[2]) {
  close(fds[0]);
  close(fds[1]);
}

}  // namespace

NodeProcess::NodeProcess(const std::string& node, const std::string& script) {
  int in[2], out[2], err[2];
  if (pipe2(in, O_CLOEXEC) != 0) {
    throw std::runtime_error("jolt: pipe: " + std::string(strerror(errno)));
  }
  if (pipe2(out, O_CLOEXEC) != 0) {
    close_pair(in);
    throw std::runtime_error("jolt: pipe: " + std::string(strerror(errno)));
  }
  if (pipe2(err, O_CLOEXEC) != 0) {
    close_pair(in);
    close_pair(out);
    throw std::runtime_error("jolt: pipe: " + std::string(strerror(errno)));
  }
  std::vector<char*> argv = {const_cast<char*>(node.c_str()), const_cast<char*>(script.c_str()),
                             nullptr};
  Launch launch;
  launch.argv = argv.data();
  launch.in = in[0];
  launch.out = out[1];
  launch.err = err[1];
  launch.parent = getpid();
  spawner().launch(launch);
  close(in[0]);
  close(out[1]);
  close(err[1]);
  to_child_ = in[1];
  from_child_ = out[0];
  errors_ = err[0];
  if (launch.pid < 0) {
    close(to_child_);
    close(from_child_);
    close(errors_);
    throw std::runtime_error("jolt: cannot start " + node + ": " + strerror(launch.error));
  }
  pid_ = launch.pid;
  owner_ = launch.parent;
  // node's error stream is read as it comes, so that a chatty driver never blocks on it
  fcntl(errors_, F_SETFL, fcntl(errors_, F_GETFL) | O_NONBLOCK);
}

NodeProcess::~NodeProcess() {
  if (owner_ != getpid()) {  // another process's driver (this one was forked): not ours to end
    abandon();
    return;
  }
  for (int fd : {to_child_, from_child_, errors_}) {  // an idle driver ends at the end of its input
    if (fd >= 0) close(fd);
  }
  if (pid_ <= 0) return;
  // a busy, stopped or looping driver does not: it is killed once the grace is over
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::microseconds(static_cast<long>(kEndGraceSeconds * 1e6));
  int status = 0;
  for (;;) {
    const pid_t ended = waitpid(pid_, &status, WNOHANG);
    if (ended == pid_ || (ended < 0 && errno != EINTR)) return;
    if (!healthy_ || std::chrono::steady_clock::now() >= until) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(pid_, SIGKILL);
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
}

void NodeProcess::abandon() {
  for (int* fd : {&to_child_, &from_child_, &errors_}) {
    if (*fd >= 0) close(*fd);
    *fd = -1;
  }
  pid_ = -1;
  healthy_ = false;
}

bool NodeProcess::healthy() const { return healthy_ && owner_ == getpid(); }

void NodeProcess::drain_errors(std::chrono::milliseconds wait) {
  if (errors_ < 0) return;
  const auto until = std::chrono::steady_clock::now() + wait;
  char chunk[4096];
  for (;;) {
    const ssize_t n = read(errors_, chunk, sizeof chunk);
    if (n > 0) {
      stderr_.append(chunk, static_cast<size_t>(n));
      if (stderr_.size() > kMaxErrorBytes) stderr_.erase(0, stderr_.size() - kMaxErrorBytes);
      continue;
    }
    if (n == 0) {  // node's end of the pipe is closed: nothing more will come
      close(errors_);
      errors_ = -1;
      return;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN || std::chrono::steady_clock::now() >= until) return;
    pollfd ready{errors_, POLLIN, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        until - std::chrono::steady_clock::now());
    poll(&ready, 1, static_cast<int>(std::max<long long>(left.count(), 0)));
  }
}

void NodeProcess::fail(std::string why) {
  if (!healthy_) return;
  healthy_ = false;
  // what node said before it failed (a stack trace) goes to a log the line names, never to the
  // testbed's own stderr
  drain_errors(std::chrono::milliseconds(100));
  if (!stderr_.empty()) {
    const char* folder = std::getenv("TMPDIR");
    std::string path =
        std::string(folder && *folder ? folder : "/tmp") + "/puppet-jolt-driver-XXXXXX.log";
    const int log = mkostemps(path.data(), 4, O_CLOEXEC);
    if (log >= 0) {
      const ssize_t written = write(log, stderr_.data(), stderr_.size());
      close(log);
      if (written == static_cast<ssize_t>(stderr_.size())) why += " (node's output: " + path + ")";
    }
  }
  error_ = std::move(why);
}

bool NodeProcess::write_all(const std::string& data) {
  SigpipeBlocked blocked;
  size_t written = 0;
  while (written < data.size()) {
    const ssize_t n = write(to_child_, data.data() + written, data.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      fail("the driver stopped reading (" + std::string(strerror(errno)) + ")");
      return false;
    }
    written += static_cast<size_t>(n);
  }
  return true;
}

bool NodeProcess::fill(std::chrono::steady_clock::time_point until) {
  char chunk[1 << 16];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        until - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      fail("the driver did not answer in time");
      return false;
    }
    pollfd wait[2] = {{from_child_, POLLIN, 0}, {errors_, POLLIN, 0}};
    const int ready = poll(wait, 2, static_cast<int>(std::min<long long>(left.count(), 1 << 30)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
    if (wait[1].revents != 0) drain_errors(std::chrono::milliseconds(0));
    if (wait[0].revents == 0) continue;
    const ssize_t n = read(from_child_, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      fail("the driver ended");
      return false;
    }
    buffer_.append(chunk, static_cast<size_t>(n));
    return true;
  }
}

bool NodeProcess::request(const std::string& line, std::string& answer,
                          std::chrono::seconds deadline) {
  if (owner_ != getpid()) {
    if (healthy_) error_ = "the driver belongs to the process this one was forked from";
    healthy_ = false;
    return false;
  }
  if (!healthy_) return false;
  if (!write_all(line + '\n')) return false;
  const auto until = std::chrono::steady_clock::now() + deadline;
  size_t end;
  while ((end = buffer_.find('\n')) == std::string::npos) {
    if (!fill(until)) return false;
  }
  answer.assign(buffer_, 0, end);
  buffer_.erase(0, end + 1);
  return true;
}

bool NodeProcess::read_bytes(size_t bytes, std::vector<char>& out, std::chrono::seconds deadline) {
  if (!healthy()) return false;
  const auto until = std::chrono::steady_clock::now() + deadline;
  while (buffer_.size() < bytes) {
    if (!fill(until)) return false;
  }
  out.assign(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(bytes));
  buffer_.erase(0, bytes);
  return true;
}

}  // namespace puppet::compare
