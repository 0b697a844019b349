// The exact basic curve of elastic splines. See elastica.hpp and docs/methods/elastic.md.
//
// Everything is computed on one canonical curve, the rectangular elastica
//   p(u) = (√2 sin u, X(u)),  X(u) = ∫_0^u √2 sin²v / √(1 + sin²v) dv,  u ∈ [−π, π],
// with tangent angle θ(u) ∈ [0, π] (sin θ = sin²u, cos θ = cos u √(1 + sin²u)), curvature
// κ = √2 sin u (inflections at u = 0, ±π), ds = √2 du / √(1 + sin²u) and κ² ds = 2 dX. The piece
// for (α, β) is an arc [u0, u1] of it, mapped onto the chord by a similarity; its energy on the
// unit chord is 2 ΔX |C| (C the canonical chord).
#include "detail/elastica.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <boost/math/policies/policy.hpp>
#include <boost/math/special_functions/ellint_rd.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>

#include "detail/format.hpp"
#include "fairspline/error.hpp"

namespace fairspline::detail {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kSqrt2 = std::numbers::sqrt2;
constexpr double kEps = std::numeric_limits<double>::epsilon();
/// X(π/2) = 2E(1/√2) − K(1/√2) = π / (2K(1/√2)): the along-axis extent of a quarter wave.
constexpr double kXHalf = 0.84721308479397908660649912348219;
/// Arc length of a quarter wave, √2 ∫_0^{π/2} dv/√(1 + sin²v) = K(1/√2).
constexpr double kSHalf = 1.85407467730137191843385034719526;
/// Below this largest angle E_1 is its Taylor polynomial to degree 4 (small_angle_energy): the
/// remainder is O(angle⁶) with coefficients below 0.05 (docs), i.e. 1e-18 relative, while the
/// solved arc would lose accuracy (a short arc near the apex loses ~eps/angle).
constexpr double kSmallAngle = 1e-4;
/// Where the second derivatives do not exist (|α − β| = π) they are taken at this distance.
constexpr double kEdgeFloor = 1e-16;

// No promotion to long double: the double algorithms are accurate to a few ulp and 8× faster.
using Policy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;

// ---- the canonical elastica ----------------------------------------------------------------

/// X and arc length on |u| ≤ π/2 in Carlson's form, accurate relative to their size
/// (X ≈ √2u³/3 near the inflection).
double x_quarter(double s, double c) {
  return kSqrt2 / 3.0 * (s * s * s) * boost::math::ellint_rd(c * c, 1.0 + s * s, 1.0, Policy());
}
double s_quarter(double s, double c) {
  return kSqrt2 * s * boost::math::ellint_rf(c * c, 1.0 + s * s, 1.0, Policy());
}

/// X(u) for u ∈ [−π, π]: odd, and symmetric about the apex u = π/2.
double x_of(double u) {
  const double a = std::abs(u);
  const double r = a <= kPi / 2 ? x_quarter(std::sin(a), std::cos(a))
                                : 2.0 * kXHalf - x_quarter(std::sin(kPi - a), std::cos(kPi - a));
  return std::copysign(r, u);
}

/// Arc length from u = 0, same symmetries.
double s_of(double u) {
  const double a = std::abs(u);
  const double r = a <= kPi / 2 ? s_quarter(std::sin(a), std::cos(a))
                                : 2.0 * kSHalf - s_quarter(std::sin(kPi - a), std::cos(kPi - a));
  return std::copysign(r, u);
}

/// X(u1) − X(u0), accurate relative to itself: short arcs (where the difference of two X values
/// would cancel) by 10-point Gauss–Legendre, exact to 6e-16 for u1 − u0 ≤ 0.5 (the integrand's
/// poles are ≥ 0.88 from the real axis).
double delta_x(double u0, double u1) {
  if (u1 - u0 > 0.5) return x_of(u1) - x_of(u0);
  static constexpr std::array<double, 5> kNode = {0.148874338981631210885, 0.433395394129247190799,
                                                  0.679409568299024406234, 0.865063366688984510732,
                                                  0.973906528517171720078};
  static constexpr std::array<double, 5> kWeight = {
      0.295524224714752870174, 0.269266719309996355091, 0.219086362515982043996,
      0.149451349150580593146, 0.0666713443086881375936};
  const double m = 0.5 * (u0 + u1), h = 0.5 * (u1 - u0);
  const double sm = std::sin(m), cm = std::cos(m);
  double sum = 0.0;
  for (std::size_t i = 0; i < kNode.size(); ++i) {
    // sin(m ± h x) from one sincos per node pair.
    const double sh = std::sin(h * kNode[i]), ch = std::cos(h * kNode[i]);
    const double sp = sm * ch + cm * sh, sn = sm * ch - cm * sh;
    sum += kWeight[i] * (sp * sp / std::sqrt(1.0 + sp * sp) + sn * sn / std::sqrt(1.0 + sn * sn));
  }
  return kSqrt2 * h * sum;
}

/// sin u1 − sin u0 without cancellation.
double delta_sin(double u0, double u1) {
  return 2.0 * std::cos(0.5 * (u0 + u1)) * std::sin(0.5 * (u1 - u0));
}

/// p(u1) − p(u0).
Vec2 chord_of(double u0, double u1) {
  return {kSqrt2 * delta_sin(u0, u1), delta_x(u0, u1)};
}

/// Tangent angle θ(u) ∈ [0, π] and its derivative 2 sin u / √(1 + sin²u).
double theta(double u) {
  const double s = std::sin(u);
  return std::atan2(s * s, std::cos(u) * std::sqrt(1.0 + s * s));
}
double dtheta(double u) {
  const double s = std::sin(u);
  return 2.0 * s / std::sqrt(1.0 + s * s);
}
/// Unit tangent (cos θ, sin θ) at u.
Vec2 tangent_of(double u) {
  const double s = std::sin(u);
  return {std::cos(u) * std::sqrt(1.0 + s * s), s * s};
}
/// p'(u) = √2 / √(1 + sin²u) · (cos θ, sin θ).
Vec2 dp(double u) {
  const double s = std::sin(u), w = std::sqrt(1.0 + s * s);
  return {kSqrt2 * std::cos(u), kSqrt2 * s * s / w};
}
/// p''(u).
Vec2 ddp(double u) {
  const double s = std::sin(u), c = std::cos(u), w2 = 1.0 + s * s;
  return {-kSqrt2 * s, kSqrt2 * s * c * (2.0 + s * s) / (w2 * std::sqrt(w2))};
}

/// The u ∈ [0, π] with θ(u) = t, t ∈ [0, π]: sin²u = sin t, cos²u = cos²t / (1 + sin t).
double inv_theta(double t) {
  const double s = std::max(std::sin(t), 0.0);
  return std::atan2(std::sqrt(s), std::cos(t) / std::sqrt(1.0 + s));
}

/// inv_theta(t) given also d = π − t computed separately: exact where t is near π (sin of the
/// double nearest π is 1.2e-16, whose square root would move u by 1e-8).
double inv_theta(double t, double d) {
  return t <= kPi / 2 ? inv_theta(t) : kPi - inv_theta(d);
}

// ---- complex helpers for the similarity maps ------------------------------------------------

Vec2 cmul(Vec2 a, Vec2 b) {
  return {a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x};
}
Vec2 cdiv(Vec2 a, Vec2 b) {
  const double n = norm2(b);
  return {(a.x * b.x + a.y * b.y) / n, (a.y * b.x - a.x * b.y) / n};
}
Vec2 conj(Vec2 a) {
  return {a.x, -a.y};
}

// ---- the canonical problem ------------------------------------------------------------------
//
// Canonical angles: a ≥ |b| (reversal swaps α, β; reflection negates both), a ∈ (0, π),
// b ∈ [a − π, a]. The piece then turns clockwise first: u0 ∈ [−π, 0). Along the "path" u1 ↦
// arc with θ(u1) − θ(u0) = b − a (u0 = −U(θ(u1) + a − b)), the chord direction must equal
// θ(u0) − a: a root of G(u1) = χ(u0, u1) − (θ(u1) − b). u1 runs over [−U(Θ), U(Θ)],
// Θ = π − (a − b): u1 < 0 gives arcs without inflection, u1 > 0 arcs through the inflection;
// at either end the start is an inflection (u0 = −π).

struct Canonical {
  double a = 0.0, b = 0.0;
  double q = 0.0;      ///< a − b ∈ [0, π]
  double theta = 0.0;  ///< Θ = π − q, computed from a and b (exact 0 at the box corners)
};

struct PathPoint {
  double u0 = 0.0, u1 = 0.0;
  Vec2 c;          ///< chord p(u1) − p(u0)
  double g = 0.0;  ///< G(u1)
  double dg = std::numeric_limits<double>::quiet_NaN();
};

PathPoint path_at(const Canonical& k, double u1, bool with_derivative) {
  PathPoint r;
  r.u1 = u1;
  // Trigonometry once: sin²u = sin θ and cos u = cos θ / √(1 + sin θ) give u0 from θ0.
  const double s1 = std::sin(u1), c1 = std::cos(u1), w1 = std::sqrt(1.0 + s1 * s1);
  const double t1 = std::atan2(s1 * s1, c1 * w1);
  const double t0 = std::min(t1 + k.q, kPi);
  double st0, ct0;
  if (t0 <= kPi / 2) {
    st0 = std::sin(t0);
    ct0 = std::cos(t0);
  } else {  // from the deficit π − t0: exact at t0 = π
    const double d0 = std::max(k.theta - t1, 0.0);
    st0 = std::sin(d0);
    ct0 = -std::cos(d0);
  }
  st0 = std::max(st0, 0.0);
  const double w0 = std::sqrt(1.0 + st0);
  const double s0 = -std::sqrt(st0), c0 = ct0 / w0;
  r.u0 = std::atan2(s0, c0);  // in [−π, 0]
  const double dsin = u1 - r.u0 > 0.5 ? s1 - s0 : delta_sin(r.u0, u1);
  r.c = {kSqrt2 * dsin, delta_x(r.u0, u1)};
  // χ − θ1 as the angle from the end tangent to the chord, accurate also where both are near
  // π/2 (short arcs near the apex); atan2(0, 0) = 0 is the right limit when the arc shrinks to
  // the inflection (q = 0, u1 → 0).
  const Vec2 tan1{c1 * w1, s1 * s1};
  r.g = std::atan2(cross(tan1, r.c), dot(tan1, r.c)) + k.b;
  if (with_derivative) {
    const double th1 = 2.0 * s1 / w1, th0 = 2.0 * s0 / w0;
    const Vec2 dp1{kSqrt2 * c1, kSqrt2 * s1 * s1 / w1}, dp0{kSqrt2 * c0, kSqrt2 * st0 / w0};
    const double n2 = norm2(r.c);
    if (th0 != 0.0 && n2 > 0.0) {
      const double du0 = th1 / th0;  // θ(u0) = θ(u1) + q
      r.dg = (cross(r.c, dp1) - cross(r.c, dp0) * du0) / n2 - th1;
    }
  }
  return r;
}

/// Root of G in [lo, hi] with sign(G(lo)) = −sign(G(hi)) ≠ 0: Newton steps, bisection whenever
/// a step leaves the bracket (G is not monotone on the whole path). Returns the last point
/// evaluated (within a rounding step of the root).
PathPoint bracketed_newton(const Canonical& k, double lo, double hi, double glo, double x0) {
  const bool lo_positive = glo > 0.0;
  double x = (x0 > lo && x0 < hi) ? x0 : 0.5 * (lo + hi);
  const double gscale = kEps * std::max(std::abs(k.a), std::abs(k.b));
  PathPoint p;
  for (int it = 0; it < 100; ++it) {
    p = path_at(k, x, true);
    if (std::abs(p.g) <= gscale) break;
    if ((p.g > 0.0) == lo_positive)
      lo = x;
    else
      hi = x;
    double next = x - p.g / p.dg;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 2.0 * kEps * std::abs(x) ||
        hi - lo <= 2.0 * kEps * std::max(std::abs(lo), std::abs(hi)))
      break;
    x = next;
  }
  return p;
}

