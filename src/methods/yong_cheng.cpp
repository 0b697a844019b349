// Yong–Cheng OGH / COH curves. See include/fairspline/methods/yong_cheng.hpp and
// docs/methods/yong-cheng.md for the reconstruction of M2, M3 and the dispatcher.
#include "fairspline/methods/yong_cheng.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <new>
#include <numbers>
#include <span>
#include <string>
#include <utility>

#include "detail/angles.hpp"
#include "detail/choices.hpp"
#include "detail/finite.hpp"
#include "detail/huge_pages.hpp"
#include "detail/input.hpp"
#include "detail/knots.hpp"
#include "detail/numbers.hpp"
#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"

namespace fairspline {

namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kThird = 1.0 / 3.0;
const double kCos30 = std::sqrt(3.0) / 2.0;
const Vec2 kE10{std::cos(10.0 * kDeg), std::sin(10.0 * kDeg)};  // e^{iπ/18}
const Vec2 kE20{std::cos(20.0 * kDeg), std::sin(20.0 * kDeg)};

// ---- small complex-number helpers on unit vectors (local frame) ----
inline Vec2 mul(Vec2 a, Vec2 b) {
  return {a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x};
}
inline Vec2 conj(Vec2 a) {
  return {a.x, -a.y};
}
inline Vec2 quick_unit(Vec2 a) {
  return a / std::sqrt(norm2(a));
}
/// Unit vector of any finite non-zero vector (no overflow or underflow of the squared norm).
inline Vec2 safe_unit(Vec2 a) {
  const double m = std::max(std::abs(a.x), std::abs(a.y));
  return quick_unit(a / m);
}
inline Vec2 expi(double a) {
  return {std::cos(a), std::sin(a)};
}
/// Unit vector at half the angle of the unit vector u (angle in (−π, π)).
inline Vec2 half(Vec2 u) {
  return quick_unit({1.0 + u.x, u.y});
}
/// Unit bisector of two unit vectors less than π apart.
inline Vec2 bisector(Vec2 a, Vec2 b) {
  return quick_unit(a + b);
}
/// Angle of u in [0, 2π).
inline double angle_2pi(Vec2 u) {
  const double a = std::atan2(u.y, u.x);
  return a < 0.0 ? a + 2.0 * kPi : a;
}

void check_vector(Vec2 v, const char* what) {
  if (!is_finite(v)) throw Error(ErrorCode::kNonFinite, std::string(what) + " is not finite");
  if (v.x == 0.0 && v.y == 0.0) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + " is the zero vector");
  }
}

void check_interval(double t0, double t1) {
  if (!(std::isfinite(t0) && std::isfinite(t1) && t1 > t0)) {
    throw Error(ErrorCode::kInvalidArgument,
                "the parameter interval [t0, t1] must be finite with t0 < t1");
  }
}

double finite_or_throw(double x, const char* what) {
  if (!std::isfinite(x)) throw Error(ErrorCode::kNonFinite, std::string(what) + " overflows");
  return x;
}

/// OGH magnitudes m0 = a0*(t1 − t0)|V0|, m1 for a chord q and unit directions u0, u1:
/// the solution of 2 m0 + c m1 = 3 q·u0, c m0 + 2 m1 = 3 q·u1 with c = u0·u1 (proof of Thm 2).
inline OghCoefficients ogh_magnitudes(Vec2 q, Vec2 u0, Vec2 u1) {
  const double c = dot(u0, u1);
  const double p0 = dot(q, u0), p1 = dot(q, u1);
  const double inv = 1.0 / (4.0 - c * c);
  return {(6.0 * p0 - 3.0 * c * p1) * inv, (6.0 * p1 - 3.0 * c * p0) * inv};
}

/// E_unit from the cosines/sines of θ, φ (see ogh_unit_energy).
inline double unit_energy(Vec2 u0, Vec2 u1) {
  const double c = dot(u0, u1);     // cos(θ − φ)
  const double sd = cross(u1, u0);  // sin(θ − φ)
  const double num = 3.0 * u0.y * u0.y + 3.0 * u1.y * u1.y - 3.0 * u0.y * u1.y * c - 2.0 * sd * sd;
  return 12.0 * std::max(num, 0.0) / (4.0 - c * c);
}

// ---- COH constructions in the local frame P0 = (0, 0), P1 = (1, 0) ----

/// Nodes and unit directions of a construction in the local frame: q[0] = (0, 0),
/// q[count] = (1, 0); u[0] and u[count] are the given end directions.
struct Polygon {
  int count = 1;
  std::array<Vec2, 4> q{};
  std::array<Vec2, 4> u{};
};

struct LocalData {
  Vec2 u0;  // (cos θ, sin θ)
  Vec2 u1;  // (cos φ, sin φ)
};

// CohSymmetry's values are bit sets: 1 = T, 2 = R, 3 = RT.
constexpr bool has_t(CohSymmetry s) {
  return (static_cast<unsigned>(s) & 1u) != 0;
}
constexpr bool has_r(CohSymmetry s) {
  return (static_cast<unsigned>(s) & 2u) != 0;
}

/// The symmetry acting on the end conditions (an involution; T and R commute), branch-free:
/// R swaps the ends and conjugates, T conjugates.
inline LocalData apply(CohSymmetry s, LocalData d) {
  // Indexing instead of selects: the compiler turned `r ? u1 : u0` into a branch, which random
  // data mispredicts half the time.
  const unsigned r = has_r(s), flip = r ^ unsigned(has_t(s));
  const std::array<Vec2, 2> ends{d.u0, d.u1};
  const Vec2 a = ends[r], b = ends[r ^ 1u];
  const double sy = 1.0 - 2.0 * flip;  // ±1: the products below are exact
  return {{a.x, sy * a.y}, {b.x, sy * b.y}};
}

[[noreturn]] void no_joint(const char* method) {
  throw Error(ErrorCode::kInfeasible, std::string("COH method ") + method +
                                          ": the joints do not exist for these tangent angles "
                                          "(outside the method's applicable region)");
}

/// Intersection A + s·da = B − u·db with s, u > 0 (rays from A forwards and from B backwards).
Point meet(Point a, Vec2 da, Point b, Vec2 db, const char* method) {
  const double den = cross(da, db);
  const Vec2 ab = b - a;
  const double s = cross(ab, db) / den;
  const double u = cross(da, ab) / den;
  if (!(s > 0.0 && u > 0.0 && std::isfinite(s) && std::isfinite(u))) no_joint(method);
  return a + s * da;
}

