// The testbed's commands from Python (python/puppet/studies.py reads back what they write): the
// command line's own parsing and checks, its messages raised as exceptions.
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.h"
#include "testbed.h"

namespace puppet::python {

void bind_testbed(py::module_& m) {
  m.def(
      "_testbed",
      [](const std::vector<std::string>& args) {
        std::vector<std::string> argv{"testbed"};
        argv.insert(argv.end(), args.begin(), args.end());
        testbed::Outcome outcome;
        {
          // the study's threads need no Python; Python's own handlers keep SIGINT
          py::gil_scoped_release release;
          outcome = testbed::run_testbed(argv, false);
        }
        if (outcome.status == 2) throw py::value_error(outcome.error);
        if (outcome.status != 0) {
          throw std::runtime_error(outcome.error.empty()
                                       ? "testbed: exit status " + std::to_string(outcome.status)
                                       : outcome.error);
        }
      },
      py::arg("args"),
      "runs `testbed ARGS...` in this process: ValueError for bad input (its exit status 2), "
      "RuntimeError for a failure");
}

}  // namespace puppet::python