/// One candidate minimizer in canonical angles.
struct Candidate {
  ElasticaArc::Kind kind = ElasticaArc::Kind::kElastica;
  double u0 = 0.0, u1 = 0.0, segment = 0.0;
  Vec2 chord;
  ElasticaEnergy en;
};

/// Energy, gradient (first variation: −2κ_a, 2κ_b) and Hessian (implicit differentiation of
/// the two arc equations) of the elastica arc [u0, u1] solving canonical (a, b).
Candidate elastica_candidate(const Canonical& k, double u0, double u1) {
  Candidate r;
  r.u0 = u0;
  r.u1 = u1;
  r.chord = chord_of(u0, u1);
  const Vec2 c = r.chord;
  const double n = norm(c);
  const double s0 = std::sin(u0), s1 = std::sin(u1);
  ElasticaEnergy& e = r.en;
  e.e = 2.0 * c.y * n;
  e.ea = -2.0 * kSqrt2 * s0 * n;
  e.eb = 2.0 * kSqrt2 * s1 * n;
  if (k.theta < kEdgeFloor) {
    // The corner (π/2, −π/2): E ≈ E_c − (8/3) X_h Θ^{3/2}, so H → 2X_h/√Θ [[−1, 1], [1, −1]].
    const double h = 2.0 * kXHalf / std::sqrt(kEdgeFloor);
    e.eaa = e.ebb = -h;
    e.eab = h;
    return r;
  }
  // Residuals R1 = θ(u1) − θ(u0) − (b − a), R2 = θ(u0) − χ − a; J = ∂R/∂(u0, u1).
  const Vec2 p0 = dp(u0), p1 = dp(u1);
  const double n2 = n * n;
  const double th0 = dtheta(u0), th1 = dtheta(u1);
  const double chi0 = -cross(c, p0) / n2, chi1 = cross(c, p1) / n2;
  const double j00 = -th0, j01 = th1, j10 = th0 - chi0, j11 = -chi1;
  const double det = j00 * j11 - j01 * j10;
  // du/d(a, b) = −J⁻¹ [[1, −1], [−1, 0]].
  const double inv00 = j11 / det, inv01 = -j01 / det, inv10 = -j10 / det, inv11 = j00 / det;
  const double d00 = -(inv00 - inv01), d01 = inv00;  // du0/da, du0/db
  const double d10 = -(inv10 - inv11), d11 = inv10;  // du1/da, du1/db
  const double n0 = -dot(c, p0) / n, n1 = dot(c, p1) / n;
  const double ea0 = -2.0 * kSqrt2 * (std::cos(u0) * n + s0 * n0);
  const double ea1 = -2.0 * kSqrt2 * s0 * n1;
  const double eb0 = 2.0 * kSqrt2 * s1 * n0;
  const double eb1 = 2.0 * kSqrt2 * (std::cos(u1) * n + s1 * n1);
  e.eaa = ea0 * d00 + ea1 * d10;
  e.ebb = eb0 * d01 + eb1 * d11;
  e.eab = 0.5 * ((ea0 * d01 + ea1 * d11) + (eb0 * d00 + eb1 * d10));
  return r;
}