void two(Polygon& p, Vec2 u0, Point t, Vec2 vt, Vec2 u1) {
  p.count = 2;
  p.q[0] = {0.0, 0.0};
  p.q[1] = t;
  p.q[2] = {1.0, 0.0};
  p.u[0] = u0;
  p.u[1] = vt;
  p.u[2] = u1;
}

void three(Polygon& p, Vec2 u0, Point t0, Vec2 v0, Point t1, Vec2 v1, Vec2 u1) {
  p.count = 3;
  p.q[0] = {0.0, 0.0};
  p.q[1] = t0;
  p.q[2] = t1;
  p.q[3] = {1.0, 0.0};
  p.u[0] = u0;
  p.u[1] = v0;
  p.u[2] = v1;
  p.u[3] = u1;
}

// Each construction runs in two steps so that a batch can do the trigonometry of all its
// items in one loop (latency hiding): trig_step() names the angle ϕ = (arg w [+ 2π]) / k whose
// e^{iϕ} the construction needs, build_post() builds the polygon from the data and r = e^{iϕ}.
struct TrigStep {
  Vec2 w{1.0, 0.0};
  double wrap = -10.0;  ///< add 2π to arg w when it is below this
  double k = 0.0;       ///< 0: no trigonometry needed
};

/// P0T's direction e^{iβ} of M2.
inline Vec2 m2_beta(Vec2 u0) {
  return u0.x > kE20.x && u0.y < kE20.y ? kE10 : half(u0);
}

TrigStep trig_step(CohMethod m, const LocalData& d) {
  switch (m) {
    case CohMethod::kM2:  // 3ϕ = 2π − φ + β ∈ [70°, 240°]: arg(conj(V1)·e^{iβ}) in [0, 2π)
      return {mul(conj(d.u1), m2_beta(d.u0)), 0.0, 3.0};
    case CohMethod::kM3:  // φ/3 with φ ∈ [0, 2π)
      return {d.u1, 0.0, 3.0};
    case CohMethod::kM5:  // (2π + θ − φ)/6: θ − φ ∈ [−240°, 0°] or [120°, 180°]
      return {mul(d.u0, conj(d.u1)), kPi / 3.0, 6.0};
    case CohMethod::kM6:  // (2π + φ/2 − θ)/5
      return {mul(half(d.u1), conj(d.u0)), 10.0, 5.0};
    case CohMethod::kM7:  // (2π + φ − θ)/6
      return {mul(d.u1, conj(d.u0)), 10.0, 6.0};
    default:
      return {};
  }
}

inline double step_angle(const TrigStep& t) {
  double a = detail::atan2_fast(t.w.y, t.w.x);
  if (a < t.wrap) a += 2.0 * kPi;
  return a / t.k;
}

/// e^{iϕ} for a step angle ϕ (in [0, 2π/3] for every construction's region): the Taylor
/// polynomials about π/3 turned by e^{iπ/3} = (1/2, √3/2), within a few ulp of libm's sincos at
/// a fraction of its cost; angles beyond the polynomials' range go to libm.
inline Vec2 step_rotation(double phi) {
  constexpr double kThirdPiHi = 1.0471975511965979, kThirdPiLo = -1.072081766451091e-16;
  const double x = (phi - kThirdPiHi) - kThirdPiLo;
  if (!(std::abs(x) <= 1.05)) return expi(phi);
  double s = 0.0, c = 1.0;
  detail::sincos_taylor<17>(x, s, c);  // 1.05^19/19! = 2e-17
  return {0.5 * c - kCos30 * s, 0.5 * s + kCos30 * c};
}

// M1, (θ, φ) ∈ [0, π/6] × [π/3, 2π/3]: |TP1| = |P0P1|/3 with ∠(TP1, V1) = φ/2; V_t bisects
// ∠(P0T, TP1).
void build_m1(const LocalData& d, Polygon& p) {
  const Vec2 h1 = half(d.u1);  // direction of TP1 (angle φ/2)
  const Point t = Vec2{1.0, 0.0} - kThird * h1;
  two(p, d.u0, t, bisector(quick_unit(t), h1), d.u1);
}

// M2, (θ, φ) ∈ [0, π/3] × [π, 5π/3] ∪ [π/3, 2π/3] × [4π/3, 5π/3]. P0T at angle β = θ − φ1
// (φ1 = θ − π/18 for θ < π/9, else θ/2); ∠(V1, TP1) = ∠(TP1, V_t) = ∠(V_t, P0T) = ϕ. The paper
// prints ϕ = (2π − φ + φ1)/3, which closes the turn only when φ1 = θ/2; the consistent value is
// ϕ = (2π − φ + β)/3 (docs). r = e^{iϕ}.
void build_m2(const LocalData& d, Vec2 r, Polygon& p) {
  const Vec2 dir_tp1 = mul(d.u1, r);
  const Point t = meet({0.0, 0.0}, m2_beta(d.u0), {1.0, 0.0}, dir_tp1, "M2");
  two(p, d.u0, t, mul(dir_tp1, r), d.u1);
}

// M3, (θ, φ) ∈ [0, π/3] × [π/3, π]. ϕ6 = φ/3, so T1P1 is at α5 = 2φ/3; P0T0 at
// α1 = (θ − φ/3)/2 − π/18 with T0 on the perpendicular bisector x = 1/2; T0T1 at
// α3 = 17π/9 (−20°); V_t0, V_t1 bisect the chord directions meeting there (docs: the paper's
// α2, α4 formulas are garbled; bisectors are what its figure and Theorem 6 need). r = e^{iφ/3}.
void build_m3(const LocalData& d, Vec2 r, Polygon& p) {
  const Vec2 e5 = mul(d.u1, conj(r));                         // e^{i2φ/3}
  const Vec2 e1 = mul(half(mul(d.u0, conj(r))), conj(kE10));  // e^{i((θ − φ/3)/2 − 10°)}
  const Vec2 e3 = mul(conj(kE10), conj(kE10));                // e^{−i20°}
  if (!(e1.x > 0.0)) no_joint("M3");
  const Point t0{0.5, 0.5 * e1.y / e1.x};
  const Point t1 = meet(t0, e3, {1.0, 0.0}, e5, "M3");
  three(p, d.u0, t0, bisector(e1, e3), t1, bisector(e3, e5), d.u1);
}

// M4, (θ, φ) ∈ [π/3, 2π/3] × [0, 2π/3]: P0T0 at θ/2 with length 1/3, T1P1 at φ/2 with length
// 1/6; V_t0, V_t1 bisect the chord directions.
void build_m4(const LocalData& d, Polygon& p) {
  const Vec2 h0 = half(d.u0), h1 = half(d.u1);
  const Point t0 = kThird * h0;
  const Point t1 = Vec2{1.0, 0.0} - (1.0 / 6.0) * h1;
  const Vec2 c = quick_unit(t1 - t0);
  three(p, d.u0, t0, bisector(h0, c), t1, bisector(c, h1), d.u1);
}

