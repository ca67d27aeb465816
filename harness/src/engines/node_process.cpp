#include "node_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace puppet::compare {
namespace {

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

}  // namespace

NodeProcess::NodeProcess(const std::string& node, const std::string& script) {
  int in[2], out[2];
  if (pipe2(in, O_CLOEXEC) != 0)
    throw std::runtime_error("jolt: pipe: " + std::string(strerror(errno)));
  if (pipe2(out, O_CLOEXEC) != 0) {
    close(in[0]);
    close(in[1]);
    throw std::runtime_error("jolt: pipe: " + std::string(strerror(errno)));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  std::vector<char*> argv = {const_cast<char*>(node.c_str()), const_cast<char*>(script.c_str()),
                             nullptr};
  const int status = posix_spawn(&pid_, node.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(in[0]);
  close(out[1]);
  to_child_ = in[1];
  from_child_ = out[0];
  if (status != 0) {
    close(to_child_);
    close(from_child_);
    throw std::runtime_error("jolt: cannot start " + node + ": " + strerror(status));
  }
}

NodeProcess::~NodeProcess() {
  close(to_child_);  // the driver ends at the end of its input
  close(from_child_);
  if (pid_ > 0) {
    if (!healthy_) kill(pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

void NodeProcess::fail(std::string why) {
  if (healthy_) error_ = std::move(why);
  healthy_ = false;
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
    pollfd wait{from_child_, POLLIN, 0};
    const int ready = poll(&wait, 1, static_cast<int>(std::min<long long>(left.count(), 1 << 30)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;
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
  if (!healthy_) return false;
  const auto until = std::chrono::steady_clock::now() + deadline;
  while (buffer_.size() < bytes) {
    if (!fill(until)) return false;
  }
  out.assign(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(bytes));
  buffer_.erase(0, bytes);
  return true;
}

}  // namespace puppet::compare