/// The U-turn piece of canonical (a, b), a > π/2: a full first turn [−π, 0], a segment along
/// the inflection tangent, then [0, u1] with θ(u1) = Θ. Chord direction χ = π − a, so the
/// segment length is −C_y cot a − √2 sin u1 and E = 2 C_y² / sin a. Returns false when that
/// length is negative (then no U-turn piece exists).
bool uturn_candidate(const Canonical& k, Candidate& r) {
  if (!(k.a > kPi / 2)) return false;
  const double u1 = inv_theta(k.theta, k.q);
  const double cy = x_of(u1) + 2.0 * kXHalf;
  const double sa = std::sin(k.a), ca = std::cos(k.a);
  const double segment = -cy * ca / sa - kSqrt2 * std::sin(u1);
  if (!(segment >= 0.0)) return false;
  r.kind = ElasticaArc::Kind::kUTurn;
  r.u0 = -kPi;
  r.u1 = u1;
  r.segment = segment;
  r.chord = {-cy * ca / sa, cy};
  // E = 2Y(t)² f(a), t = b − a + π, Y = X(U(t)) + 2X_h, f = 1/sin a; Y' = (√2/2) sin u1,
  // Y'' = (√2/2) cos u1 / θ'(u1) (unbounded at the edge Θ = 0: floored there).
  const double s1 = std::max(std::sin(u1), std::sqrt(kEdgeFloor));
  const double y = cy, y1 = 0.5 * kSqrt2 * std::sin(u1);
  const double y2 = 0.5 * kSqrt2 * std::cos(u1) * std::sqrt(1.0 + s1 * s1) / (2.0 * s1);
  const double f = 1.0 / sa, f1 = -ca / (sa * sa), f2 = (1.0 + ca * ca) / (sa * sa * sa);
  ElasticaEnergy& e = r.en;
  e.e = 2.0 * y * y * f;
  e.eb = 4.0 * y * y1 * f;
  e.ea = -4.0 * y * y1 * f + 2.0 * y * y * f1;
  const double yy = y1 * y1 + y * y2;
  e.ebb = 4.0 * yy * f;
  e.eab = -4.0 * yy * f + 4.0 * y * y1 * f1;
  e.eaa = 4.0 * yy * f - 8.0 * y * y1 * f1 + 2.0 * y * y * f2;
  return true;
}

