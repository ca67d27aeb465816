// testbed: runs the scenarios in the solvers and writes what it measured.
//
// The commands are one file each (commands.h lists them), run by run_testbed (testbed.h); their
// shared flags are defined once in flags.cpp. Bad input (an unknown name, a malformed flag, a bad
// model file, an unwritable folder) exits with status 2 and one line naming the flag or file and
// the problem, before anything is written.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "cli.h"
#include "puppet/testbed/testbed.h"

// what a command printed reached standard output, or the command fails: a full disk or a closed
// file there is not success
int main(int argc, char** argv) {
  using namespace puppet;
  using namespace puppet::testbed;
  const Outcome outcome = run_testbed(std::vector<std::string>(argv, argv + argc), true);
  // a stop is reported after a blank line, below the progress it interrupted
  if (!outcome.error.empty())
    std::cerr << (outcome.status > 128 ? "\n" : "") << outcome.error << '\n';
  const int status = outcome.status;
  std::cout.flush();
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
    const int error = errno;
    print_error("testbed: ", std::string("cannot write to standard output (") +
                                 (error ? std::strerror(error) : "write failed") + ")");
    return status == 0 ? 1 : status;
  }
  return status;
}
