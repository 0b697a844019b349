// Numbers in error messages (private): the shortest text that reads back as the same double
// ("1e+308", "1e-07", "0.1"), not std::to_string's fixed six decimals, which printed 1e308 as
// 309 digits and 1e-7 as "0.000000".
#pragma once

#include <charconv>
#include <string>

#include "fairspline/vec2.hpp"

namespace fairspline::detail {

inline std::string format_number(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::string("?");
}

/// "(x, y)".
inline std::string format_point(Vec2 p) {
  std::string s(1, '(');  // (appended, not "(" + …: GCC 12 warns -Wrestrict on that)
  s += format_number(p.x);
  s += ", ";
  s += format_number(p.y);
  s += ')';
  return s;
}

}  // namespace fairspline::detail
