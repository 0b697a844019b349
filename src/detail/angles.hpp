// Half angles, and angles of directions in the right half-plane faster than libm's atan2
// (private).
#pragma once

#include <cmath>

namespace fairspline::detail {

/// The cosine and sine of half an angle ψ in (−π, π].
struct HalfAngle {
  double c = 1.0, s = 0.0;
};

/// cos(ψ/2) and sin(ψ/2) from c = cos ψ and sn = sin ψ by the half-angle formulas, without
/// trigonometry: the square root of the one of (1 ± c)/2 that does not cancel, the other from
/// sin ψ = 2 sin(ψ/2) cos(ψ/2). The cosine is never negative (a right-half-plane direction,
/// for atan2_right).
inline HalfAngle half_angle(double c, double sn) {
  if (c > -0.5) {
    const double hc = std::sqrt(0.5 * (1.0 + c));
    return {hc, sn / (2.0 * hc)};
  }
  const double hs = (sn < 0.0 ? -1.0 : 1.0) * std::sqrt(0.5 * (1.0 - c));
  return {sn / (2.0 * hs), hs};
}

/// atan2(y, x) for x >= 0 (directions in the right half-plane, e.g. the half angle of a turn,
/// whose cosine is not negative), within 1.6 ulp of the exact angle (tests/angles_test.cpp
/// measures it against long double atan2l). glibc's atan2 is correctly rounded in nearly all
/// cases and costs ~25 ns; this costs about a third of that.
///
/// With a = min(|y|, x), b = max(|y|, x): atan(a/b) in [0, π/4], with a/b above 0.66 reduced
/// by atan(a/b) = π/4 + atan((a − b)/(a + b)) (one division either way), is
/// atan(u) = u + u·z·P(z)/Q(z), z = u², with Cephes' rational coefficients for |u| <= 0.66
/// (relative error below 2e-16). Then π/2 minus it where |y| > x, and y's sign.
/// For finite arguments (NaN in gives NaN); (0, 0) gives 0 with y's sign.
inline double atan2_right(double y, double x) {
  const double ay = std::abs(y);
  const bool steep = ay > x;
  const double a = steep ? x : ay, b = steep ? ay : x;
  // Above 0.66 the argument is reduced, so that a − b is exact (a >= b/2).
  const bool upper = a > 0.66 * b;
  const double num = upper ? a - b : a, den = upper ? a + b : b;
  const double u = den > 0.0 ? num / den : 0.0;
  const double z = u * u;
  const double p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z -
                     7.500855792314704667340e1) *
                        z -
                    1.228866684490136173410e2) *
                       z -
                   6.485021904942025371773e1;
  const double q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z +
                     4.328810604912902668951e2) *
                        z +
                    4.853903996359136964868e2) *
                       z +
                   1.945506571482613964425e2;
  // π/4 split in two doubles, so that adding the small part keeps its bits.
  constexpr double kQuarterHi = 7.85398163397448278999e-1, kQuarterLo = 3.06161699786838301793e-17;
  double r = u + (u * z * p / q);
  if (upper) r = kQuarterHi + (r + kQuarterLo);
  constexpr double kHalfHi = 1.57079632679489655800e0, kHalfLo = 6.12323399573676603587e-17;
  if (steep) r = kHalfHi - (r - kHalfLo);
  if (x != x || y != y) return x + y;  // NaN
  return std::copysign(r, y);
}

}  // namespace fairspline::detail
