// The testbed's command line as a function: parse the arguments, run the command, and return its
// exit status with the one-line error it ended on. main.cpp prints that line; the Python module
// (python/) raises it as an exception.
#pragma once

#include <string>
#include <vector>

namespace puppet::testbed {

struct Outcome {
  int status = 0;     ///< 0, kBadInput (2) for bad input, 1 for a failure, 128 + a signal
  std::string error;  ///< one line of at most kMessageLength characters; empty when none
};

/// `args` as argv, the program's name first. `signals`: SIGINT and SIGTERM stop the command and
/// leave its output folder as it was (stop_on_signals); a host with its own handlers (Python)
/// passes false
Outcome run_testbed(const std::vector<std::string>& args, bool signals);

}  // namespace puppet::testbed
