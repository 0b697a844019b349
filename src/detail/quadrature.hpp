// Private numerical helpers of energy.cpp and diagnostics.cpp:
//   - adaptive Gauss–Kronrod (15/31) quadrature of a vector-valued integrand, globally adaptive
//     (QUADPACK QAG strategy) with a fixed-capacity interval buffer: no heap allocation;
//   - real roots in [0,1] of polynomials of degree <= 3 (monotone bracketing + safeguarded
//     Newton), used for the minimum speed of a cubic.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/energy.hpp"

namespace fairspline::detail {

/// Result of a vector quadrature: one value and error estimate per component.
template <std::size_t N>
struct QuadratureN {
  std::array<double, N> value{};
  std::array<double, N> error{};
  bool converged = true;
  int intervals = 0;
};

/// Gauss–Kronrod 15/31 abscissae (positive half, the centre last) and weights (QUADPACK qk31;
/// tests/energy_test.cpp checks them against Boost.Math's). On the report's pieces the 31-point
/// rule needs 1.6 rules per piece where 7/15 needed 5.6: 50 integrand values instead of 85.
inline constexpr std::array<double, 16> kGkNodes = {
    0.99800229869339707, 0.98799251802048538, 0.96773907567913908, 0.93727339240070595,
    0.89726453234408188, 0.84820658341042721, 0.79041850144246595, 0.72441773136017007,
    0.65099674129741703, 0.57097217260853883, 0.4850818636402397,  0.39415134707756339,
    0.29918000715316884, 0.20119409399743451, 0.10114206691871749, 0.0};
inline constexpr std::array<double, 16> kKronrodWeights = {
    0.0053774798729233492, 0.015007947329316122, 0.02546084732671532,  0.035346360791375847,
    0.044589751324764879,  0.053481524690928088, 0.062009567800670642, 0.069854121318728257,
    0.076849680757720376,  0.083080502823133021, 0.088564443056211764, 0.093126598170825317,
    0.096642726983623681,  0.099173598721791961, 0.10076984552387559,  0.10133000701479154};
/// Gauss 15-point weights for the nodes kGkNodes[1], [3], ..., [13] and the centre [15].
inline constexpr std::array<double, 8> kGaussWeights = {
    0.030753241996117269, 0.070366047488108124, 0.10715922046717194, 0.13957067792615432,
    0.16626920581699392,  0.18616100001556221,  0.19843148532711158, 0.20257824192556129};
/// Nodes of one rule: kGkNodes mirrored, [kRuleCentre] the centre, [j] and [kRuleSize-1-j].
inline constexpr std::size_t kRuleSize = 31, kRuleCentre = 15;

/// One Gauss–Kronrod 31-point rule on [a, b] for each component; the error estimate is
/// QUADPACK's: resasc·min(1, (200|K−G|/resasc)^1.5), floored at 50·eps·∫|f| (round-off).
template <std::size_t N, class F>
void gauss_kronrod(F& f, double a, double b, std::array<double, N>& value,
                   std::array<double, N>& error) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  constexpr std::size_t c0 = kRuleCentre, last = kRuleSize - 1;
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  std::array<std::array<double, N>, kRuleSize> fv;  // f at the nodes: [c0] centre, [j], [last-j]
  if constexpr (requires(std::array<double, kRuleSize> u) { f.batch(u, fv); }) {
    // All nodes at once (an integrand written as loops over them, which vectorize).
    std::array<double, kRuleSize> u;
    u[c0] = c;
    for (std::size_t j = 0; j < c0; ++j) {
      u[j] = c - h * kGkNodes[j];
      u[last - j] = c + h * kGkNodes[j];
    }
    f.batch(u, fv);
  } else {
    fv[c0] = f(c);
    for (std::size_t j = 0; j < c0; ++j) {
      fv[j] = f(c - h * kGkNodes[j]);
      fv[last - j] = f(c + h * kGkNodes[j]);
    }
  }
  for (std::size_t k = 0; k < N; ++k) {
    double resk = kKronrodWeights[c0] * fv[c0][k];
    double resg = kGaussWeights[c0 / 2] * fv[c0][k];
    double resabs = std::abs(resk);
    for (std::size_t j = 0; j < c0; ++j) {
      const double s = fv[j][k] + fv[last - j][k];
      resk += kKronrodWeights[j] * s;
      resabs += kKronrodWeights[j] * (std::abs(fv[j][k]) + std::abs(fv[last - j][k]));
      if (j % 2 == 1) resg += kGaussWeights[j / 2] * s;
    }
    const double mean = 0.5 * resk;
    double resasc = kKronrodWeights[c0] * std::abs(fv[c0][k] - mean);
    for (std::size_t j = 0; j < c0; ++j)
      resasc += kKronrodWeights[j] * (std::abs(fv[j][k] - mean) + std::abs(fv[last - j][k] - mean));
    const double ah = std::abs(h);
    double err = std::abs((resk - resg) * h);
    resasc *= ah;
    resabs *= ah;
    if (resasc != 0.0 && err != 0.0) {
      const double r = 200.0 * err / resasc;  // r^1.5 as r·√r: pow was a tenth of a report
      err = resasc * std::min(1.0, r * std::sqrt(r));
    }
    err = std::max(err, 50.0 * kEps * resabs);
    value[k] = resk * h;
    error[k] = err;
  }
}

