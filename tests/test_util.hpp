// Small helpers shared by the test files.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/methods/min_energy.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline::testing {

/// Random walk with turn angles uniform in ±max_turn_deg and steps uniform in [0.5, 2].
inline std::vector<Point> random_walk(std::size_t n, std::uint64_t seed,
                                      double max_turn_deg = 120) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> turn(-max_turn_deg * std::numbers::pi / 180,
                                              max_turn_deg * std::numbers::pi / 180);
  std::uniform_real_distribution<double> step(0.5, 2.0);
  std::vector<Point> pts;
  pts.reserve(n);
  Point p{0, 0};
  double heading = 0;
  for (std::size_t i = 0; i < n; ++i) {
    pts.push_back(p);
    heading += turn(rng);
    p += step(rng) * from_angle(heading);
  }
  return pts;
}

/// Distance from q to a polyline (its segments): the reference of the flattening tests.
inline double distance_to_polyline(Point q, const std::vector<Point>& line) {
  double best = HUGE_VAL;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Vec2 ab = line[i + 1] - line[i];
    const double l2 = norm2(ab);
    const double u = l2 > 0 ? std::clamp(dot(q - line[i], ab) / l2, 0.0, 1.0) : 0.0;
    best = std::min(best, distance(q, line[i] + u * ab));
  }
  return best;
}

/// n points on an ellipse (closed polygon without the repeated first point).
/// Dense Gaussian elimination with partial pivoting: the reference of the banded solvers'
/// tests. T is double or Vec2 (one right-hand side per coordinate).
template <typename T>
std::vector<T> dense_solve(std::vector<std::vector<double>> a, std::vector<T> b) {
  const std::size_t n = b.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < n; ++r) {
      if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
    }
    std::swap(a[c], a[piv]);
    std::swap(b[c], b[piv]);
    for (std::size_t r = c + 1; r < n; ++r) {
      const double f = a[r][c] / a[c][c];
      for (std::size_t k = c; k < n; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  std::vector<T> x(n);
  for (std::size_t r = n; r-- > 0;) {
    T s = b[r];
    for (std::size_t k = r + 1; k < n; ++k) s -= a[r][k] * x[k];
    x[r] = s / a[r][r];
  }
  return x;
}

inline std::vector<Point> ellipse(std::size_t n, double a = 2, double b = 1) {
  std::vector<Point> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    pts.push_back({a * std::cos(t), b * std::sin(t)});
  }
  return pts;
}

/// The tangent vector s'(t_i) of a C1 result at each point, read off the Bézier pieces.
inline std::vector<Vec2> hermite_tangents(const FitResult& r) {
  const auto& segs = r.spline.segments;
  std::vector<Vec2> m(r.points.size());
  for (std::size_t k = 0; k < segs.size(); ++k) {
    const double h = segs[k].t1 - segs[k].t0;
    m[segs[k].span] = 3.0 / h * (segs[k].bezier.p[1] - segs[k].bezier.p[0]);
  }
  if (!r.closed) {
    const auto& last = segs.back();
    m.back() = 3.0 / (last.t1 - last.t0) * (last.bezier.p[3] - last.bezier.p[2]);
  }
  return m;
}

/// Largest coordinate magnitude of a point set (scale for relative tolerances).
inline double scale_of(const std::vector<Point>& pts) {
  double s = 0;
  for (const Point& p : pts) s = std::max({s, std::abs(p.x), std::abs(p.y)});
  return s;
}

/// True when b traverses a's curve backwards: same number of pieces, piece k of a equals
/// piece m-1-k of b reversed, control points within tol.
inline bool is_reversed_curve(const FitResult& a, const FitResult& b, double tol) {
  const std::size_t m = a.spline.segments.size();
  if (b.spline.segments.size() != m) return false;
  for (std::size_t k = 0; k < m; ++k) {
    const auto& fwd = a.spline.segments[k].bezier;
    const auto& bwd = b.spline.segments[m - 1 - k].bezier;
    for (int j = 0; j < 4; ++j) {
      if (!(norm(fwd.p[j] - bwd.p[3 - j]) <= tol)) return false;
    }
  }
  return true;
}

/// Runs `fn`, expects a fairspline::Error and returns it (a test failure otherwise).
template <typename F>
Error expect_error(F&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "expected fairspline::Error";
  return Error(ErrorCode::kInvalidArgument, "no error");
}

/// fn throws Error with `code` and a message containing every one of `parts`.
template <typename F>
Error expect_error(ErrorCode code, F&& fn, const std::vector<std::string>& parts = {}) {
  const Error e = expect_error(std::forward<F>(fn));
  EXPECT_EQ(e.code(), code) << e.what();
  for (const std::string& part : parts) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << part << " in " << e.what();
  }
  return e;
}

