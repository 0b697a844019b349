// Numeric constants shared by the library's sources (private). One definition, so that the
// sources can be compiled together in a unity build.
#pragma once

#include <limits>
#include <numbers>

namespace fairspline {

inline constexpr double kPi = std::numbers::pi;
/// The spacing of doubles at 1 (a unit of rounding, not a tolerance).
inline constexpr double kEps = std::numeric_limits<double>::epsilon();

}  // namespace fairspline
