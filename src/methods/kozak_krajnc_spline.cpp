// Kozak–Krajnc, Section 4: sweeps, selection and the `kozak-krajnc` method.
// See include/fairspline/methods/kozak_krajnc_spline.hpp and docs/methods/kozak-krajnc.md.
#include "fairspline/methods/kozak_krajnc_spline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>

#include "detail/choices.hpp"
#include "detail/finite.hpp"
#include "detail/format.hpp"
#include "detail/input.hpp"
#include "detail/progress.hpp"
#include "detail/tridiagonal.hpp"
#include "fairspline/error.hpp"
#include "fairspline/methods/kozak_krajnc.hpp"
#include "fairspline/methods/yong_cheng.hpp"

namespace fairspline {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string pt(std::size_t i) {
  std::string s = std::to_string(i);
  s.insert(s.begin(), 'T');  // (not "T" + …: GCC 12 warns -Wrestrict on that)
  return s;
}

/// (aξ + b) / (cξ + d) on (0, 1), with no pole inside (0, 1).
struct Mobius {
  double a = 0, b = 0, c = 0, d = 0;

  double operator()(double x) const { return (a * x + b) / (c * x + d); }
  /// The limit at x from inside (0, 1): `from_above` = approaching from larger ξ.
  double limit(double x, bool from_above) const {
    const double num = a * x + b, den = c * x + d;
    if (den != 0.0) return num / den;
    const double s = (from_above ? 1.0 : -1.0) * (c > 0 ? 1.0 : -1.0);
    return (num > 0 ? 1.0 : -1.0) * s * kInf;
  }
  /// Sign of the denominator on (0, 1).
  double den_sign() const { return c * 0.5 + d > 0 ? 1.0 : -1.0; }

  /// Image of an interval of ξ (monotone map).
  XiInterval image(const XiInterval& x) const {
    if (x.point) {
      const double v = (*this)(x.lo);
      return {v, v, true};
    }
    const double p = limit(x.lo, true), q = limit(x.hi, false);
    return {std::min(p, q), std::max(p, q), false};
  }
  /// {ξ ∈ (0, 1) : lo < M(ξ) < hi} (open; lo = −∞ / hi = +∞ allowed).
  XiInterval preimage(double lo, double hi) const {
    double from = 0.0, to = 1.0;
    const double s = den_sign();
    auto half = [&](double k, double k0) {  // s·(kξ + k0) > 0
      k *= s;
      k0 *= s;
      if (k > 0) {
        from = std::max(from, -k0 / k);
      } else if (k < 0) {
        to = std::min(to, -k0 / k);
      } else if (!(k0 > 0)) {
        to = from;  // empty
      }
    };
    if (lo > -kInf) half(a - lo * c, b - lo * d);
    if (hi < kInf) half(hi * c - a, hi * d - b);
    return {from, to, false};
  }
};

bool empty(const XiInterval& x) {
  return x.point ? false : !(x.lo < x.hi);
}

std::optional<XiInterval> intersect(const XiInterval& x, const XiInterval& y) {
  if (x.point && y.point) {
    if (x.lo == y.lo) return x;
    return std::nullopt;
  }
  if (x.point || y.point) {
    const XiInterval& p = x.point ? x : y;
    const XiInterval& o = x.point ? y : x;
    if (o.contains(p.lo)) return p;
    return std::nullopt;
  }
  XiInterval r{std::max(x.lo, y.lo), std::min(x.hi, y.hi), false};
  if (empty(r)) return std::nullopt;
  return r;
}

/// Sorts and merges overlapping open intervals (touching ones stay apart: the point between is
/// excluded).
void normalize(XiSet& s) {
  std::sort(s.begin(), s.end(), [](const auto& x, const auto& y) { return x.lo < y.lo; });
  std::size_t k = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (k > 0 && !s[k - 1].point && !s[i].point && s[i].lo < s[k - 1].hi) {
      s[k - 1].hi = std::max(s[k - 1].hi, s[i].hi);
    } else {
      s[k++] = s[i];
    }
  }
  s.resize(k);
}

/// Everything the sweeps need about T0..T3m, computed once.
struct Geometry {
  std::span<const Point> T;    ///< T0..T3m
  std::span<const Point> all;  ///< T0..T3m and the remainder points that follow (if any)
  std::size_t m = 0;
  std::vector<Vec2> dT;
  struct Piece {
    double lambda1 = 0, lambda2 = 0;
    bool convex = false;
    double phi1 = 0, phi2 = 0;  // convex only
    Mobius mu_left, mu_right;   // μ2ℓ−1(ξℓ−1), μ2ℓ(ξℓ)
  };
  std::vector<Piece> piece;  // 1-based: piece[0] unused
  std::vector<Vec2> u, v;    // dℓ(ξ) = (1 − ξ) u + ξ v

  double D(std::size_t i, std::size_t j) const { return cross(dT[i], dT[j]); }
};

/// (1 − ξ)u + ξv, to about ε² of |u| + |v| (error-free sums and fma products). Where u, v are
/// nearly opposite (T3ℓ−1, T3ℓ, T3ℓ+1 straight to rounding, but σ turning the cone (4.1) to
/// the half-plane beside them) the terms cancel to ~1e-17 of their size inside a ξ-window
/// narrower than an ulp, and plain double arithmetic returned a zero vector (its direction NaN).
/// u × v ≠ 0 exactly (geometry() requires the chords' determinant non-zero), so the exact
/// value is not zero, and its leading digits are what this returns.
Vec2 cone_point(Vec2 u, Vec2 v, double xi) {
  auto two_sum = [](double a, double b, double& err) {
    const double s = a + b, bb = s - a;
    err = (a - (s - bb)) + (b - bb);
    return s;
  };
  double a_lo = 0.0;
  const double a = two_sum(1.0, -xi, a_lo);  // 1 − ξ = a + a_lo exactly
  auto coordinate = [&](double uc, double vc) {
    const double p = a * uc, q = xi * vc;
    const double p_lo = std::fma(a, uc, -p), q_lo = std::fma(xi, vc, -q);
    double s_lo = 0.0;
    const double s = two_sum(p, q, s_lo);
    return s + (s_lo + p_lo + q_lo + a_lo * uc);
  };
  return {coordinate(u.x, v.x), coordinate(u.y, v.y)};
}

Mobius mobius(double n0, double n1, double e0, double e1) {
  return {n1 - n0, n0, e1 - e0, e0};
}

/// Throws when three consecutive points T(k), T(k+1), T(k+2) are collinear (kind 0) or the
/// chords T(k)T(k+1), T(k+2)T(k+3) are parallel (kind 1), i.e. when D = det(a, b) of those
/// chords is zero; with `rounding`, also when |D| is within its rounding error. The sweeps take
/// σ and the signs of λ, δ, μ from such determinants: below their rounding these are noise
/// (stress inputs with points collinear to 1e-17 rad gave a tangent cone (4.1) whose admissible
/// part was narrower than an ulp of ξ, and NaN directions). The message is built only then.
void require_independent(Vec2 a, Vec2 b, std::size_t k, int kind, bool rounding) {
  const double d = cross(a, b);
  // The chords' own rounding (ε/2 each) and the determinant's (< 1.5ε), with a margin.
  const double bound = rounding ? 4.0 * std::numeric_limits<double>::epsilon() *
                                      (std::abs(a.x * b.y) + std::abs(a.y * b.x))
                                : 0.0;
  if (std::abs(d) > bound) return;
  const std::string which =
      kind == 0 ? pt(k) + ", " + pt(k + 1) + ", " + pt(k + 2) + " are "
                : "chords " + pt(k) + pt(k + 1) + " and " + pt(k + 2) + pt(k + 3) + " are ";
  const std::string what = kind == 0 ? "collinear" : "parallel";
  const std::string how =
      d == 0.0
          ? what
          : what + " to within rounding (they turn by " +
                detail::format_number(std::asin(std::min(1.0, std::abs(d) / (norm(a) * norm(b))))) +
                " rad, below what double precision resolves)";
  throw Error(ErrorCode::kInvalidArgument,
              "kozak-krajnc: " + which + how + " (Theorem 4.1 needs them not to be)", k + 1);
}

/// `all` (optional) continues T with remainder points: then T3m is not the end of the curve and
/// its direction is parameterized like an interior breakpoint of (4.1) (σ3m = +1 when ΔT3m+1
/// does not exist), so that the curve can go on G1 past it.
/// `sweeps` = false (every direction prescribed): only what solving the pieces needs is
/// checked; Theorem 4.1's further assumptions (no parallel chords, no piece turning past a half
/// turn, interior breakpoints off the chords' line) do not apply.
Geometry geometry(std::span<const Point> T, std::span<const Point> all = {}, bool sweeps = true) {
  Geometry g;
  g.T = T;
  g.all = all.size() > T.size() ? all : T;
  g.m = (T.size() - 1) / 3;
  const std::size_t m = g.m;
  g.dT.resize(g.all.size() - 1);
  for (std::size_t i = 0; i + 1 < g.all.size(); ++i) g.dT[i] = g.all[i + 1] - g.all[i];
  const bool goes_on = g.all.size() > T.size();
  g.u.resize(m + 1);
  g.v.resize(m + 1);
  for (std::size_t l = 1; l <= m; ++l) {  // assumptions of Theorem 4.1 on piece ℓ
    const std::size_t k = 3 * l - 3;
    require_independent(g.dT[k], g.dT[k + 1], k, 0, sweeps);
    require_independent(g.dT[k + 1], g.dT[k + 2], k + 1, 0, sweeps);
    // λ's numerator: exact test still (parallel-to-rounding chords are open, docs/hardening.md).
    if (sweeps) require_independent(g.dT[k], g.dT[k + 2], k, 1, false);
  }
  for (std::size_t l = 1; sweeps && l < m + (goes_on ? 1 : 0); ++l) {
    require_independent(g.dT[3 * l - 1], g.dT[3 * l], 3 * l - 1, 0, true);
  }
  // (4.1)
  g.u[0] = -1.0 * g.dT[1];
  g.v[0] = g.dT[0];
  for (std::size_t l = 1; l < m; ++l) {
    const std::size_t k = 3 * l;
    const double sk = g.D(k - 1, k) * g.D(k, k + 1) > 0 ? 1.0 : -1.0;       // σ3ℓ
    const double sk1 = g.D(k - 2, k - 1) * g.D(k - 1, k) > 0 ? 1.0 : -1.0;  // σ3ℓ−1
    g.u[l] = sk * g.dT[k - 1];
    g.v[l] = sk1 * g.dT[k];
  }
  if (goes_on) {
    const std::size_t k = 3 * m;
    const double sk = k + 1 < g.dT.size() && g.D(k - 1, k) * g.D(k, k + 1) < 0 ? -1.0 : 1.0;
    const double sk1 = g.D(k - 2, k - 1) * g.D(k - 1, k) > 0 ? 1.0 : -1.0;
    g.u[m] = sk * g.dT[k - 1];
    g.v[m] = sk1 * g.dT[k];
  } else {
    g.u[m] = g.dT[3 * m - 1];
    g.v[m] = -1.0 * g.dT[3 * m - 2];
  }

  g.piece.resize(m + 1);
  for (std::size_t l = 1; l <= m; ++l) {
    const std::size_t k = 3 * l - 3;
    Geometry::Piece& p = g.piece[l];
    p.lambda1 = g.D(k, k + 2) / g.D(k, k + 1);
    p.lambda2 = g.D(k, k + 2) / g.D(k + 1, k + 2);
    // Reported for every piece (method_report), swept or not.
    p.convex = p.lambda1 > 0 && p.lambda2 > 0;
    if (!sweeps) continue;
    if (p.lambda1 < 0 && p.lambda2 < 0) {
      throw Error(ErrorCode::kInvalidArgument,
                  "kozak-krajnc: points " + pt(k) + ".." + pt(k + 3) +
                      " turn by more than a half turn (λ" + std::to_string(2 * l - 1) + ", λ" +
                      std::to_string(2 * l) +
                      " < 0); the sweeps of Section 4 (Theorem 4.1) do not cover this piece",
                  k);
    }
    if (p.convex) {
      p.phi1 = *kozak_krajnc_phi1(p.lambda1, p.lambda2);
      p.phi2 = *kozak_krajnc_phi2(p.lambda1, p.lambda2);
    }
    // μ2ℓ−1(ξ) = det(dℓ−1, ΔTk+1) / det(dℓ−1, ΔTk); μ2ℓ(ξ) = det(ΔTk+1, dℓ) / det(ΔTk+2, dℓ).
    const Vec2 ul = g.u[l - 1], vl = g.v[l - 1], ur = g.u[l], vr = g.v[l];
    p.mu_left = mobius(cross(ul, g.dT[k + 1]), cross(vl, g.dT[k + 1]), cross(ul, g.dT[k]),
                       cross(vl, g.dT[k]));
    p.mu_right = mobius(cross(g.dT[k + 1], ur), cross(g.dT[k + 1], vr), cross(g.dT[k + 2], ur),
                        cross(g.dT[k + 2], vr));
  }
  return g;
}