/// Globally adaptive quadrature of f: [0,1] -> R^N over the sub-intervals delimited by
/// `breaks` (sorted, inside (0,1); integrable kinks belong there). Bisects the interval with the
/// largest relative error until every component meets error <= rel_accuracy·|value|, no
/// interval can be split without exceeding max_depth, or the buffer (kCapacity) is full.
template <std::size_t N, class F>
QuadratureN<N> integrate_adaptive(F f, std::span<const double> breaks, double rel_accuracy,
                                  int max_depth) {
  constexpr int kCapacity = 256;
  struct Cell {
    double a, b;
    std::array<double, N> value, error;
    int depth;
  };
  std::array<Cell, kCapacity> cells;
  int count = 0;
  QuadratureN<N> out;
  auto add = [&](double a, double b, int depth) {
    Cell& c = cells[count++];
    c.a = a;
    c.b = b;
    c.depth = depth;
    gauss_kronrod<N>(f, a, b, c.value, c.error);
  };
  double prev = 0.0;
  for (double x : breaks) {
    if (x > prev && x < 1.0 && count + 2 < kCapacity) {
      add(prev, x, 0);
      prev = x;
    }
  }
  add(prev, 1.0, 0);
  const double acc = std::max(rel_accuracy, 0.0);
  for (;;) {
    std::array<double, N> total{}, total_err{};
    for (int i = 0; i < count; ++i)
      for (std::size_t k = 0; k < N; ++k) {
        total[k] += cells[i].value[k];
        total_err[k] += cells[i].error[k];
      }
    // Worst component's ratio error / tolerance decides convergence and which cell to split.
    std::array<double, N> tol{};
    bool done = true;
    for (std::size_t k = 0; k < N; ++k) {
      tol[k] = acc * std::abs(total[k]);
      if (total_err[k] > tol[k]) done = false;
    }
    out.value = total;
    out.error = total_err;
    out.intervals = count;
    if (done) return out;
    if (count + 1 >= kCapacity) break;
    int worst = -1;
    double worst_ratio = 0.0;
    for (int i = 0; i < count; ++i) {
      if (cells[i].depth >= max_depth) continue;
      double ratio = 0.0;
      for (std::size_t k = 0; k < N; ++k) {
        const double t = tol[k] > 0.0 ? tol[k] : std::numeric_limits<double>::min();
        ratio = std::max(ratio, cells[i].error[k] / t);
      }
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = i;
      }
    }
    if (worst < 0) break;
    const Cell old = cells[worst];
    const double m = 0.5 * (old.a + old.b);
    if (!(m > old.a && m < old.b)) {
      cells[worst].depth = max_depth;  // cannot split further in floating point
      continue;
    }
    // Replace the worst cell by its left half, append the right half.
    cells[worst].b = m;
    cells[worst].depth = old.depth + 1;
    gauss_kronrod<N>(f, old.a, m, cells[worst].value, cells[worst].error);
    add(m, old.b, old.depth + 1);
  }
  out.converged = false;
  return out;
}

