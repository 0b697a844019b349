// Finiteness checks of fit output (private): "no NaN or Inf ever leaves the library".
#pragma once

#include <bit>
#include <cstdint>
#include <string_view>

#include "fairspline/fit.hpp"

namespace fairspline::detail {

/// 1 when x is NaN or ±Inf (all exponent bits set), else 0. Integer tests OR-reduce without a
/// serial floating-point dependency chain.
inline std::uint64_t non_finite_bits(double x) {
  constexpr std::uint64_t kExponent = 0x7ff0000000000000ull;
  return static_cast<std::uint64_t>((std::bit_cast<std::uint64_t>(x) & kExponent) == kExponent);
}

inline std::uint64_t non_finite_bits(Vec2 v) {
  return non_finite_bits(v.x) | non_finite_bits(v.y);
}

inline std::uint64_t non_finite_bits(const Segment& s) {
  std::uint64_t bad = non_finite_bits(s.t0) | non_finite_bits(s.t1);
  for (const Point& p : s.bezier.p) bad |= non_finite_bits(p);
  return bad;
}

/// Scans the whole result; throws Error(kNonFinite) naming the first offending segment (its
/// span) or tangent. `method` names the method in the message.
void check_finite_output(const FitResult& r, std::string_view method);

}  // namespace fairspline::detail
