// The extension of the Python package `puppet` (python/puppet/, docs/python.md): the model, the
// environment and pins, the procedural solver and the crowd (solver.cpp, crowd.cpp), and the
// testbed's commands (testbed.cpp). Errors are Python exceptions with the command line's one-line
// messages.
#include <pybind11/pybind11.h>

#include "bindings.h"

PYBIND11_MODULE(_puppet, m) {
  m.doc() = "The procedural articulated-body solver (Bae et al. 2001), its family and its testbed";
  puppet::python::bind_model(m);
  puppet::python::bind_solver(m);
  puppet::python::bind_crowd(m);
  puppet::python::bind_engine(m);
  puppet::python::bind_testbed(m);
}
