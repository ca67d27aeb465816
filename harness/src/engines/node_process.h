// A Node.js script run as a child process that answers one JSON line per request line, some
// answers followed by bytes (the jolt engine's driver, reference/jolt/server.mjs). Blocking, with
// a deadline on every answer, so that a driver that hangs or dies is an error, never a hang.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace puppet::compare {

class NodeProcess {
 public:
  // starts `node script`; throws std::runtime_error when it cannot
  NodeProcess(const std::string& node, const std::string& script);
  ~NodeProcess();
  NodeProcess(const NodeProcess&) = delete;
  NodeProcess& operator=(const NodeProcess&) = delete;

  // writes `line` and a newline, then reads the answer's line (without its newline); false when
  // the process died, hung past `deadline` or wrote something else: `error` then says what
  bool request(const std::string& line, std::string& answer, std::chrono::seconds deadline);
  // reads `bytes` more bytes of the last answer into `out`
  bool read_bytes(size_t bytes, std::vector<char>& out, std::chrono::seconds deadline);
  // whether it still answers (no request failed)
  bool healthy() const { return healthy_; }
  const std::string& error() const { return error_; }

 private:
  bool write_all(const std::string& data);
  // fills buffer_ with more of the child's output before the deadline
  bool fill(std::chrono::steady_clock::time_point until);
  void fail(std::string why);

  pid_t pid_ = -1;
  int to_child_ = -1;
  int from_child_ = -1;
  std::string buffer_;  // read and not yet consumed
  bool healthy_ = true;
  std::string error_;
};

}  // namespace puppet::compare