/// Convex pieces (Theorem 2.4): μ-values below (above) the threshold `from` have as partners
/// the values below (above) `to` on the other end.
void convex_partners(const XiInterval& mu, double from, double to, XiSet& out) {
  const double lo = mu.lo, hi = mu.hi;
  const bool below = mu.point ? (lo > 0 && lo < from) : (lo < from && hi > 0);
  const bool above = mu.point ? lo > from : hi > from;
  if (below) out.push_back({0.0, to, false});
  if (above) out.push_back({to, kInf, false});
}

/// μ2ℓ-values with an admissible partner in the μ2ℓ−1-interval `mu` (ForwardSplit's J).
void forward_split(const Geometry::Piece& p, const XiInterval& mu, XiSet& out) {
  if (p.convex) return convex_partners(mu, p.phi1, p.phi2, out);
  const auto r = p.lambda1 > 0 ? kozak_krajnc_r1(mu, p.lambda1, p.lambda2)
                               : kozak_krajnc_r2(mu, p.lambda2, p.lambda1);
  if (r) out.push_back(*r);
}

/// μ2ℓ−1-values with an admissible partner in the μ2ℓ-interval `mu` (BackwardSplit's J).
void backward_split(const Geometry::Piece& p, const XiInterval& mu, XiSet& out) {
  if (p.convex) return convex_partners(mu, p.phi2, p.phi1, out);
  const auto r = p.lambda1 > 0 ? kozak_krajnc_r2(mu, p.lambda1, p.lambda2)
                               : kozak_krajnc_r1(mu, p.lambda2, p.lambda1);
  if (r) out.push_back(*r);
}

/// {ξ ∈ base : M(ξ) ∈ J} for a set J of open μ-intervals.
XiSet pull_back(const Mobius& M, const XiSet& J, const XiSet& base) {
  XiSet out;
  for (const XiInterval& j : J) {
    const XiInterval pre = M.preimage(j.lo, j.hi);
    if (empty(pre)) continue;
    for (const XiInterval& b : base) {
      if (auto x = intersect(pre, b)) out.push_back(*x);
    }
  }
  normalize(out);
  return out;
}

std::string describe(const XiSet& s) {
  std::string r;
  for (const XiInterval& x : s) {
    if (!r.empty()) r += " ∪ ";
    r += x.point ? "{" + detail::format_number(x.lo) + "}"
                 : "(" + detail::format_number(x.lo) + ", " + detail::format_number(x.hi) + ")";
  }
  return r.empty() ? "∅" : r;
}

/// A point of one component of `s`: the component containing `guide`, else the one nearest to
/// it (without a guide, NaN: the longest one). In it, the γ-point; with gamma = NaN ("auto") the
/// guide itself, kept 10% of the component's width away from its ends.
double pick(const XiSet& s, double gamma, double guide) {
  const XiInterval* best = &s.front();
  double best_key = kInf;
  for (const XiInterval& x : s) {
    double key;
    if (std::isnan(guide)) {
      key = x.point ? 0.0 : -(x.hi - x.lo);
    } else {
      key = x.contains(guide) ? -1.0 : std::min(std::abs(guide - x.lo), std::abs(guide - x.hi));
    }
    if (key < best_key) best_key = key, best = &x;
  }
  if (!std::isnan(gamma) || best->point) return best->at(std::isnan(gamma) ? 0.5 : gamma);
  if (std::isnan(guide)) return best->at(0.5);
  const double margin = 0.1 * (best->hi - best->lo);
  return std::clamp(guide, best->lo + margin, best->hi - margin);
}

}  // namespace

std::optional<XiInterval> kozak_krajnc_r1(XiInterval mu, double lambda1, double lambda2) {
  const double a = std::max(mu.lo, 0.0), b = mu.hi;
  if (b <= 0.0 || (mu.point && mu.lo <= 0.0)) return std::nullopt;
  const double lo = kozak_krajnc_phi3(lambda1, lambda2, a);
  const double hi = b == kInf ? (1.0 + 2.0 * lambda1) / (lambda1 * lambda1)
                              : kozak_krajnc_phi4(lambda1, lambda2, b);
  if (!(lo < hi)) return std::nullopt;
  return XiInterval{lo, hi, false};
}

std::optional<XiInterval> kozak_krajnc_r2(XiInterval mu, double lambda1, double lambda2) {
  const double a = std::max(mu.lo, 0.0), b = mu.hi;
  if (b <= 0.0 || (mu.point && mu.lo <= 0.0)) return std::nullopt;
  if (a >= (1.0 + 2.0 * lambda1) / (lambda1 * lambda1)) return std::nullopt;
  const double lo = kozak_krajnc_phi3(lambda2, lambda1, a);
  const double hi = b < 1.0 / lambda1 ? kozak_krajnc_phi4(lambda2, lambda1, b) : kInf;
  if (!(lo < hi)) return std::nullopt;
  return XiInterval{lo, hi, false};
}

namespace {

KozakKrajncSweep sweep(const Geometry& g, std::span<const std::optional<double>> fixed) {
  const std::size_t m = g.m;
  KozakKrajncSweep s;
  s.pieces = m;
  s.I.resize(m + 1);
  // Iℓ: both μ at breakpoint ℓ positive.
  for (std::size_t l = 0; l <= m; ++l) {
    XiInterval I{0.0, 1.0, false};
    if (l >= 1) {
      if (auto x = intersect(I, g.piece[l].mu_right.preimage(0.0, kInf))) {
        I = *x;
      } else {
        I = {1.0, 0.0, false};
      }
    }
    if (l < m && !empty(I)) {
      if (auto x = intersect(I, g.piece[l + 1].mu_left.preimage(0.0, kInf))) {
        I = *x;
      } else {
        I = {1.0, 0.0, false};
      }
    }
    if (empty(I)) {
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: no tangent direction at " + pt(3 * l) + " makes both constants μ" +
                      std::to_string(2 * l) + ", μ" + std::to_string(2 * l + 1) +
                      " positive ((4.4)-(4.6) hold): the admissible set is empty there",
                  3 * l);
    }
    s.I[l] = I;
  }
  auto base = [&](std::size_t l) {
    XiSet b{s.I[l]};
    if (l < fixed.size() && fixed[l]) {
      const XiInterval p{*fixed[l], *fixed[l], true};
      if (!s.I[l].contains(*fixed[l])) {
        throw Error(ErrorCode::kInfeasible,
                    "kozak-krajnc: the prescribed tangent at " + pt(3 * l) +
                        " (ξ = " + detail::format_number(*fixed[l]) +
                        ") makes a constant μ non-positive; Iℓ = " + describe(b),
                    3 * l);
      }
      b = {p};
    }
    return b;
  };
  s.forward.resize(m + 1);
  s.forward[0] = base(0);
  for (std::size_t l = 1; l <= m; ++l) {
    const Geometry::Piece& p = g.piece[l];
    XiSet J;
    for (const XiInterval& x : s.forward[l - 1]) forward_split(p, p.mu_left.image(x), J);
    normalize(J);
    s.forward[l] = pull_back(p.mu_right, J, base(l));
    if (s.forward[l].empty()) {
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: the forward sweep found no admissible tangent direction at " +
                      pt(3 * l) + ": the admissible set became empty at piece " +
                      std::to_string(l) + " (" + pt(3 * l - 3) + ".." + pt(3 * l) + "); Ξ" +
                      std::to_string(l - 1) + " = " + describe(s.forward[l - 1]),
                  3 * l - 3);
    }
  }
  s.xi = s.forward;
  for (std::size_t l = m; l >= 1; --l) {
    const Geometry::Piece& p = g.piece[l];
    XiSet J;
    for (const XiInterval& x : s.xi[l]) backward_split(p, p.mu_right.image(x), J);
    normalize(J);
    s.xi[l - 1] = pull_back(p.mu_left, J, s.forward[l - 1]);
    if (s.xi[l - 1].empty()) {  // only by rounding at an interval end
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: the backward sweep emptied Ξ" + std::to_string(l - 1) + " at " +
                      pt(3 * l - 3) + " (rounding at an end of the admissible interval)",
                  3 * l - 3);
    }
  }
  return s;
}

/// Tangent of the parabola through T[i−1], T[i], T[i+1] (or the first/last three points at the
/// ends) at T[i], with uniform or chord-length parameters.
Vec2 local_quadratic_direction(std::span<const Point> T, std::size_t i, bool chordal) {
  const std::size_t n = T.size();
  const std::size_t c = i == 0 ? 1 : (i + 1 == n ? n - 2 : i);
  const Point a = T[c - 1], b = T[c], e = T[c + 1];
  const double h0 = chordal ? norm(b - a) : 1.0, h1 = chordal ? norm(e - b) : 1.0, h = h0 + h1;
  if (i == 0) return (-(2 * h0 + h1) / (h0 * h)) * a + (h / (h0 * h1)) * b + (-h0 / (h1 * h)) * e;
  if (i + 1 == n)
    return (h1 / (h0 * h)) * a + (-h / (h0 * h1)) * b + ((2 * h1 + h0) / (h1 * h)) * e;
  return (-h1 / (h0 * h)) * a + ((h1 - h0) / (h0 * h1)) * b + (h0 / (h1 * h)) * e;
}

std::optional<double> xi_of(const Geometry& g, std::size_t l, Vec2 direction) {
  const Vec2 u = g.u[l], v = g.v[l];
  // cross((1 − ξ)u + ξv, d) = 0.
  const double cu = cross(u, direction), cv = cross(v, direction);
  if (cu == cv) return std::nullopt;
  const double xi = cu / (cu - cv);
  if (!(xi > 0.0 && xi < 1.0)) return std::nullopt;
  if (!(dot((1.0 - xi) * u + xi * v, direction) > 0.0)) return std::nullopt;
  return xi;
}

/// The ξ of the chord-length parabola's tangent at each breakpoint (NaN outside the cone (4.1)):
/// the guide that picks a component when Ξ splits.
std::vector<double> quadratic_guide(const Geometry& g) {
  std::vector<double> guide(g.m + 1);
  for (std::size_t l = 0; l <= g.m; ++l) {
    guide[l] = xi_of(g, l, local_quadratic_direction(g.all, 3 * l, true))
                   .value_or(std::numeric_limits<double>::quiet_NaN());
  }
  return guide;
}

std::vector<double> select(const Geometry& g, const KozakKrajncSweep& s, double gamma) {
  const std::vector<double> guide = quadratic_guide(g);
  std::vector<double> xi(g.m + 1);
  xi[0] = pick(s.xi[0], gamma, guide[0]);
  for (std::size_t l = 1; l <= g.m; ++l) {
    const Geometry::Piece& p = g.piece[l];
    XiSet J;
    forward_split(p, p.mu_left.image({xi[l - 1], xi[l - 1], true}), J);
    normalize(J);
    const XiSet C = pull_back(p.mu_right, J, s.xi[l]);
    if (C.empty()) {
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: no admissible ξ at " + pt(3 * l) + " for the chosen ξ at " +
                      pt(3 * l - 3) + " (rounding at an end of the admissible interval)",
                  3 * l);
    }
    xi[l] = pick(C, gamma, guide[l]);
  }
  return xi;
}

}  // namespace

KozakKrajncSweep kozak_krajnc_sweep(std::span<const Point> points,
                                    std::span<const std::optional<double>> fixed) {
  if (points.size() < 4 || (points.size() - 1) % 3 != 0) {
    throw Error(ErrorCode::kWrongPointCount,
                "kozak-krajnc: the sweeps need 3m+1 points, got " + std::to_string(points.size()));
  }
  return sweep(geometry(points), fixed);
}

std::vector<double> kozak_krajnc_select(std::span<const Point> points,
                                        const KozakKrajncSweep& sweep, double gamma) {
  return select(geometry(points), sweep, gamma);
}

// ---------------------------------------------------------------------------------------------
// The method.

