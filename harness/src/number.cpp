#include "puppet/compare/number.h"

#include <cmath>
#include <cstdlib>

namespace puppet::compare {
namespace {

// a decimal number as a whole: digits, one sign, one point, an exponent; nothing else (no
// spaces, hex, inf or nan, which strtod would take)
bool parse_decimal(const std::string& text, double* out) {
  if (text.empty() || text.find_first_not_of("0123456789+-.eE") != std::string::npos) return false;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value)) return false;
  *out = value;
  return true;
}

}  // namespace

bool parse_whole(const std::string& text, uint64_t* out) {
  if (text.empty() || text.size() > 18 || (text.size() > 1 && text[0] == '0') ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return false;
  }
  *out = std::stoull(text);
  return true;
}

bool parse_finite(const std::string& text, double* out) {
  const auto slash = text.find('/');
  double value = 0.0;
  if (slash == std::string::npos) {
    if (!parse_decimal(text, &value)) return false;
  } else {
    // one fraction of two decimals, such as 1/240 (1/3/4 is not one)
    double num = 0.0, den = 0.0;
    if (!parse_decimal(text.substr(0, slash), &num) ||
        !parse_decimal(text.substr(slash + 1), &den) || den == 0.0) {
      return false;
    }
    value = num / den;
    if (!std::isfinite(value)) return false;
  }
  *out = value;
  return true;
}

}  // namespace puppet::compare