/// Every root of G on [lo, hi]: sign changes between `samples` + 1 samples, and pairs of roots
/// inside one cell, found where G turns back towards zero inside it (the derivative changes
/// sign; the extremum is located by golden section). Such pairs occur just below the U-turn
/// threshold, e.g. two roots 0.06 apart at (118.2°, 50°), and one of them can be the minimizer.
template <class Out>
void scan_roots(const Canonical& k, double lo, double hi, int samples, Out&& out) {
  struct Sample {
    double x, g, dg;
  };
  auto sample = [&](double x) {
    const PathPoint p = path_at(k, x, true);
    double dg = p.dg;
    if (!std::isfinite(dg)) {  // at the ends G has a square-root singularity: one-sided slope
      const double h = 1e-7 * (hi - lo) * (x > lo ? -1.0 : 1.0);
      dg = (path_at(k, x + h, false).g - p.g) / h;
    }
    return Sample{x, p.g, dg};
  };
  Sample prev = sample(lo);
  for (int i = 1; i <= samples; ++i) {
    const Sample cur = sample(i == samples ? hi : lo + (hi - lo) * i / samples);
    if (prev.g == 0.0 && i > 1) out(prev.x);
    if ((prev.g > 0.0 && cur.g < 0.0) || (prev.g < 0.0 && cur.g > 0.0)) {
      out(bracketed_newton(k, prev.x, cur.x, prev.g, 0.5 * (prev.x + cur.x)).u1);
    } else if (prev.g != 0.0 && cur.g != 0.0) {
      const double s = prev.g > 0.0 ? 1.0 : -1.0;  // both of this sign
      if (s * prev.dg < 0.0 && s * cur.dg > 0.0) {
        // Golden section for the minimum of s·G; stop as soon as it changes sign.
        constexpr double kGold = 0.6180339887498949;
        double a = prev.x, b = cur.x;
        double x1 = b - kGold * (b - a), x2 = a + kGold * (b - a);
        double f1 = s * path_at(k, x1, false).g, f2 = s * path_at(k, x2, false).g;
        // Down to 1e-6 of the cell: a dip missed below that is a near-double root, a fold,
        // whose pair of arcs is not the minimizer (docs).
        while (f1 > 0.0 && f2 > 0.0 && b - a > 1e-6 * (cur.x - prev.x)) {
          if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - kGold * (b - a);
            f1 = s * path_at(k, x1, false).g;
          } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + kGold * (b - a);
            f2 = s * path_at(k, x2, false).g;
          }
        }
        const double xm = f1 <= 0.0 ? x1 : x2;
        if (std::min(f1, f2) < 0.0) {
          out(bracketed_newton(k, prev.x, xm, prev.g, 0.5 * (prev.x + xm)).u1);
          out(bracketed_newton(k, xm, cur.x, -prev.g, 0.5 * (xm + cur.x)).u1);
        }
      }
    }
    prev = cur;
  }
}

/// The path's ends: u1 ∈ [lo, hi] (lo = hi at Θ = 0, where only the full turn [−π, 0] or a
/// U-turn piece is left).
std::pair<double, double> path_range(const Canonical& k) {
  const double hi = inv_theta(k.theta, k.q);
  return {k.q > 0.0 ? -hi : 0.0, hi};
}

/// Every piece satisfying the first-order conditions that a scan of G at `samples` points
/// finds, and the U-turn piece when it exists.
std::vector<Candidate> canonical_candidates(const Canonical& k, int samples) {
  std::vector<Candidate> out;
  const auto [lo, hi] = path_range(k);
  if (hi - lo <= 0.0) {
    if (k.a <= kPi / 2) out.push_back(elastica_candidate(k, -kPi, 0.0));  // the full turn
  } else {
    scan_roots(k, lo, hi, samples, [&](double u1) {
      const PathPoint p = path_at(k, u1, false);
      if (p.u0 < u1) out.push_back(elastica_candidate(k, p.u0, u1));
    });
  }
  Candidate u;
  if (uturn_candidate(k, u)) out.push_back(u);
  return out;
}

/// The minimizing piece for canonical (a, b).
Candidate solve_canonical(const Canonical& k) {
  const auto [lo, hi] = path_range(k);
  // Inside the box (a ≤ π/2) exactly one root, G(lo) > 0 > G(hi) (docs): Newton from the
  // small-angle solution u1 ≈ (a + 2b)/√(3(a + b)), checked afterwards (a root strictly inside).
  if (k.a <= kPi / 2 && hi > lo) {
    const double s = k.a + k.b;
    const double guess = s > 0.0 ? (k.a + 2.0 * k.b) / std::sqrt(3.0 * s) : lo;
    const PathPoint p = bracketed_newton(k, lo, hi, 1.0, guess);
    if (p.u1 > lo && p.u1 < hi && std::abs(p.g) <= 1e-9 * k.a)
      return elastica_candidate(k, p.u0, p.u1);
  }
  // Outside the box: up to two elastica arcs and the U-turn piece; the least energy wins. With
  // the search for root pairs inside a cell, 12 samples already found the minimizer on a 1°
  // grid of the canonical region (16290 points, against 3000 samples); 24 for margin.
  const std::vector<Candidate> all = canonical_candidates(k, 24);
  if (all.empty()) {
    // Not reached on the feasible domain (tests scan it); fail loudly rather than guess.
    throw Error(ErrorCode::kNotConverged,
                "elastica: no minimizing s-curve found for the canonical angles (" +
                    format_number(k.a) + ", " + format_number(k.b) + ")");
  }
  return *std::min_element(all.begin(), all.end(),
                           [](const Candidate& x, const Candidate& y) { return x.en.e < y.en.e; });
}

/// Reduction to canonical angles: reversal when |β| > |α|, then reflection when α < 0.
struct Reduction {
  Canonical k;
  bool reversed = false, mirrored = false;
};

void check_angles(double alpha, double beta) {
  if (!std::isfinite(alpha) || !std::isfinite(beta))
    throw Error(ErrorCode::kNonFinite, "elastica: the end angles must be finite, got (" +
                                           format_number(alpha) + ", " + format_number(beta) + ")");
  if (!elastica_feasible(alpha, beta))
    throw Error(ErrorCode::kInfeasible,
                "elastica: no s-curve has the end angles (" + format_number(alpha) + ", " +
                    format_number(beta) +
                    ") (radians from the chord); it needs |alpha| < pi, |beta| < pi and "
                    "|alpha - beta| <= pi");
}

Reduction reduce(double alpha, double beta) {
  check_angles(alpha, beta);
  Reduction r;
  double a = alpha, b = beta;
  if (std::abs(b) > std::abs(a)) {
    std::swap(a, b);
    r.reversed = true;
  }
  if (a < 0.0) {
    a = -a;
    b = -b;
    r.mirrored = true;
  }
  r.k.a = a;
  r.k.b = b;
  r.k.q = std::min(a - b, kPi);
  // Θ = π − (a − b) as (π − a) + b: exactly 0 for a = π/2, b = −π/2 in double.
  r.k.theta = std::clamp((kPi - a) + b, 0.0, kPi);
  return r;
}

/// Gradient and Hessian of E(α, β) from those of the canonical angles.
ElasticaEnergy to_input(const Reduction& r, ElasticaEnergy e) {
  if (r.mirrored) {
    e.ea = -e.ea;
    e.eb = -e.eb;
  }
  if (r.reversed) {
    std::swap(e.ea, e.eb);
    std::swap(e.eaa, e.ebb);
  }
  return e;
}