namespace {

struct PieceFit {
  KozakKrajncSolutions all;
  KozakKrajncSolution s;
  Vec2 d0, d3;  // unit
  CubicBezier c;
};

/// Solves piece ℓ for unit directions d0, d3; with `near`, continues that branch (nearest
/// (t1, t2)) instead of taking the least-energy solution. False when it has no solution.
bool solve_piece(const Geometry& g, std::size_t l, Vec2 d0, Vec2 d3, const PieceFit* near,
                 PieceFit& out) {
  const std::size_t k = 3 * l - 3;
  out.d0 = d0;
  out.d3 = d3;
  out.all = kozak_krajnc_solve(g.T[k], g.T[k + 1], g.T[k + 2], g.T[k + 3], d0, d3);
  if (out.all.count == 0) return false;
  int best = out.all.chosen;
  if (near) {
    double dist = kInf;
    for (int i = 0; i < out.all.count; ++i) {
      const auto& s = out.all.items[i];
      const double d = std::abs(s.t1 - near->s.t1) + std::abs(s.t2 - near->s.t2);
      if (d < dist) dist = d, best = i;
    }
  }
  out.s = out.all.items[best];
  out.c = kozak_krajnc_bezier(g.T[k], g.T[k + 3], d0, d3, out.s);
  return true;
}

Vec2 direction(const Geometry& g, std::size_t l, double xi) {
  return normalized(cone_point(g.u[l], g.v[l], xi));
}

bool admissible(const Geometry& g, std::size_t l, Vec2 d0, Vec2 d3) {
  const std::size_t k = 3 * l - 3;
  const KozakKrajncConstants c =
      kozak_krajnc_constants(g.T[k], g.T[k + 1], g.T[k + 2], g.T[k + 3], d0, d3);
  return kozak_krajnc_theorem_2_4(c) || kozak_krajnc_theorem_2_5(c);
}

/// The G2 Newton stops when every scaled curvature jump (1.4) is below this.
constexpr double kG2Tolerance = 1e-10;
/// The largest scaled jump accepted, as optimal to double precision, at a sign change of the
/// jump between two adjacent doubles of ξ (docs/methods/kozak-krajnc.md, "g2=true").
constexpr double kG2Resolved = 1e-6;
/// Step of the finite-difference Jacobian of (1.4) in ξ.
constexpr double kG2JacobianStep = 1e-7;

/// Result of the optional G2 Newton iteration on (1.4).
struct G2Report {
  bool converged = false;
  bool at_cap = false;  ///< stopped by the iteration limit (else: by `reason`)
  /// Not converged, but the jump changes sign between two adjacent doubles of ξ and is within
  /// kG2Resolved there: the tolerance is below what double precision resolves (not an error).
  bool at_precision = false;
  int iterations = 0;
  double residual = 0.0;
  std::string reason;
};

/// (1.4) as a curvature jump, made dimensionless by the local chord length.
double g2_residual(const Geometry& g, std::size_t l, const PieceFit& left, const PieceFit& right) {
  const double len = 0.5 * (norm(g.dT[3 * l - 1]) + norm(g.dT[3 * l]));
  return (left.c.curvature(1.0) - right.c.curvature(0.0)) * len;
}

/// The scaled jump at T3l as the output shows it (the pieces split at t1, t2: the last span of
/// piece l against the first of piece l + 1), and a bound of its rounding (relative error
/// ~ε·size/arm in each end curvature, as the stress certificate allows).
struct SplitJump {
  double jump = 0.0, rounding = 0.0;
};
SplitJump split_jump(const Geometry& g, std::size_t l, const PieceFit& left,
                     const PieceFit& right) {
  const CubicBezier a = left.c.subsegment(left.s.t2, 1.0), b = right.c.subsegment(0.0, right.s.t1);
  const double len = 0.5 * (norm(g.dT[3 * l - 1]) + norm(g.dT[3 * l]));
  const double kl = a.curvature(1.0), kr = b.curvature(0.0);
  double size = 0.0;
  for (const CubicBezier* c : {&a, &b}) {
    for (const Point& q : c->p) size = std::max({size, std::abs(q.x), std::abs(q.y)});
  }
  const double arm = std::min(norm(a.p[3] - a.p[2]), norm(b.p[1] - b.p[0]));
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  return {std::abs(kl - kr) * len,
          16.0 * kEpsilon * (size / arm) * (std::abs(kl) + std::abs(kr) + 1.0 / arm) * len};
}

G2Report solve_g2(const Geometry& g, std::vector<double>& xi, std::span<const char> pinned,
                  int max_iterations, std::vector<PieceFit>& pieces) {
  G2Report rep;
  const std::size_t m = g.m;
  if (m < 2) {
    rep.converged = true;
    return rep;
  }
  // Evaluates every piece for `x` (continuing the branches of `ref`) and the residuals.
  auto evaluate = [&](const std::vector<double>& x, const std::vector<PieceFit>& ref,
                      std::vector<PieceFit>& fit, std::vector<double>& r) {
    fit.resize(m + 1);
    r.assign(m + 1, 0.0);
    for (std::size_t l = 1; l <= m; ++l) {
      if (!(x[l - 1] > 0.0 && x[l - 1] < 1.0 && x[l] > 0.0 && x[l] < 1.0)) return false;
      const Vec2 d0 = direction(g, l - 1, x[l - 1]), d3 = direction(g, l, x[l]);
      if (!solve_piece(g, l, d0, d3, &ref[l], fit[l])) return false;
    }
    for (std::size_t l = 1; l < m; ++l) {
      if (!pinned[l]) r[l] = g2_residual(g, l, fit[l], fit[l + 1]);
    }
    return true;
  };
  auto max_abs = [](const std::vector<double>& r) {
    double v = 0.0;
    for (double x : r) v = std::max(v, std::abs(x));
    return v;
  };
  std::vector<double> r, rp, sub(m - 1), diag(m - 1), super(m - 1), scratch;
  std::vector<Vec2> rhs(m - 1);
  std::vector<PieceFit> trial;
  if (!evaluate(xi, pieces, pieces, r)) {
    rep.reason = "the G1 solution could not be re-evaluated";
    return rep;
  }
  const double h = kG2JacobianStep;
  for (rep.iterations = 0; rep.iterations < max_iterations; ++rep.iterations) {
    detail::checkpoint("g2", static_cast<std::size_t>(rep.iterations));
    rep.residual = max_abs(r);
    if (rep.residual <= kG2Tolerance) {
      rep.converged = true;
      return rep;
    }
    // Tridiagonal Jacobian by finite differences, three colours (ξ indices mod 3).
    std::fill(sub.begin(), sub.end(), 0.0);
    std::fill(super.begin(), super.end(), 0.0);
    for (std::size_t l = 1; l < m; ++l) diag[l - 1] = pinned[l] ? 1.0 : 0.0;
    for (std::size_t colour = 0; colour < 3; ++colour) {
      std::vector<double> x = xi;
      bool any = false;
      for (std::size_t j = 1; j < m; ++j) {
        if (j % 3 == colour && !pinned[j]) x[j] += h, any = true;
      }
      if (!any) continue;
      if (!evaluate(x, pieces, trial, rp)) {
        rep.reason = "a finite-difference step left the directions with admissible pieces";
        return rep;
      }
      for (std::size_t l = 1; l < m; ++l) {
        if (pinned[l]) continue;
        for (std::size_t j = l - 1; j <= l + 1; ++j) {
          if (j < 1 || j >= m || j % 3 != colour || pinned[j]) continue;
          const double dr = (rp[l] - r[l]) / h;
          if (j + 1 == l) sub[l - 1] = dr;
          if (j == l) diag[l - 1] = dr;
          if (j == l + 1) super[l - 1] = dr;
        }
      }
    }
    for (std::size_t l = 1; l < m; ++l) rhs[l - 1] = {-r[l], 0.0};
    if (!detail::solve_tridiagonal(sub, diag, super, rhs, scratch)) {
      rep.reason = "singular Jacobian";
      return rep;
    }
    double step = 1.0;
    bool accepted = false;
    for (int half = 0; half < 30 && !accepted; ++half, step *= 0.5) {
      std::vector<double> x = xi;
      for (std::size_t l = 1; l < m; ++l) x[l] += step * rhs[l - 1].x;
      if (evaluate(x, pieces, trial, rp) && max_abs(rp) < (1.0 - 1e-4 * step) * rep.residual) {
        xi = x;
        pieces.swap(trial);
        r.swap(rp);
        accepted = true;
      }
    }
    if (!accepted) {
      rep.reason = "no step that keeps every piece admissible reduces the curvature jumps";
      rep.residual = max_abs(r);
      return rep;
    }
  }
  rep.residual = max_abs(r);
  rep.converged = rep.residual <= kG2Tolerance;
  if (!rep.converged) rep.reason = "iteration limit reached", rep.at_cap = true;
  return rep;
}

nlohmann::json interval_json(const XiInterval& x) {
  return nlohmann::json::array({x.lo, x.hi});
}

nlohmann::json set_json(const XiSet& s) {
  nlohmann::json a = nlohmann::json::array();
  for (const XiInterval& x : s) a.push_back(interval_json(x));
  return a;
}

/// What method_report holds, typed; serialized once by report_json. Solutions are in the input's
/// units.
struct KozakKrajncReport {
  struct Solution {
    double t1 = 0, t2 = 0, alpha0 = 0, alpha3 = 0;
    int multiplicity = 1;
    std::optional<double> energy;  ///< empty: beyond the double range (null)
  };
  struct Piece {
    Solution chosen;
    std::size_t first = 0, last = 0;  ///< T3ℓ−3, T3ℓ
    std::vector<Solution> solutions;
    double xi_left = 0, xi_right = 0;
    bool convex = false;
    double lambda1 = 0, lambda2 = 0;
    bool theorem = false;
  };
  struct Breakpoint {
    std::size_t point = 0;
    double xi = 0;
    bool prescribed = false;
    bool swept = false;  ///< the sweep entries below are reported
    XiSet xi_set, forward;
    XiInterval I;
    bool in_xi = false;
  };
  struct Remainder {
    std::size_t spans = 0, first_point = 0;
    int pieces = 0;
  };
  struct G2 {
    bool converged = false;
    bool at_precision = false;  ///< optimal to double precision (kG2Resolved)
    int iterations = 0;
    double residual = 0;
    std::string reason, start;
  };
  std::size_t pieces = 0;
  bool detailed = false;  ///< level != kNone: segments and breakpoints are reported
  std::vector<Piece> segments;
  std::vector<Breakpoint> breakpoints;
  bool sweeps = false;
  std::string tangents;
  double gamma = 0;  ///< NaN: "auto"
  std::optional<Remainder> remainder;
  std::optional<G2> g2;
};

/// A solution of the scaled problem in the input's units (α ∝ length, energy ∝ length²). An
/// energy beyond the double range (chords near 1e±300: length² is 1e±600) is null, not Inf.
KozakKrajncReport::Solution solution_report(const KozakKrajncSolution& s, double unscale) {
  const double energy = s.energy * unscale * unscale;
  KozakKrajncReport::Solution r{.t1 = s.t1,
                                .t2 = s.t2,
                                .alpha0 = s.alpha0 * unscale,
                                .alpha3 = s.alpha3 * unscale,
                                .multiplicity = s.multiplicity,
                                .energy = std::nullopt};
  if (std::isfinite(energy) && (energy > 0.0 || s.energy == 0.0)) r.energy = energy;
  return r;
}

nlohmann::json solution_json(const KozakKrajncReport::Solution& s) {
  return {{"t1", s.t1},
          {"t2", s.t2},
          {"alpha0", s.alpha0},
          {"alpha3", s.alpha3},
          {"multiplicity", s.multiplicity},
          {"energy", s.energy ? nlohmann::json(*s.energy) : nlohmann::json(nullptr)}};
}

/// The per-piece and per-breakpoint entries (diagnostics), O(n) in size.
void detail_json(const KozakKrajncReport& r, nlohmann::json& j) {
  nlohmann::json segs = nlohmann::json::array();
  for (const KozakKrajncReport::Piece& p : r.segments) {
    nlohmann::json sols = nlohmann::json::array();
    for (const KozakKrajncReport::Solution& s : p.solutions) sols.push_back(solution_json(s));
    nlohmann::json seg = solution_json(p.chosen);
    seg["points"] = {p.first, p.last};
    seg["solutions"] = sols;
    seg["xi"] = {p.xi_left, p.xi_right};
    seg["convex"] = p.convex;
    seg["lambda"] = {p.lambda1, p.lambda2};
    seg["theorem"] = p.theorem;
    segs.push_back(seg);
  }
  j["segments"] = segs;
  nlohmann::json bps = nlohmann::json::array();
  for (const KozakKrajncReport::Breakpoint& b : r.breakpoints) {
    nlohmann::json bp = {{"point", b.point}, {"xi", b.xi}, {"prescribed", b.prescribed}};
    if (b.swept) {
      bp["Xi"] = set_json(b.xi_set);
      bp["Xi_forward"] = set_json(b.forward);
      bp["I"] = interval_json(b.I);
      bp["in_Xi"] = b.in_xi;
    }
    bps.push_back(bp);
  }
  j["breakpoints"] = bps;
}

nlohmann::json report_json(const KozakKrajncReport& r) {
  nlohmann::json j = nlohmann::json::object();
  j["pieces"] = r.pieces;
  if (r.detailed) detail_json(r, j);
  j["sweeps"] = r.sweeps;
  j["tangents"] = r.tangents;
  j["gamma"] = std::isnan(r.gamma) ? nlohmann::json("auto") : nlohmann::json(r.gamma);
  if (r.remainder) {
    j["remainder"] = {{"spans", r.remainder->spans},
                      {"first_point", r.remainder->first_point},
                      {"construction", "yong-cheng-coh"},
                      {"pieces", r.remainder->pieces}};
  }
  if (r.g2) {
    j["g2"] = {{"converged", r.g2->converged},
               {"status", r.g2->converged      ? "converged"
                          : r.g2->at_precision ? "conditioning_limit"
                                               : "not_converged"},
               {"iterations", r.g2->iterations},
               {"max_scaled_curvature_jump", r.g2->residual},
               {"reason", r.g2->reason},
               {"start", r.g2->start}};
  }
  return j;
}

constexpr detail::ChoiceTable<KozakKrajncTangents, 3> kTangentRule{
    {{"sweep", KozakKrajncTangents::kSweep},
     {"local-quadratic-uniform", KozakKrajncTangents::kLocalQuadraticUniform},
     {"local-quadratic-chordal", KozakKrajncTangents::kLocalQuadraticChordal}}};

// The sweeps of Section 4 run from T0 to T3m with free end directions: open curves only.
const Capabilities& kozak_krajnc_capabilities() {
  static const Capabilities caps{
      .closed = false,
      .points = {.min_open = 4,
                 .min_closed = 4,
                 .step = 3,
                 .relaxed_by = "remainder",
                 .relaxed_value = "hermite"},
      .needs_turns = true,
      .examples = {
          R"({"points": [[0,0],[1,0.875],[2.25,1.5],[3.5,1.375],[4.625,0.75],[5.5,0],[6.625,-0.5]]})",
          R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0]], "options": {"remainder": "hermite"}})",
          R"({"points": [[0,0],[1,0.875],[2.25,1.5],[3.5,1.375],[4.625,0.75],[5.5,0],[6.625,-0.5]],
              "options": {"g2": true}})"}};
  return caps;
}