/// Calls out(u) for every real root u in [0,1] of c0 + c1 u + c2 u² + c3 u³ (not identically
/// zero), each simple root once; roots are located by sign changes on monotone pieces and
/// polished by safeguarded Newton, so a double root shows up as a critical point of the
/// polynomial, which callers include as a candidate anyway.
template <class Out>
void for_each_root_in_unit(double c0, double c1, double c2, double c3, Out&& out) {
  auto p = [&](double u) { return ((c3 * u + c2) * u + c1) * u + c0; };
  auto dp = [&](double u) { return (3.0 * c3 * u + 2.0 * c2) * u + c1; };
  // Critical points: roots of 3c3 u² + 2c2 u + c1 (stable quadratic formula).
  std::array<double, 4> knots{0.0, 0.0, 0.0, 1.0};
  int nk = 1;
  {
    const double a = 3.0 * c3, b = 2.0 * c2, c = c1;
    std::array<double, 2> r{};
    int nr = 0;
    if (a == 0.0) {
      if (b != 0.0) r[nr++] = -c / b;
    } else {
      const double disc = b * b - 4.0 * a * c;
      if (disc >= 0.0) {
        const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
        if (q != 0.0) {
          r[nr++] = q / a;
          r[nr++] = c / q;
        } else {
          r[nr++] = 0.0;
        }
      }
    }
    if (nr == 2 && r[0] > r[1]) std::swap(r[0], r[1]);
    for (int i = 0; i < nr; ++i)
      if (r[i] > 0.0 && r[i] < 1.0) knots[nk++] = r[i];
  }
  knots[nk++] = 1.0;
  for (int i = 0; i + 1 < nk; ++i) {
    double lo = knots[i], hi = knots[i + 1];
    double plo = p(lo), phi = p(hi);
    if (plo == 0.0) {
      out(lo);
      continue;
    }
    if (i + 2 == nk && phi == 0.0) {
      out(hi);
      continue;
    }
    if ((plo < 0.0) == (phi < 0.0)) continue;
    double u = 0.5 * (lo + hi);
    for (int it = 0; it < 100; ++it) {
      const double pu = p(u);
      if (pu == 0.0) break;
      if ((pu < 0.0) == (plo < 0.0)) {
        lo = u;
        plo = pu;
      } else {
        hi = u;
      }
      const double d = dp(u);
      double next = (d != 0.0) ? u - pu / d : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (next == u || hi - lo <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, hi))
        break;
      u = next;
    }
    out(u);
  }
}

/// Length of the control polygon |p1-p0| + |p2-p1| + |p3-p2|: the scale of a piece.
inline double control_polygon_length(const CubicBezier& b) {
  return distance(b.p[0], b.p[1]) + distance(b.p[1], b.p[2]) + distance(b.p[2], b.p[3]);
}

/// Minimum of |b'(u)| over [0,1] and where it is attained (smallest u on ties).
struct SpeedMinimum {
  double speed = 0.0;
  double u = 0.0;
};

/// Exact minimum speed: |b'|² is a quartic whose critical points are the roots of the cubic
/// b'·b''; the minimum is at one of them or at an end. The candidates are compared by their
/// squares where those cannot over- or underflow (hypot per candidate was a tenth of the
/// report); the speed of the one chosen is taken with hypot either way.
inline SpeedMinimum min_speed(const CubicBezier& b) {
  const QuadBezier h = b.hodograph();
  // Power form h(u) = c0 + c1 u + c2 u².
  const Vec2 c0 = h.p[0], c1 = 2.0 * (h.p[1] - h.p[0]), c2 = h.p[0] - 2.0 * h.p[1] + h.p[2];
  double big = 0.0;
  for (const Vec2& q : h.p) big = std::max({big, std::abs(q.x), std::abs(q.y)});
  const bool squares = big > 1e-100 && big < 1e100;
  auto size = [&](Vec2 v) { return squares ? norm2(v) : norm(v); };
  double best_size = size(h.p[0]);
  double best_u = 0.0;
  const double s1 = size(h.p[2]);
  if (s1 < best_size) {
    best_size = s1;
    best_u = 1.0;
  }
  for_each_root_in_unit(dot(c0, c1), 2.0 * dot(c0, c2) + dot(c1, c1), 3.0 * dot(c1, c2),
                        2.0 * dot(c2, c2), [&](double u) {
                          const double s = size(h.eval(u));
                          if (s < best_size) {
                            best_size = s;
                            best_u = u;
                          }
                        });
  return {squares ? norm(h.eval(best_u)) : best_size, best_u};
}

/// True when the four control points are collinear to within the rounding of their
/// coordinates (so the piece is a straight line, traversed possibly non-uniformly).
inline bool is_straight(const CubicBezier& b) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  Vec2 d{};
  double magnitude = 0.0;
  for (const Point& q : b.p) magnitude = std::max({magnitude, std::abs(q.x), std::abs(q.y)});
  for (int k = 1; k < 4; ++k)
    if (norm2(b.p[k] - b.p[0]) > norm2(d)) d = b.p[k] - b.p[0];
  if (norm2(d) == 0.0) return true;
  const double tol = 16.0 * kEps * magnitude * norm(d);
  for (int k = 1; k < 4; ++k)
    if (std::abs(cross(d, b.p[k] - b.p[0])) > tol) return false;
  return true;
}

/// Bending, curvature variation and length of one piece.
struct PieceEnergies {
  Quadrature bending;
  Quadrature curvature_variation;  ///< zero unless asked for
  Quadrature length;
};
/// Implemented in energy.cpp (same conventions as the public per-piece functions); `m` is
/// min_speed(b), passed in when the caller already has it. Bending and length come from one
/// adaptive quadrature, the curvature variation (when `variation`) from another.
PieceEnergies piece_energies(const CubicBezier& b, const EnergyOptions& options,
                             const SpeedMinimum& m, bool variation);

}  // namespace fairspline::detail
