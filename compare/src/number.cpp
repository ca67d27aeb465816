#include "puppet/compare/number.h"

#include <cmath>
#include <sstream>

namespace puppet::compare {

bool parse_finite(const std::string& text, double* out) {
  std::istringstream in(text);
  double value = 0.0;
  in >> value;
  if (!in || !in.eof() || !std::isfinite(value)) {
    // also accept simple fractions such as 1/240
    const auto slash = text.find('/');
    if (slash == std::string::npos) return false;
    double num = 0.0, den = 0.0;
    if (!parse_finite(text.substr(0, slash), &num) || !parse_finite(text.substr(slash + 1), &den) ||
        den == 0.0) {
      return false;
    }
    value = num / den;
  }
  if (!std::isfinite(value)) return false;
  *out = value;
  return true;
}

}  // namespace puppet::compare