/// The prepare stage's output: the points scaled by a power of two, the prescribed directions
/// and the geometry of the pieces. Not copyable: `g` views `scaled`.
struct Prepared {
  std::size_t n = 0;     ///< points
  std::size_t rest = 0;  ///< spans left to the Hermite remainder
  std::size_t nk = 0;    ///< points covered by Kozak–Krajnc pieces
  double unscale = 1.0;
  std::vector<Point> scaled;
  std::vector<std::optional<Vec2>> given;  ///< per point
  bool all_given = false;                  ///< every breakpoint prescribed: no sweeps
  Geometry g;
  std::vector<std::optional<double>> fixed;  ///< per breakpoint: the prescribed ξ

  Prepared() = default;
  Prepared(const Prepared&) = delete;
  Prepared& operator=(const Prepared&) = delete;
};

/// The directions stage's output.
struct Directions {
  KozakKrajncSweep sw;
  std::vector<double> xi;
  std::vector<char> in_xi;  ///< ξℓ lies in the swept set Ξℓ
};

/// The optional G2 stage's output.
struct G2Outcome {
  G2Report rep;
  std::string start;  ///< the start that converged (else the first one tried)
};

/// The power of two that brings the chords to size ~1 (scaling by it is exact): the constants
/// (2.6) are products of chord coordinates and would overflow or underflow for data near the
/// ends of the double range. The curve is scaled back at the end.
int scale_exponent(const std::vector<Point>& points) {
  const std::size_t n = points.size();
  double max_chord = 0.0, max_coord = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    max_coord = std::max({max_coord, std::abs(points[i].x), std::abs(points[i].y)});
    if (i + 1 < n) {
      const Vec2 c = points[i + 1] - points[i];
      max_chord = std::max({max_chord, std::abs(c.x), std::abs(c.y)});
    }
  }
  int exponent = 0;
  std::frexp(max_chord, &exponent);
  int coord_exponent = 0;
  std::frexp(max_coord, &coord_exponent);
  return std::max(exponent, coord_exponent - 1000);  // scaled coordinates stay finite
}

