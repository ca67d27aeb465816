// The testbed's commands from Python (python/puppet/studies.py reads back what they write): the
// command line's own parsing and checks, its messages raised as exceptions. A command runs on a
// thread of its own while this one waits with the interpreter's lock released, waking every
// kPoll to let Python's handlers run: Ctrl-C (KeyboardInterrupt) stops the command as SIGINT stops
// the command line, the output folder left as it was.
#include <pybind11/stl.h>

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bindings.h"
#include "puppet/compare/cancel.h"
#include "puppet/testbed/testbed.h"

namespace puppet::python {
namespace {

constexpr std::chrono::milliseconds kPoll{50};

void run_command(const std::vector<std::string>& args) {
  std::vector<std::string> argv{"testbed"};
  argv.insert(argv.end(), args.begin(), args.end());
  compare::clear_cancel();
  testbed::Outcome outcome;
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::thread command([&] {
    testbed::Outcome result = testbed::run_testbed(argv, false);
    const std::lock_guard lock(mutex);
    outcome = std::move(result);
    done = true;
    finished.notify_one();
  });
  bool interrupted = false;
  for (;;) {
    {
      py::gil_scoped_release release;
      std::unique_lock lock(mutex);
      if (finished.wait_for(lock, kPoll, [&] { return done; })) break;
    }
    // a handler that raises (Ctrl-C's KeyboardInterrupt) asks the command to stop; the error
    // stays set, and is raised once the command has tidied up
    if (!interrupted && PyErr_CheckSignals() != 0) {
      interrupted = true;
      compare::request_cancel(SIGINT);
    }
  }
  command.join();
  compare::clear_cancel();
  if (interrupted) throw py::error_already_set();
  if (outcome.status == 2) throw py::value_error(bounded(outcome.error));
  if (outcome.status != 0) {
    throw std::runtime_error(outcome.error.empty()
                                 ? "testbed: exit status " + std::to_string(outcome.status)
                                 : bounded(outcome.error));
  }
}

}  // namespace

void bind_testbed(py::module_& m) {
  m.def("_testbed", &run_command, py::arg("args"),
        "runs `testbed ARGS...` in this process: ValueError for bad input (its exit status 2), "
        "RuntimeError for a failure, KeyboardInterrupt for Ctrl-C");
}

}  // namespace puppet::python
