// The text of a double in fairspline's JSON (private): exactly what nlohmann::json's dump()
// writes, without nlohmann's internal headers.
//
// Why not std::to_chars: dump() generates digits with Grisu2, which always round-trips but is
// not always the shortest or the closest decimal: on 10^7 random bit patterns 0.14% differ from
// std::to_chars's shortest-closest digits (0.05% of uniform doubles in [-200, 200], e.g.
// 190.18124141243771 where to_chars gives 190.1812414124377). A JSON writer built on to_chars
// would have changed ~14% of the records of a 20-point batch against every earlier output and
// against anything nlohmann still dumps, so the digits come from a port of the same algorithm
// (number_format.cpp), and tests/io/json_test.cpp compares the two on ~10^5 doubles.
#pragma once

#include <cstddef>

namespace fairspline::detail {

/// Room format_json_number needs: sign, 17 digits, point, "e-308" and some.
inline constexpr std::size_t kJsonNumberChars = 32;

/// Writes `v` as nlohmann::json's dump() does to `first`, which has room for kJsonNumberChars
/// characters, and returns the end of the text (not terminated): round-trip digits by Grisu2,
/// fixed notation for 1e-4 <= |v| < 1e15 ("1.0", "-0.0", "0.0001", "123456789012345.0"),
/// exponent notation otherwise ("1e-05", "1e+15", "1.5e+300", "5e-324"), "null" for NaN and
/// infinities (JSON has no such numbers).
char* format_json_number(char* first, double v);

}  // namespace fairspline::detail