void prepare(const FitInput& input, const KozakKrajncOptions& options, FitResult& out,
             Prepared& p) {
  // Each cubic passes through four consecutive points: 3m+1 points unless remainder=hermite.
  detail::prepare_input(input, kozak_krajnc_capabilities(), "kozak-krajnc", out,
                        options.remainder_hermite);
  if (!std::isnan(options.gamma) && !(options.gamma >= 0.0 && options.gamma <= 1.0)) {
    throw Error(ErrorCode::kBadOption, "kozak-krajnc: gamma must lie in [0, 1]");
  }
  const std::size_t n = out.points.size();
  p.n = n;
  p.rest = (n - 1) % 3;
  p.nk = n - p.rest;
  const std::size_t nk = p.nk;
  const int exponent = scale_exponent(out.points);
  const double scale = std::ldexp(1.0, -exponent);
  p.unscale = std::ldexp(1.0, exponent);
  p.scaled.resize(n);
  for (std::size_t i = 0; i < n; ++i) p.scaled[i] = scale * out.points[i];
  const std::span<const Point> T(p.scaled.data(), nk);
  // Prescribed directions: per-point tangents at breakpoints, start/end tangents.
  p.given.assign(n, std::nullopt);
  for (std::size_t i = 0; i < std::min(input.tangents.size(), n); ++i) {
    p.given[i] = input.tangents[i];
  }
  if (input.start_tangent) p.given[0] = input.start_tangent;
  if (input.end_tangent) p.given[n - 1] = input.end_tangent;
  // Every breakpoint prescribed (e.g. one piece with both ends clamped): no sweeps, each piece
  // is the single-piece problem of Section 2, solved exactly whatever the directions.
  p.all_given = true;
  for (std::size_t i = 0; i < nk; i += 3) p.all_given = p.all_given && p.given[i].has_value();
  p.g = geometry(T, p.scaled, !p.all_given);

  p.fixed.assign(p.g.m + 1, std::nullopt);
  for (std::size_t i = 0; i < nk; ++i) {
    if (!p.given[i]) continue;
    if (i % 3 != 0) {
      throw Error(ErrorCode::kInvalidArgument,
                  "kozak-krajnc: a tangent is given at " + pt(i) +
                      ", which lies inside a cubic piece (only every third point T3ℓ is a "
                      "breakpoint with a free direction)",
                  i);
    }
    const auto x = xi_of(p.g, i / 3, *p.given[i]);
    if (p.all_given) {
      p.fixed[i / 3] = x.value_or(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    if (!x) {
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: the tangent given at " + pt(i) +
                      " lies outside the cone of directions (4.1) that the sweeps can admit there",
                  i);
    }
    p.fixed[i / 3] = *x;
  }
}

/// Membership of each ξℓ in its swept set Ξℓ (always true for tangents=sweep).
std::vector<char> in_swept_sets(const KozakKrajncSweep& sw, const std::vector<double>& xi) {
  std::vector<char> in_xi(xi.size(), 0);
  for (std::size_t l = 0; l < xi.size(); ++l) {
    for (const XiInterval& c : sw.xi[l]) in_xi[l] = in_xi[l] || c.contains(xi[l]);
  }
  return in_xi;
}

/// ξ at every breakpoint of the local parabolas' directions; prescribed ones stay. Empty when
/// one lies outside the cone (4.1), with that breakpoint in `outside`.
std::vector<double> local_quadratic_xi(const Prepared& p, bool chordal, std::size_t& outside) {
  std::vector<double> xi(p.g.m + 1);
  for (std::size_t l = 0; l <= p.g.m; ++l) {
    if (p.fixed[l]) {
      xi[l] = *p.fixed[l];
      continue;
    }
    const auto x = xi_of(p.g, l, local_quadratic_direction(p.g.all, 3 * l, chordal));
    if (!x) {
      outside = l;
      return {};
    }
    xi[l] = *x;
  }
  return xi;
}

/// Directions stage: the sweeps (unless every direction is prescribed) and the ξ chosen by the
/// tangent rule.
Directions choose_directions(const Prepared& p, const KozakKrajncOptions& options) {
  const std::size_t m = p.g.m;
  Directions d;
  if (p.all_given) {
    d.sw.pieces = m;
    d.sw.I.assign(m + 1, {0.0, 1.0, false});
    d.sw.forward.assign(m + 1, {});
    d.sw.xi.assign(m + 1, {});
    d.xi.resize(m + 1);
    for (std::size_t l = 0; l <= m; ++l) d.xi[l] = *p.fixed[l];
  } else {
    d.sw = sweep(p.g, p.fixed);
    if (options.tangents == KozakKrajncTangents::kSweep) {
      d.xi = select(p.g, d.sw, options.gamma);
    } else {
      const bool chordal = options.tangents == KozakKrajncTangents::kLocalQuadraticChordal;
      std::size_t l = 0;
      d.xi = local_quadratic_xi(p, chordal, l);
      if (d.xi.empty()) {
        throw Error(ErrorCode::kInfeasible,
                    "kozak-krajnc: the " + std::string(kTangentRule.name(options.tangents)) +
                        " direction at " + pt(3 * l) +
                        " lies outside the cone of directions (4.1) admitted there; use "
                        "tangents=sweep",
                    3 * l);
      }
    }
  }
  d.in_xi = in_swept_sets(d.sw, d.xi);
  return d;
}

/// Pieces stage: solves every piece for the chosen directions; the error names why a piece has
/// no admissible solution.
std::vector<PieceFit> solve_pieces(const Prepared& p, const Directions& d,
                                   const KozakKrajncOptions& options) {
  const Geometry& g = p.g;
  const std::size_t m = g.m;
  std::vector<PieceFit> pieces(m + 1);
  auto dir_at = [&](std::size_t l) {
    return p.all_given ? normalized(*p.given[3 * l]) : direction(g, l, d.xi[l]);
  };
  for (std::size_t l = 1; l <= m; ++l) {
    bool solved = false;
    try {
      solved = solve_piece(g, l, dir_at(l - 1), dir_at(l), nullptr, pieces[l]);
    } catch (const Error& e) {  // degenerate constants (2.6), e.g. a direction along a chord
      throw Error(e.code(), "kozak-krajnc: piece " + std::to_string(l) + ": " + e.what(),
                  3 * l - 3);
    }
    if (!solved && p.all_given) {
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: piece " + std::to_string(l) + " (" + pt(3 * l - 3) + ".." +
                      pt(3 * l) +
                      ") has no admissible solution (0 < t1 < t2 < 1, alpha0, alpha3 > 0) for "
                      "the prescribed directions",
                  3 * l - 3);
    }
    if (!solved) {
      const bool outside = !d.in_xi[l - 1] || !d.in_xi[l];
      throw Error(
          ErrorCode::kInfeasible,
          "kozak-krajnc: piece " + std::to_string(l) + " (" + pt(3 * l - 3) + ".." + pt(3 * l) +
              ") has no admissible solution for the " +
              std::string(kTangentRule.name(options.tangents)) + " directions" +
              (outside ? std::string(" (they lie outside the swept sets Ξ: ") + pt(3 * l - 3) +
                             " " + describe(d.sw.xi[l - 1]) + ", " + pt(3 * l) + " " +
                             describe(d.sw.xi[l]) + "); use tangents=sweep"
               : admissible(g, l, pieces[l].d0, pieces[l].d3)
                   ? std::string(" although they satisfy the theorems "
                                 "(numerically borderline data)")
                   : std::string(" (each lies in its swept set Ξ but the pair "
                                 "fails Theorems 2.4/2.5); use tangents=sweep")),
          3 * l - 3);
    }
  }
  return pieces;
}

/// A piece's (t1, t2) that moves by more than this between adjacent doubles of ξ has switched
/// to another branch of solutions (on one branch it moves by ulps times its derivative, at most
/// ~1e-8 beside a fold).
constexpr double kBranchGap = 1e-6;

/// The one-unknown G2 problem (m = 2) settled by a scan of ξ1.
struct G2Scan {
  bool found = false;
  std::vector<double> xi;
  std::vector<PieceFit> pieces;
  G2Report rep;
  int sign = 0;            ///< when not found: the sign every admissible jump has (0: none)
  double smallest = kInf;  ///< its smallest magnitude, at ξ1 = at
  double at = 0.0;
  std::string where;  ///< at the edge of the admissible ξ1, or inside
  std::string scope;  ///< empty, or how the scan was narrowed
  /// Sign changes of a continued branch pair that bisect to adjacent doubles of ξ where a
  /// piece's (t1, t2) jumps by more than kBranchGap (the continuation switched to another
  /// solution where its branch ends) or the jump has a pole: not roots.
  int switches = 0;
  /// A sign change that ended neither at a root nor at such a switch (e.g. the pieces lost
  /// their solutions inside the bracket): nothing can be claimed.
  bool unexplained = false;
  /// Jumps of both signs, but each continued branch pair keeps its sign (up to the grid's
  /// resolution): no root either.
  bool branchwise() const { return !found && sign == 0 && smallest < kInf && !unexplained; }
};

/// Scans ξ1 ∈ (0, 1) on a fine grid for a sign change of the scaled curvature jump (1.4) at T3,
/// over every pair of piece solutions, each continued to the next grid point by nearest
/// (t1, t2); a sign change is bisected and polished by the G2 Newton. Without one, reports the
/// sign and the smallest jump. `xi1`: the G1 solution's ξ1 (admissible), whose neighbourhood
/// is scanned on its own when no grid point is admissible.
G2Scan scan_g2(const Geometry& g, double xi0, double xi1, double xi2, int max_iterations) {
  G2Scan out;
  constexpr int kGrid = 4000;
  const std::vector<char> pinned = {1, 0, 1};
  auto pieces_at = [&](double x, const PieceFit* near1, const PieceFit* near2, PieceFit& f1,
                       PieceFit& f2) {
    const Vec2 d3 = direction(g, 1, x);
    return solve_piece(g, 1, direction(g, 0, xi0), d3, near1, f1) &&
           solve_piece(g, 2, d3, direction(g, 2, xi2), near2, f2);
  };
  auto jump = [&](const PieceFit& f1, const PieceFit& f2) { return g2_residual(g, 1, f1, f2); };
  // Piece l (1 or 2) of `f` on its solution i: its curve too (the jump reads the curve).
  auto with = [&](const PieceFit& f, std::size_t l, int i) {
    PieceFit c = f;
    c.s = f.all.items[i];
    c.c = kozak_krajnc_bezier(g.T[3 * l - 3], g.T[3 * l], f.d0, f.d3, c.s);
    return c;
  };
  bool any_pos = false, any_neg = false;
  auto record = [&](double x, double r) {
    (r > 0 ? any_pos : any_neg) = true;
    if (std::abs(r) < out.smallest) out.smallest = std::abs(r), out.at = x;
  };
  // A sign change of the jump between ξ = xl (pieces l1, l2) and x, continuing those branches:
  // bisected and polished by Newton; true when a root was found (then `out` has it).
  auto bracket = [&](double xl, PieceFit l1, PieceFit l2, double x) {
    PieceFit r1, r2;
    if (!pieces_at(x, &l1, &l2, r1, r2)) return false;
    const double jl = jump(l1, l2), jr = jump(r1, r2);
    if (!(std::isfinite(jl) && std::isfinite(jr)) || (jl > 0) == (jr > 0)) return false;
    double lo = xl, hi = x, jlo = jl, jhi = jr;
    PieceFit h1 = r1, h2 = r2;
    for (int it = 0; it < 80 && std::nextafter(lo, hi) != hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      PieceFit m1, m2;
      if (!pieces_at(mid, &l1, &l2, m1, m2)) break;  // (then unexplained, below)
      const double jm = jump(m1, m2);
      if ((jm > 0) == (jlo > 0)) {
        lo = mid, jlo = jm, l1 = m1, l2 = m2;
      } else {
        hi = mid, jhi = jm, h1 = m1, h2 = m2;
      }
    }
    record(lo, jlo);
    record(hi, jhi);
    std::vector<double> xi = {xi0, lo, xi2};
    std::vector<PieceFit> fit = {PieceFit{}, l1, l2};
    const G2Report rep = solve_g2(g, xi, pinned, max_iterations, fit);
    if (rep.converged) {
      out.found = true, out.xi = xi, out.pieces = std::move(fit), out.rep = rep;
      return true;
    }
    // The sign change between two adjacent doubles of ξ with a small jump: a root that double
    // precision cannot resolve to the tolerance (a 5-point request: 8e-9 and −4e-9 on either
    // side of one ulp). A larger value on either side is a discontinuity.
    if (std::nextafter(lo, hi) == hi && std::abs(jlo) <= kG2Resolved &&
        std::abs(jhi) <= kG2Resolved) {
      out.found = true, out.xi = {xi0, lo, xi2}, out.pieces = {PieceFit{}, l1, l2};
      out.rep = G2Report{.converged = false,
                         .at_precision = true,
                         .iterations = rep.iterations,
                         .residual = std::abs(jlo),
                         .reason = "the jump changes sign between adjacent doubles of ξ"};
      return true;
    }
    // Between adjacent doubles, a sign change is a root blurred by rounding (s40-c7446: a
    // staircase of steps 4e-5 through zero), unless a piece's (t1, t2) jumps there (the
    // continuation switched to another solution where its branch ends) or the jump passes
    // through a pole.
    auto gap = [](const PieceFit& a, const PieceFit& b) {
      return std::max(std::abs(a.s.t1 - b.s.t1), std::abs(a.s.t2 - b.s.t2));
    };
    const bool adjacent = std::nextafter(lo, hi) == hi;
    const bool switched = std::max(gap(l1, h1), gap(l2, h2)) > kBranchGap;
    const bool pole = std::min(std::abs(jlo), std::abs(jhi)) > 1.0 / kG2Resolved;
    if (adjacent && !switched && !pole) {
      // A blurred root: no double of ξ comes nearer than the better side, so the jump there is
      // what the problem's conditioning allows (s40-c857: 3.6e-6 and −2.3e-6 either side of
      // ξ = 1 − 2.1e-13, a direction that close to its chord), provided the output shows it:
      // its spans (the pieces split at t1, t2) must carry that jump to within their control
      // points' rounding (s40-c7446: handles 1e7 times the chord, 2.6e-5 here, 10.6 read off
      // the split Béziers; it stays not_converged).
      const bool low_side = std::abs(jlo) <= std::abs(jhi);
      const PieceFit& a = low_side ? l1 : h1;
      const PieceFit& b = low_side ? l2 : h2;
      const double residual = std::min(std::abs(jlo), std::abs(jhi));
      const SplitJump shown = split_jump(g, 1, a, b);
      if (shown.jump <= std::max(residual, kG2Resolved) + shown.rounding) {
        out.found = true, out.xi = {xi0, low_side ? lo : hi, xi2};
        out.pieces = {PieceFit{}, a, b};
        out.rep = G2Report{.converged = false,
                           .at_precision = true,
                           .iterations = rep.iterations,
                           .residual = std::max(residual, shown.jump),
                           .reason =
                               "the jump changes sign between adjacent doubles of ξ on "
                               "one branch of each piece's solutions"};
        return true;
      }
    }
    if (adjacent && (switched || pole)) {
      ++out.switches;
    } else {
      out.unexplained = true;
    }
    return false;
  };
  // The grid over (x0, x1) in `cells` cells; true when a root was polished (then `out` has it).
  auto scan = [&](double x0, double x1, int cells) {
    bool prev_ok = false;
    PieceFit p1, p2, q1, q2;
    for (int k = 1; k < cells; ++k) {
      const double x = x0 + (x1 - x0) * k / cells;
      const bool ok = pieces_at(x, nullptr, nullptr, q1, q2);
      if (ok) {
        for (int a = 0; a < q1.all.count; ++a) {
          for (int b = 0; b < q2.all.count; ++b) {
            const double r = jump(with(q1, 1, a), with(q2, 2, b));
            if (std::isfinite(r)) record(x, r);
          }
        }
      }
      if (ok && prev_ok) {
        // Every pair at the previous point, continued here: a sign change brackets a root.
        const double xl = x0 + (x1 - x0) * (k - 1) / cells;
        for (int a = 0; a < p1.all.count; ++a) {
          for (int b = 0; b < p2.all.count; ++b) {
            if (bracket(xl, with(p1, 1, a), with(p2, 2, b), x)) return true;
          }
        }
      }
      prev_ok = ok;
      if (ok) p1 = q1, p2 = q2;
    }
    return false;
  };
  // From the grid's first (or last) point towards ξ = 0 (or 1), where the grid has no point:
  // each step halves the distance to the edge (ξ = edge ∓ step·2⁻ᵏ), or, once the pieces lose
  // their solutions, to the nearest point known to have none, every branch continued, until the
  // doubles run out. A sign change is bracketed as on the grid (issue 18: roots 1.7e-4 from
  // ξ = 0, and 1.2e-5 from ξ = 1 just before the pieces lose their solutions, lay in the grid's
  // end cells). `lost_edge`: the pieces lost their solutions on the way. True when a root was
  // found.
  bool lost_edge[2] = {false, false};
  auto follow = [&](bool low, double step) {
    const double dir = low ? 1.0 : -1.0;
    double target = low ? 0.0 : 1.0, x_prev = target + dir * step;
    PieceFit c1, c2;
    if (!pieces_at(x_prev, nullptr, nullptr, c1, c2)) return false;
    for (int k = 0; k < 120; ++k) {
      const double x = 0.5 * (x_prev + target);
      if (x == x_prev || x == target) break;
      bool any = false;
      PieceFit n1, n2;
      for (int a = 0; a < c1.all.count; ++a) {
        for (int b = 0; b < c2.all.count; ++b) {
          const PieceFit l1 = with(c1, 1, a), l2 = with(c2, 2, b);
          PieceFit r1, r2;
          if (!pieces_at(x, &l1, &l2, r1, r2)) continue;
          const double jl = jump(l1, l2), jr = jump(r1, r2);
          if (!std::isfinite(jr)) continue;
          if (!any) n1 = r1, n2 = r2, any = true;
          record(x, jr);
          if (std::isfinite(jl) && (jl > 0) != (jr > 0) && bracket(x_prev, l1, l2, x)) {
            return true;
          }
        }
      }
      if (any) {
        c1 = n1, c2 = n2, x_prev = x;
      } else {
        target = x, lost_edge[low ? 0 : 1] = true;
      }
    }
    return false;
  };
  double step = 1.0 / kGrid;
  // A tenth of the grid first: where a root exists it is usually found there, at a tenth of the
  // cost (each piece solve near a root cluster costs ~50 µs: a 9-point request with a
  // near-repeated pair took 5.3 s, issue 18); the full grid is what proves there is none.
  if (scan(0.0, 1.0, kGrid / 10) || scan(0.0, 1.0, kGrid)) return out;
  if (follow(true, step) || follow(false, step)) return out;
  if (!any_pos && !any_neg && xi1 > 0.0 && xi1 < 1.0) {
    // No grid point admits both pieces, but the G1 solution's ξ1 does (near-repeated points):
    // the admissible ξ1 around it is narrower than a cell. Its ends by doubling steps and
    // bisection, then the same scan over it.
    PieceFit f1, f2;
    auto admissible = [&](double x) {
      return x > 0.0 && x < 1.0 && pieces_at(x, nullptr, nullptr, f1, f2);
    };
    double ends[2];
    for (int side = 0; side < 2; ++side) {
      const double dir = side == 0 ? -1.0 : 1.0;
      double in = xi1, h = 1e-12;
      while (h < 1.0 && admissible(xi1 + dir * h)) in = xi1 + dir * h, h *= 2.0;
      double outside = xi1 + dir * h;
      for (int it = 0; it < 60 && std::abs(outside - in) > 1e-15; ++it) {
        const double mid = 0.5 * (in + outside);
        (admissible(mid) ? in : outside) = mid;
      }
      ends[side] = in;
    }
    if (ends[1] > ends[0]) {
      step = (ends[1] - ends[0]) / kGrid;
      out.scope = " around the G1 spline's ξ (from " + detail::format_number(ends[0]) + " to " +
                  detail::format_number(ends[1]) + "; no point of a 4000-point grid on (0, 1) " +
                  "admits both pieces)";
      if (scan(ends[0], ends[1], kGrid)) return out;
    }
  }
  out.sign = any_pos && !any_neg ? 1 : (any_neg && !any_pos ? -1 : 0);
  // Where the least jump lies: at an end of the grid the edge was followed (above) and the
  // jump fell towards it, e.g. like (1 − ξ)³ (s18-m60-c3050).
  const bool low = out.at <= 1.5 * step, high = out.at >= 1.0 - 1.5 * step;
  if (low || high) {
    const bool lost = lost_edge[low ? 0 : 1];
    out.where = lost ? "falling towards ξ = " + std::string(low ? "0" : "1") +
                           " until the pieces lose their solutions"
                     : "falling to zero only at ξ = " + std::string(low ? "0" : "1") +
                           ", where the direction meets a chord (not admissible)";
  } else {
    PieceFit e1, e2;
    const bool edge =
        !(out.at - step > 0.0 && pieces_at(out.at - step, nullptr, nullptr, e1, e2)) ||
        !(out.at + step < 1.0 && pieces_at(out.at + step, nullptr, nullptr, e1, e2));
    out.where = edge ? "at the edge of the admissible ξ, where a piece loses its solutions"
                     : "inside the admissible ξ";
  }
  return out;
}

/// The chain scan (m ≥ 3) covers (0, 1) at each free breakpoint with kChainCells equal cells
/// and kChainTail cells halving towards each edge of the cone (4.1) (the last ones 2⁻²⁰ of a
/// cell wide): (kChainCells + 2·kChainTail)² piece solves per inner piece.
constexpr int kChainCells = 200;
constexpr int kChainTail = 20;
/// Above this many pieces the scan is not tried: it costs ~0.1 s per piece (1.6 s at this
/// bound, up to 1 + kChainRefineBudget times that with the refinements).
constexpr std::size_t kChainMaxPieces = 16;
/// Newton starts taken from the chains of cells that pass the scan.
constexpr std::size_t kChainStarts = 20;
constexpr std::size_t kNoBudget = std::numeric_limits<std::size_t>::max();
/// The refinements (towards the G1 directions, splitting passing chains' cells) may take this
/// many times the piece solves of the first scan in all; a grid that needs more is not scanned.
/// (3 allowed no split on 15 inputs of seeds 18 and 40 that one split proves infeasible.)
constexpr std::size_t kChainRefineBudget = 12;
/// When Newton from every passing chain fails, the chains' cells are split into this many
/// parts and the grid scanned again, at most kChainRounds times.
constexpr int kChainSplit = 8;
constexpr int kChainRounds = 3;
/// Newton starts drawn at random in the cones where the chain scan neither proved that (1.4)
/// has no solution nor reached one from its chains: half uniform in each unknown's cone, half
/// within 10^-6..1 of the G1 spline's ξ (a fixed seed: the same input gives the same result).
constexpr int kRandomStarts = 64;
constexpr std::uint64_t kRandomSeed = 0x6b6b2d67322d7273;

/// A closed interval of scaled curvatures.
struct CurvatureRange {
  double lo = kInf, hi = -kInf;
  void add(double v) { lo = std::min(lo, v), hi = std::max(hi, v); }
  bool meets(const CurvatureRange& o) const { return lo <= o.hi && o.lo <= hi; }
};

/// Result of chain_scan.
struct ChainScan {
  bool feasible = false;  ///< some chain of cells passes every relaxed condition
  /// The grid resolves the admissible set: each piece admits every corner of the cell holding
  /// the G1 spline's directions. Without that, "no chain" proves nothing.
  bool resolved = true;
  std::size_t first_empty = 0;  ///< when not feasible: the breakpoint where the chains end
  std::vector<std::vector<double>> starts;               ///< ξ at the centres of passing chains
  std::vector<std::vector<ParameterPair>> start_branch;  ///< per start and piece: (t1, t2)
  /// Per start and breakpoint: the cell (lower and upper node) its ξ lies in.
  std::vector<std::vector<std::pair<double, double>>> start_cells;
  std::size_t solves = 0;  ///< piece solves of the grid (also when skipped)
  bool skipped = false;    ///< the grid needs more solves than the budget: nothing was scanned
};

/// Nodes of one free breakpoint's grid on (0, 1) (see kChainCells).
std::vector<double> chain_nodes() {
  std::vector<double> x;
  const double h = 1.0 / kChainCells;
  for (int k = kChainTail; k >= 1; --k) x.push_back(std::ldexp(h, -k));
  for (int i = 1; i < kChainCells; ++i) x.push_back(static_cast<double>(i) / kChainCells);
  for (int k = 1; k <= kChainTail; ++k) x.push_back(1.0 - std::ldexp(h, -k));
  return x;
}

/// The nodes of chain_nodes() and kChainTail·2 more halving towards `at` from either side, down
/// to 2⁻⁴⁰ of a cell: where the admissible set around the G1 spline is narrower than a cell.
std::vector<double> chain_nodes_around(double at) {
  std::vector<double> x = chain_nodes();
  const double h = 1.0 / kChainCells;
  for (int k = 1; k <= 2 * kChainTail; ++k) {
    for (const double v : {at - std::ldexp(h, -k), at + std::ldexp(h, -k)}) {
      if (v > 0.0 && v < 1.0) x.push_back(v);
    }
  }
  std::sort(x.begin(), x.end());
  x.erase(std::unique(x.begin(), x.end()), x.end());
  return x;
}

/// Whether (1.4) can hold at every interior breakpoint, decided on a grid of cells (ξ0, ξm
/// and nothing else pinned). Jump ℓ is κℓ(1) − κℓ+1(0): piece ℓ's end curvature, a function
/// of (ξℓ−1, ξℓ), against piece ℓ+1's start curvature, of (ξℓ, ξℓ+1) — a chain. Over a cell
/// each branch of each piece has a range of both end curvatures (its values at the cell's
/// admissible corners, continued by nearest (t1, t2), widened by their spread on each side);
/// K[ℓ][c] = the curvatures at T3ℓ that a chain of cells from T0 reaches with ξℓ in cell c,
/// every jump on the way able to vanish. No G2 spline if the last jump cannot vanish on any
/// chain. Dynamic programming: (m − 2)·cells² branch ranges instead of cells^(m−1) boxes.
ChainScan chain_scan(const Geometry& g, const std::vector<double>& xi,
                     const std::vector<char>& pinned, bool refined,
                     const std::vector<std::vector<double>>& extra, std::size_t budget) {
  ChainScan out;
  const std::size_t m = g.m;
  std::vector<std::vector<double>> X(m + 1);
  for (std::size_t l = 0; l <= m; ++l) {
    if (pinned[l]) {
      X[l] = {xi[l]};
      continue;
    }
    X[l] = refined ? chain_nodes_around(xi[l]) : chain_nodes();
    X[l].insert(X[l].end(), extra[l].begin(), extra[l].end());
    std::sort(X[l].begin(), X[l].end());
    X[l].erase(std::unique(X[l].begin(), X[l].end()), X[l].end());
  }
  for (std::size_t l = 1; l <= m; ++l) out.solves += X[l - 1].size() * X[l].size();
  if (out.solves > budget) {
    out.skipped = true;
    out.resolved = false;
    return out;
  }
  auto cells = [&](std::size_t l) { return X[l].size() == 1 ? std::size_t{1} : X[l].size() - 1; };
  auto scale = [&](std::size_t l) { return 0.5 * (norm(g.dT[3 * l - 1]) + norm(g.dT[3 * l])); };
  // Every solution of every piece at every node pair: (t1, t2, κ(0)·len, κ(1)·len).
  struct NodeSolution {
    double t1, t2, kb, ka;
  };
  std::vector<std::vector<std::vector<NodeSolution>>> table(m + 1);
  std::size_t rows = 0, row = 0;
  for (std::size_t l = 1; l <= m; ++l) rows += X[l - 1].size();
  for (std::size_t l = 1; l <= m; ++l) {
    const std::size_t k = 3 * l - 3, nj = X[l].size();
    const double sl = l > 1 ? scale(l - 1) : 0.0, sr = l < m ? scale(l) : 0.0;
    table[l].resize(X[l - 1].size() * nj);
    for (std::size_t i = 0; i < X[l - 1].size(); ++i) {
      detail::checkpoint("g2 scan", row++, rows);
      const Vec2 d0 = direction(g, l - 1, X[l - 1][i]);
      for (std::size_t j = 0; j < nj; ++j) {
        const Vec2 d3 = direction(g, l, X[l][j]);
        KozakKrajncSolutions all;
        try {
          all = kozak_krajnc_solve(g.T[k], g.T[k + 1], g.T[k + 2], g.T[k + 3], d0, d3);
        } catch (const Error&) {  // degenerate constants (2.6): no piece at this node
          continue;
        }
        for (const KozakKrajncSolution& s : all) {
          const CubicBezier c = kozak_krajnc_bezier(g.T[k], g.T[k + 3], d0, d3, s);
          const double kb = c.curvature(0.0) * sl, ka = c.curvature(1.0) * sr;
          if (std::isfinite(kb) && std::isfinite(ka))
            table[l][i * nj + j].push_back({s.t1, s.t2, kb, ka});
        }
      }
    }
  }
  auto cell_of = [&](std::size_t l) {
    if (X[l].size() == 1) return std::size_t{0};
    const auto it = std::upper_bound(X[l].begin(), X[l].end(), xi[l]);
    if (it == X[l].begin() || it == X[l].end()) return std::numeric_limits<std::size_t>::max();
    return static_cast<std::size_t>(it - X[l].begin()) - 1;
  };
  // Piece ℓ over the cell (ci, cj): one range pair per (corner, solution) there.
  struct Branch {
    CurvatureRange b, a;
    ParameterPair t;
  };
  auto corners = [&](std::size_t l, std::size_t ci, std::size_t cj) {
    const std::size_t ni = X[l - 1].size(), nj = X[l].size();
    std::vector<const std::vector<NodeSolution>*> c;
    for (std::size_t i = ci; i <= (ni == 1 ? ci : ci + 1); ++i) {
      for (std::size_t j = cj; j <= (nj == 1 ? cj : cj + 1); ++j)
        c.push_back(&table[l][i * nj + j]);
    }
    return c;
  };
  for (std::size_t l = 1; l <= m; ++l) {  // the resolution the claim needs
    const std::size_t ci = cell_of(l - 1), cj = cell_of(l);
    if (ci == std::numeric_limits<std::size_t>::max() ||
        cj == std::numeric_limits<std::size_t>::max()) {
      out.resolved = false;
      continue;
    }
    for (const auto* c : corners(l, ci, cj)) out.resolved = out.resolved && !c->empty();
  }
  std::vector<Branch> bs;
  auto branches = [&](std::size_t l, std::size_t ci, std::size_t cj) {
    bs.clear();
    const auto c = corners(l, ci, cj);
    for (const auto* from : c) {
      for (const NodeSolution& s : *from) {
        Branch br;
        br.t = {s.t1, s.t2};
        for (const auto* to : c) {
          const NodeSolution* near = nullptr;
          double dist = kInf;
          for (const NodeSolution& q : *to) {
            const double d = std::abs(q.t1 - s.t1) + std::abs(q.t2 - s.t2);
            if (d < dist) dist = d, near = &q;
          }
          if (near) br.b.add(near->kb), br.a.add(near->ka);
        }
        for (CurvatureRange* r : {&br.b, &br.a}) {
          const double w = r->hi - r->lo;
          r->lo -= w, r->hi += w;
        }
        bs.push_back(br);
      }
    }
  };
  // Forward over the breakpoints, with one parent per reached cell for the Newton starts.
  // The parent kept is the one whose chain matches best: `score` sums, over the chain's links,
  // how far the centre of each tested range lies outside what it had to meet, in its widths.
  struct Parent {
    std::size_t cell = std::numeric_limits<std::size_t>::max();
    ParameterPair t;
    double score = kInf;
    CurvatureRange a;
  };
  auto miss = [](const CurvatureRange& b, const CurvatureRange& r) {
    const double mid = 0.5 * (b.lo + b.hi);
    const double out = std::max({r.lo - mid, mid - r.hi, 0.0});
    return out == 0.0 ? 0.0 : out / (b.hi - b.lo + std::abs(mid));
  };
  std::vector<std::vector<std::vector<CurvatureRange>>> K(m);
  std::vector<std::vector<Parent>> parent(m);
  K[0].assign(1, {CurvatureRange{-kInf, kInf}});  // no condition at T0
  for (std::size_t l = 1; l < m; ++l) {
    K[l].assign(cells(l), {});
    parent[l].assign(cells(l), {});
    bool any = false;
    for (std::size_t ci = 0; ci < cells(l - 1); ++ci) {
      if (K[l - 1][ci].empty()) continue;
      for (std::size_t cj = 0; cj < cells(l); ++cj) {
        branches(l, ci, cj);
        const double before = l == 1 ? 0.0 : parent[l - 1][ci].score;
        for (const Branch& br : bs) {
          double gap = kInf;
          for (const CurvatureRange& r : K[l - 1][ci]) {
            if (br.b.meets(r)) gap = std::min(gap, miss(br.b, r));
          }
          if (gap == kInf) continue;
          K[l][cj].push_back(br.a);
          if (before + gap < parent[l][cj].score) parent[l][cj] = {ci, br.t, before + gap, br.a};
          any = true;
        }
      }
    }
    if (!any) {  // link ℓ tests the jump at T3(ℓ−1) (with ℓ = 1: piece 1 has no solution)
      out.first_empty = std::max<std::size_t>(l - 1, 1);
      return out;
    }
    for (std::vector<CurvatureRange>& v : K[l]) {  // merged, so that the lists stay short
      std::sort(v.begin(), v.end(),
                [](const CurvatureRange& p, const CurvatureRange& q) { return p.lo < q.lo; });
      std::size_t n = 0;
      for (const CurvatureRange& r : v) {
        if (n > 0 && r.lo <= v[n - 1].hi) {
          v[n - 1].hi = std::max(v[n - 1].hi, r.hi);
        } else {
          v[n++] = r;
        }
      }
      v.resize(n);
    }
    if (pinned[l]) {  // a given direction: no jump is asked there, the chain starts afresh
      for (std::vector<CurvatureRange>& v : K[l]) {
        if (!v.empty()) v.assign(1, CurvatureRange{-kInf, kInf});
      }
    }
  }
  out.first_empty = m - 1;
  struct End {
    double score;
    std::size_t cell;
    ParameterPair t;
  };
  std::vector<End> ends;
  for (std::size_t ci = 0; ci < cells(m - 1); ++ci) {
    if (K[m - 1][ci].empty()) continue;
    branches(m, ci, 0);
    for (const Branch& br : bs) {
      if (!std::any_of(K[m - 1][ci].begin(), K[m - 1][ci].end(),
                       [&](const CurvatureRange& r) { return br.b.meets(r); })) {
        continue;
      }
      out.feasible = true;
      const Parent& q = parent[m - 1][ci];
      const double last = br.b.meets(q.a) ? miss(br.b, q.a) : 1.0;  // against the kept chain
      ends.push_back({q.score + last, ci, br.t});
    }
  }
  // Newton starts from the best-matching chains first.
  std::sort(ends.begin(), ends.end(), [](const End& p, const End& q) { return p.score < q.score; });
  for (std::size_t e = 0; e < std::min(ends.size(), kChainStarts); ++e) {
    std::vector<double> x(m + 1);
    std::vector<ParameterPair> t(m + 1);
    std::vector<std::pair<double, double>> cell(m + 1, {0.0, 0.0});
    x[0] = xi[0], x[m] = xi[m], t[m] = ends[e].t;
    for (std::size_t l = m - 1, c = ends[e].cell; l >= 1; --l) {
      x[l] = X[l].size() == 1 ? X[l][0] : 0.5 * (X[l][c] + X[l][c + 1]);
      if (X[l].size() > 1) cell[l] = {X[l][c], X[l][c + 1]};
      t[l] = parent[l][c].t;
      c = parent[l][c].cell;
    }
    out.starts.push_back(std::move(x));
    out.start_branch.push_back(std::move(t));
    out.start_cells.push_back(std::move(cell));
  }
  return out;
}

/// Optional G2 stage: Newton on (1.4) from the G1 solution. On convergence `d` and `pieces`
/// take the G2 directions and pieces. Throws kNotConverged unless a best effort is asked for.
G2Outcome g2_stage(const Prepared& p, const KozakKrajncOptions& options, Directions& d,
                   std::vector<PieceFit>& pieces) {
  const Geometry& g = p.g;
  const std::size_t m = g.m;
  G2Outcome o;
  if (p.all_given) {
    // Every breakpoint is pinned, and (1.4) is not asked at a pinned one: no equation is left,
    // so the request is met as it stands (as for m = 1, which has no interior breakpoint).
    o.rep.converged = true;
    o.rep.reason = "every direction is prescribed: nothing to solve for";
  } else {
    // Newton is local, so if the G1 start fails, the directions of the local parabolas are
    // tried as further starts (reported as "start").
    std::vector<char> pinned(m + 1);  // ends and prescribed directions stay
    for (std::size_t l = 0; l <= m; ++l) pinned[l] = l == 0 || l == m || p.fixed[l].has_value();
    for (const char* start : {"g1", "local-quadratic-chordal", "local-quadratic-uniform"}) {
      std::vector<double> x = d.xi;
      std::vector<PieceFit> fit = pieces;
      if (std::string(start) != "g1") {
        const bool chordal = std::string(start) == "local-quadratic-chordal";
        bool ok = true;
        for (std::size_t l = 0; l <= m && ok; ++l) {
          if (p.fixed[l]) continue;
          const auto q = xi_of(g, l, local_quadratic_direction(g.all, 3 * l, chordal));
          ok = q.has_value();
          if (ok) x[l] = *q;
        }
        for (std::size_t l = 1; l <= m && ok; ++l) {
          ok = solve_piece(g, l, direction(g, l - 1, x[l - 1]), direction(g, l, x[l]), nullptr,
                           fit[l]);
        }
        if (!ok) continue;
      }
      const G2Report attempt = solve_g2(g, x, pinned, options.g2_max_iterations, fit);
      if (o.start.empty() || attempt.converged) o.rep = attempt, o.start = start;
      if (attempt.converged) {
        d.xi = x;
        pieces = std::move(fit);
        d.in_xi = in_swept_sets(d.sw, d.xi);
        break;
      }
    }
  }
  std::string scan_note;  // what a scan found, when it ran and did not settle (1.4)
  if (!o.rep.converged && m == 2 && !p.fixed[1]) {
    // One unknown ξ1 between the tangent rule's end directions: (1.4) is one equation in one
    // variable, settled either way by a scan of every admissible ξ1 and every pair of piece
    // solutions (Newton alone stalls where a piece's solutions disappear, or creeps towards an
    // edge of the admissible ξ until the iteration cap: then only a proof of no root counts).
    const G2Scan scan = scan_g2(g, d.xi[0], d.xi[1], d.xi[2], options.g2_max_iterations);
    // At the iteration cap a root the scan finds stays unused (the cap is the user's: the
    // answer remains the iteration limit); a proof that none exists is still reported.
    if (scan.found && !o.rep.at_cap) {
      d.xi = scan.xi;
      pieces = scan.pieces;
      d.in_xi = in_swept_sets(d.sw, d.xi);
      o.rep = scan.rep;
      o.start = "scan";
    } else if (!scan.found && (scan.sign != 0 || scan.branchwise()) && !options.best_effort) {
      // No root: one sign over every admissible ξ, or one sign on each branch.
      const std::string why =
          scan.sign != 0
              ? std::string("keeps ") + (scan.sign > 0 ? "positive" : "negative") +
                    " sign (smallest " + detail::format_number(scan.smallest) +
                    " at ξ = " + detail::format_number(scan.at) + ", " + scan.where + ")"
              : "has both signs, but on each branch of the pieces' solutions it keeps one "
                "(smallest " +
                    detail::format_number(scan.smallest) +
                    " at ξ = " + detail::format_number(scan.at) + "; " +
                    std::to_string(scan.switches) +
                    " sign changes, each between adjacent doubles of ξ where a piece's "
                    "solution switches branch or the jump has a pole)";
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: no G2 spline for the end directions of the tangent rule: over "
                  "every ξ at " +
                      pt(3) + " with admissible pieces" + scan.scope +
                      " the scaled curvature jump there " + why +
                      "; ask for a best effort to get the G1 spline instead",
                  3);
    } else if (!scan.found && scan.sign == 0 && scan.smallest < kInf) {
      // Both signs, and a sign change on one branch that is neither a polished root nor a
      // switch of branch: neither a root nor a proof that none exists.
      scan_note = "; a scan of every ξ at " + pt(3) +
                  " found jumps of both signs but no sign change that polishes to a root (least " +
                  detail::format_number(scan.smallest) +
                  " at ξ = " + detail::format_number(scan.at) + ")";
    }
  }
  std::vector<char> pinned(m + 1, 0);
  std::size_t free_inner = 0;
  for (std::size_t l = 0; l <= m; ++l) {
    pinned[l] = l == 0 || l == m || p.fixed[l].has_value();
    free_inner += pinned[l] ? 0 : 1;
  }
  if (!o.rep.converged && !o.rep.at_precision && m >= 3 && m <= kChainMaxPieces && free_inner > 0) {
    // Two or more unknowns: the chain scan either proves that (1.4) has no solution (up to its
    // grid's resolution) or gives Newton starts near every chain of cells where it may have one.
    std::vector<std::vector<double>> extra(m + 1);
    ChainScan chain = chain_scan(g, d.xi, pinned, false, extra, kNoBudget);
    // The finer grids below may take kChainRefineBudget times the first one's solves in all.
    std::size_t budget = kChainRefineBudget * chain.solves;
    const auto rescan = [&](bool finer) {
      ChainScan next = chain_scan(g, d.xi, pinned, finer, extra, budget);
      if (next.skipped) return false;
      budget -= next.solves;
      chain = std::move(next);
      return true;
    };
    // Unresolved: the grid again, with nodes converging on the G1 spline's directions.
    const bool refined = !chain.feasible && !chain.resolved && rescan(true);
    // Newton from x (each piece on the branch nearest `branch`, if given): kept if it converges.
    const auto start_at = [&](std::vector<double> x, const std::vector<ParameterPair>* branch,
                              const char* name) {
      std::vector<PieceFit> fit(m + 1);
      bool ok = true;
      G2Report attempt;
      try {  // a start near a cone's edge can lead Newton onto a chord: (2.6) degenerates
        for (std::size_t l = 1; l <= m && ok; ++l) {
          PieceFit near;
          if (branch) near.s.t1 = (*branch)[l].t1, near.s.t2 = (*branch)[l].t2;
          ok = solve_piece(g, l, direction(g, l - 1, x[l - 1]), direction(g, l, x[l]),
                           branch ? &near : nullptr, fit[l]);
        }
        if (ok) attempt = solve_g2(g, x, pinned, options.g2_max_iterations, fit);
      } catch (const Error&) {
        ok = false;
      }
      if (!ok || !attempt.converged) return false;
      d.xi = std::move(x);
      pieces = std::move(fit);
      d.in_xi = in_swept_sets(d.sw, d.xi);
      o.rep = attempt;
      o.start = name;
      return true;
    };
    // Passing chains whose starts all fail: their cells are split (kChainSplit parts) and the
    // whole grid scanned again, at most kChainRounds times. Each scan covers all of (0, 1), so
    // a scan where no chain passes is a claim at its own (finer) resolution.
    int rounds = 0;
    for (;; ++rounds) {
      bool converged = false;
      for (std::size_t s = 0; chain.feasible && !o.rep.at_cap && s < chain.starts.size(); ++s) {
        converged = start_at(chain.starts[s], &chain.start_branch[s], "chain-scan");
        if (converged) break;
      }
      // (At the iteration limit no start is tried, but finer grids may still prove infeasibility.)
      if (converged || !chain.feasible || rounds == kChainRounds) break;
      for (const auto& cells : chain.start_cells) {
        for (std::size_t l = 1; l < m; ++l) {
          const auto [lo, hi] = cells[l];
          for (int k = 1; k < kChainSplit && hi > lo; ++k)
            extra[l].push_back(lo + (hi - lo) * k / kChainSplit);
        }
      }
      if (!rescan(refined)) break;
    }
    // (Also after a start that reached the iteration limit, as the three starts above are
    // tried: the limit is per Newton run. s18-c17687: the G1 start stops at the limit, a
    // random one converges in 7 iterations.)
    const bool random = !o.rep.converged && (chain.feasible || !chain.resolved);
    if (random) {
      std::mt19937_64 rng(kRandomSeed);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (int k = 0; k < kRandomStarts && !o.rep.converged; ++k) {
        std::vector<double> x = d.xi;
        for (std::size_t l = 1; l < m; ++l) {
          if (pinned[l]) continue;
          if (k % 2 == 0) {
            x[l] = unit(rng);
          } else {  // towards either edge of the cone by 10^-6..1 of the way
            const double step = std::pow(10.0, -6.0 * unit(rng));
            x[l] = unit(rng) < 0.5 ? d.xi[l] * (1.0 - step) : d.xi[l] + (1.0 - d.xi[l]) * step;
          }
          if (!(x[l] > 0.0 && x[l] < 1.0)) x[l] = d.xi[l];
        }
        start_at(std::move(x), nullptr, "random");
      }
    }
    const std::string splits = rounds == 1 ? "once" : std::to_string(rounds) + " times";
    scan_note =
        !chain.feasible
            ? "; the chain scan's grid is coarser than the set of "
              "admissible directions around the G1 spline, so it proves "
              "nothing"
            : "; the chain scan found " + std::to_string(chain.starts.size()) +
                  " chains of cells where a solution may lie (their cells split " + splits +
                  (o.rep.at_cap ? "), not tried as starts since the iteration limit was reached"
                                : "), and Newton from each stopped short of it");
    if (random && !o.rep.converged) {
      scan_note += "; Newton from " + std::to_string(kRandomStarts) +
                   " random starts in the cones stopped short too";
    }
    if (!chain.feasible && chain.resolved && !options.best_effort) {
      const std::size_t at = 3 * chain.first_empty;
      throw Error(ErrorCode::kInfeasible,
                  "kozak-krajnc: no G2 spline for the end directions of the tangent rule: with "
                  "the directions not given at " +
                      pt(3) + ".." + pt(3 * (m - 1)) + " on a grid of " +
                      std::to_string(kChainCells) +
                      " cells each (finer towards the edges of their cones" +
                      (refined ? " and towards the G1 spline's directions" : "") +
                      (rounds > 0 ? ", cells of chains that passed coarser grids split " + splits
                                  : std::string()) +
                      "), no chain of cells from " + pt(0) +
                      " lets the scaled curvature jumps vanish up to " + pt(at) +
                      " (each piece's end curvatures ranging over a cell as its corners "
                      "suggest); ask for a best effort to get the G1 spline instead",
                  at);
    }
  }
  if (!o.rep.converged && !o.rep.at_precision && !options.best_effort) {
    throw Error(ErrorCode::kNotConverged,
                "kozak-krajnc: the G2 Newton iteration on (1.4) stopped after " +
                    std::to_string(o.rep.iterations) + " iterations with scaled curvature jump " +
                    detail::format_number(o.rep.residual) + " (tolerance " +
                    detail::format_number(kG2Tolerance) + "): " + o.rep.reason + scan_note +
                    "; ask for a best effort to get the G1 spline instead");
  }
  return o;
}

