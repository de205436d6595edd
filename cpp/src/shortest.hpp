// Numbers in error messages: the shortest decimal that reads back as the value (0.3, not
// 0.29999999999999999), so a message quotes what the user typed.
#pragma once

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

namespace pydrill::detail {

inline std::string shortest(double value) {
  std::ostringstream o;
  for (int digits = 6; digits <= 17; ++digits) {
    o.str("");
    o.precision(digits);
    o << value;
    // strtod, not stod: near ±DBL_MAX a short decimal reads back beyond the range, and
    // stod would throw out_of_range (seen as "IndexError: stod" from W_ob = -1.8e308).
    if (!std::isfinite(value) || std::strtod(o.str().c_str(), nullptr) == value) break;
  }
  return o.str();
}

}  // namespace pydrill::detail