/// E_1 = 4(α² + αβ + β²) − (2/21)(4α⁴ + 2α³β + 3α²β² + 2αβ³ + 4β⁴) + O(angle⁶): the
/// small-deflection beam (the Hermite cubic y with slopes tan α, tan β) with the first
/// correction of κ² ds = y''² (1 + y'²)^(−5/2) dx (docs).
ElasticaEnergy small_angle_energy(double a, double b) {
  const double a2 = a * a, b2 = b * b, ab = a * b, c = 2.0 / 21.0;
  ElasticaEnergy e;
  e.e = 4.0 * (a2 + ab + b2) -
        c * (4.0 * a2 * a2 + 2.0 * a2 * ab + 3.0 * ab * ab + 2.0 * ab * b2 + 4.0 * b2 * b2);
  e.ea = 8.0 * a + 4.0 * b - c * (16.0 * a2 * a + 6.0 * a2 * b + 6.0 * a * b2 + 2.0 * b2 * b);
  e.eb = 4.0 * a + 8.0 * b - c * (2.0 * a2 * a + 6.0 * a2 * b + 6.0 * a * b2 + 16.0 * b2 * b);
  e.eaa = 8.0 - c * (48.0 * a2 + 12.0 * ab + 6.0 * b2);
  e.eab = 4.0 - c * (6.0 * a2 + 12.0 * ab + 6.0 * b2);
  e.ebb = 8.0 - c * (6.0 * a2 + 12.0 * ab + 48.0 * b2);
  return e;
}

}  // namespace

bool elastica_feasible(double alpha, double beta) {
  if (!std::isfinite(alpha) || !std::isfinite(beta)) return false;
  return std::abs(alpha) < kPi && std::abs(beta) < kPi &&
         std::abs(alpha - beta) <= kPi * (1.0 + 4.0 * kEps);
}

namespace {

ElasticaEnergy energy_of(const Reduction& r, double alpha, double beta) {
  if (r.k.a <= kSmallAngle) return small_angle_energy(alpha, beta);
  const Candidate c = solve_canonical(r.k);
  ElasticaEnergy e = c.en;
  // On the diagonals |α| = |β| the symmetries E(α, β) = E(β, α) = E(−α, −β) tie ∂E/∂α to
  // ±∂E/∂β: impose it exactly (the solved values differ in the last bits). For α = β on a
  // U-turn piece (both turns full) E has a kink across the diagonal, the one-sided gradients
  // being each other's swap: the mean is then a symmetric subgradient.
  if (r.k.a == r.k.b || r.k.a == -r.k.b) {
    const double sign = r.k.a == r.k.b ? 1.0 : -1.0;
    e.ea = 0.5 * (e.ea + sign * e.eb);
    e.eb = sign * e.ea;
    e.eaa = e.ebb = 0.5 * (e.eaa + e.ebb);
  }
  return to_input(r, e);
}

}  // namespace

ElasticaEnergy elastica_energy(double alpha, double beta) {
  ElasticaEnergy e = energy_of(reduce(alpha, beta), alpha, beta);
  if (std::isfinite(e.eaa) && std::isfinite(e.eab) && std::isfinite(e.ebb)) return e;
  // Not reached on the tests' dense grids (a root exactly at a fold would get here): central
  // differences of the gradient, which is finite everywhere, one-sided at the domain's edge.
  const double h = 1e-7;
  auto grad = [](double a, double b) { return energy_of(reduce(a, b), a, b); };
  auto diff = [&](double da, double db) {
    const bool fwd = elastica_feasible(alpha + da, beta + db);
    const bool bwd = elastica_feasible(alpha - da, beta - db);
    const ElasticaEnergy p = fwd ? grad(alpha + da, beta + db) : e;
    const ElasticaEnergy m = bwd ? grad(alpha - da, beta - db) : e;
    const double w = (fwd && bwd ? 2.0 : 1.0) * h;
    return std::pair{(p.ea - m.ea) / w, (p.eb - m.eb) / w};
  };
  const auto [haa, hba] = diff(h, 0.0);
  const auto [hab, hbb] = diff(0.0, h);
  e.eaa = haa;
  e.ebb = hbb;
  e.eab = 0.5 * (hab + hba);
  return e;
}

// ---- the piece ------------------------------------------------------------------------------

