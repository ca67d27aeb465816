// Numbers typed on a command line: the testbed's and the viewer's flags read them alike.
#pragma once

#include <cstdint>
#include <string>

namespace puppet::compare {

// a finite number, or a fraction of two such as 1/240; false (out untouched) otherwise
bool parse_finite(const std::string& text, double* out);
// a count in plain decimal digits (no sign, no leading zero, at most 18 digits, so no 0x10 or
// 010); false (out untouched) otherwise
bool parse_whole(const std::string& text, uint64_t* out);

}  // namespace puppet::compare
