// Numbers typed on a command line: the testbed's and the viewer's flags read them alike.
#pragma once

#include <string>

namespace puppet::compare {

// a finite number, or a fraction of two such as 1/240; false (out untouched) otherwise
bool parse_finite(const std::string& text, double* out);

}  // namespace puppet::compare