/// Assemble stage: each piece split at t1, t2 into one Bézier per span, the remainder's Hermite
/// curves, scaled back. Returns the number of remainder pieces.
int assemble(const Prepared& p, const std::vector<PieceFit>& pieces, FitResult& out) {
  const std::size_t n = p.n, nk = p.nk, m = p.g.m;
  out.spline.closed = false;
  out.spline.segments.clear();
  out.spline.segments.reserve(n - 1);
  out.tangents.resize(n);
  std::vector<double> knots = out.knots;
  for (std::size_t l = 1; l <= m; ++l) {
    const std::size_t k = 3 * l - 3;
    const PieceFit& f = pieces[l];
    const double t[4] = {0.0, f.s.t1, f.s.t2, 1.0};
    const double u0 = knots[k], u3 = knots[k + 3];
    for (int i = 0; i < 3; ++i) {
      const double ta = u0 + t[i] * (u3 - u0), tb = u0 + t[i + 1] * (u3 - u0);
      out.knots[k + i] = ta;
      out.spline.segments.push_back({f.c.subsegment(t[i], t[i + 1]), ta, tb, k + i});
      out.tangents[k + i] = i == 0 ? f.d0 : normalized(f.c.d1(t[i]));
    }
  }
  out.knots[nk - 1] = knots[nk - 1];
  out.tangents[nk - 1] = pieces[m].d3;
  // Remainder: G1 Hermite curves through the last one or two spans.
  int remainder_pieces = 0;
  if (p.rest != 0) {
    std::vector<Vec2> d(n);
    d[nk - 1] = pieces[m].d3;
    const std::span<const Point> all(p.scaled.data(), n);
    for (std::size_t i = nk; i < n; ++i) {
      d[i] = p.given[i] ? normalized(*p.given[i])
                        : normalized(local_quadratic_direction(all, i, true));
    }
    for (std::size_t i = nk - 1; i + 1 < n; ++i) {
      // Yong–Cheng's composite optimized geometric Hermite curve: one OGH cubic, or two or three
      // when the directions would give a loop, cusp or fold (any angles allowed).
      const CohCurve c = coh_curve(p.scaled[i], p.scaled[i + 1], d[i], d[i + 1]);
      const double ta = out.knots[i], tb = out.knots[i + 1];
      for (int k = 0; k < c.count; ++k) {
        out.spline.segments.push_back(
            {c.pieces[k], ta + (tb - ta) * k / c.count, ta + (tb - ta) * (k + 1) / c.count, i});
      }
      out.tangents[i + 1] = d[i + 1];
      remainder_pieces += c.count;
    }
  }
  for (Segment& s : out.spline.segments) {
    for (Point& q : s.bezier.p) {
      q = p.unscale * q;
      if (!is_finite(q)) {
        throw Error(ErrorCode::kNonFinite,
                    "kozak-krajnc: a control point overflowed on span " + std::to_string(s.span),
                    s.span);
      }
    }
  }
  return remainder_pieces;
}

