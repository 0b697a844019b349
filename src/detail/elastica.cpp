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

#include "detail/format.hpp"
#include "detail/numbers.hpp"
#include "fairspline/error.hpp"

namespace fairspline::detail {

namespace {

constexpr double kSqrt2 = std::numbers::sqrt2;

/// Angles (rad) up to which a piece is the straight segment: 50 times the largest at which a scan
/// of (α, β) found the canonical arc unresolved (u0 = u1, 2e-15), and a deviation from the chord
/// (a/4 of its length) below the finest Bézier accuracy, 1e-13.
constexpr double kStraightAngle = 1e-13;
/// X(π/2) = 2E(1/√2) − K(1/√2) = π / (2K(1/√2)): the along-axis extent of a quarter wave.
constexpr double kXHalf = 0.84721308479397908660649912348219;
/// Arc length of a quarter wave, √2 ∫_0^{π/2} dv/√(1 + sin²v) = K(1/√2).
constexpr double kSHalf = 1.85407467730137191843385034719526;
/// Below this largest angle E_1 is its Taylor polynomial to degree 4 (small_angle_energy): the
/// remainder is O(angle⁶) with coefficients below 0.05 (docs), i.e. 1e-18 relative, while the
/// solved arc would lose accuracy (a short arc near the apex loses ~eps/angle).
constexpr double kSmallAngle = 1e-4;
/// A Newton step on the path below this (relative to the arc's width and to |u1|, at least
/// 1e-2) is taken as the last: the next one would be below rounding.
constexpr double kFinalStep = 1e-8;
/// How far past π/2 (radians) an angle still counts as on the box |α| <= π/2 (a few ulp of
/// an angle sum; solve_canonical).
constexpr double kBoxSlack = 1e-12;
/// Where the second derivatives do not exist (|α − β| = π) they are taken at this distance.
constexpr double kEdgeFloor = 1e-16;

// ---- the canonical elastica ----------------------------------------------------------------

/// X(u) or the arc length from u = 0 on [0, π] (`kLength`), as the value at the nearest of 129
/// nodes jπ/128 plus the integral from there, a Chebyshev polynomial of degree 8 per cell; near
/// u = 0, X/u³ (S/u) as a polynomial of degree 8 in u². The polynomials interpolate integrals
/// by 4-point Gauss–Legendre, exact to rounding over half a cell (the integrands' poles lie
/// ≥ 0.88 from the real axis), and fit them to ~1e-18 (Bernstein ellipse ρ ≈ 140). Against
/// long-double Carlson forms (Boost's R_D, R_F) on 2·10⁶ values: within 1e-15 relative, as
/// Boost's double forms, in a fifth of their time (the optimizer's root-finds evaluate X ~90
/// times per span; tests/elastica_test.cpp checks it).
template <bool kLength>
class Tabulated {
 public:
  static constexpr int kCells = 128, kDegree = 8;

  Tabulated() {
    std::array<double, kDegree + 1> node_x{};
    for (int i = 0; i <= kDegree; ++i) node_x[i] = std::cos(kPi * (i + 0.5) / (kDegree + 1));
    // The node values as compensated sums of the cells' integrals (each cell whole, from node
    // to node: halves meeting at a rounded midpoint left gaps that drifted by 3e-15).
    double sum = 0.0, carry = 0.0;
    for (int j = 1; j <= kCells; ++j) {
      const double x = integral(j - 1, node(j), 2), t = sum + x;
      carry += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
      sum = t;
      value_[j] = sum + carry;
    }
    std::array<double, kDegree + 1> f{};
    for (int j = kSeriesCells + 1; j <= kCells; ++j) {
      for (int i = 0; i <= kDegree; ++i) f[i] = integral(j, node(j) + 0.5 * kH * node_x[i], 1);
      chebyshev(f, coef_[j]);
    }
    for (int i = 0; i <= kDegree; ++i) {
      const double u = std::sqrt(0.5 * kSeries * (node_x[i] + 1.0));
      const double y = integral(0, u, 2 * kSeriesCells + 1) / (kLength ? u : u * u * u);
      f[i] = y - (kLength ? kSqrt2 : kSqrt2 / 3.0);
    }
    chebyshev(f, coef_[0]);
  }

  double operator()(double a) const {  // a ∈ [0, π]
    const int j = std::clamp(static_cast<int>(std::lround(a * (kCells / kPi))), 0, kCells);
    if (j <= kSeriesCells) {  // from u = 0: relative to X ≈ √2u³/3 (S ≈ √2u) itself
      const double z = a * a, y = clenshaw(coef_[0], 2.0 * z / kSeries - 1.0);
      return kLength ? a * (kSqrt2 + y) : a * z * (kSqrt2 / 3.0 + y);
    }
    return value_[j] + clenshaw(coef_[j], (a - node(j)) / (0.5 * kH));
  }

 private:
  static constexpr double kH = kPi / kCells;
  /// Nodes 0..3 use the series in u² ∈ [0, kSeries], up to 3.5 cells: from node 4 down to
  /// there X halves (the node value and the integral cancel by at most 1.5×).
  static constexpr int kSeriesCells = 3;
  static constexpr double kSeries = (kSeriesCells + 0.5) * (kSeriesCells + 0.5) * kH * kH;
  using Coefficients = std::array<double, kDegree + 1>;

  static double node(int j) { return j * kH; }

  /// ∫ from node j to a of the integrand by 4-point Gauss–Legendre in `parts` equal parts
  /// (each at most half a cell: exact to rounding).
  static double integral(int j, double a, int parts) {
    static constexpr std::array<double, 2> kNode = {0.339981043584856264803,
                                                    0.861136311594052575224};
    static constexpr std::array<double, 2> kWeight = {0.652145154862546142627,
                                                      0.347854845137453857373};
    const double t = (a - node(j)) / parts, m = 0.5 * t;
    double sum = 0.0;
    for (int part = 0; part < parts; ++part) {
      for (std::size_t i = 0; i < kNode.size(); ++i) {
        for (const double sign : {-1.0, 1.0}) {
          const double sn = std::sin(node(j) + (part * t + m + sign * m * kNode[i]));
          const double w = std::sqrt(1.0 + sn * sn);
          sum += kWeight[i] * (kLength ? 1.0 / w : sn * sn / w);
        }
      }
    }
    return kSqrt2 * m * sum;
  }

  static void chebyshev(const Coefficients& f, Coefficients& c) {
    for (int k = 0; k <= kDegree; ++k) {
      double sum = 0.0;
      for (int i = 0; i <= kDegree; ++i)
        sum += f[i] * std::cos(kPi * k * (i + 0.5) / (kDegree + 1));
      c[k] = (k == 0 ? 1.0 : 2.0) * sum / (kDegree + 1);
    }
  }

