// A Node.js script run as a child process that answers one JSON line per request line, some
// answers followed by bytes (the jolt engine's driver, reference/jolt/server.mjs). Blocking, with
// a deadline on every answer, so that a driver that hangs or dies is an error, never a hang.
//
// No child outlives the process that started it (docs/reliability.md): each is started by one
// thread that lasts as long as the process, with PR_SET_PDEATHSIG set to SIGKILL, so that the
// kernel kills it when that process ends for any reason (a signal, the stop watchdog's _exit, a
// crash, a Python interpreter killed); it runs in a process group of its own, so that a
// terminal's Ctrl-C reaches the testbed, which decides when it ends; and its end is waited for
// at most kEndGraceSeconds before it is killed and reaped. Node's own output (a stack trace) goes
// to a log file, made when there is something to write and named in the one-line error.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace puppet::compare {

class NodeProcess {
 public:
  // how long a driver whose input has ended may take to end itself before it is killed
  static constexpr double kEndGraceSeconds = 0.2;

  // starts `node script`; throws std::runtime_error when it cannot
  NodeProcess(const std::string& node, const std::string& script);
  // closes the driver's input and reaps it, killed if it has not ended within kEndGraceSeconds
  ~NodeProcess();
  NodeProcess(const NodeProcess&) = delete;
  NodeProcess& operator=(const NodeProcess&) = delete;

  // writes `line` and a newline, then reads the answer's line (without its newline); false when
  // the process died, hung past `deadline` or wrote something else: `error` then says what
  bool request(const std::string& line, std::string& answer, std::chrono::seconds deadline);
  // reads `bytes` more bytes of the last answer into `out`
  bool read_bytes(size_t bytes, std::vector<char>& out, std::chrono::seconds deadline);
  // whether it still answers (no request failed), in the process that started it
  bool healthy() const;
  const std::string& error() const { return error_; }
  // the driver's process id (tests count children by it)
  pid_t pid() const { return pid_; }

  // forgets the driver without ending it: for a process forked after it started, whose driver
  // is its parent's (the descriptors are closed, the process is neither signalled nor waited for)
  void abandon();

 private:
  bool write_all(const std::string& data);
  // fills buffer_ with more of the child's output before the deadline
  bool fill(std::chrono::steady_clock::time_point until);
  // reads what node wrote on its error stream, without waiting (up to `wait` once it ended)
  void drain_errors(std::chrono::milliseconds wait);
  void fail(std::string why);

  pid_t pid_ = -1;
  pid_t owner_ = -1;  // the process that started it
  int to_child_ = -1;
  int from_child_ = -1;
  int errors_ = -1;     // node's stderr
  std::string buffer_;  // read and not yet consumed
  std::string stderr_;  // the last of node's stderr, kept for the log (bounded)
  bool healthy_ = true;
  std::string error_;
};

}  // namespace puppet::compare