/// The three chord directions and two joint directions of an equal-angle construction
/// turning by ϕ per end angle (r = e^{±iϕ}) starting from u0 (powers of r computed in
/// parallel rather than as a chain of products).
struct Fan {
  Vec2 d1, v0, d2, v1, d3;
};
Fan fan(Vec2 u0, Vec2 r) {
  const Vec2 r2 = mul(r, r);
  const Vec2 r3 = mul(r2, r), r4 = mul(r2, r2);
  const Vec2 r5 = mul(r4, r);
  return {mul(u0, r), mul(u0, r2), mul(u0, r3), mul(u0, r4), mul(u0, r5)};
}

// M5, (θ, φ) ∈ [π/3, 2π/3] × [π, 4π/3] ∪ [2π/3, π] × [π, 5π/3]: six equal clockwise end angles
// ϕ = (2π + θ − φ)/6 and T0T1 tangent to the circle on P0P1 as diameter. r = e^{iϕ}.
void build_m5(const LocalData& d, Vec2 r, Polygon& p) {
  const Fan f = fan(d.u0, conj(r));
  const Vec2 n = perp(f.d2);  // the arch lies on the left of T0T1
  const Point m{0.5, 0.0};
  const double s = (0.5 + dot(n, m)) / dot(n, f.d1);
  const double u = (dot(n, Vec2{1.0, 0.0} - m) - 0.5) / dot(n, f.d3);
  if (!(s > 0.0 && u > 0.0 && std::isfinite(s) && std::isfinite(u))) no_joint("M5");
  const Point t0 = s * f.d1, t1 = Vec2{1.0, 0.0} - u * f.d3;
  if (!(dot(t1 - t0, f.d2) > 0.0)) no_joint("M5");
  three(p, d.u0, t0, f.v0, t1, f.v1, d.u1);
}

// M6, (θ, φ) ∈ [2π/3, π] × [π/6, 2π/3]: T1P1 at α5 = φ/2, five equal counter-clockwise end
// angles ϕ = (2π + α5 − θ)/5, |P0T0| = |P0P1|/2. r = e^{iϕ}.
void build_m6(const LocalData& d, Vec2 r, Polygon& p) {
  const Fan f = fan(d.u0, r);
  const Point t0 = 0.5 * f.d1;
  const Point t1 = meet(t0, f.d2, {1.0, 0.0}, half(d.u1), "M6");
  three(p, d.u0, t0, f.v0, t1, f.v1, d.u1);
}

// M7, (θ, φ) ∈ [2π/3, π]²: six equal counter-clockwise end angles ϕ = (2π + φ − θ)/6,
// |P0T0| = |P0P1|/2. r = e^{iϕ}.
void build_m7(const LocalData& d, Vec2 r, Polygon& p) {
  const Fan f = fan(d.u0, r);
  const Point t0 = 0.5 * f.d1;
  const Point t1 = meet(t0, f.d2, {1.0, 0.0}, f.d3, "M7");
  three(p, d.u0, t0, f.v0, t1, f.v1, d.u1);
}

/// The base construction M_m on (base-frame) data d, given r = e^{iϕ} from trig_step.
void build_post(CohMethod m, const LocalData& d, Vec2 r, Polygon& p) {
  switch (m) {
    case CohMethod::kM0:
      p.count = 1;
      p.q[0] = {0.0, 0.0};
      p.q[1] = {1.0, 0.0};
      p.u[0] = d.u0;
      p.u[1] = d.u1;
      return;
    case CohMethod::kM1:
      return build_m1(d, p);
    case CohMethod::kM2:
      return build_m2(d, r, p);
    case CohMethod::kM3:
      return build_m3(d, r, p);
    case CohMethod::kM4:
      return build_m4(d, p);
    case CohMethod::kM5:
      return build_m5(d, r, p);
    case CohMethod::kM6:
      return build_m6(d, r, p);
    case CohMethod::kM7:
      return build_m7(d, r, p);
  }
}

/// The symmetry acting on a construction in place: T mirrors about the base line, R mirrors
/// about the perpendicular bisector x = 1/2 and reverses the order.
void apply_in_place(CohSymmetry s, Polygon& p) {
  const int n = p.count;
  if (has_r(s)) {
    for (int k = 0; 2 * k < n; ++k) {
      std::swap(p.q[k], p.q[n - k]);
      std::swap(p.u[k], p.u[n - k]);
    }
    for (int k = 0; k <= n; ++k) {
      p.q[k].x = 1.0 - p.q[k].x;
      p.u[k] = conj(p.u[k]);
    }
  }
  if (has_t(s)) {
    for (int k = 0; k <= n; ++k) {
      p.q[k].y = -p.q[k].y;
      p.u[k] = conj(p.u[k]);
    }
  }
  p.q[0] = {0.0, 0.0};
  p.q[n] = {1.0, 0.0};
}

/// The canonical image (Section 4's symmetries as a Klein four-group acting on (θ, φ)):
/// the symmetry g with g(data) in D = {0 ≤ θ ≤ π, |φ| ≤ θ}. Branch-free: random data would
/// mispredict every branch here.
inline CohSymmetry canonical(LocalData d) {
  const unsigned swap = d.u0.x > d.u1.x;  // |φ| > |θ|: R or RT
  // Masks, not `swap ? … : …`, which the compiler made a branch.
  const unsigned t = (unsigned(d.u1.y >= 0.0) & swap) | (unsigned(d.u0.y < 0.0) & (swap ^ 1u));
  return static_cast<CohSymmetry>(t | (swap << 1));
}

/// The tests of the table on D, one bit each (angles in degrees, θ ∈ [0, 180], φ ∈ [−θ, θ]).
/// The regions are closed: a threshold on a cosine or sine gives way by kClosed (far below any
/// construction's margin) to the construction with fewer pieces, so that rounding of angles
/// that lie on a region's edge does not cost a piece. M0 keeps (6) strict.
enum DecisionBit : unsigned {
  kSmooth = 1u << 0,      // cos θ > 1/3: (6), M0
  kSmallNeg = 1u << 1,    // φ ∈ [−60, 0]
  kUpTo120 = 1u << 2,     // θ ≤ 120
  kNegative = 1u << 3,    // φ < 0
  kUpTo30 = 1u << 4,      // φ ≤ 30 (closed)
  kThetaPi = 1u << 5,     // θ = π and φ ≤ 60
  kBelow30 = 1u << 6,     // φ < 30 (open)
  kUpTo120Phi = 1u << 7,  // φ ≤ 120
};