  static double clenshaw(const Coefficients& c, double x) {
    double b1 = 0.0, b2 = 0.0;
    for (int k = kDegree; k >= 1; --k) {
      const double b0 = 2.0 * x * b1 - b2 + c[k];
      b2 = b1;
      b1 = b0;
    }
    return x * b1 - b2 + c[0];
  }

  std::array<double, kCells + 1> value_{};
  std::array<Coefficients, kCells + 1> coef_{};  ///< coef_[0]: the series near u = 0
};

}  // namespace

double elastica_x(double u) {
  static const Tabulated<false> table;
  return std::copysign(table(std::abs(u)), u);
}

double elastica_arc_length(double u) {
  static const Tabulated<true> table;
  return std::copysign(table(std::abs(u)), u);
}

namespace {

double x_of(double u) {
  return elastica_x(u);
}
double s_of(double u) {
  return elastica_arc_length(u);
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

/// Tangent angle θ(u) ∈ [0, π] (its derivative is 2 sin u / √(1 + sin²u)).
double theta(double u) {
  const double s = std::sin(u);
  return std::atan2(s * s, std::cos(u) * std::sqrt(1.0 + s * s));
}
/// Unit tangent (cos θ, sin θ) at u.
Vec2 tangent_of(double u) {
  const double s = std::sin(u);
  return {std::cos(u) * std::sqrt(1.0 + s * s), s * s};
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
  double cos_q = 1.0, sin_q = 0.0;
};

/// The start u0 ∈ [−π, 0] of the path's arc ending at u1 (θ(u0) = θ(u1) + q), with sin u0,
/// cos u0, sin θ(u0) and the trigonometry of u1 it needs.
struct PathStart {
  double s1, c1, w1;  ///< sin u1, cos u1, √(1 + sin²u1)
  double u0, s0, c0, st0, w0;
};

struct PathPoint {
  double u0 = 0.0, u1 = 0.0;
  Vec2 c;          ///< chord p(u1) − p(u0)
  double g = 0.0;  ///< G(u1)
  double dg = std::numeric_limits<double>::quiet_NaN();
  PathStart trig;  ///< the trigonometry of u0 and u1
};

PathStart path_start(const Canonical& k, double u1) {
  PathStart r;
  // sin θ(u1) = sin²u1 and cos θ(u1) = cos u1 √(1 + sin²u1); θ(u0) = θ(u1) + q by the addition
  // formulas, and sin²u0 = sin θ0, cos u0 = cos θ0 / √(1 + sin θ0) give u0.
  r.s1 = std::sin(u1);
  r.c1 = std::cos(u1);
  r.w1 = std::sqrt(1.0 + r.s1 * r.s1);
  const double sin1 = r.s1 * r.s1, cos1 = r.c1 * r.w1;
  double st0 = sin1 * k.cos_q + cos1 * k.sin_q, ct0 = cos1 * k.cos_q - sin1 * k.sin_q;
  if (!(st0 > 1e-6)) {
    // Near θ0 = π, from the deficit π − θ0 = Θ − θ1 as angles: exactly u0 = −π at the path's
    // end (the sum's rounding would leave u0 a square root of it, 1e-8, away).
    const double d0 = std::max(k.theta - std::atan2(sin1, cos1), 0.0);
    st0 = std::sin(d0);
    ct0 = -std::cos(d0);
  }
  r.st0 = std::max(st0, 0.0);
  r.w0 = std::sqrt(1.0 + r.st0);
  r.s0 = -std::sqrt(r.st0);
  r.c0 = ct0 / r.w0;
  r.u0 = std::atan2(r.s0, r.c0);
  return r;
}

/// p'(u0), p'(u1) from their trigonometry.
Vec2 dp_start(const PathStart& t) {
  return {kSqrt2 * t.c0, kSqrt2 * t.st0 / t.w0};
}
Vec2 dp_end(const PathStart& t) {
  return {kSqrt2 * t.c1, kSqrt2 * t.s1 * t.s1 / t.w1};
}

PathPoint path_at(const Canonical& k, double u1, bool with_derivative) {
  PathPoint r;
  r.u1 = u1;
  const PathStart ps = path_start(k, u1);
  r.trig = ps;
  const double s1 = ps.s1, c1 = ps.c1, w1 = ps.w1, s0 = ps.s0, c0 = ps.c0, st0 = ps.st0, w0 = ps.w0;
  r.u0 = ps.u0;  // in [−π, 0]
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
    if (!(next > lo && next < hi)) {
      next = 0.5 * (lo + hi);
    } else if (const double scale = std::min(std::max(std::abs(x), 1e-2), x - p.u0);
               std::abs(next - x) <= kFinalStep * scale) {
      // Quadratic convergence: the root is within ~(step)² of `next`, below the rounding of u1
      // and of the arc's width. Take it without evaluating G there (the caller needs only u0,
      // u1; G's chord is the cost).
      // The chord moves with it by the trapezoidal rule (error O(step³), below rounding).
      const PathStart t = path_start(k, next);
      p.c = p.c + (0.5 * (next - x)) * (dp_end(p.trig) + dp_end(t)) -
            (0.5 * (t.u0 - p.u0)) * (dp_start(p.trig) + dp_start(t));
      p.u1 = next;
      p.u0 = t.u0;
      p.trig = t;
      p.g *= (next - x) / scale;  // an estimate of the residual there
      p.dg = std::numeric_limits<double>::quiet_NaN();
      break;
    }
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
  double du1_da = 0.0, du1_db = 0.0;  ///< kElastica: the root's derivatives (0 at the corner)
  Vec2 chord;
  ElasticaEnergy en;
};

/// Energy, gradient (first variation: −2κ_a, 2κ_b) and Hessian (implicit differentiation of
/// the two arc equations) of the elastica arc [u0, u1] solving canonical (a, b), given its
/// chord and the trigonometry of its ends (the root-find's).
Candidate elastica_candidate(const Canonical& k, const PathPoint& p) {
  Candidate r;
  r.u0 = p.u0;
  r.u1 = p.u1;
  r.chord = p.c;
  const Vec2 c = r.chord;
  const double n = std::sqrt(norm2(c));  // (canonical: no overflow, and 3× cheaper than hypot)
  const double s0 = p.trig.s0, s1 = p.trig.s1;
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
  const Vec2 p0 = dp_start(p.trig), p1 = dp_end(p.trig);
  const double n2 = n * n;
  const double th0 = 2.0 * s0 / p.trig.w0, th1 = 2.0 * s1 / p.trig.w1;
  const double chi0 = -cross(c, p0) / n2, chi1 = cross(c, p1) / n2;
  const double j00 = -th0, j01 = th1, j10 = th0 - chi0, j11 = -chi1;
  const double det = j00 * j11 - j01 * j10;
  // du/d(a, b) = −J⁻¹ [[1, −1], [−1, 0]].
  const double inv00 = j11 / det, inv01 = -j01 / det, inv10 = -j10 / det, inv11 = j00 / det;
  const double d00 = -(inv00 - inv01), d01 = inv00;  // du0/da, du0/db
  const double d10 = -(inv10 - inv11), d11 = inv10;  // du1/da, du1/db
  const double n0 = -dot(c, p0) / n, n1 = dot(c, p1) / n;
  const double ea0 = -2.0 * kSqrt2 * (p.trig.c0 * n + s0 * n0);
  const double ea1 = -2.0 * kSqrt2 * s0 * n1;
  const double eb0 = 2.0 * kSqrt2 * s1 * n0;
  const double eb1 = 2.0 * kSqrt2 * (p.trig.c1 * n + s1 * n1);
  r.du1_da = d10;
  r.du1_db = d11;
  e.eaa = ea0 * d00 + ea1 * d10;
  e.ebb = eb0 * d01 + eb1 * d11;
  e.eab = 0.5 * ((ea0 * d01 + ea1 * d11) + (eb0 * d00 + eb1 * d10));
  return r;
}

/// The same for any arc [u0, u1] (u0 ∈ [−π, 0], as on the path).
Candidate elastica_candidate(const Canonical& k, double u0, double u1) {
  PathPoint p;
  p.u0 = u0;
  p.u1 = u1;
  p.c = chord_of(u0, u1);
  p.trig.s0 = std::sin(u0);
  p.trig.c0 = std::cos(u0);
  p.trig.st0 = p.trig.s0 * p.trig.s0;
  p.trig.w0 = std::sqrt(1.0 + p.trig.st0);
  p.trig.s1 = std::sin(u1);
  p.trig.c1 = std::cos(u1);
  p.trig.w1 = std::sqrt(1.0 + p.trig.s1 * p.trig.s1);
  return elastica_candidate(k, p);
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

/// The minimizing piece for canonical (a, b); `guess`: a root of nearby angles (NaN: none).
Candidate solve_canonical(const Canonical& k,
                          double guess = std::numeric_limits<double>::quiet_NaN()) {
  const auto [lo, hi] = path_range(k);
  // Inside the box (a ≤ π/2) exactly one root, G(lo) > 0 > G(hi) (docs): Newton from the
  // small-angle solution u1 ≈ (a + 2b)/√(3(a + b)), checked afterwards (a root strictly inside).
  // The box's edge α = x + a computed in double lands up to a few ulp past π/2: the same root
  // continues there (the U-turn and the second roots appear only far beyond), and the scan
  // below would cost 6× more on every bound node of a restricted fit.
  if (k.a <= kPi / 2 + kBoxSlack && hi > lo) {
    const double s = k.a + k.b;
    if (!(guess > lo && guess < hi)) guess = s > 0.0 ? (k.a + 2.0 * k.b) / std::sqrt(3.0 * s) : lo;
    const PathPoint p = bracketed_newton(k, lo, hi, 1.0, guess);
    if (p.u1 > lo && p.u1 < hi && std::abs(p.g) <= 1e-9 * k.a) return elastica_candidate(k, p);
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
  r.k.cos_q = std::cos(r.k.q);
  r.k.sin_q = std::sin(r.k.q);
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

/// The hint's root moved to first order to the new canonical angles (NaN: no hint applies).
double predicted_root(const ElasticaHint* hint, const Reduction& r) {
  if (!hint || hint->reversed != r.reversed || hint->mirrored != r.mirrored)
    return std::numeric_limits<double>::quiet_NaN();
  return hint->u1 + hint->du1_da * (r.k.a - hint->a) + hint->du1_db * (r.k.b - hint->b);
}

ElasticaEnergy energy_of(const Reduction& r, double alpha, double beta,
                         ElasticaHint* hint = nullptr) {
  if (r.k.a <= kSmallAngle) return small_angle_energy(alpha, beta);
  const Candidate c = solve_canonical(r.k, predicted_root(hint, r));
  if (hint) {
    const bool arc = c.kind == ElasticaArc::Kind::kElastica && std::isfinite(c.du1_da) &&
                     std::isfinite(c.du1_db);
    *hint = {arc ? c.u1 : std::numeric_limits<double>::quiet_NaN(),
             r.k.a,
             r.k.b,
             arc ? c.du1_da : 0.0,
             arc ? c.du1_db : 0.0,
             r.reversed,
             r.mirrored};
  }
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
  ElasticaHint none;
  return elastica_energy(alpha, beta, none);
}

ElasticaEnergy elastica_energy(double alpha, double beta, ElasticaHint& hint) {
  ElasticaEnergy e = energy_of(reduce(alpha, beta), alpha, beta, &hint);
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

bool elastica_ridge_capable(double alpha, double beta) {
  constexpr double kRidgeAngle = 98.5 * kPi / 180.0;
  return std::min(std::abs(alpha), std::abs(beta)) > kRidgeAngle && alpha * beta > 0.0;
}

double elastica_ridge_half_jump(double mid, const ElasticaEnergy& on) {
  // (The plain value at δ = 1e-7 was 2e-4 of it short: a ridge held at its limit was released,
  // and a stress walk stopped 1.6e-4 from KKT.)
  constexpr double kSide = 1e-8;
  const ElasticaEnergy near = elastica_energy(mid + kSide, mid - kSide);
  const ElasticaEnergy far = elastica_energy(mid + 2 * kSide, mid - 2 * kSide);
  const double side =
      (std::numbers::sqrt2 * (near.ea - near.eb) - (far.ea - far.eb)) / (std::numbers::sqrt2 - 1.0);
  return 0.5 * (side - (on.ea - on.eb));
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

ElasticaArc elastica_arc(Point p0, Point p1, double alpha, double beta, const ElasticaHint* hint) {
  check_points(p0, p1);
  const Reduction r = reduce(alpha, beta);
  // Within kStraightAngle of the chord the piece deviates from it by at most a/4 of its length
  // (the small-deflection beam, |y| <= a x(1 − x)), below every Bézier accuracy: the straight
  // segment. The arc is also unsolvable there: with b near −a it is centred on the apex
  // u = −π/2 and √2·a wide, a few spacings of doubles at π/2 (a span beside a near-repeated
  // point; data balls pressing three points onto a line).
  if (r.k.a <= kStraightAngle) {
    ElasticaArc arc;
    arc.p0 = p0;
    arc.p1 = p1;
    arc.alpha = alpha;
    arc.beta = beta;
    arc.unit_energy = small_angle_energy(alpha, beta).e;
    return arc;
  }
  return make_arc(p0, p1, alpha, beta, r, solve_canonical(r.k, predicted_root(hint, r)));
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
//
// Each candidate cubic is certified against its sub-arc by a bound of the Hausdorff distance
// that holds everywhere, not only at samples (hausdorff_bound; derivation in
// docs/methods/elastic.md). The sub-arc is evaluated in one sweep over cells of width at most
// (48 tol/kM4)^{1/4}: positions by per-cell Gauss–Legendre quadrature of X' and closed-form
// increments of √2 sin u, summed with compensation; no elliptic integral and no projection
// onto the arc, only Newton foot points on the cubic (a polynomial). The cubics are placed
// greedily, each about as long as the error model d ∝ length⁶ of G2 Hermite interpolation
// says it can be.

namespace {

/// One cubic of the approximation in canonical coordinates: start point (relative to p(u0)),
/// unit tangents, handle lengths, end point.
struct HermitePiece {
  Vec2 p0, t0, t1, p3;
  double a = 0.0, b = 0.0;
  CubicBezier bezier() const { return {{p0, p0 + a * t0, p3 - b * t1, p3}}; }
};

/// A part of the piece to approximate: the elastica over [u_start, u_end].
struct Part {
  double u_start = 0.0, u_end = 0.0;

  /// Total turn of [ua, ub] (θ decreases before the inflection, increases after it).
  double turn(double ua, double ub) const {
    const double a = theta(ua), b = theta(ub);
    return ua < 0.0 && ub > 0.0 ? a + b : std::abs(b - a);
  }
};

/// Bound of |p''''| on the whole canonical curve: the maximum is 5.964084 (a 2·10⁵-point scan
/// of the closed form; |p⁽⁵⁾| < 28.4, so the scan misses at most 5·10⁻⁴), rounded up.
constexpr double kM4 = 6.0;
/// Cells are at most this wide in u: the 5-point Gauss–Legendre rule is then exact to
/// ~4·10⁻¹⁶ relative (the integrands' poles are ≥ 0.88 from the real axis).
constexpr double kMaxCell = 0.1;
/// Cells per sub-arc at least (also the least-squares points come from the cells).
constexpr int kMinCells = 4;
/// The first cubic of a part is tried this long (in u) times tol^(1/6), at most the part: the
/// G2 Hermite cubic's distance grows like the sixth power of the length, and on a 1000-point
/// walk the accepted lengths were 2.0–2.7 tol^(1/6) where |u| < 1 (longer towards the apex).
/// Trying the whole part first failed on half of the parts, at three times the cost of a try.
constexpr double kFirstTry = 2.5;

/// A sub-arc [ua, ub] sampled at the ends of its cells, relative to p(ua).
struct Sweep {
  std::vector<double> u;       ///< sample parameters, u.front() = ua, u.back() = ub
  std::vector<Vec2> pos;       ///< p(u) − p(ua)
  std::vector<Vec2> tan;       ///< unit tangent
  std::vector<double> speed;   ///< |p'(u)|
  std::vector<double> length;  ///< arc length from ua
  double k0 = 0.0, k1 = 0.0;   ///< curvature at ua and ub

  int cells() const { return static_cast<int>(u.size()) - 1; }
  void clear() {
    u.clear();
    pos.clear();
    tan.clear();
    speed.clear();
    length.clear();
  }
};

/// Compensated (Neumaier) sum.
struct Sum {
  double s = 0.0, c = 0.0;
  void add(double x) {
    const double t = s + x;
    c += std::abs(s) >= std::abs(x) ? (s - t) + x : (x - t) + s;
    s = t;
  }
  double value() const { return s + c; }
};

/// 5-point Gauss–Legendre on [−1, 1]: the centre and the two symmetric pairs.
constexpr std::array<double, 3> kGlNode = {0.0, 0.538469310105683091036, 0.906179845938663992798};
constexpr std::array<double, 3> kGlWeight = {0.568888888888888888889, 0.478628670499366468041,
                                             0.236926885056189087514};

/// Appends the samples of the elastica [a, b] in n cells, after the sample at a (position 0,
/// arc length 0). One sincos and six square roots per cell.
void sweep_cells(double a, double b, int n, Sweep& sw) {
  const double h = (b - a) / n, r = 0.5 * h;
  std::array<double, 3> sn{}, cn{};  // sin, cos of the nodes' offsets from the cell's middle
  for (std::size_t i = 1; i < kGlNode.size(); ++i) {
    sn[i] = std::sin(r * kGlNode[i]);
    cn[i] = std::cos(r * kGlNode[i]);
  }
  const double sr = std::sin(r), cr = std::cos(r);
  Sum x, y, len;
  for (int j = 0; j < n; ++j) {
    const double m = a + (j + 0.5) * h;
    const double sm = std::sin(m), cm = std::cos(m);
    // ∫ X' = √2 ∫ sin²/√(1 + sin²) and ∫ |p'| = √2 ∫ 1/√(1 + sin²) over the cell.
    const double w0 = 1.0 / std::sqrt(1.0 + sm * sm);
    double fx = kGlWeight[0] * sm * sm * w0, fl = kGlWeight[0] * w0;
    for (std::size_t i = 1; i < kGlNode.size(); ++i) {
      const double sp = sm * cn[i] + cm * sn[i], sq = sm * cn[i] - cm * sn[i];
      const double wp = 1.0 / std::sqrt(1.0 + sp * sp), wq = 1.0 / std::sqrt(1.0 + sq * sq);
      fx += kGlWeight[i] * (sp * sp * wp + sq * sq * wq);
      fl += kGlWeight[i] * (wp + wq);
    }
    x.add(2.0 * kSqrt2 * cm * sr);  // √2 (sin(m + r) − sin(m − r))
    y.add(kSqrt2 * r * fx);
    len.add(kSqrt2 * r * fl);
    const double u = j + 1 == n ? b : a + (j + 1) * h;
    double s, c;
    if (j + 1 == n) {
      s = std::sin(b);
      c = std::cos(b);
    } else {
      s = sm * cr + cm * sr;
      c = cm * cr - sm * sr;
    }
    const double w = std::sqrt(1.0 + s * s);
    sw.u.push_back(u);
    sw.pos.push_back({x.value(), y.value()});
    sw.tan.push_back({c * w, s * s});
    sw.speed.push_back(kSqrt2 / w);
    sw.length.push_back(len.value());
  }
}

/// Samples [ua, ub] in cells at most h wide, at least kMinCells of them.
void sweep(double ua, double ub, double h, Sweep& sw) {
  sw.clear();
  const double cells = std::ceil((ub - ua) / h);
  // NaN here (an empty range over a zero cell width) was found by fuzz_fit; a cast of NaN to int
  // is undefined.
  if (std::isnan(cells)) {
    throw Error(ErrorCode::kNonFinite,
                "elastica: a piece's arc could not be sampled (its parameter range or the "
                "approximation's cell width is degenerate)");
  }
  const int n = static_cast<int>(std::clamp(cells, double{kMinCells}, 1e7));
  const double s = std::sin(ua), c = std::cos(ua), w = std::sqrt(1.0 + s * s);
  sw.u.push_back(ua);
  sw.pos.push_back({0.0, 0.0});
  sw.tan.push_back({c * w, s * s});
  sw.speed.push_back(kSqrt2 / w);
  sw.length.push_back(0.0);
  sw.k0 = kSqrt2 * s;
  sweep_cells(ua, ub, n, sw);
  sw.k1 = kSqrt2 * std::sin(ub);
}

/// The Bernstein coefficients c_0..c_9 of q(ρ(s)) − h(s), s ∈ [0, 1]: the cubic q
/// reparameterized by the cubic ρ with Bernstein coefficients (0, r1, r2, 1) (composed
/// exactly), minus the cubic h (degree-elevated). In the scaled Bernstein basis sⁱ(1 − s)ⁿ⁻ⁱ
/// products are plain convolutions.
std::array<Vec2, 10> composed_difference(const std::array<Vec2, 4>& q, double r1, double r2,
                                         const std::array<Vec2, 4>& h) {
  // ρ = (0, 3r1, 3r2, 1) and 1 − ρ = (1, 3(1 − r1), 3(1 − r2), 0) in the scaled basis; their
  // zero coefficients skipped (the compiler may not drop products with 0: 0·∞ is NaN).
  const std::array<double, 4> a = {0.0, 3.0 * r1, 3.0 * r2, 1.0};
  const std::array<double, 4> b = {1.0, 3.0 * (1.0 - r1), 3.0 * (1.0 - r2), 0.0};
  std::array<double, 7> aa{}, bb{};  // aa: indices 2..6, bb: 0..4
  for (int i = 1; i < 4; ++i)
    for (int j = 1; j < 4; ++j) aa[i + j] += a[i] * a[j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) bb[i + j] += b[i] * b[j];
  // q0 (1 − ρ)³ + 3 q1 ρ(1 − ρ)² + 3 q2 ρ²(1 − ρ) + q3 ρ³ against h times (s + (1 − s))⁶.
  static constexpr std::array<double, 7> kSix = {1, 6, 15, 20, 15, 6, 1};
  // 1 / C(9, k): products instead of divisions (within an ulp; the bound's allowance covers it).
  static constexpr std::array<double, 10> kInvNine = {
      1.0, 1.0 / 9, 1.0 / 36, 1.0 / 84, 1.0 / 126, 1.0 / 126, 1.0 / 84, 1.0 / 36, 1.0 / 9, 1.0};
  std::array<double, 10> w0{}, w1{}, w2{}, w3{}, e1{}, e2{};
  for (int m = 0; m < 5; ++m) {
    for (int i = 0; i < 3; ++i) w0[i + m] += b[i] * bb[m];
    for (int i = 1; i < 4; ++i) w1[i + m] += a[i] * bb[m];
  }
  for (int m = 2; m < 7; ++m) {
    for (int i = 0; i < 3; ++i) w2[i + m] += b[i] * aa[m];
    for (int i = 1; i < 4; ++i) w3[i + m] += a[i] * aa[m];
  }
  static constexpr std::array<double, 4> kThree = {1, 3, 3, 1};
  for (int i = 0; i < 4; ++i)
    for (int m = 0; m < 7; ++m) {
      const double w = kThree[i] * kSix[m];
      e1[i + m] += w * h[i].x;
      e2[i + m] += w * h[i].y;
    }
  const Vec2 q1 = 3.0 * q[1], q2 = 3.0 * q[2];
  std::array<Vec2, 10> c{};
  for (int k = 0; k < 10; ++k)
    c[k] =
        (w0[k] * q[0] + w1[k] * q1 + w2[k] * q2 + w3[k] * q[3] - Vec2{e1[k], e2[k]}) * kInvNine[k];
  return c;
}

/// Upper bound of the Hausdorff distance between the cubic (relative to p(ua)) and the swept
/// sub-arc, valid everywhere up to rounding (an allowance of 32ε times the arc length is
/// added); docs/methods/elastic.md has the proof. Per cell [u_{j−1}, u_j]: the arc,
/// parameterized linearly in u, is within R = kM4·Δu⁴/384 of its cubic Hermite interpolant H
/// ; the cubic's piece between the foot points of the cell's ends,
/// reparameterized by a cubic ρ so that its speed matches H's at both ends, differs from H by
/// a degree-9 polynomial D whose Bernstein coefficients bound it. Seen as graphs over the
/// cell's chord (both curves turn by little there), a point of one curve and the point of the
/// other above the same place on the chord are at most N + R + τ(T + R) apart, N and T the
/// largest components of D across and along the chord, τ the tangent of the largest angle of
/// either curve's tangent to the chord: what remains of the cubic's uneven parameter speed
/// after ρ (T) counts only τ ≈ 0.01 times. Foot points by Newton from the previous one;
/// whatever they are, the bound stays valid as long as they increase, which is enforced; the
/// search stops once the foot point moves by less than `resolution` (far below the target:
/// the bound is then as tight as the exact foot point's up to that).
double hausdorff_bound(const Sweep& sw, const CubicBezier& bz, double resolution, bool& regular) {
  const int n = sw.cells();
  double worst = 0.0;
  regular = true;
  double t0 = 0.0;
  Vec2 b0 = bz.p[0], d0 = bz.d1(0.0);
  // The foot points' Newton in the power basis (any foot points keep the bound valid; the
  // points entering it are evaluated in Bernstein form).
  const Vec2 k1 = 3.0 * (bz.p[1] - bz.p[0]), k2 = 3.0 * (bz.p[2] - 2.0 * bz.p[1] + bz.p[0]),
             k3 = bz.p[3] - 3.0 * bz.p[2] + 3.0 * bz.p[1] - bz.p[0];
  for (int j = 1; j <= n; ++j) {
    double t1 = 1.0;
    if (j < n) {
      const Vec2 q = sw.pos[j];
      const double v0 = std::sqrt(norm2(d0));
      double t = v0 > 0.0 ? t0 + (sw.length[j] - sw.length[j - 1]) / v0 : t0;
      t = std::min(t, 1.0);
      for (int it = 0; it < 6; ++it) {
        const Vec2 e = bz.p[0] + t * (k1 + t * (k2 + t * k3)) - q,
                   e1 = k1 + t * (2.0 * k2 + (3.0 * t) * k3), e2 = 2.0 * k2 + (6.0 * t) * k3;
        const double den = dot(e1, e1) + dot(e, e2);
        if (!(den > 0.0)) break;
        const double step = dot(e, e1) / den;
        t = std::clamp(t - step, t0, 1.0);
        // Quadratic convergence: the remaining error is ~step², far below this step.
        if (!(std::abs(step) > 1e-15) || step * step * dot(e1, e1) < resolution * resolution) break;
      }
      if (!(t > t0 && t < 1.0)) t = t0 + (1.0 - t0) / (n - j + 1);
      t1 = t;
    }
    const Vec2 b1 = j < n ? bz.eval(t1) : bz.p[3], d1 = bz.d1(t1);
    const double dt = t1 - t0, du = sw.u[j] - sw.u[j - 1];
    // Relative to the arc's point p(u_{j−1}): the arc's chord and Hermite handles, the cubic
    // piece's ends and handles.
    const Vec2 o = sw.pos[j - 1], chord = sw.pos[j] - o;
    const Vec2 h0 = (du / 3.0 * sw.speed[j - 1]) * sw.tan[j - 1],
               h1 = (du / 3.0 * sw.speed[j]) * sw.tan[j];
    const Vec2 f0 = b0 - o, f1 = b1 - o, c0 = (dt / 3.0) * d0, c1 = (dt / 3.0) * d1;
    // ρ'(0) = 3 r1 and ρ'(1) = 3(1 − r2) make the speeds equal, clamped to [0, 3]: ρ maps
    // [0, 1] onto [0, 1] whatever r1, r2 ∈ [0, 1] are.
    const double n0 = std::sqrt(norm2(c0)), n1 = std::sqrt(norm2(c1));
    const double r1 = n0 > 0.0 ? std::min(1.0, std::sqrt(norm2(h0)) / (3.0 * n0)) : 1.0;
    const double r2 = n1 > 0.0 ? 1.0 - std::min(1.0, std::sqrt(norm2(h1)) / (3.0 * n1)) : 0.0;
    const std::array<Vec2, 10> c = composed_difference({f0, f0 + c0, f1 - c1, f1}, r1, r2,
                                                       {Vec2{0.0, 0.0}, h0, chord - h1, chord});
    const double r = kM4 / 384.0 * (du * du) * (du * du);
    // Common parameter: |D| + R.
    double full = 0.0;
    for (const Vec2& x : c) full = std::max(full, norm2(x));
    double cell = std::sqrt(full) + r;
    // Graphs over the chord: the arc turns by at most √2 times its length on the cell; the
    // cubic's piece by at most the angles of its hodograph's control points (q1 − q0,
    // q2 − q1, q3 − q2), which must all point forwards.
    const double ell = std::sqrt(norm2(chord));
    const double turn = kSqrt2 * (sw.length[j] - sw.length[j - 1]);
    if (!(ell > 0.0 && turn <= 0.5)) regular = false;  // (not reached: cells are short)
    if (ell > 0.0 && turn <= 0.5) {
      const Vec2 tc = chord / ell;
      double tau = turn * (1.0 + 0.5 * turn * turn);  // ≥ tan(turn) for turn ≤ 0.5
      bool forwards = true;
      for (const Vec2& v : {c0, (f1 - c1) - (f0 + c0), c1}) {
        const double along = dot(v, tc);
        forwards = forwards && along > 0.0;
        if (forwards) tau = std::max(tau, std::abs(cross(tc, v)) / along);
      }
      regular = regular && forwards;
      if (forwards) {
        double across = 0.0, along = 0.0;
        for (const Vec2& x : c) {
          across = std::max(across, std::abs(cross(tc, x)));
          along = std::max(along, std::abs(dot(tc, x)));
        }
        // Points whose partner above the same place lies in a neighbouring cell are within
        // |e| + (1 + τ)|e·T| of the cell's end, e the cubic's offset there.
        const Vec2 e0 = f0, e3 = f1 - chord;
        const double graph = std::max({across + r + tau * (along + r),
                                       std::sqrt(norm2(e0)) + (1.0 + tau) * std::abs(dot(e0, tc)),
                                       std::sqrt(norm2(e3)) + (1.0 + tau) * std::abs(dot(e3, tc))});
        cell = std::min(cell, graph);
      }
    }
    worst = std::max(worst, cell);
    t0 = t1;
    b0 = b1;
    d0 = d1;
  }
  return worst + 32.0 * kEps * sw.length.back();
}

/// G2 Hermite handles: (3/2)κ0 a² = cross(T0, D) − b cross(T0, T1) and the mirror equation at
/// the end (de Boor, Höllig, Sabin), by Newton from a = b = |D|/3. Converged when the step
/// is below 1e-14 |D|, or below 1e-9 |D| and no longer shrinking (the system is often
/// ill-conditioned on short sub-arcs, where Newton ends in a cycle of rounding-sized steps).
bool g2_handles(Vec2 d, Vec2 t0, Vec2 t1, double k0, double k1, double& a, double& b) {
  const double len = std::sqrt(norm2(d));
  const double c = cross(t0, t1), d0 = cross(t0, d), d1 = cross(d, t1);
  a = b = len / 3.0;
  double previous = std::numeric_limits<double>::infinity();
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
    const double step = std::abs(da) + std::abs(db);
    if (step <= 1e-14 * len || (step <= 1e-9 * len && step >= 0.5 * previous)) return true;
    previous = step;
  }
  return false;
}

/// Where the G2 system has no solution (for a circular arc its two solution branches cross at
/// a = b ≈ |D|/3, so on sub-arcs of slowly varying curvature they either split into two
/// solutions or miss each other), the handles that come closest to it: least squares of the
/// two residuals by Levenberg–Marquardt from a = b = |D|/3. The cubic then matches the end
/// curvatures only approximately, but is about as close as a G2 one would be.
bool near_g2_handles(Vec2 d, Vec2 t0, Vec2 t1, double k0, double k1, double& a, double& b) {
  const double len = std::sqrt(norm2(d));
  const double c = cross(t0, t1), d0 = cross(t0, d), d1 = cross(d, t1);
  auto residual = [&](double x, double y, double& f0, double& f1) {
    f0 = 1.5 * k0 * x * x + c * y - d0;
    f1 = 1.5 * k1 * y * y + c * x - d1;
    return f0 * f0 + f1 * f1;
  };
  a = b = len / 3.0;
  double f0, f1;
  double f = residual(a, b, f0, f1), lambda = 1e-3;
  for (int it = 0; it < 60 && f > 0.0; ++it) {
    const double j00 = 3.0 * k0 * a, j11 = 3.0 * k1 * b;  // J = [[j00, c], [c, j11]]
    const double h00 = j00 * j00 + c * c, h01 = (j00 + j11) * c, h11 = c * c + j11 * j11;
    const double g0 = j00 * f0 + c * f1, g1 = c * f0 + j11 * f1;
    bool improved = false;
    while (lambda < 1e12) {
      const double m00 = h00 * (1.0 + lambda), m11 = h11 * (1.0 + lambda);
      const double det = m00 * m11 - h01 * h01;
      if (!(det > 0.0)) {
        lambda *= 4.0;
        continue;
      }
      const double x = a - (g0 * m11 - h01 * g1) / det, y = b - (m00 * g1 - h01 * g0) / det;
      double e0 = 0.0, e1 = 0.0;
      const double fe =
          (x > 0.0 && y > 0.0 && x < len && y < len) ? residual(x, y, e0, e1) : f + 1.0;
      if (fe < f) {
        const bool tiny = std::abs(x - a) + std::abs(y - b) <= 1e-14 * len;
        a = x;
        b = y;
        f = fe;
        f0 = e0;
        f1 = e1;
        lambda = std::max(lambda / 3.0, 1e-12);
        improved = !tiny;
        break;
      }
      lambda *= 4.0;
    }
    if (!improved) break;
  }
  return a > 0.0 && b > 0.0 && std::isfinite(a) && std::isfinite(b);
}

/// Points of the least-squares fallback.
constexpr int kLeastSquaresPoints = 17;

/// Least-squares handles against the swept points (at most 17 of them; their arc-length
/// fractions as first parameters), with 4 rounds of parameter correction (the points'
/// parameters projected onto the current cubic).
void least_squares_handles(const Sweep& sw, HermitePiece& h) {
  constexpr int kMaxPoints = kLeastSquaresPoints;
  std::array<Vec2, kMaxPoints> q;
  std::array<double, kMaxPoints> tau;
  const int n = sw.cells();
  const int stride = (n + kMaxPoints - 2) / (kMaxPoints - 1);
  int m = 0;
  for (int j = 0; j <= n; j += stride) {
    q[m] = sw.pos[j];
    tau[m++] = sw.length[j] / sw.length.back();
  }
  if (tau[m - 1] != 1.0) {  // the last sample when the stride skips it
    q[m] = sw.pos.back();
    tau[m++] = 1.0;
  }
  h.a = h.b = norm(h.p3 - h.p0) / 3.0;
  for (int round = 0; round < 5; ++round) {
    double m00 = 0, m01 = 0, m11 = 0, r0 = 0, r1 = 0;
    for (int j = 0; j < m; ++j) {
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
    for (int j = 1; j + 1 < m; ++j) {  // parameter correction
      for (int it = 0; it < 3; ++it) {
        const Vec2 e = bz.eval(tau[j]) - q[j], d1 = bz.d1(tau[j]), d2 = bz.d2(tau[j]);
        const double den = dot(d1, d1) + dot(e, d2);
        if (!(den > 0.0)) break;
        tau[j] = std::clamp(tau[j] - dot(e, d1) / den, 0.0, 1.0);
      }
    }
  }
}

/// Scratch space reused by every sub-arc of one call.
struct Workspace {
  Sweep sweep, points;
  double cell = 0.0;      ///< largest cell width in u for the tolerance
  double accuracy = 0.0;  ///< relative accuracy (tolerance / |C|)
  double floor = 0.0;     ///< energy allowance per canonical length: 1 / (|C| · length)
};

/// ∫κ² ds of a cubic: 5-point Gauss–Legendre on the four quarters of [0, 1].
double cubic_bending(const CubicBezier& bz) {
  double sum = 0.0;
  for (int p = 0; p < 4; ++p) {
    const double mid = 0.125 + 0.25 * p;
    for (std::size_t i = 0; i < kGlNode.size(); ++i)
      for (double side : {-1.0, 1.0}) {
        if (i == 0 && side > 0.0) continue;
        const double t = mid + side * 0.125 * kGlNode[i];
        const Vec2 d1 = bz.d1(t), d2 = bz.d2(t);
        const double v2 = norm2(d1), k = cross(d1, d2);
        sum += kGlWeight[i] * k * k / (v2 * v2 * std::sqrt(v2));
      }
  }
  return 0.125 * sum;
}

/// How far the cubic is from being accepted, as a distance comparable with the tolerance
/// (accepted when at most `target`): its certified distance from the swept sub-arc, or more
/// when it is not regular (its tangent turns back somewhere: a cusp or a loop, which the
/// distance alone does not exclude; or a handle shorter than 5% of the chord, which would leave
/// the end tangent directions to the rounding of the control points), or when its bending
/// energy (quadrature) misses the sub-arc's, 2ΔX, by more than accuracy·(E_sub + ℓ_sub/(|C|·ℓ))
/// (ℓ_sub its length, ℓ the piece's): summed, the output's energy is within
/// accuracy·(E + 1/|C|) of the exact one. The energy's margin counts as the distance
/// target·(miss/allowance)^{6/4} (energy errors of G2 cubics shrink like the fourth power of
/// the length, distances like the sixth), so that the placement sees whichever binds.
double assess(const Sweep& sw, const CubicBezier& bz, double target, const Workspace& ws) {
  bool regular;
  double d = hausdorff_bound(sw, bz, 1e-3 * target, regular);
  const double chord = std::sqrt(norm2(bz.p[3] - bz.p[0]));
  regular = regular && norm2(bz.p[1] - bz.p[0]) >= 0.0025 * chord * chord &&
            norm2(bz.p[3] - bz.p[2]) >= 0.0025 * chord * chord;
  if (!regular) d = std::max(d, 2.0 * target);
  if (d <= target) {
    const double allow =
        ws.accuracy * (2.0 * std::abs(sw.pos.back().y) + ws.floor * sw.length.back());
    const double miss = std::abs(cubic_bending(bz) - 2.0 * sw.pos.back().y);
    const double e = target * std::pow(miss / allow, 1.5);  // above target when miss > allow
    d = std::isnan(e) ? 2.0 * target : std::max(d, e);
  }
  return d;
}

/// The cubic of [ua, ub] in coordinates relative to its start: the G2 Hermite cubic (the one
/// closest to it where the G2 system has no solution), which keeps the curvature continuous
/// at the joints; only where neither exists, the least-squares cubic. Sets `distance` to its
/// assessment (assess; infinity when no cubic was found). (Also trying the least-squares cubic
/// when the G2 one missed by less than 8x saved 4% of the cubics but cost a fifth of a
/// restricted-elastic fit: it passed in one try of four.)
HermitePiece fit_sub_arc(double ua, double ub, double target, Workspace& ws, double& distance) {
  Sweep& sw = ws.sweep;
  sweep(ua, ub, ws.cell, sw);
  HermitePiece h;
  h.p0 = {0.0, 0.0};
  h.p3 = sw.pos.back();
  h.t0 = sw.tan.front();
  h.t1 = sw.tan.back();
  double a, b;
  if (g2_handles(h.p3, h.t0, h.t1, sw.k0, sw.k1, a, b) ||
      near_g2_handles(h.p3, h.t0, h.t1, sw.k0, sw.k1, a, b)) {
    h.a = a;
    h.b = b;
    distance = assess(sw, h.bezier(), target, ws);
    return h;
  }
  if (sw.cells() >= (kLeastSquaresPoints - 1) / 2) {
    least_squares_handles(sw, h);
  } else {
    sweep(ua, ub, (ub - ua) / (kLeastSquaresPoints - 1), ws.points);
    least_squares_handles(ws.points, h);
  }
  distance = assess(sw, h.bezier(), target, ws);
  return h;
}

/// Appends the certified cubics of the part, each placed at the running end of the previous
/// one (compensated sums; `origin` is where the part starts, relative to p(u0)). Greedy from
/// the start: each cubic is made about as long as it can be. The distance of the G2 Hermite
/// cubic scales like the sixth power of the sub-arc's length, so a fit at distance d suggests
/// the length times (0.9 tol/d)^{1/6}: a failed fit is retried shorter, a passing one far below
/// the tolerance longer (bisecting once both are known), within 10%. The first try for each
/// cubic cuts the rest of the part into equal sub-arcs no longer than the last cubic suggests
/// (up to 15% longer when that saves one of the last few). No try exceeds a sub-arc turning
/// about 90° (a cubic cannot follow much more).
void approximate_part(const Part& part, Vec2 origin, double tol, Workspace& ws,
                      std::vector<HermitePiece>& out) {
  const double ua = part.u_start, ub = part.u_end;
  const int turns = std::max(1, static_cast<int>(std::ceil(part.turn(ua, ub) / (kPi / 2) - 1e-9)));
  const double longest = (ub - ua) / turns;
  Sum base[2];
  base[0].add(origin.x);
  base[1].add(origin.y);
  auto ratio = [&](double d) { return std::pow(0.9 * tol / d, 1.0 / 6.0); };
  double a = ua, want = std::min(longest, kFirstTry * std::pow(tol, 1.0 / 6.0));
  while (a < ub) {
    const double rest = ub - a;
    // Equal sub-arcs no longer than `want`, or up to 15% longer when that saves one of the
    // last few cubics.
    double m = std::ceil(rest / want * (1.0 - 1e-12));
    if (m <= 4.0) m = std::min(m, std::ceil(rest / (1.15 * want)));
    double len = rest / m;
    double passed = 0.0, failed = std::numeric_limits<double>::infinity(), best_d = 0.0;
    double best_b = ub;
    HermitePiece best;
    for (int tries = 0;; ++tries) {
      const double b = len >= rest * (1.0 - 1e-12) ? ub : a + len;
      len = b - a;
      double d;
      HermitePiece h = fit_sub_arc(a, b, tol, ws, d);
      // Below 1e-12 of u: never reached for accuracy >= 1e-13.
      if (d <= tol || len <= 1e-12 || tries >= 100) {
        passed = len;
        best = h;
        best_d = d;
        best_b = b;
        const double grow = ratio(d);
        if (b == ub || grow < 1.15 || failed < 1.1 * len || tries >= 12) break;
        len = std::min({len * std::min(grow, 4.0), 0.5 * (len + failed), longest});
        if (1.15 * len >= rest && failed > rest) len = rest;  // try to the end
        if (len <= passed) break;
      } else {
        failed = len;
        if (passed > 0.0 && (failed < 1.1 * passed || tries >= 12)) break;
        len *= std::isfinite(d) ? std::clamp(ratio(d), 0.2, 0.95) : 0.5;
        if (passed > 0.0) len = std::max(len, 0.5 * (passed + failed));
      }
    }
    const Vec2 at{base[0].value(), base[1].value()};
    best.p0 = at;
    best.p3 = best.p3 + at;
    base[0].add(best.p3.x - at.x);
    base[1].add(best.p3.y - at.y);
    out.push_back(best);
    a = best_b;
    want = std::min(longest, passed * std::clamp(ratio(best_d), 1.0, 2.0));
  }
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
  if (arc.kind == ElasticaArc::Kind::kStraight)  // (angles up to kStraightAngle)
    return {{{arc.p0, arc.p0 + (L / 3.0) * d_start, arc.p1 - (L / 3.0) * d_end, arc.p1}}};
  // Canonical pieces in canonical order. Parts split at the inflection only where both sides
  // are substantial: a sliver of a cubic would have handles too short for its directions to
  // survive rounding of the control points.
  const double nc = norm(arc.chord);
  const double tol = accuracy * nc;
  Workspace ws;
  // Cells so narrow that the Hermite remainder kM4·w⁴/384 is at most 1/8 of the tolerance.
  ws.cell = std::min(kMaxCell, std::pow(384.0 / (8.0 * kM4) * tol, 0.25));
  ws.accuracy = accuracy;
  ws.floor = 1.0 / (nc * canonical_length(arc));
  std::vector<HermitePiece> pieces;
  if (arc.kind == ElasticaArc::Kind::kUTurn) {
    // The half-wave, the segment as one straight cubic (exact, and G2: κ = 0 at both of its
    // ends; a part combining it with the last arc needed more cubics, and for long segments
    // lost the arc's detail to rounding), then the last arc. A segment shorter than tol/1000
    // is left out: the last arc, shifted by it, gets that much less tolerance.
    approximate_part({-kPi, 0.0}, {0.0, 0.0}, tol, ws, pieces);
    double rest = tol;
    if (arc.segment > 1e-3 * tol) {
      HermitePiece line;
      line.p0 = canonical_point(arc, 0.0, false);
      line.p3 = canonical_point(arc, 0.0, true);
      line.t0 = line.t1 = {1.0, 0.0};
      line.a = line.b = arc.segment / 3.0;
      pieces.push_back(line);
    } else {
      rest -= arc.segment;
    }
    approximate_part({0.0, arc.u1}, canonical_point(arc, 0.0, true), rest, ws, pieces);
  } else if (arc.u0 < 0.0 && arc.u1 > 0.0 && std::min(-arc.u0, arc.u1) > 0.05 * (arc.u1 - arc.u0)) {
    approximate_part({arc.u0, 0.0}, {0.0, 0.0}, tol, ws, pieces);
    approximate_part({0.0, arc.u1}, canonical_point(arc, 0.0, false), tol, ws, pieces);
  } else {
    approximate_part({arc.u0, arc.u1}, {0.0, 0.0}, tol, ws, pieces);
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
