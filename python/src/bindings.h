// What the module's files share (docs/python.md): the model as Python holds it, and how a value
// from Python is checked. Every check raises ValueError with one line naming the argument.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "puppet/model/model.h"

namespace puppet::python {

namespace py = pybind11;

/// a model the solvers made from it keep alive (a solver holds a reference to its model)
using ModelPtr = std::shared_ptr<Model>;

/// [[noreturn]] ValueError("<name>: <problem>")
[[noreturn]] void refuse(const std::string& name, const std::string& problem);
/// a finite number, else ValueError naming it
double finite(const char* name, double value);
/// three finite numbers from any sequence of three (a tuple, a list, an array of real numbers)
Vector3d vector3(const char* name, const py::handle& value);
/// ValueError naming it unless the array holds real numbers (floating point or whole; not
/// complex, bool, objects or text)
void check_kind(const char* name, const py::array& a);
/// a (rows, width) array of finite real numbers from an array or a nested sequence, as doubles;
/// kind and shape are checked before anything is copied (a broadcast array of gigabytes is
/// refused, not copied); ValueError naming it otherwise
py::array_t<double, py::array::c_style> real_array(const char* name, const py::handle& value,
                                                   ssize_t rows, ssize_t width);
/// a Python int (not a bool) within [lo, hi], else ValueError naming it and the range
long long whole(const char* name, const py::handle& value, long long lo, long long hi);
/// a message as one line of at most 400 bytes (the command line's bound), cut between characters
/// (Python decodes it as UTF-8)
std::string bounded(const std::string& message);

void bind_model(py::module_& m);
void bind_solver(py::module_& m);
void bind_crowd(py::module_& m);
void bind_testbed(py::module_& m);
void bind_engine(py::module_& m);

}  // namespace puppet::python