/// Issue 18's "which minimum": fit_min_energy with search=newton and with search=coordinate, the
/// other options as given.
struct Searches {
  FitResult newton_fit, coordinate_fit;
  MinEnergyReport newton, coordinate;
};
inline Searches fit_both_searches(const FitInput& in, MinEnergyOptions opt,
                                  ReportLevel level = ReportLevel::kNone) {
  Searches s;
  opt.search = MinEnergySearch::kNewton;
  fit_min_energy(in, opt, level, s.newton_fit, &s.newton);
  opt.search = MinEnergySearch::kCoordinate;
  fit_min_energy(in, opt, level, s.coordinate_fit, &s.coordinate);
  return s;
}

/// Four points whose end directions are given, so that the energy Σ E_1/L has two unknowns,
/// the directions at p[1] and p[2] (absolute angles).
struct TwoFreeDirections {
  std::array<Point, 4> p;
  double start = 0.0, end = 0.0;  ///< the given directions at p[0] and p[3]
  FitInput input() const {
    FitInput in;
    in.points = {p.begin(), p.end()};
    in.kinds = {PointKind::kClamped, PointKind::kSmooth, PointKind::kSmooth, PointKind::kClamped};
    in.tangents = {from_angle(start), std::nullopt, std::nullopt, from_angle(end)};
    return in;
  }
  /// E_1(α, β)/L of span i with directions xa, xb at its ends: infinite outside the box Ω and,
  /// for the elastic bases, where the directions are 180° or more apart.
  double span(const BasicCurveMethod& m, std::size_t i, double xa, double xb) const {
    const Vec2 d = p[i + 1] - p[i];
    const double phi = std::atan2(d.y, d.x);
    const double a = std::remainder(xa - phi, 2 * std::numbers::pi),
                 b = std::remainder(xb - phi, 2 * std::numbers::pi);
    if (std::abs(a) > m.omega || std::abs(b) > m.omega) return HUGE_VAL;
    if (is_elastic(m.basis) && !(std::abs(a - b) < std::numbers::pi * (1 - 1e-12))) {
      return HUGE_VAL;
    }
    return basic_energy(m, a, b).e / norm(d);
  }
  /// Σ E_1/L with the directions x1, x2 at p[1], p[2].
  double energy(const BasicCurveMethod& m, double x1, double x2) const {
    return span(m, 0, start, x1) + span(m, 1, x1, x2) + span(m, 2, x2, end);
  }
  /// The least energy by brute force: every pair of directions on a grid of `cells` per turn,
  /// then pattern moves about the best, halving down to 1e-13 rad.
  double brute_force(const BasicCurveMethod& m, int cells = 360) const {
    const double h = 2 * std::numbers::pi / cells;
    std::vector<double> first(cells), last(cells);
    for (int i = 0; i < cells; ++i) {
      first[i] = span(m, 0, start, i * h);
      last[i] = span(m, 2, i * h, end);
    }
    double best = HUGE_VAL, x1 = 0.0, x2 = 0.0;
    for (int i = 0; i < cells; ++i) {
      for (int j = 0; j < cells; ++j) {
        if (!(first[i] + last[j] < best)) continue;
        const double e = first[i] + span(m, 1, i * h, j * h) + last[j];
        if (e < best) best = e, x1 = i * h, x2 = j * h;
      }
    }
    for (double s = h; s > 1e-13; s *= 0.5) {
      for (bool moved = true; moved;) {
        moved = false;
        for (const auto& [d1, d2] : {std::pair{s, 0.0},
                                     {-s, 0.0},
                                     {0.0, s},
                                     {0.0, -s},
                                     {s, s},
                                     {-s, -s},
                                     {s, -s},
                                     {-s, s}}) {
          const double e = energy(m, x1 + d1, x2 + d2);
          if (e < best) best = e, x1 += d1, x2 += d2, moved = true;
        }
      }
    }
    return best;
  }
};

/// A random TwoFreeDirections: turns within ±max_turn_deg, steps 1 to 10, given directions within
/// ±given_deg of their chords.
inline TwoFreeDirections two_free_directions(std::uint64_t seed, double max_turn_deg,
                                             double given_deg) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr double deg = std::numbers::pi / 180;
  TwoFreeDirections t;
  double heading = 0.0;
  t.p[0] = {0, 0};
  for (std::size_t i = 1; i < 4; ++i) {
    if (i > 1) heading += u(rng) * max_turn_deg * deg;
    t.p[i] = t.p[i - 1] + std::pow(10.0, 0.5 * (u(rng) + 1.0)) * from_angle(heading);
  }
  t.start = u(rng) * given_deg * deg;
  t.end = heading + u(rng) * given_deg * deg;
  return t;
}

}  // namespace fairspline::testing
