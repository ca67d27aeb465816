// Reading back the CSV the testbed writes: one line into its fields.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace puppet::test {

// the fields of one CSV line (no quoting: the testbed never writes any); a trailing comma gives
// a trailing empty field
inline std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

}  // namespace puppet::test
