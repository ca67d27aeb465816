// A one-line progress bar on a terminal, a line every tenth of the way otherwise (a log file).
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace puppet::testbed {

class Progress {
 public:
  explicit Progress(std::string label);
  void operator()(size_t done, size_t total);

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  bool terminal_;
  Clock::time_point start_;
  int last_tenth_ = -1;
};

}  // namespace puppet::testbed
