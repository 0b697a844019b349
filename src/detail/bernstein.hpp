// Real-root isolation of a univariate polynomial in Bernstein form on [0, 1]: Descartes' rule of
// signs on the Bernstein coefficients with de Casteljau subdivision, then a safeguarded Newton
// refinement inside each isolating interval. Used by the Kozak–Krajnc single-piece solver to
// find every root of the eliminated (resultant) polynomial.
#pragma once

#include <array>
#include <cstddef>

namespace fairspline::detail {

/// Maximum supported degree.
inline constexpr int kBernsteinMaxDegree = 15;

/// Bernstein coefficients b[0..degree] of a polynomial on [0, 1].
struct BernsteinPoly {
  std::array<double, kBernsteinMaxDegree + 1> b{};
  int degree = 0;

  /// Value at u by de Casteljau (stable for u in [0, 1]).
  double eval(double u) const;
};

/// A root (or an unresolved cluster of roots) of a BernsteinPoly in [0, 1].
struct BernsteinRoot {
  double u = 0.0;
  /// Number of sign variations of the Bernstein coefficients on the final interval: 1 for an
  /// isolated simple root; more for a cluster narrower than the resolution (a multiple root, or
  /// roots closer than rounding can separate); 0 for a near tangency (see `touch` below).
  int count = 1;
};

/// Roots found in [0, 1]; capacity bounds the output (extra roots are dropped, `overflow` set).
struct BernsteinRoots {
  static constexpr int kCapacity = 2 * kBernsteinMaxDegree;
  std::array<BernsteinRoot, kCapacity> items{};
  int count = 0;
  bool overflow = false;
};

/// Isolates and refines the real roots of `p` in [0, 1]. Intervals are halved until Descartes'
/// bound is 0 or 1, or until they are narrower than `resolution` (then reported as a cluster).
/// With `touch` > 0, near tangencies are reported too, with count 0: local minima of |p| of at
/// most `touch` (absolute) that do not reach zero, as at a double root that rounding lifted off
/// the axis. They are looked for (as roots of p') only in intervals without sign variation whose
/// coefficients come within `touch` of zero, and in one-root intervals that small at an end
/// and not monotone. A polynomial whose coefficients all vanish has no isolated roots: returns
/// none and the caller must detect that case itself.
BernsteinRoots bernstein_roots(const BernsteinPoly& p, double resolution, double touch = 0.0);

}  // namespace fairspline::detail