inline unsigned decision_bits(LocalData c) {
  constexpr double kClosed = 1e-12;
  const double c0 = c.u0.x, s0 = c.u0.y, c1 = c.u1.x, s1 = c.u1.y;
  const unsigned up_to_60 = c1 >= 0.5 - kClosed;
  return unsigned(c0 > kThird) | (unsigned(s1 <= kClosed) & up_to_60) << 1 |
         unsigned(c0 >= -0.5 - kClosed) << 2 | unsigned(s1 < 0.0) << 3 |
         unsigned(c1 >= kCos30 - kClosed) << 4 | (unsigned(s0 <= kClosed) & up_to_60) << 5 |
         unsigned(c1 > kCos30) << 6 | unsigned(c1 >= -0.5) << 7;
}

/// The table on D, fewest pieces first, as a function of the decision bits.
constexpr CohChoice decide(unsigned b) {
  using M = CohMethod;
  using S = CohSymmetry;
  if (b & kSmooth) return {M::kM0, S::kNone};      // (6)
  if (b & kSmallNeg) return {M::kM2, S::kR};       // φ ∈ [−60, 0]
  if (b & kUpTo120) {                              // θ ≤ 120
    if (b & kNegative) return {M::kM2, S::kNone};  // φ < −60
    if (b & kUpTo30) return {M::kM1, S::kRT};      // φ ∈ (0, 30]
    return {M::kM4, S::kNone};                     // φ ∈ (30, θ]
  }
  if (b & kNegative) return {M::kM5, S::kNone};  // φ < −60
  // θ = π: M2^RT's region [π, 5π/3] × [0, π/3] meets D on this line only.
  if (b & kThetaPi) return {M::kM2, S::kRT};       // φ ∈ (0, 60]
  if (b & kBelow30) return {M::kM3, S::kRT};       // φ ∈ (0, 30)
  if (b & kUpTo120Phi) return {M::kM6, S::kNone};  // φ ∈ [30, 120]
  return {M::kM7, S::kNone};                       // φ ∈ (120, θ]
}

constexpr std::array<CohChoice, 256> kDecisions = [] {
  std::array<CohChoice, 256> t{};
  for (unsigned b = 0; b < 256; ++b) t[b] = decide(b);
  return t;
}();

CohChoice choose(LocalData d) {
  const CohSymmetry g = canonical(d);
  const CohChoice base = kDecisions[decision_bits(apply(g, d))];
  // Data d = g(c); M_i^h applies at c, so M_i^(h∘g) applies at d (the group is Z2 × Z2: XOR).
  // M0 is its own mirror image.
  const unsigned keep = base.method == CohMethod::kM0 ? 0u : 3u;
  return {base.method,
          static_cast<CohSymmetry>(
              (static_cast<unsigned>(base.symmetry) ^ static_cast<unsigned>(g)) & keep)};
}

/// World frame of a span: X = p0 + x·d + y·perp(d).
struct Frame {
  Point p0;
  Vec2 d;
  Point to_world(Vec2 l) const { return p0 + l.x * d + l.y * perp(d); }
  Vec2 dir_to_world(Vec2 l) const { return l.x * d + l.y * perp(d); }
};

LocalData local_data(Point p0, Point p1, Vec2 v0, Vec2 v1) {
  // (d·v, d×v) is v in the chord's frame scaled by |d||v|; normalizing it costs one square
  // root. Its squared length is |d|²|v|², so rescale first when that leaves double's range.
  const Vec2 d = p1 - p0;
  const Vec2 w0{dot(d, v0), cross(d, v0)}, w1{dot(d, v1), cross(d, v1)};
  const double n0 = norm2(w0), n1 = norm2(w1);
  if (n0 >= 0x1p-1000 && n0 <= 0x1p1000 && n1 >= 0x1p-1000 && n1 <= 0x1p1000) {
    return {w0 / std::sqrt(n0), w1 / std::sqrt(n1)};
  }
  const Vec2 e = safe_unit(d), e0 = safe_unit(v0), e1 = safe_unit(v1);
  return {quick_unit(Vec2{dot(e, e0), cross(e, e0)}), quick_unit(Vec2{dot(e, e1), cross(e, e1)})};
}

/// Pieces of a construction in world coordinates, written into `out`.
void realize(CohChoice c, const Polygon& p, const Frame& f, CohCurve& out) {
  out.method = c.method;
  out.symmetry = c.symmetry;
  out.count = p.count;
  out.preserved = true;
  // sqrt of the squared length where that cannot overflow or underflow (within an ulp of
  // hypot's, at a fraction of its cost), else hypot: the square of a chord of 1e300 overflows.
  const double n2 = norm2(f.d);
  const double len = n2 >= 0x1p-1000 && n2 <= 0x1p1000 ? std::sqrt(n2) : norm(f.d);
  Point b3 = f.to_world(p.q[0]);
  for (int k = 0; k < p.count; ++k) {
    const Vec2 q = p.q[k + 1] - p.q[k];
    const OghCoefficients mk = ogh_magnitudes(q, p.u[k], p.u[k + 1]);
    const Point b0 = b3;  // the joint, mapped once for both pieces
    b3 = f.to_world(p.q[k + 1]);
    const Point b1 = f.to_world(p.q[k] + (mk.a0 * kThird) * p.u[k]);
    const Point b2 = f.to_world(p.q[k + 1] - (mk.a1 * kThird) * p.u[k + 1]);
    out.pieces[k] = {{b0, b1, b2, b3}};
    out.coefficients[k] = {mk.a0 * len, mk.a1 * len};
    out.preserved = out.preserved && mk.a0 > 0.0 && mk.a1 > 0.0;
  }
}

void check_ends(const HermiteEnds& e, std::size_t index) {
  const bool finite = is_finite(e.p0) && is_finite(e.p1) && is_finite(e.v0) && is_finite(e.v1);
  if (finite && (e.v0.x != 0.0 || e.v0.y != 0.0) && (e.v1.x != 0.0 || e.v1.y != 0.0) &&
      !detail::coincident(e.p0, e.p1)) {
    return;
  }
  if (!is_finite(e.p0) || !is_finite(e.p1)) {
    throw Error(ErrorCode::kNonFinite, "an end point is not finite", index);
  }
  if (detail::coincident(e.p0, e.p1)) {
    throw Error(ErrorCode::kRepeatedPoint, "the two end points coincide", index);
  }
  for (const auto& [v, name] : {std::pair{e.v0, "V0"}, std::pair{e.v1, "V1"}}) {
    if (!is_finite(v)) {
      throw Error(ErrorCode::kNonFinite, std::string(name) + " is not finite", index);
    }
    if (v.x == 0.0 && v.y == 0.0) {
      throw Error(ErrorCode::kInvalidArgument, std::string(name) + " is the zero vector", index);
    }
  }
}