namespace {

/// Canonical position relative to the start p(u0) at canonical parameter u of the piece;
/// `past_segment`: a kUTurn point on its last part [0, u1] (shifted by the segment).
Vec2 canonical_point(const ElasticaArc& arc, double u, bool past_segment) {
  Vec2 v = chord_of(arc.u0, u);
  if (past_segment) v.x += arc.segment;
  return v;
}

/// Canonical arc length of the piece.
double canonical_length(const ElasticaArc& arc) {
  if (arc.kind == ElasticaArc::Kind::kStraight) return norm(arc.chord);
  return s_of(arc.u1) - s_of(arc.u0) + arc.segment;
}

/// u with s_of(u) = target, u ∈ [ua, ub] (Newton; ds/du ∈ [1, √2]).
double u_at_length(double target, double ua, double ub) {
  const double sa = s_of(ua), sb = s_of(ub);
  double u = sb > sa ? ua + (ub - ua) * (target - sa) / (sb - sa) : ua;
  for (int it = 0; it < 8; ++it) {
    const double s = std::sin(u);
    const double step = (s_of(u) - target) * std::sqrt(1.0 + s * s) / kSqrt2;
    u = std::clamp(u - step, ua, ub);
    if (std::abs(step) <= 2.0 * kEps * std::max(1.0, std::abs(u))) break;
  }
  return u;
}

/// Where the arc-length fraction t of the input piece lies on the canonical piece.
struct CanonicalLocation {
  Vec2 point;    ///< relative to p(u0)
  Vec2 tangent;  ///< canonical unit tangent
  double curvature = 0.0;
};

CanonicalLocation locate(const ElasticaArc& arc, double t) {
  t = std::clamp(t, 0.0, 1.0);
  if (arc.reversed) t = 1.0 - t;
  CanonicalLocation r;
  if (arc.kind == ElasticaArc::Kind::kStraight) {
    r.point = {t, 0.0};
    r.tangent = {1.0, 0.0};
    return r;
  }
  const double s = t * canonical_length(arc);
  double u;
  bool past_segment = false;
  if (arc.kind == ElasticaArc::Kind::kUTurn) {
    const double first = 2.0 * kSHalf;  // the full turn [−π, 0]
    if (s <= first) {
      u = u_at_length(s_of(arc.u0) + s, arc.u0, 0.0);
    } else if (s <= first + arc.segment) {
      r.point = canonical_point(arc, 0.0, false) + Vec2{s - first, 0.0};
      r.tangent = {1.0, 0.0};
      return r;
    } else {
      u = u_at_length(s - first - arc.segment, 0.0, arc.u1);
      past_segment = true;
    }
  } else {
    u = u_at_length(s_of(arc.u0) + s, arc.u0, arc.u1);
  }
  r.point = canonical_point(arc, u, past_segment);
  r.tangent = tangent_of(u);
  r.curvature = kSqrt2 * std::sin(u);
  return r;
}

/// The similarity from canonical coordinates (relative to p(u0)) to the world: unit chord,
/// reflection, reversal (w ↦ 1 − w), then p0 + (p1 − p0) w.
Point to_world_point(const ElasticaArc& arc, Vec2 v) {
  Vec2 w = arc.kind == ElasticaArc::Kind::kStraight ? v : cdiv(v, arc.chord);
  if (arc.mirrored) w = conj(w);
  if (arc.reversed) w = Vec2{1.0, 0.0} - w;
  return arc.p0 + cmul(arc.p1 - arc.p0, w);
}
/// Directions keep their sense under the reversal (a point reflection traversed backwards).
Vec2 to_world_direction(const ElasticaArc& arc, Vec2 d) {
  Vec2 w = arc.kind == ElasticaArc::Kind::kStraight ? d : cdiv(d, arc.chord);
  if (arc.mirrored) w = conj(w);
  return normalized(cmul(arc.p1 - arc.p0, w));
}

}  // namespace

namespace {

void check_points(Point p0, Point p1) {
  if (!is_finite(p0) || !is_finite(p1))
    throw Error(ErrorCode::kNonFinite, "elastica: the end points must be finite, got " +
                                           format_point(p0) + " and " + format_point(p1));
  if (p0 == p1)
    throw Error(ErrorCode::kInvalidArgument,
                "elastica: the end points coincide at " + format_point(p0));
}

ElasticaArc make_arc(Point p0, Point p1, double alpha, double beta, const Reduction& r,
                     const Candidate& c) {
  ElasticaArc arc;
  arc.p0 = p0;
  arc.p1 = p1;
  arc.alpha = alpha;
  arc.beta = beta;
  arc.reversed = r.reversed;
  arc.mirrored = r.mirrored;
  arc.kind = c.kind;
  arc.u0 = c.u0;
  arc.u1 = c.u1;
  arc.segment = c.segment;
  arc.chord = c.chord;
  arc.unit_energy = r.k.a <= kSmallAngle ? small_angle_energy(alpha, beta).e : c.en.e;
  return arc;
}

}  // namespace

ElasticaArc elastica_arc(Point p0, Point p1, double alpha, double beta) {
  check_points(p0, p1);
  const Reduction r = reduce(alpha, beta);
  if (r.k.a <= 1e-150) {  // deviates from the chord by less than 1e-150 of its length
    ElasticaArc arc;
    arc.p0 = p0;
    arc.p1 = p1;
    arc.alpha = alpha;
    arc.beta = beta;
    arc.unit_energy = small_angle_energy(alpha, beta).e;
    return arc;
  }
  return make_arc(p0, p1, alpha, beta, r, solve_canonical(r.k));
}

std::vector<ElasticaArc> elastica_candidates(Point p0, Point p1, double alpha, double beta,
                                             int samples) {
  check_points(p0, p1);
  const Reduction r = reduce(alpha, beta);
  std::vector<ElasticaArc> out;
  if (r.k.a == 0.0) return out;
  for (const Candidate& c : canonical_candidates(r.k, std::max(samples, 2)))
    out.push_back(make_arc(p0, p1, alpha, beta, r, c));
  return out;
}

double ElasticaArc::length() const {
  return canonical_length(*this) / norm(chord) * distance(p0, p1);
}

Point ElasticaArc::point(double t) const {
  if (t <= 0.0) return p0;
  if (t >= 1.0) return p1;
  return to_world_point(*this, locate(*this, t).point);
}

Vec2 ElasticaArc::tangent(double t) const {
  return to_world_direction(*this, locate(*this, t).tangent);
}

double ElasticaArc::curvature(double t) const {
  const CanonicalLocation c = locate(*this, t);
  double k = c.curvature * (kind == Kind::kStraight ? 1.0 : norm(chord)) / distance(p0, p1);
  if (mirrored) k = -k;
  if (reversed) k = -k;
  return k;
}

// ---- Bézier approximation -------------------------------------------------------------------

namespace {

/// One cubic of the approximation in canonical coordinates: start point (relative to p(u0)),
/// unit tangents, handle lengths, end point.
struct HermitePiece {
  Vec2 p0, t0, t1, p3;
  double a = 0.0, b = 0.0;
  CubicBezier bezier() const { return {{p0, p0 + a * t0, p3 - b * t1, p3}}; }
};

/// A part of the piece to approximate: the elastica over [u_start, u_end], optionally after a
/// straight lead of length `lead` along the inflection tangent that ends at u = 0 (the U-turn's
/// segment; it is parameterized by u ∈ [−lead/√2, 0], the elastica's speed at u = 0, so the
/// parameterization stays C¹ there). Positions are relative to where the part starts.
struct Part {
  double u_start = 0.0, u_end = 0.0;
  double lead = 0.0;

