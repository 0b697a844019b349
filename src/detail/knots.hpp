// Knot interval lengths |d|^alpha (private), shared by alpha_knots and the fused input pass.
#pragma once

#include <cmath>
#include <type_traits>

#include "fairspline/vec2.hpp"

namespace fairspline::detail {

/// |d|; the squared norm under/overflows for |d| outside ~[1e-145, 1e145]: hypot there.
inline double safe_norm(Vec2 d) {
  const double d2 = d.x * d.x + d.y * d.y;
  if (d2 > 1e-290 && d2 < 1e290) return std::sqrt(d2);
  return std::hypot(d.x, d.y);
}

/// Exponent classes with fast paths (pow is ~10x slower than sqrt).
enum class AlphaKind { kUniform, kCentripetal, kChordal, kGeneral };

inline AlphaKind alpha_kind(double alpha) {
  if (alpha == 0.0) return AlphaKind::kUniform;
  if (alpha == 0.5) return AlphaKind::kCentripetal;
  if (alpha == 1.0) return AlphaKind::kChordal;
  return AlphaKind::kGeneral;
}

/// |d|^alpha for the exponent class K.
template <AlphaKind K>
inline double span_length(Vec2 d, [[maybe_unused]] double alpha) {
  if constexpr (K == AlphaKind::kUniform) {
    return 1.0;
  } else if constexpr (K == AlphaKind::kCentripetal) {
    return std::sqrt(safe_norm(d));
  } else if constexpr (K == AlphaKind::kChordal) {
    return safe_norm(d);
  } else {
    return std::pow(norm(d), alpha);
  }
}

/// Calls f(std::integral_constant<AlphaKind, K>{}) for the class of alpha.
template <typename F>
inline decltype(auto) with_alpha_kind(double alpha, F&& f) {
  switch (alpha_kind(alpha)) {
    case AlphaKind::kUniform:
      return f(std::integral_constant<AlphaKind, AlphaKind::kUniform>{});
    case AlphaKind::kCentripetal:
      return f(std::integral_constant<AlphaKind, AlphaKind::kCentripetal>{});
    case AlphaKind::kChordal:
      return f(std::integral_constant<AlphaKind, AlphaKind::kChordal>{});
    default:
      return f(std::integral_constant<AlphaKind, AlphaKind::kGeneral>{});
  }
}

}  // namespace fairspline::detail