/// Scratch of one item of a batch.
struct Work {
  LocalData d;  // local end data
  LocalData b;  // the base method's data s(d)
  CohChoice c;
  Vec2 r{1.0, 0.0};
  Polygon p;
};

constexpr std::size_t kEndBlock = 32;

/// 0..31: the construction's method and symmetry.
inline unsigned key(CohChoice c) {
  return static_cast<unsigned>(c.method) * 4u + static_cast<unsigned>(c.symmetry);
}

/// out[i] = M_c^s for ends[i], i < n <= kEndBlock, with (M, s) = pick(local data). The work runs
/// stage by stage over the block, so that the long dependency chains of different items
/// (square roots, divisions, atan2, sincos) overlap. Errors carry index_base + i.
template <std::size_t kCap = kEndBlock, typename Pick>
[[gnu::flatten]] void construct_block(const HermiteEnds* ends, std::size_t n,
                                      std::size_t index_base, Pick&& pick, CohCurve* out) {
  // Work is an implicit-lifetime aggregate, so bytes hold its objects without the zero-fill
  // that its members' initializers would cost (a few percent of a dispatch); every member is
  // written below before it is read.
  alignas(Work) std::byte storage[sizeof(Work) * kCap];
  Work* const w = std::launder(reinterpret_cast<Work*>(storage));
  for (std::size_t i = 0; i < n; ++i) {
    check_ends(ends[i], index_base + i);
    Work& x = w[i];
    x.d = local_data(ends[i].p0, ends[i].p1, ends[i].v0, ends[i].v1);
    x.c = pick(x.d);
    if (x.c.method == CohMethod::kM0) x.c.symmetry = CohSymmetry::kNone;
    x.b = apply(x.c.symmetry, x.d);
    x.r = {1.0, 0.0};
  }
  // Visit the items grouped by construction (a counting sort on method and symmetry): the
  // per-construction branches below then run in predictable streaks.
  std::array<std::uint8_t, kCap> order;
  {
    std::array<std::uint8_t, 33> start{};
    for (std::size_t i = 0; i < n; ++i) ++start[key(w[i].c) + 1];
    for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    for (std::size_t i = 0; i < n; ++i) order[start[key(w[i].c)]++] = static_cast<std::uint8_t>(i);
  }
  for (std::size_t j = 0; j < n; ++j) {
    Work& x = w[order[j]];
    const TrigStep t = trig_step(x.c.method, x.b);
    if (t.k != 0.0) x.r = step_rotation(step_angle(t));
  }
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = order[j];
    Work& x = w[i];
    build_post(x.c.method, x.b, x.r, x.p);
    apply_in_place(x.c.symmetry, x.p);
    // The end directions are the given ones exactly (sign flips are exact; copy regardless).
    x.p.u[0] = x.d.u0;
    x.p.u[x.p.count] = x.d.u1;
    realize(x.c, x.p, Frame{ends[i].p0, ends[i].p1 - ends[i].p0}, out[i]);
  }
}

}  // namespace

// ---- OGH ----

namespace detail {

OghCoefficients ogh_coefficients_slow(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0, double t1) {
  check_vector(v0, "V0");
  check_vector(v1, "V1");
  check_interval(t0, t1);
  // Unit directions (no under/overflow of the squared lengths); a_k scales as 1/|V_k|.
  const double m0 = std::max(std::abs(v0.x), std::abs(v0.y));
  const double m1 = std::max(std::abs(v1.x), std::abs(v1.y));
  const Vec2 w0 = v0 / m0, w1 = v1 / m1;
  const double n0 = std::sqrt(norm2(w0)), n1 = std::sqrt(norm2(w1));
  const OghCoefficients u = ogh_magnitudes(p1 - p0, w0 / n0, w1 / n1);
  const double h = t1 - t0;
  const double a0 = u.a0 / h / n0 / m0, a1 = u.a1 / h / n1 / m1;
  return {finite_or_throw(a0, "a0*"), finite_or_throw(a1, "a1*")};
}

}  // namespace detail

double ogh_equal_ratio_coefficient(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0, double t1) {
  check_vector(v0, "V0");
  check_vector(v1, "V1");
  check_interval(t0, t1);
  const double a =
      3.0 * dot(p1 - p0, v0 + v1) / (2.0 * (norm2(v0) + dot(v0, v1) + norm2(v1)) * (t1 - t0));
  return finite_or_throw(a, "a*");
}

double hermite_strain_energy(Point p0, Point p1, Vec2 w0, Vec2 w1, double t0, double t1) {
  check_interval(t0, t1);
  // Q''(t) is linear: B at t0, A + B at t1 (the paper's A and B), ∫ = h(B² + A·B + A²/3).
  const double h = t1 - t0;
  const Vec2 d = p1 - p0;
  const Vec2 b = (6.0 / (h * h)) * d - (4.0 / h) * w0 - (2.0 / h) * w1;
  const Vec2 a = (-12.0 / (h * h)) * d + (6.0 / h) * (w0 + w1);
  return h * (norm2(b) + dot(a, b) + norm2(a) / 3.0);
}

double ogh_strain_energy(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0, double t1) {
  check_vector(v0, "V0");
  check_vector(v1, "V1");
  check_interval(t0, t1);
  const Vec2 d = p1 - p0;
  if (d.x == 0.0 && d.y == 0.0) return 0.0;  // a0 = a1 = 0: the constant curve
  const LocalData l = local_data(p0, p1, v0, v1);
  const double h = t1 - t0;
  return finite_or_throw(unit_energy(l.u0, l.u1) * norm2(d) / (h * h * h), "the OGH energy");
}

double ogh_unit_energy(double theta, double phi) {
  return unit_energy(expi(theta), expi(phi));
}

bool ogh_preserves_directions(double theta, double phi) {
  return 3.0 * std::cos(theta) > std::cos(theta - 2.0 * phi) &&
         3.0 * std::cos(phi) > std::cos(phi - 2.0 * theta);
}

bool ogh_geometrically_smooth(double theta, double phi) {
  return std::cos(theta) > kThird && std::cos(phi) > kThird;
}