  bool on_lead(double u) const { return lead > 0.0 && u <= 0.0; }
  /// position(u) − position(v), without cancellation for nearby u, v.
  Vec2 diff(double v, double u) const {
    if (lead <= 0.0) return chord_of(v, u);
    const Vec2 straight{kSqrt2 * (std::min(u, 0.0) - std::min(v, 0.0)), 0.0};
    if (u <= 0.0 && v <= 0.0) return straight;
    if (u >= 0.0 && v >= 0.0) return chord_of(v, u);
    return u > v ? straight + chord_of(0.0, u) : straight - chord_of(0.0, v);
  }
  Vec2 tangent(double u) const { return on_lead(u) ? Vec2{1.0, 0.0} : tangent_of(u); }
  double curvature(double u) const { return on_lead(u) ? 0.0 : kSqrt2 * std::sin(u); }
  Vec2 d1(double u) const { return on_lead(u) ? Vec2{kSqrt2, 0.0} : dp(u); }
  Vec2 d2(double u) const { return on_lead(u) ? Vec2{0.0, 0.0} : ddp(u); }
  /// Arc length from the part's start (for the least-squares parameters).
  double length_to(double u) const {
    if (lead <= 0.0) return s_of(u) - s_of(u_start);
    return kSqrt2 * (std::min(u, 0.0) - u_start) + (u > 0.0 ? s_of(u) : 0.0);
  }
  /// Total turn of [ua, ub] (θ decreases before the inflection, increases after it).
  double turn(double ua, double ub) const {
    const double a = on_lead(ua) ? 0.0 : theta(ua), b = on_lead(ub) ? 0.0 : theta(ub);
    return ua < 0.0 && ub > 0.0 ? a + b : std::abs(b - a);
  }
};

/// G2 Hermite handles: (3/2)κ0 a² = cross(T0, D) − b cross(T0, T1) and the mirror equation at
/// the end (de Boor, Höllig, Sabin), by Newton from a = b = |D|/3.
bool g2_handles(Vec2 d, Vec2 t0, Vec2 t1, double k0, double k1, double& a, double& b) {
  const double len = norm(d);
  const double c = cross(t0, t1), d0 = cross(t0, d), d1 = cross(d, t1);
  a = b = len / 3.0;
  for (int it = 0; it < 40; ++it) {
    const double f0 = 1.5 * k0 * a * a + c * b - d0;
    const double f1 = 1.5 * k1 * b * b + c * a - d1;
    const double j00 = 3.0 * k0 * a, j11 = 3.0 * k1 * b;
    const double det = j00 * j11 - c * c;
    if (det == 0.0 || !std::isfinite(det)) return false;
    const double da = (f0 * j11 - c * f1) / det, db = (j00 * f1 - c * f0) / det;
    a -= da;
    b -= db;
    if (!(a > 0.0 && b > 0.0 && a < len && b < len)) return false;
    if (std::abs(da) + std::abs(db) <= 1e-14 * len) return true;
  }
  return false;
}

/// Least-squares handles against 33 points of [ua, ub], with 4 rounds of parameter correction
/// (the points' parameters projected onto the current cubic).
void least_squares_handles(const Part& part, double ua, double ub, HermitePiece& h) {
  constexpr int kPoints = 33;
  std::array<Vec2, kPoints> q;
  std::array<double, kPoints> tau;
  const double s0 = part.length_to(ua), len = part.length_to(ub) - s0;
  for (int j = 0; j < kPoints; ++j) {
    const double u = ua + (ub - ua) * j / (kPoints - 1);
    q[j] = part.diff(ua, u);
    tau[j] = (part.length_to(u) - s0) / len;
  }
  h.a = h.b = norm(h.p3 - h.p0) / 3.0;
  for (int round = 0; round < 5; ++round) {
    double m00 = 0, m01 = 0, m11 = 0, r0 = 0, r1 = 0;
    for (int j = 0; j < kPoints; ++j) {
      const double t = tau[j], v = 1.0 - t;
      const double b0 = v * v * v, b1 = 3 * t * v * v, b2 = 3 * t * t * v, b3 = t * t * t;
      const Vec2 base = (b0 + b1) * h.p0 + (b2 + b3) * h.p3;
      const Vec2 ca = b1 * h.t0, cb = -b2 * h.t1, res = q[j] - base;
      m00 += dot(ca, ca);
      m01 += dot(ca, cb);
      m11 += dot(cb, cb);
      r0 += dot(ca, res);
      r1 += dot(cb, res);
    }
    const double det = m00 * m11 - m01 * m01;
    if (!(det > 0.0)) break;
    const double a = (r0 * m11 - m01 * r1) / det, b = (m00 * r1 - m01 * r0) / det;
    if (!(a > 0.0 && b > 0.0)) break;
    h.a = a;
    h.b = b;
    const CubicBezier bz = h.bezier();
    for (int j = 1; j + 1 < kPoints; ++j) {  // parameter correction
      for (int it = 0; it < 3; ++it) {
        const Vec2 e = bz.eval(tau[j]) - q[j], d1 = bz.d1(tau[j]), d2 = bz.d2(tau[j]);
        const double den = dot(d1, d1) + dot(e, d2);
        if (!(den > 0.0)) break;
        tau[j] = std::clamp(tau[j] - dot(e, d1) / den, 0.0, 1.0);
      }
    }
  }
}

/// Upper bound of the Hausdorff distance between the cubic and [ua, ub], measured at 65
/// points each way: each distance is to an actual point of the other curve (a foot point
/// polished by Newton), so it bounds the distance at that sample from above.
double sampled_distance(const Part& part, double ua, double ub, const CubicBezier& bz) {
  constexpr int kSamples = 64;
  double worst = 0.0;
  for (int i = 0; i <= kSamples; ++i) {
    const double t = static_cast<double>(i) / kSamples;
    // cubic → arc
    const Vec2 q = bz.eval(t);
    double u = ua + (ub - ua) * t;
    for (int it = 0; it < 6; ++it) {
      const Vec2 e = part.diff(ua, u) - q, d1 = part.d1(u), d2 = part.d2(u);
      const double den = dot(d1, d1) + dot(e, d2);
      if (!(den > 0.0)) break;
      const double next = std::clamp(u - dot(e, d1) / den, ua, ub);
      if (next == u) break;
      u = next;
    }
    worst = std::max(worst, norm(part.diff(ua, u) - q));
    // arc → cubic
    const Vec2 r = part.diff(ua, ua + (ub - ua) * t);
    double v = t;
    for (int it = 0; it < 6; ++it) {
      const Vec2 e = bz.eval(v) - r, d1 = bz.d1(v), d2 = bz.d2(v);
      const double den = dot(d1, d1) + dot(e, d2);
      if (!(den > 0.0)) break;
      const double next = std::clamp(v - dot(e, d1) / den, 0.0, 1.0);
      if (next == v) break;
      v = next;
    }
    worst = std::max(worst, norm(bz.eval(v) - r));
  }
  return worst;
}

/// The cubic of [ua, ub] in coordinates relative to its start: the G2 Hermite cubic, or the
/// least-squares one when that has no solution or misses `target` (it is often twice as
/// close, while the G2 one keeps the curvature continuous at the joints). Sets `distance` to
/// its sampled distance from the sub-arc.
HermitePiece fit_sub_arc(const Part& part, double ua, double ub, double target, double& distance) {
  HermitePiece h;
  h.p0 = {0.0, 0.0};
  h.p3 = part.diff(ua, ub);
  h.t0 = part.tangent(ua);
  h.t1 = part.tangent(ub);
  double a, b;
  if (g2_handles(h.p3, h.t0, h.t1, part.curvature(ua), part.curvature(ub), a, b)) {
    h.a = a;
    h.b = b;
    distance = sampled_distance(part, ua, ub, h.bezier());
    if (distance <= target) return h;
  } else {
    distance = std::numeric_limits<double>::infinity();
  }
  HermitePiece ls = h;
  least_squares_handles(part, ua, ub, ls);
  const double d = sampled_distance(part, ua, ub, ls.bezier());
  if (d < distance) {
    distance = d;
    return ls;
  }
  return h;
}

/// Appends the certified cubics of [ua, ub], halving it until each passes; `origin` is where
/// the part starts, relative to p(u0).
void approximate(const Part& part, Vec2 origin, double ua, double ub, double tol, int depth,
                 std::vector<HermitePiece>& out) {
  double d;
  HermitePiece h = fit_sub_arc(part, ua, ub, 0.5 * tol, d);
  // 40 halvings leave 1e-12 of a quarter wave: never reached for accuracy >= 1e-13.
  if (d <= 0.5 * tol || depth >= 40) {
    const Vec2 base = origin + part.diff(part.u_start, ua);
    h.p0 = base;
    h.p3 = h.p3 + base;
    out.push_back(h);
    return;
  }
  const double um = 0.5 * (ua + ub);
  approximate(part, origin, ua, um, tol, depth + 1, out);
  approximate(part, origin, um, ub, tol, depth + 1, out);
}

/// Starts with sub-arcs turning at most 90° (a cubic cannot follow much more).
void approximate_part(const Part& part, Vec2 origin, double tol, std::vector<HermitePiece>& out) {
  const double ua = part.u_start, ub = part.u_end;
  const int n = std::max(1, static_cast<int>(std::ceil(part.turn(ua, ub) / (kPi / 2) - 1e-9)));
  for (int i = 0; i < n; ++i)
    approximate(part, origin, ua + (ub - ua) * i / n,
                i + 1 == n ? ub : ua + (ub - ua) * (i + 1) / n, tol, 0, out);
}

}  // namespace

