// Exact rescaling by powers of two (private). Multiplying by 2^k commutes with every rounding
// unless a result leaves the normal range, so a computation on 2^-e·x gives the bits of the one
// on x wherever that one neither overflows nor underflows. Quantities of extreme data (1e±300)
// are computed on points scaled to unit size and scaled back.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>

#include "fairspline/vec2.hpp"

namespace fairspline::detail {

/// The binary exponent e of the largest |coordinate| (2^e <= it < 2^(e+1)); 0 when every
/// coordinate is 0 or one is not finite (ilogb(0) is INT_MIN, not a usable scale).
inline int scale_exponent(std::span<const Vec2> v) {
  double big = 0.0;
  for (const Vec2& p : v) big = std::max({big, std::abs(p.x), std::abs(p.y)});
  return big > 0.0 && std::isfinite(big) ? std::ilogb(big) : 0;
}

/// v·2^e, exactly (while the result stays normal).
inline Vec2 scaled(Vec2 v, int e) {
  return {std::scalbn(v.x, e), std::scalbn(v.y, e)};
}

}  // namespace fairspline::detail