TangentAngles tangent_angles(Point p0, Point p1, Vec2 v0, Vec2 v1) {
  // Unit vectors first: cross and dot of vectors near 1e308 (or 1e-300) over/underflow and
  // atan2(Inf, Inf) would be NaN (found by fuzz_fit).
  const Vec2 d = safe_unit(p1 - p0), e0 = safe_unit(v0), e1 = safe_unit(v1);
  return {std::atan2(cross(d, e0), dot(d, e0)), std::atan2(cross(d, e1), dot(d, e1))};
}

// ---- COH ----

int coh_piece_count(CohMethod method) {
  switch (method) {
    case CohMethod::kM0:
      return 1;
    case CohMethod::kM1:
    case CohMethod::kM2:
      return 2;
    default:
      return 3;
  }
}

std::string coh_name(CohMethod method, CohSymmetry symmetry) {
  // A lookup (not string concatenation: GCC 12 raises a false -Wrestrict on `s + "^T"`).
  static constexpr const char* kSuffix[] = {"", "^T", "^R", "^RT"};
  std::string name(1, 'M');
  name.push_back(static_cast<char>('0' + static_cast<int>(method)));
  if (method != CohMethod::kM0) name.append(kSuffix[static_cast<int>(symmetry)]);
  return name;
}

bool coh_applicable(CohMethod method, CohSymmetry symmetry, double theta, double phi) {
  if (method == CohMethod::kM0) {
    return ogh_geometrically_smooth(theta, phi);  // M0^s = M0: (6) is symmetric
  }
  // Map the angles to the base method's frame (the symmetries are involutions).
  const LocalData d = apply(symmetry, LocalData{expi(theta), expi(phi)});
  const double th = angle_2pi(d.u0) / kDeg, ph = angle_2pi(d.u1) / kDeg;
  // Angles at the upper end 2π are also 0; test both representatives.
  auto in = [](double x, double lo, double hi) {
    constexpr double kSlack = 1e-9;  // degrees: rounding of the round trip through sin/cos
    return (x >= lo - kSlack && x <= hi + kSlack) ||
           (x + 360.0 >= lo - kSlack && x + 360.0 <= hi + kSlack) ||
           (x - 360.0 >= lo - kSlack && x - 360.0 <= hi + kSlack);
  };
  auto box = [&](double a, double b, double c, double e) { return in(th, a, b) && in(ph, c, e); };
  switch (method) {
    case CohMethod::kM1:
      return box(0, 30, 60, 120);
    case CohMethod::kM2:
      return box(0, 60, 180, 300) || box(60, 120, 240, 300);
    case CohMethod::kM3:
      return box(0, 60, 60, 180);
    case CohMethod::kM4:
      return box(60, 120, 0, 120);
    case CohMethod::kM5:
      return box(60, 120, 180, 240) || box(120, 180, 180, 300);
    case CohMethod::kM6:
      return box(120, 180, 30, 120);
    case CohMethod::kM7:
      return box(120, 180, 120, 180);
    default:
      return false;
  }
}

CohCurve coh_construct(CohMethod method, CohSymmetry symmetry, Point p0, Point p1, Vec2 v0,
                       Vec2 v1) {
  const HermiteEnds e{p0, p1, v0, v1};
  CohCurve out;
  construct_block<1>(
      &e, 1, 0,
      [&](const LocalData&) {
        return CohChoice{method, symmetry};
      },
      &out);
  return out;
}

CohChoice coh_choose(double theta, double phi) {
  return choose(LocalData{expi(theta), expi(phi)});
}

CohCurve coh_curve(Point p0, Point p1, Vec2 v0, Vec2 v1) {
  const HermiteEnds e{p0, p1, v0, v1};
  CohCurve out;
  construct_block<1>(&e, 1, 0, choose, &out);
  return out;
}

void coh_curves(std::span<const HermiteEnds> ends, std::span<CohCurve> out) {
  if (out.size() < ends.size()) {
    throw Error(ErrorCode::kInvalidArgument,
                "coh_curves: the output span is shorter than the input");
  }
  for (std::size_t i = 0; i < ends.size(); i += kEndBlock) {
    construct_block(
        ends.data() + i, std::min(kEndBlock, ends.size() - i), i,
        [](LocalData d) { return choose(d); }, out.data() + i);
  }
}

double coh_min_margin(const CohCurve& curve) {
  double margin = 1.0;
  for (int k = 0; k < curve.count; ++k) {
    const CubicBezier& b = curve.pieces[k];
    const Vec2 chord = b.p[3] - b.p[0];
    // The given directions: the control legs times the signs of the coefficients. Cosines of
    // unit vectors (safe_unit), so that legs of 1e300 or 1e-300 neither overflow nor underflow.
    const Vec2 l0 = b.p[1] - b.p[0], l1 = b.p[3] - b.p[2];
    const auto nonzero = [](Vec2 v) { return v.x != 0.0 || v.y != 0.0; };
    if (!(nonzero(chord) && nonzero(l0) && nonzero(l1))) return -1.0;
    const Vec2 e = safe_unit(chord);
    const double c0 = dot(e, safe_unit(l0)) * (curve.coefficients[k].a0 > 0.0 ? 1 : -1);
    const double c1 = dot(e, safe_unit(l1)) * (curve.coefficients[k].a1 > 0.0 ? 1 : -1);
    margin = std::min({margin, c0 - kThird, c1 - kThird});
  }
  return margin;
}

}  // namespace fairspline

// ---- spline level ----

namespace fairspline {

namespace {

constexpr detail::ChoiceTable<YongChengRatio, 2> kRatio{
    {{"free", YongChengRatio::kFree}, {"equal", YongChengRatio::kEqual}}};

const Capabilities& yong_cheng_capabilities() {
  static const Capabilities caps{
      .tangents = TangentUse::kRequired,
      .examples = {R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0],[8,1],[9,3]],
                            "options": {"tangents_from": "jaklic-zagar"}})",
                   R"({"points": [[0,0],[1,0],[2,0]],
                            "tangents": [[0,1],[1,-1],[0,1]]})",
                   R"({"points": [[0,0],[4,0],[4,4],[0,4]], "closed": true,
                            "tangents": [[1,-1],[1,1],[-1,1],[-1,-1]]})"}};
  return caps;
}

/// The tangent vector at every point (prepare_input has checked that each has one).
void collect_tangents(const FitInput& input, std::span<Vec2> v) {
  const std::size_t n = v.size();
  std::fill(v.begin(), v.end(), Vec2{});
  for (std::size_t i = 0; i < std::min(input.tangents.size(), n); ++i) {
    if (input.tangents[i]) v[i] = *input.tangents[i];
  }
  if (input.start_tangent) v[0] = *input.start_tangent;
  if (input.end_tangent && !input.closed) v[n - 1] = *input.end_tangent;
}