std::vector<CubicBezier> elastica_to_beziers(const ElasticaArc& arc, double accuracy) {
  if (!(accuracy >= 1e-13) || !std::isfinite(accuracy))
    throw Error(
        ErrorCode::kInvalidArgument,
        "elastica: the Bezier accuracy must be a number >= 1e-13, got " + format_number(accuracy));
  const Vec2 chord_w = arc.p1 - arc.p0;
  const double L = norm(chord_w);
  const Vec2 d_start = rotate(chord_w / L, arc.alpha), d_end = rotate(chord_w / L, arc.beta);
  if (arc.kind == ElasticaArc::Kind::kStraight)  // (angles 0, or below 1e-150)
    return {{{arc.p0, arc.p0 + (L / 3.0) * d_start, arc.p1 - (L / 3.0) * d_end, arc.p1}}};
  // Canonical pieces in canonical order. Parts split at the inflection only where both sides
  // are substantial: a sliver of a cubic would have handles too short for its directions to
  // survive rounding of the control points.
  const double nc = norm(arc.chord);
  const double tol = accuracy * nc;
  std::vector<HermitePiece> pieces;
  if (arc.kind == ElasticaArc::Kind::kUTurn) {
    approximate_part({-kPi, 0.0, 0.0}, {0.0, 0.0}, tol, pieces);
    // The segment and the last turn as one part.
    approximate_part({-arc.segment / kSqrt2, arc.u1, arc.segment}, canonical_point(arc, 0.0, false),
                     tol, pieces);
  } else if (arc.u0 < 0.0 && arc.u1 > 0.0 && std::min(-arc.u0, arc.u1) > 0.05 * (arc.u1 - arc.u0)) {
    approximate_part({arc.u0, 0.0, 0.0}, {0.0, 0.0}, tol, pieces);
    approximate_part({0.0, arc.u1, 0.0}, canonical_point(arc, 0.0, false), tol, pieces);
  } else {
    approximate_part({arc.u0, arc.u1, 0.0}, {0.0, 0.0}, tol, pieces);
  }
  // To the world, in the input's order; joints and their tangents shared exactly.
  const double scale = L / nc;
  struct World {
    Point p0, p3;
    Vec2 t0, t1;
    double a, b;
  };
  std::vector<World> w;
  w.reserve(pieces.size());
  for (const HermitePiece& h : pieces) {
    World x{to_world_point(arc, h.p0),
            to_world_point(arc, h.p3),
            to_world_direction(arc, h.t0),
            to_world_direction(arc, h.t1),
            h.a * scale,
            h.b * scale};
    if (arc.reversed) {
      std::swap(x.p0, x.p3);
      std::swap(x.t0, x.t1);
      std::swap(x.a, x.b);
    }
    w.push_back(x);
  }
  if (arc.reversed) std::reverse(w.begin(), w.end());
  w.front().p0 = arc.p0;
  w.front().t0 = d_start;
  w.back().p3 = arc.p1;
  w.back().t1 = d_end;
  for (std::size_t i = 0; i + 1 < w.size(); ++i) {
    w[i + 1].p0 = w[i].p3;
    w[i + 1].t0 = w[i].t1;
  }
  std::vector<CubicBezier> out;
  out.reserve(w.size());
  for (const World& x : w) out.push_back({{x.p0, x.p0 + x.a * x.t0, x.p3 - x.b * x.t1, x.p3}});
  return out;
}

}  // namespace fairspline::detail