/// Describe stage: collects the report of the fit.
KozakKrajncReport describe_fit(const Prepared& p, const Directions& d,
                               const std::vector<PieceFit>& pieces, int remainder_pieces,
                               const std::optional<G2Outcome>& g2,
                               const KozakKrajncOptions& options, ReportLevel level) {
  const Geometry& g = p.g;
  const std::size_t m = g.m;
  KozakKrajncReport r;
  r.pieces = m;
  r.detailed = level != ReportLevel::kNone;
  for (std::size_t l = 1; r.detailed && l <= m; ++l) {
    const PieceFit& f = pieces[l];
    KozakKrajncReport::Piece seg;
    for (const KozakKrajncSolution& s : f.all)
      seg.solutions.push_back(solution_report(s, p.unscale));
    seg.chosen = solution_report(f.s, p.unscale);
    seg.first = 3 * l - 3;
    seg.last = 3 * l;
    seg.xi_left = d.xi[l - 1];
    seg.xi_right = d.xi[l];
    seg.convex = g.piece[l].convex;
    seg.lambda1 = g.piece[l].lambda1;
    seg.lambda2 = g.piece[l].lambda2;
    seg.theorem = admissible(g, l, f.d0, f.d3);
    r.segments.push_back(std::move(seg));
  }
  for (std::size_t l = 0; r.detailed && l <= m; ++l) {
    KozakKrajncReport::Breakpoint bp{.point = 3 * l,
                                     .xi = d.xi[l],
                                     .prescribed = p.fixed[l].has_value(),
                                     .swept = !p.all_given,  // no sweeps: nothing to report
                                     .xi_set = d.sw.xi[l],
                                     .forward = d.sw.forward[l],
                                     .I = d.sw.I[l],
                                     .in_xi = d.in_xi[l] != 0};
    r.breakpoints.push_back(std::move(bp));
  }
  r.sweeps = !p.all_given;
  r.tangents = std::string(kTangentRule.name(options.tangents));
  r.gamma = options.gamma;
  if (p.rest != 0) {
    r.remainder = KozakKrajncReport::Remainder{
        .spans = p.rest, .first_point = p.nk - 1, .pieces = remainder_pieces};
  }
  if (g2) {
    r.g2 = KozakKrajncReport::G2{.converged = g2->rep.converged,
                                 .at_precision = g2->rep.at_precision,
                                 .iterations = g2->rep.iterations,
                                 .residual = g2->rep.residual,
                                 .reason = g2->rep.reason,
                                 .start = g2->start};
  }
  return r;
}

}  // namespace