/// One span's entry of method_report.
struct YongChengSpanReport {
  std::string construction;
  int pieces = 0;
  double theta_deg = 0.0, phi_deg = 0.0;
  std::vector<std::array<double, 2>> coefficients;  ///< (a0, a1) per piece
  bool preserved = false;
};

/// What method_report holds, typed; serialized once by report_json.
struct YongChengReport {
  bool composite = true;
  std::string ratio, tangents_from;
  bool detailed = false;  ///< level != kNone: the entries below are reported
  std::vector<YongChengSpanReport> spans;
  std::map<std::string, int> constructions;
  bool all_preserved = true;
};

nlohmann::json report_json(const YongChengReport& r) {
  nlohmann::json j = {
      {"composite", r.composite}, {"ratio", r.ratio}, {"tangents_from", r.tangents_from}};
  if (!r.detailed) return j;
  nlohmann::json spans = nlohmann::json::array();
  for (const YongChengSpanReport& s : r.spans) {
    nlohmann::json coeffs = nlohmann::json::array();
    for (const auto& a : s.coefficients) coeffs.push_back({a[0], a[1]});
    spans.push_back({{"construction", s.construction},
                     {"pieces", s.pieces},
                     {"theta_deg", s.theta_deg},
                     {"phi_deg", s.phi_deg},
                     {"coefficients", std::move(coeffs)},
                     {"preserved", s.preserved}});
  }
  j["spans"] = std::move(spans);
  j["constructions"] = r.constructions;
  j["all_preserved"] = r.all_preserved;
  return j;
}

/// Composite spans are built a chunk at a time by the batch dispatcher (coh_curves).
constexpr std::size_t kChunk = 256;

/// The free-ratio curves of spans first..first+count−1 into `chunk`.
void free_ratio_chunk(const FitResult& out, const std::vector<Vec2>& v, std::size_t first,
                      std::size_t count, bool composite,
                      std::array<HermiteEnds, kChunk>& chunk_ends, std::vector<CohCurve>& chunk) {
  const std::size_t n = out.points.size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t a = first + k, b = a + 1 == n ? 0 : a + 1;
    chunk_ends[k] = {out.points[a], out.points[b], v[a], v[b]};
  }
  try {
    if (composite) {
      coh_curves({chunk_ends.data(), count}, chunk);
    } else {
      for (std::size_t k = 0; k < count; ++k) {
        const HermiteEnds& e = chunk_ends[k];
        chunk[k] = coh_construct(CohMethod::kM0, CohSymmetry::kNone, e.p0, e.p1, e.v0, e.v1);
      }
    }
  } catch (const Error& e) {
    // coh_curves numbers the spans of the chunk; name the span of the curve.
    const std::size_t span = first + e.index().value_or(0);
    throw Error(e.code(), "yong-cheng: span " + std::to_string(span) + ": " + e.what(), span);
  }
}

/// The equal-ratio curve (a0 = a1 = a*) of span i.
CohCurve equal_ratio_curve(Point p0, Point p1, Vec2 v0, Vec2 v1, double ta, double tb,
                           std::size_t i) {
  const double a = ogh_equal_ratio_coefficient(p0, p1, v0, v1, ta, tb);
  if (!(a > 0.0)) {
    throw Error(ErrorCode::kInfeasible,
                "span " + std::to_string(i) +
                    ": the equal-ratio coefficient a* is not positive (|V0| cos(theta) + "
                    "|V1| cos(phi) <= 0), so the curve would reverse the given tangents; "
                    "use ratio=free",
                i);
  }
  CohCurve c;
  c.count = 1;
  c.pieces[0] = hermite_bezier(p0, p1, a * v0, a * v1, ta, tb);
  c.coefficients[0] = {a, a};
  return c;
}

/// [ta, tb] split among the pieces in proportion to their chords.
std::array<double, 4> piece_cuts(const CohCurve& c, double ta, double tb) {
  std::array<double, 4> cut{ta, tb, tb, tb};
  if (c.count > 1) {
    double total = 0.0;
    std::array<double, 3> len{};
    for (int k = 0; k < c.count; ++k) {
      len[k] = detail::safe_norm(c.pieces[k].p[3] - c.pieces[k].p[0]);
      total += len[k];
    }
    double acc = 0.0;
    for (int k = 0; k < c.count; ++k) {
      cut[k] = ta + (tb - ta) * (acc / total);
      acc += len[k];
    }
    cut[c.count] = tb;
  }
  return cut;
}

/// The report entry of span i (from point i to point j). Throws when a coefficient is not
/// representable: called in span order, so that the first failing span is named.
YongChengSpanReport span_report(const CohCurve& c, bool equal, Point p0, Point p1, Vec2 v0, Vec2 v1,
                                const std::array<double, 4>& cut, std::size_t i, std::size_t j) {
  YongChengSpanReport r;
  r.construction = equal ? std::string("equal-ratio") : coh_name(c.method, c.symmetry);
  r.pieces = c.count;
  const TangentAngles ang = tangent_angles(p0, p1, v0, v1);
  r.theta_deg = ang.theta / kDeg;
  r.phi_deg = ang.phi / kDeg;
  r.preserved = c.preserved;
  for (int k = 0; k < c.count; ++k) {
    if (equal) {
      r.coefficients.push_back({c.coefficients[k].a0, c.coefficients[k].a1});
      continue;
    }
    // World coefficients are relative to unit directions on [0, 1]; rescale to the given
    // vector at a span end and to the piece's parameter interval.
    // (norm, not sqrt(norm2): the square of a tangent of length 1e-170 underflows.) A
    // tangent so short that the coefficient relative to it overflows (a denormal one) is
    // refused rather than reported as Inf (found by fuzz_fit).
    // |V| as m·|V/m| (m = max |component|): hypot of a tangent near 1e308 is Inf.
    const double hk = cut[k + 1] - cut[k];
    const auto per_length = [](double a, Vec2 v) {
      const double m = std::max(std::abs(v.x), std::abs(v.y));
      return a / m / norm(v / m);
    };
    const double a0 =
        k == 0 ? per_length(c.coefficients[k].a0 / hk, v0) : c.coefficients[k].a0 / hk;
    const double a1 =
        k + 1 == c.count ? per_length(c.coefficients[k].a1 / hk, v1) : c.coefficients[k].a1 / hk;
    if (!std::isfinite(a0) || !std::isfinite(a1)) {
      const std::size_t at = std::isfinite(a0) ? j : i;
      throw Error(ErrorCode::kNonFinite,
                  "yong-cheng: the tangent at point " + std::to_string(at) +
                      " is too short for its Hermite coefficient to be represented in double "
                      "precision; scale it up",
                  at);
    }
    r.coefficients.push_back({a0, a1});
  }
  return r;
}

