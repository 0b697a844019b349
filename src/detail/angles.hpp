// Half angles, angles of directions and sines and cosines of small angles, faster than libm's
// atan2 and sincos and inlined, so that loops over many of them overlap or vectorize (private).
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

/// atan2(y, x) in [−π, π] from atan2_right: for x < 0 it is ±π (y's sign) minus the angle of
/// the mirror image (−x, y) from the axis, π split in two doubles. Within ~2 ulp of the
/// exact angle (tests/angles_test.cpp). For finite arguments (NaN in gives NaN); (±0, −0)
/// gives ±0 where libm gives ±π (callers pass unit vectors).
inline double atan2_fast(double y, double x) {
  if (!(x < 0.0)) return atan2_right(y, x);
  constexpr double kPiHi = 3.14159265358979311600e0, kPiLo = 1.22464679914735320717e-16;
  return std::copysign(kPiHi - (std::abs(atan2_right(y, -x)) - kPiLo), y);
}

/// sin x and cos x by their Taylor series to degree kSinDegree / kSinDegree + 1. The default,
/// 21/22, serves |x| <= π/2: the series' error is below 2e-18 there ((π/2)^23/23!), the rounding
/// of its terms within 3·2⁻⁵³ (tests/angles_test.cpp); a caller with a narrower range may stop
/// earlier (the error is below |x|^(d+2)/(d+2)! for degree d). Unlike a libm call it is inlined,
/// so a loop over many angles vectorizes or overlaps; callers send larger angles to libm.
template <int kSinDegree = 21>
inline void sincos_taylor(double x, double& sn, double& cn) {
  static_assert(kSinDegree % 2 == 1 && kSinDegree >= 3 && kSinDegree <= 21);
  // 1/k! for k = 0 … 22 (every k! up to 22! is exact in a double, so each entry is 1/k! rounded).
  constexpr double kInvFact[] = {1.0,
                                 1.0,
                                 1.0 / 2,
                                 1.0 / 6,
                                 1.0 / 24,
                                 1.0 / 120,
                                 1.0 / 720,
                                 1.0 / 5040,
                                 1.0 / 40320,
                                 1.0 / 362880,
                                 1.0 / 3628800,
                                 1.0 / 39916800,
                                 1.0 / 479001600,
                                 1.0 / 6227020800.0,
                                 1.0 / 87178291200.0,
                                 1.0 / 1307674368000.0,
                                 1.0 / 20922789888000.0,
                                 1.0 / 355687428096000.0,
                                 1.0 / 6402373705728000.0,
                                 1.0 / 121645100408832000.0,
                                 1.0 / 2432902008176640000.0,
                                 1.0 / 51090942171709440000.0,
                                 1.0 / 1124000727777607680000.0};
  // The sign of the x^j term of either series.
  constexpr auto sign = [](int j) { return (j / 2) % 2 == 0 ? 1.0 : -1.0; };
  const double z = x * x;
  // sin x = x Σ (−z)^k / (2k+1)!, cos x = Σ (−z)^k / (2k)! (Horner).
  double ps = sign(kSinDegree) * kInvFact[kSinDegree];
  double pc = sign(kSinDegree + 1) * kInvFact[kSinDegree + 1];
  for (int j = kSinDegree - 2; j >= 1; j -= 2) ps = ps * z + sign(j) * kInvFact[j];
  for (int j = kSinDegree - 1; j >= 0; j -= 2) pc = pc * z + sign(j) * kInvFact[j];
  sn = x * ps;
  cn = pc;
}

}  // namespace fairspline::detail