void fit_kozak_krajnc(const FitInput& input, const KozakKrajncOptions& options, ReportLevel level,
                      FitResult& out) {
  Prepared p;
  prepare(input, options, out, p);
  Directions d = choose_directions(p, options);
  std::vector<PieceFit> pieces = solve_pieces(p, d, options);
  std::optional<G2Outcome> g2;
  if (options.g2) g2 = g2_stage(p, options, d, pieces);
  const int remainder_pieces = assemble(p, pieces, out);
  out.method_report = report_json(describe_fit(p, d, pieces, remainder_pieces, g2, options, level));
  // The solver's outcome is O(1) in size: reported at every level, like the other solvers'.
  if (g2) {
    const G2Report& rep = g2->rep;
    out.solver = SolverReport{.status = rep.converged      ? SolverStatus::kConverged
                                        : rep.at_precision ? SolverStatus::kConditioningLimit
                                        : rep.at_cap       ? SolverStatus::kIterationLimit
                                                           : SolverStatus::kStalled,
                              .iterations = rep.iterations,
                              .residual = rep.residual,
                              .tolerance = kG2Tolerance};
  }
}

Vec2 kozak_krajnc_direction(std::span<const Point> points, std::size_t breakpoint, double xi) {
  const Geometry g = geometry(points);
  return cone_point(g.u[breakpoint], g.v[breakpoint], xi);
}

std::optional<double> kozak_krajnc_xi_of(std::span<const Point> points, std::size_t breakpoint,
                                         Vec2 direction) {
  return xi_of(geometry(points), breakpoint, direction);
}

bool kozak_krajnc_piece_admissible(std::span<const Point> points, std::size_t piece, double xi_left,
                                   double xi_right) {
  const Geometry g = geometry(points);
  const std::size_t k = 3 * piece - 3;
  const Vec2 d0 = cone_point(g.u[piece - 1], g.v[piece - 1], xi_left);
  const Vec2 d3 = cone_point(g.u[piece], g.v[piece], xi_right);
  const KozakKrajncConstants c =
      kozak_krajnc_constants(points[k], points[k + 1], points[k + 2], points[k + 3], d0, d3);
  return kozak_krajnc_theorem_2_4(c) || kozak_krajnc_theorem_2_5(c);
}

FitResult fit_kozak_krajnc(const FitInput& input, const KozakKrajncOptions& options,
                           ReportLevel level) {
  FitResult result;
  fit_kozak_krajnc(input, options, level, result);
  return result;
}

}  // namespace fairspline

// ---- registry entry ----
#include "methods/builtin.hpp"

namespace fairspline::detail {

std::vector<MethodInfo> kozak_krajnc_methods() {
  return {{
      .name = "kozak-krajnc",
      .description =
          "G1 cubic spline through 3m+1 points, each cubic through four consecutive points at "
          "unknown parameters; tangent directions from the admissible sets of the "
          "forward/backward sweeps, so that every piece provably exists.",
      .paper = "J. Kozak, M. Krajnc, Geometric interpolation by planar cubic G1 splines, BIT 47 "
               "(2007), Sections 2-4",
      .options = {{.name = "gamma",
                   .type = OptionType::kChoiceOrNumber,
                   .default_value = 0.5,
                   .min = 0.0,
                   .max = 1.0,
                   .choices = {"auto"},
                   .doc = "place each free ξ at γ·inf Ξ + (1−γ)·sup Ξ of its admissible interval "
                          "(the paper's rule); auto: at the direction of the chord-length "
                          "parabola through the breakpoint and its neighbours, kept inside Ξ "
                          "(fairer curves when Ξ is wide)"},
                  {.name = "tangents",
                   .type = OptionType::kChoice,
                   .default_value = "sweep",
                   .choices = kTangentRule.names(),
                   .doc = "sweep: ξ placed by gamma; local-quadratic-*: directions of the "
                          "parabola through each breakpoint and its neighbours (uniform or "
                          "chord-length parameters), checked against the admissible sets (error "
                          "if outside)"},
                  {.name = "remainder",
                   .type = OptionType::kChoice,
                   .default_value = "error",
                   .choices = {"error", "hermite"},
                   .doc = "point counts other than 3m+1: error, or finish the last one or two "
                          "spans with G1 Hermite curves (Yong–Cheng composite OGH cubics; "
                          "directions of the chord-length parabola, the given end tangent if "
                          "any)"},
                  {.name = "g2",
                   .type = OptionType::kBoolean,
                   .default_value = false,
                   .doc = "solve (1.4) for G2 continuity at the interior breakpoints by Newton's "
                          "method from the G1 solution, inside the admissible sets; an error "
                          "(not_converged) if it does not converge, unless a best effort is asked "
                          "for: then the G1 spline is returned with the solver's status"},
                  {.name = "g2_max_iterations",
                   .type = OptionType::kInteger,
                   .default_value = 30,
                   .min = 1.0,
                   .max = 1000.0,
                   .doc = "Newton iteration limit for g2"}},
      .fit =
          [](const FitInput& in, const nlohmann::json& o, const FitOptions& f, FitResult& out) {
            KozakKrajncOptions opt;
            const nlohmann::json& gamma = o.at("gamma");
            opt.gamma =
                gamma.is_string() ? std::numeric_limits<double>::quiet_NaN() : gamma.get<double>();
            opt.tangents = kTangentRule.parse(o.at("tangents").get<std::string>());
            opt.remainder_hermite = o.at("remainder").get<std::string>() == "hermite";
            opt.g2 = o.at("g2").get<bool>();
            opt.g2_max_iterations = o.at("g2_max_iterations").get<int>();
            opt.best_effort = f.best_effort;
            fit_kozak_krajnc(in, opt, f.method_report_level(), out);
          },
      .capabilities = kozak_krajnc_capabilities(),
      .report_units = {{"segments/*/alpha0", 1, 0},
                       {"segments/*/alpha3", 1, 0},
                       {"segments/*/energy", 2, 0},
                       {"segments/*/solutions/*/alpha0", 1, 0},
                       {"segments/*/solutions/*/alpha3", 1, 0},
                       {"segments/*/solutions/*/energy", 2, 0}},
  }};
}

}  // namespace fairspline::detail