/// Names the first span with a non-finite control point, else the tangent (`bad`: the OR of
/// their bits).
void check_finite(const FitResult& out, std::uint64_t bad) {
  if (!bad) return;
  for (const Segment& s : out.spline.segments) {
    if (detail::non_finite_bits(s)) {
      throw Error(ErrorCode::kNonFinite,
                  "yong-cheng: span " + std::to_string(s.span) +
                      " overflows (coordinates too large for double arithmetic)",
                  s.span);
    }
  }
  // (The registry's own check is skipped for this method, so this one names a tangent too.)
  detail::check_finite_output(out, "yong-cheng");
}

}  // namespace

void fit_yong_cheng(const FitInput& input, const YongChengOptions& options, ReportLevel level,
                    FitResult& out) {
  const std::size_t spans =
      detail::prepare_input(input, yong_cheng_capabilities(), "yong-cheng", out);
  const std::size_t n = out.points.size();
  // The given tangents go into the result's tangents as they are (the constructions read them)
  // and are normalized there after the spans: a vector of their own was 16 MB of fresh pages
  // for a fresh 10⁶-point fit.
  out.spline.closed = out.closed;
  detail::resize_huge(out.tangents, n);
  collect_tangents(input, out.tangents);
  const std::vector<Vec2>& v = out.tangents;
  std::uint64_t bad = 0;  // non-finite output (the registry leaves the check to the method)

  const bool free_ratio = options.ratio == YongChengRatio::kFree;
  YongChengReport report{.composite = options.composite,
                         .ratio = std::string(kRatio.name(options.ratio)),
                         .tangents_from = options.tangents_from,
                         .detailed = level != ReportLevel::kNone,
                         .spans = {},
                         .constructions = {},
                         .all_preserved = true};
  out.spline.segments.clear();
  // One to three pieces a span (COH curves): room for the most, so that the vector never
  // moves, with the first `spans` mapped in (the rest is address space until written).
  const std::size_t most = options.composite ? 3 * spans : spans;
  if (most > out.spline.segments.capacity()) {
    detail::reserve_huge(out.spline.segments, most);
    detail::prefault(out.spline.segments.data(), spans * sizeof(Segment));
  }
  std::array<HermiteEnds, kChunk> chunk_ends;
  std::vector<CohCurve> chunk(free_ratio ? std::min(kChunk, spans) : 0);
  for (std::size_t i = 0; i < spans; ++i) {
    const std::size_t j = i + 1 == n ? 0 : i + 1;
    const Point p0 = out.points[i], p1 = out.points[j];
    const Vec2 v0 = v[i], v1 = v[j];
    const double ta = out.knots[i], tb = out.knots[i + 1];
    if (free_ratio && i % kChunk == 0) {
      free_ratio_chunk(out, v, i, std::min(kChunk, spans - i), options.composite, chunk_ends,
                       chunk);
    }
    CohCurve equal;
    if (!free_ratio) equal = equal_ratio_curve(p0, p1, v0, v1, ta, tb, i);
    const CohCurve& c = free_ratio ? chunk[i % kChunk] : equal;
    const std::array<double, 4> cut = piece_cuts(c, ta, tb);
    for (int k = 0; k < c.count; ++k) {
      Segment s{c.pieces[k], cut[k], cut[k + 1], i};
      bad |= detail::non_finite_bits(s);
      out.spline.segments.push_back(s);
    }
    report.all_preserved = report.all_preserved && c.preserved;
    if (report.detailed) {
      report.spans.push_back(span_report(c, !free_ratio, p0, p1, v0, v1, cut, i, j));
      ++report.constructions[report.spans.back().construction];
    }
  }
  for (Vec2& t : out.tangents) {
    t = safe_unit(t);
    bad |= detail::non_finite_bits(t);
  }
  check_finite(out, bad);
  out.method_report = report_json(report);
}

FitResult fit_yong_cheng(const FitInput& input, const YongChengOptions& options,
                         ReportLevel level) {
  FitResult result;
  fit_yong_cheng(input, options, level, result);
  return result;
}

}  // namespace fairspline

// ---- registry entry ----
#include "methods/builtin.hpp"

namespace fairspline::detail {

std::vector<MethodInfo> yong_cheng_methods() {
  return {{
      .name = "yong-cheng",
      .description =
          "Hermite G1 spline through points with given tangent directions: each span is the "
          "optimized geometric Hermite (OGH) cubic of least strain energy, or a composite of two "
          "or three OGH pieces (M1-M7 and mirror images) when the angles would give a loop, "
          "cusp, fold or reversed tangent.",
      .paper = "J.-H. Yong, F. Cheng, Geometric Hermite curves with minimum strain energy, "
               "Computer Aided Geometric Design 21 (2004), Theorems 2-7",
      .options = {{.name = "composite",
                   .type = OptionType::kBoolean,
                   .default_value = true,
                   .doc = "use composite (COH) curves where a single OGH curve would violate the "
                          "geometric smoothness conditions (6); false keeps one OGH per span and "
                          "reports spans whose directions are reversed"},
                  {.name = "ratio",
                   .type = OptionType::kChoice,
                   .default_value = "free",
                   .choices = kRatio.names(),
                   .doc = "free: independent optimized coefficients a0, a1 (Theorem 2); equal: "
                          "a0 = a1 (the equal-ratio variant, one piece per span, error if a* <= "
                          "0)"}},
      // tangents_from is added by the registry (TangentUse::kRequired).
      .fit =
          [](const FitInput& in, const nlohmann::json& o, const FitOptions& f, FitResult& out) {
            YongChengOptions opt;
            opt.composite = o.at("composite").get<bool>();
            opt.ratio = kRatio.parse(o.at("ratio").get<std::string>());
            opt.tangents_from = o.at(kTangentsFromOption).get<std::string>();
            fit_yong_cheng(in, opt, f.method_report_level(), out);
          },
      .capabilities = yong_cheng_capabilities(),
      .checks_own_output = true,
      // Derivative lengths dP/dt per unit of the given vector's length.
      .report_units = {{"spans/*/coefficients/*/*", 1, -1}},
  }};
}

}  // namespace fairspline::detail
