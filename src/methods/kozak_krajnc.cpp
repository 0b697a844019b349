// Kozak–Krajnc building blocks. See include/fairspline/methods/kozak_krajnc.hpp.
#include "fairspline/methods/kozak_krajnc.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "detail/bernstein.hpp"
#include "fairspline/error.hpp"
#include "methods/kozak_krajnc_detail.hpp"

namespace fairspline {

namespace {

[[noreturn]] void throw_zero_denominator(const char* what) {
  throw Error(ErrorCode::kInvalidArgument, std::string("kozak-krajnc: ") + what +
                                               " is zero, so the constants (2.6) are undefined");
}

double ratio(double num, double den, const char* what) {
  if (den == 0.0) throw_zero_denominator(what);
  return num / den;
}

}  // namespace

KozakKrajncConstants kozak_krajnc_constants(Point t0, Point t1, Point t2, Point t3, Vec2 d0,
                                            Vec2 d3) {
  for (Vec2 v : {t0, t1, t2, t3, d0, d3}) {
    if (!is_finite(v)) throw Error(ErrorCode::kNonFinite, "kozak-krajnc: non-finite data");
  }
  const Vec2 a = t1 - t0, b = t2 - t1, c = t3 - t2;
  const double d01 = cross(a, b), d02 = cross(a, c), d12 = cross(b, c);
  const double e0 = cross(d0, a), e3 = cross(c, d3);
  KozakKrajncConstants k;
  k.lambda1 = ratio(d02, d01, "det(dT0, dT1) (T0, T1, T2 collinear)");
  k.lambda2 = ratio(d02, d12, "det(dT1, dT2) (T1, T2, T3 collinear)");
  k.mu1 = ratio(cross(d0, b), e0, "det(d0, dT0) (d0 along the first chord)");
  k.mu2 = ratio(cross(b, d3), e3, "det(dT2, d3) (d3 along the last chord)");
  k.delta1 = ratio(d01, e0, "det(d0, dT0) (d0 along the first chord)");
  k.delta2 = ratio(d12, e3, "det(dT2, d3) (d3 along the last chord)");
  return k;
}

std::optional<ParameterPair> kozak_krajnc_boundary_alpha0(double lambda1, double lambda2) {
  if (!(lambda1 > 0.0 && lambda2 > 0.0 && std::isfinite(lambda1) && std::isfinite(lambda2))) {
    return std::nullopt;
  }
  const double a = 1.0 + lambda1;
  auto t1_of = [a](double t2) { return (a * t2 * t2 * t2 - 1.0) / (a * t2 * t2 - 1.0); };
  // g decreases from g(lo) = λ2 > 0 to g(1) = −1 on (lo, 1) (proof of Lemma 2.1): Newton with
  // the derivative of the proof, kept inside the shrinking bracket (bisection fallback).
  auto g = [&](double t2, double& dg) {
    const double p = a * t2 * t2 * t2 - 1.0, q = a * t2 * t2 - 1.0, q2 = q * q;
    dg = 6.0 * lambda1 * a * (1.0 + lambda2) * t2 * (t2 - 1.0) * p / (q2 * q2);
    return lambda2 - lambda1 * (1.0 + lambda2) * p * p / (q2 * q);
  };
  double lo = 1.0 / std::cbrt(a), hi = 1.0, x = 0.5 * (lo + hi);
  for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
    double dg = 0.0;
    const double v = g(x, dg);
    if (v == 0.0) {
      lo = hi = x;
      break;
    }
    (v > 0.0 ? lo : hi) = x;
    double next = dg != 0.0 ? x - v / dg : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == x || next <= lo || next >= hi) break;
    if (std::abs(next - x) <= 1e-16 * x) {
      x = next;
      lo = hi = x;
      break;
    }
    x = next;
  }
  const double t2 = lo == hi ? lo : x;
  return ParameterPair{t1_of(t2), t2};
}

std::optional<ParameterPair> kozak_krajnc_boundary_alpha3(double lambda1, double lambda2) {
  const auto s = kozak_krajnc_boundary_alpha0(lambda2, lambda1);
  if (!s) return std::nullopt;
  return ParameterPair{1.0 - s->t2, 1.0 - s->t1};
}

std::optional<double> kozak_krajnc_phi2(double lambda1, double lambda2) {
  const auto s = kozak_krajnc_boundary_alpha0(lambda1, lambda2);
  if (!s) return std::nullopt;
  const double t1 = s->t1, t2 = s->t2;
  const double num = lambda2 * (1.0 - t1) / (t2 * t2) - lambda1 * t1 / ((1.0 - t2) * (1.0 - t2));
  const double den = lambda2 * (1.0 - t2) / (t1 * t1) - lambda1 * t2 / ((1.0 - t1) * (1.0 - t1));
  return num / den - 1.0;
}

std::optional<double> kozak_krajnc_phi1(double lambda1, double lambda2) {
  const auto s = kozak_krajnc_boundary_alpha3(lambda1, lambda2);
  if (!s) return std::nullopt;
  const double t1 = s->t1, t2 = s->t2;
  const double num = lambda1 * t2 / ((1.0 - t1) * (1.0 - t1)) - lambda2 * (1.0 - t2) / (t1 * t1);
  const double den = lambda1 * t1 / ((1.0 - t2) * (1.0 - t2)) - lambda2 * (1.0 - t1) / (t2 * t2);
  return num / den - 1.0;
}

double kozak_krajnc_phi3(double lambda1, double lambda2, double mu1) {
  return lambda2 * mu1 / (lambda1 * (lambda2 * mu1 - 1.0 - std::sqrt(1.0 + mu1)));
}

double kozak_krajnc_phi4(double lambda1, double lambda2, double mu1) {
  const double lm = lambda2 * mu1;
  return lm * (lm * (1.0 + 2.0 * lambda1) - 2.0 * lambda1) /
         (lambda1 * lambda1 * (lm - 1.0) * (lm - 1.0));
}

bool kozak_krajnc_theorem_2_4(const KozakKrajncConstants& c) {
  if (!(c.lambda1 > 0 && c.lambda2 > 0 && c.delta1 > 0 && c.delta2 > 0 && c.mu1 > 0 && c.mu2 > 0)) {
    return false;
  }
  const double p1 = *kozak_krajnc_phi1(c.lambda1, c.lambda2);
  const double p2 = *kozak_krajnc_phi2(c.lambda1, c.lambda2);
  return (c.mu1 < p1 && c.mu2 < p2) || (c.mu1 > p1 && c.mu2 > p2);
}

bool kozak_krajnc_theorem_2_5(const KozakKrajncConstants& c) {
  if (!(c.delta1 > 0 && c.delta2 > 0)) return false;
  auto holds = [](double l1, double l2, double m1, double m2) {
    return l1 > 0 && l2 < 0 && m1 > 0 && kozak_krajnc_phi3(l1, l2, m1) < m2 &&
           m2 < kozak_krajnc_phi4(l1, l2, m1);
  };
  return holds(c.lambda1, c.lambda2, c.mu1, c.mu2) || holds(c.lambda2, c.lambda1, c.mu2, c.mu1);
}

}  // namespace fairspline

// ---------------------------------------------------------------------------------------------
// Table 3.3 and the single-piece solver.

namespace fairspline {

int kozak_krajnc_table_3_3(const KozakKrajncConstants& c) {
  const double l1 = c.lambda1, l2 = c.lambda2, m1 = c.mu1, m2 = c.mu2;
  const double d1 = c.delta1, d2 = c.delta2;
  if (l1 > 0 && l2 > 0) {
    const double p1 = *kozak_krajnc_phi1(l1, l2), p2 = *kozak_krajnc_phi2(l1, l2);
    if (d1 > 0 && d2 > 0) {
      if (m1 <= 0 && kozak_krajnc_phi4(l1, l2, m1) < m2 && m2 < p2) return 1;
      if (m1 > 0 && m1 <= (1 + 2 * l2) / (l2 * l2) && kozak_krajnc_phi3(l1, l2, m1) < m2 &&
          m2 <= 0) {
        return 2;
      }
    }
    if (d1 < 0 && d2 > 0) {
      if (m1 > 1 / l2 && kozak_krajnc_phi4(l1, l2, m1) < m2 && m2 < p2) return 3;
      if (m1 <= 1 / l2 && p2 < m2) return 4;
    }
    if (d1 > 0 && d2 < 0) {
      if (m2 > 1 / l1 && kozak_krajnc_phi4(l2, l1, m2) < m1 && m1 < p1) return 5;
      if (m2 <= 1 / l1 && p1 < m1) return 6;
    }
    return 0;
  }
  if (l1 < 0 && l2 < 0 && d1 > 0 && d2 > 0) {
    if (m1 >= 0 && kozak_krajnc_phi3(l1, l2, m1) < m2) return 7;
    if (1 / l2 < m1 && m1 <= 0 && kozak_krajnc_phi4(l1, l2, m1) < m2) return 8;
  }
  return 0;
}

int KozakKrajncSolutions::total_multiplicity() const {
  int total = 0;
  for (const auto& s : *this) total += s.multiplicity;
  return total;
}

CubicBezier kozak_krajnc_bezier(Point t0, Point t3, Vec2 d0, Vec2 d3,
                                const KozakKrajncSolution& solution) {
  return {{t0, t0 + (solution.alpha0 / 3.0) * d0, t3 - (solution.alpha3 / 3.0) * d3, t3}};
}

namespace {

/// The system (2.3) cleared of denominators, as cubics in t1 whose coefficients are polynomials
/// in t2:  F = t2²(1−t2) − (1+μ1) t1²(1−t1) + A1 (t2−t1) t1² t2²,
///         G = t1(1−t1)² − (1+μ2) t2(1−t2)² + A2 (t2−t1)(1−t1)²(1−t2)²,
/// with A1 = 1 + μ1(1+λ1) − λ1/λ2, A2 = 1 + μ2(1+λ2) − λ2/λ1 (λ1/λ2 = D12/D01 needs no λ ≠ 0).
struct ClearedSystem {
  double mu1, mu2, a1, a2;

  /// Coefficients of F and G in powers of t1 at the given t2.
  void coefficients(double t2, double f[4], double g[4]) const {
    const double t22 = t2 * t2, w = (1.0 - t2) * (1.0 - t2);
    f[0] = t22 * (1.0 - t2);
    f[1] = 0.0;
    f[2] = -(1.0 + mu1) + a1 * t22 * t2;
    f[3] = (1.0 + mu1) - a1 * t22;
    g[0] = (a2 - (1.0 + mu2)) * t2 * w;
    g[1] = 1.0 - a2 * w * (2.0 * t2 + 1.0);
    g[2] = -2.0 + a2 * w * (t2 + 2.0);
    g[3] = 1.0 - a2 * w;
  }
  /// F, G and their partial derivatives at (t1, t2); `scale` gets the size of the terms.
  void eval(double x, double y, double& F, double& G, double J[2][2], double& scale) const {
    const double x2 = x * x, y2 = y * y, ux = 1.0 - x, uy = 1.0 - y;
    const double p = 1.0 + mu1, q = 1.0 + mu2;
    F = y2 * uy - p * x2 * ux + a1 * (y - x) * x2 * y2;
    G = x * ux * ux - q * y * uy * uy + a2 * (y - x) * ux * ux * uy * uy;
    J[0][0] = -p * (2.0 * x - 3.0 * x2) + a1 * y2 * (2.0 * x * y - 3.0 * x2);
    J[0][1] = 2.0 * y - 3.0 * y2 + a1 * x2 * (3.0 * y2 - 2.0 * x * y);
    J[1][0] = ux * ux - 2.0 * x * ux + a2 * uy * uy * (-ux * ux - 2.0 * (y - x) * ux);
    J[1][1] = -q * (uy * uy - 2.0 * y * uy) + a2 * ux * ux * (uy * uy - 2.0 * (y - x) * uy);
    scale = std::abs(y2 * uy) + std::abs(p * x2 * ux) + std::abs(a1 * (y - x) * x2 * y2) +
            std::abs(x * ux * ux) + std::abs(q * y * uy * uy) +
            std::abs(a2 * (y - x) * ux * ux * uy * uy);
  }
};

/// Bézout matrix of two cubics (det = resultant).
void bezout(const double f[4], const double g[4], double B[3][3]) {
  auto c = [&](int k, int l) { return f[k] * g[l] - f[l] * g[k]; };
  const double c01 = c(0, 1), c02 = c(0, 2), c03 = c(0, 3), c12 = c(1, 2), c13 = c(1, 3),
               c23 = c(2, 3);
  B[0][0] = c01, B[0][1] = c02, B[0][2] = c03;
  B[1][0] = c02, B[1][1] = c03 + c12, B[1][2] = c13;
  B[2][0] = c03, B[2][1] = c13, B[2][2] = c23;
}

/// The common root t1 of F(·, t2) and G(·, t2) from the Bézout matrix at a simple root t2 of
/// the resultant: B then has rank 2 and its null vector is (1, t1, t1²). False when that is not
/// numerically clear (B close to rank 1, i.e. several common roots on this fibre, or a null
/// vector not of that form); the caller then falls back to the roots of F(·, t2).
bool common_root(const ClearedSystem& sys, double t2, double& t1) {
  double f[4], g[4], B[3][3];
  sys.coefficients(t2, f, g);
  bezout(f, g, B);
  // The null vector is parallel to the cross product of any two independent rows; take the
  // largest of the three.
  double v[3] = {0.0, 0.0, 0.0}, vn2 = -1.0, rn2 = 0.0;
  for (int i = 0; i < 2; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double* a = B[i];
      const double* b = B[j];
      const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]};
      const double c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
      if (c2 > vn2) {
        vn2 = c2;
        rn2 = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        v[0] = c[0], v[1] = c[1], v[2] = c[2];
      }
    }
  }
  // Rows at least 1e-4 (in sine of their angle) from parallel, and v0·v2 = v1² (a Vandermonde
  // vector) to 1e-6 of |v|².
  if (!(vn2 > 1e-8 * rn2) || !(std::abs(v[0] * v[2] - v[1] * v[1]) <= 1e-6 * vn2)) return false;
  t1 = std::abs(v[0]) >= std::abs(v[2]) ? v[1] / v[0] : v[2] / v[1];
  return std::isfinite(t1);
}

double det3(const double B[3][3]) {
  return B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1]) -
         B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0]) +
         B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0]);
}

constexpr int kQDegree = 9;
constexpr int kNodes = kQDegree + 1;

/// Chebyshev nodes on (0, 1) and the matrix taking values there to degree-9 Bernstein
/// coefficients (inverse of the collocation matrix), computed once.
struct Interpolation {
  double node[kNodes];
  double weight[kNodes];  ///< 1 / (x³(1−x)³) at the nodes
  double to_bernstein[kNodes][kNodes];

  Interpolation() {
    const double pi = std::acos(-1.0);
    double a[kNodes][2 * kNodes] = {};
    for (int i = 0; i < kNodes; ++i) {
      const double x = 0.5 * (1.0 - std::cos((2 * i + 1) * pi / (2 * kNodes)));
      node[i] = x;
      weight[i] = 1.0 / std::pow(x * (1.0 - x), 3);
      double binom = 1.0;
      for (int j = 0; j < kNodes; ++j) {
        a[i][j] = binom * std::pow(x, j) * std::pow(1.0 - x, kQDegree - j);
        binom = binom * (kQDegree - j) / (j + 1);
      }
      a[i][kNodes + i] = 1.0;
    }
    for (int col = 0; col < kNodes; ++col) {  // Gauss–Jordan with partial pivoting
      int piv = col;
      for (int r = col + 1; r < kNodes; ++r) {
        if (std::abs(a[r][col]) > std::abs(a[piv][col])) piv = r;
      }
      for (int j = 0; j < 2 * kNodes; ++j) std::swap(a[col][j], a[piv][j]);
      const double inv = 1.0 / a[col][col];
      for (int j = 0; j < 2 * kNodes; ++j) a[col][j] *= inv;
      for (int r = 0; r < kNodes; ++r) {
        if (r == col) continue;
        const double m = a[r][col];
        for (int j = 0; j < 2 * kNodes; ++j) a[r][j] -= m * a[col][j];
      }
    }
    for (int i = 0; i < kNodes; ++i) {
      for (int j = 0; j < kNodes; ++j) to_bernstein[i][j] = a[i][kNodes + j];
    }
  }
};

const Interpolation& interpolation() {
  static const Interpolation table;
  return table;
}

/// The real roots t1 ∈ [0, t2] of the cubic F(·, t2) (F vanishes on every solution, so these
/// are Newton starts for the solutions on this fibre), by Bernstein isolation on [0, t2].
detail::BernsteinRoots fibre_roots(const ClearedSystem& sys, double t2) {
  double f[4], g[4];
  sys.coefficients(t2, f, g);
  // t1 = t2·u: monomial coefficients c_i = f_i t2^i, then b_j = Σ_{i≤j} C(j,i)/C(3,i) c_i.
  const double c0 = f[0], c1 = f[1] * t2, c2 = f[2] * t2 * t2, c3 = f[3] * t2 * t2 * t2;
  detail::BernsteinPoly cubic;
  cubic.degree = 3;
  cubic.b[0] = c0;
  cubic.b[1] = c0 + c1 / 3.0;
  cubic.b[2] = c0 + 2.0 * c1 / 3.0 + c2 / 3.0;
  cubic.b[3] = c0 + c1 + c2 + c3;
  detail::BernsteinRoots roots = detail::bernstein_roots(cubic, 1e-12);
  for (int i = 0; i < roots.count; ++i) roots.items[i].u *= t2;
  return roots;
}

/// Whether the gradients of F and G (the rows of J) are transversal: the sine of their angle,
/// |det J| / (|∇F| |∇G|), above 1e-6. Rows scaled to max-norm 1 first (no overflow or underflow
/// in the squares).
bool regular(const double J[2][2]) {
  const double mf = std::max(std::abs(J[0][0]), std::abs(J[0][1]));
  const double mg = std::max(std::abs(J[1][0]), std::abs(J[1][1]));
  if (!(mf > 0.0 && mg > 0.0)) return false;
  const double a = J[0][0] / mf, b = J[0][1] / mf, c = J[1][0] / mg, d = J[1][1] / mg;
  const double det = a * d - b * c;
  return det * det > 1e-12 * (a * a + b * b) * (c * c + d * d);
}

/// Newton's method on the cleared system from (x, y); false if it did not reach a root (the
/// iterate with the smallest residual is kept). `singular` reports a (numerically) singular
/// Jacobian there: the curves (2.3) are tangent or nearly so, a cluster of roots (a multiple root,
/// or close ones) that resolve_cluster takes apart. Newton stops as soon as it reaches one: it
/// would converge only linearly there, or jump away (at an exact double root, to the spurious
/// root t1 = t2 = 0 with residual 0). With `stop_in_cluster` false it goes on to the least
/// residual (for a simple root next to others, where a singular Jacobian is no cluster).
bool polish(const ClearedSystem& sys, double& x, double& y, bool& singular,
            bool stop_in_cluster = true) {
  constexpr double kResidual = 1e-11;  // relative to the size of the terms of F, G
  double best_x = x, best_y = y, best = HUGE_VAL;
  bool best_regular = false;
  for (int it = 0; it < 100; ++it) {
    double F, G, J[2][2], scale;
    sys.eval(x, y, F, G, J, scale);
    const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    const double residual = std::max(std::abs(F), std::abs(G)) / scale;
    const bool improved = residual < best;
    if (improved) {
      best = residual, best_x = x, best_y = y;
      best_regular = regular(J);
    }
    if (residual == 0.0 || !(std::abs(det) > 1e-300)) break;
    if (stop_in_cluster && improved && !best_regular && best <= kResidual) break;
    const double dx = (J[1][1] * F - J[0][1] * G) / det;
    const double dy = (J[0][0] * G - J[1][0] * F) / det;
    x -= dx;
    y -= dy;
    if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > 4.0 || std::abs(y) > 4.0) break;
    // Quadratic convergence: a step below 1e-10 from the best point, regular and already within
    // the residual bound, leaves an error far below rounding (about the step squared), so the
    // stepped point is taken without evaluating it again.
    if (std::abs(dx) + std::abs(dy) <= 1e-10 && improved && best_regular && best <= kResidual) {
      best_x = x, best_y = y;
      break;
    }
  }
  x = best_x;
  y = best_y;
  singular = !best_regular;
  return best <= kResidual;
}

/// A polynomial in two variables, dense: c[i·(ny + 1) + j] is the coefficient of u^i v^j. Used
/// only at multiple roots (rare), where F, G and their Lie derivatives are expanded about the
/// root, so nothing here is on the fast path.
struct Poly2 {
  int nx = 0, ny = 0;
  std::vector<double> c;

  Poly2(int degree_u, int degree_v)
      : nx(degree_u), ny(degree_v), c(static_cast<std::size_t>((nx + 1) * (ny + 1)), 0.0) {}
  double& at(int i, int j) { return c[static_cast<std::size_t>(i * (ny + 1) + j)]; }
  double at(int i, int j) const { return c[static_cast<std::size_t>(i * (ny + 1) + j)]; }

  /// a + u (along = 0) or a + v (along = 1).
  static Poly2 linear(double a, int along) {
    Poly2 p(along == 0 ? 1 : 0, along == 0 ? 0 : 1);
    p.c[0] = a;
    p.c[1] = 1.0;
    return p;
  }
  static Poly2 constant(double a) {
    Poly2 p(0, 0);
    p.c[0] = a;
    return p;
  }
  /// Value at (u, v): Horner in v inside Horner in u.
  double eval(double u, double v) const {
    double r = 0.0;
    for (int i = nx; i >= 0; --i) {
      double s = 0.0;
      for (int j = ny; j >= 0; --j) s = s * v + at(i, j);
      r = r * u + s;
    }
    return r;
  }
};

Poly2 operator+(const Poly2& a, const Poly2& b) {
  Poly2 r(std::max(a.nx, b.nx), std::max(a.ny, b.ny));
  for (int i = 0; i <= a.nx; ++i) {
    for (int j = 0; j <= a.ny; ++j) r.at(i, j) += a.at(i, j);
  }
  for (int i = 0; i <= b.nx; ++i) {
    for (int j = 0; j <= b.ny; ++j) r.at(i, j) += b.at(i, j);
  }
  return r;
}

Poly2 operator*(double k, Poly2 a) {
  for (double& x : a.c) x *= k;
  return a;
}

Poly2 operator-(const Poly2& a, const Poly2& b) {
  return a + (-1.0) * b;
}

Poly2 operator*(const Poly2& a, const Poly2& b) {
  Poly2 r(a.nx + b.nx, a.ny + b.ny);
  for (int i = 0; i <= a.nx; ++i) {
    for (int j = 0; j <= a.ny; ++j) {
      const double x = a.at(i, j);
      if (x == 0.0) continue;
      for (int k = 0; k <= b.nx; ++k) {
        for (int l = 0; l <= b.ny; ++l) r.at(i + k, j + l) += x * b.at(k, l);
      }
    }
  }
  return r;
}

/// ∂/∂u (along = 0) or ∂/∂v (along = 1).
Poly2 derivative(const Poly2& a, int along) {
  Poly2 r(std::max(a.nx - (along == 0), 0), std::max(a.ny - (along == 1), 0));
  for (int i = 0; i <= a.nx; ++i) {
    for (int j = 0; j <= a.ny; ++j) {
      const int p = along == 0 ? i : j;
      if (p > 0) r.at(i - (along == 0), j - (along == 1)) += p * a.at(i, j);
    }
  }
  return r;
}

/// A root (t1, t2) of the cleared system with its multiplicity (intersection multiplicity of the
/// curves F = 0, G = 0 there).
struct Root {
  double t1 = 0.0, t2 = 0.0;
  int multiplicity = 1;
  /// Roots closer than this are one root: ours are accurate to rounding (regular roots, and
  /// multiple ones refined below), except the distinct roots of a cluster, which Newton on (F, G)
  /// determines only to about ε over their spacing (then a quarter of their spacing).
  double same = 1e-10;
};

/// Where a cluster was resolved: a singular point within `radius` of (t1, t2) belongs to it.
struct ClusterRegion {
  double t1 = 0.0, t2 = 0.0, radius = 0.0;
};

/// Bounds, in units of the rounding unit, of the errors of the constants of ClearedSystem
/// (p = 1 + μ1, q = 1 + μ2, A1, A2) as computed from the data: the terms summed in absolute
/// value, each constant of (2.6) weighted by the condition of its determinants (ulps of error per
/// ulp of the data). They stand for the constants in the bound polynomials of Cluster.
struct Magnitudes {
  double p, q, a1, a2;
};

/// How many ulps of det(a, b) its rounding error can be: (|a.x b.y| + |a.y b.x|) / |det(a, b)|.
double det_condition(Vec2 a, Vec2 b) {
  return (std::abs(a.x * b.y) + std::abs(a.y * b.x)) / std::abs(cross(a, b));
}

Magnitudes magnitudes(const KozakKrajncConstants& k, Vec2 e0, Vec2 e1, Vec2 e2, Vec2 d0, Vec2 d3) {
  // A ratio of two determinants carries the sum of their conditions.
  const double c01 = det_condition(e0, e1), c02 = det_condition(e0, e2);
  const double c12 = det_condition(e1, e2);
  const double m1 = std::abs(k.mu1) * (det_condition(d0, e1) + det_condition(d0, e0));
  const double m2 = std::abs(k.mu2) * (det_condition(e1, d3) + det_condition(e2, d3));
  const double l1 = std::abs(k.lambda1), l2 = std::abs(k.lambda2);
  const double r = std::abs(cross(e1, e2) / cross(e0, e1));  // λ1/λ2
  return {1.0 + m1, 1.0 + m2,
          1.0 + m1 * (1.0 + l1) + std::abs(k.mu1) * l1 * (c02 + c01) + r * (c12 + c01),
          1.0 + m2 * (1.0 + l2) + std::abs(k.mu2) * l2 * (c02 + c12) + (c12 + c01) / r};
}

/// The highest contact order resolved: the resultant Q has degree 9, so no intersection of the
/// curves (2.3) inside the triangle can have a larger multiplicity.
constexpr int kMaxContact = 9;
/// A value vanishes "within rounding" when it is below this many ulps of its rounding bound (the
/// bound polynomial of Cluster at the point: every term in absolute value, with the constants'
/// errors from Magnitudes). Measured at 20 000 exact double and triple roots (tests' families,
/// up to 2^50 in size): at most 0.46, 99.9% below 0.13. Two distinct roots 1e-7 apart give
/// thousands.
constexpr double kVanishUlps = 4.0;
/// A cluster of k roots is resolved at the root of the (k−1)-th derivative only when the Taylor
/// model of degree k is valid well beyond the cluster: its radius (Newton polygon, left of k) at
/// most this fraction of the distance to the next terms' influence (right of k).
constexpr double kClusterGap = 1.0 / 16.0;

/// Resolution of a cluster of roots of the cleared system (a multiple root, or roots closer than
/// Newton on (F, G) can separate). Let B = 0 be one of the curves (F or G, the one whose gradient
/// is better conditioned at the cluster) and H the other. Along the flow of X = (−B_v, B_u), which
/// moves on the level curve of B, the j-th derivative of H is the Lie derivative
///   L_0 = H,  L_{j+1} = X·∇L_j = B_u ∂L_j/∂v − B_v ∂L_j/∂u      (L_1 = ±det J(F, G)),
/// so a root of contact order k is where L_0 = … = L_{k−1} = 0 ≠ L_k: there the system
/// (B, L_{k−1}) has a *simple* root (its Jacobian determinant is L_k), which Newton finds to full
/// precision although (F, G) has a k-fold one. All polynomials are expanded about the starting
/// point (u = t1 − x0, v = t2 − y0), exactly as polynomials, with companion polynomials of the
/// absolute values of every term that bound their rounding errors.
class Cluster {
 public:
  /// `base`: 0 for F, 1 for G, −1 to choose (tests fix it).
  Cluster(const ClearedSystem& sys, const Magnitudes& mag, double x0, double y0, int base = -1)
      : x0_(x0), y0_(y0) {
    const Poly2 X = Poly2::linear(x0, 0), Y = Poly2::linear(y0, 1);
    const Poly2 one = Poly2::constant(1.0);
    const Poly2 F = Y * Y * (one - Y) - (1.0 + sys.mu1) * (X * X * (one - X)) +
                    sys.a1 * ((Y - X) * X * X * Y * Y);
    const Poly2 ux = one - X, uy = one - Y;
    const Poly2 G =
        X * ux * ux - (1.0 + sys.mu2) * (Y * uy * uy) + sys.a2 * ((Y - X) * ux * ux * uy * uy);
    // The same expressions with every subtraction an addition and every constant its bound:
    // coefficientwise at least the absolute values of the terms.
    const Poly2 Xa = Poly2::linear(std::abs(x0), 0), Ya = Poly2::linear(std::abs(y0), 1);
    const Poly2 uxa = one + Xa, uya = one + Ya;
    const Poly2 Fa =
        Ya * Ya * uya + mag.p * (Xa * Xa * uxa) + mag.a1 * ((Ya + Xa) * Xa * Xa * Ya * Ya);
    const Poly2 Ga =
        Xa * uxa * uxa + mag.q * (Ya * uya * uya) + mag.a2 * ((Ya + Xa) * uxa * uxa * uya * uya);
    // The base curve: the one whose gradient is larger relative to its terms (a singular point of
    // one curve would stop the flow).
    auto relative_gradient = [](const Poly2& P, const Poly2& Pa) {
      return std::hypot(P.at(1, 0), P.at(0, 1)) / std::max(Pa.at(0, 0), 1e-300);
    };
    const bool f_base =
        base == 0 || (base < 0 && relative_gradient(F, Fa) >= relative_gradient(G, Ga));
    base_ = f_base ? F : G;
    base_abs_ = f_base ? Fa : Ga;
    bu_ = derivative(base_, 0);
    bv_ = derivative(base_, 1);
    bua_ = derivative(base_abs_, 0);
    bva_ = derivative(base_abs_, 1);
    lie_.push_back(f_base ? G : F);
    lie_abs_.push_back(f_base ? Ga : Fa);
  }

  /// L_j and its bound polynomial.
  const Poly2& lie(int j) {
    extend(j);
    return lie_[static_cast<std::size_t>(j)];
  }
  const Poly2& lie_abs(int j) {
    extend(j);
    return lie_abs_[static_cast<std::size_t>(j)];
  }
  const Poly2& base() const { return base_; }
  const Poly2& base_abs() const { return base_abs_; }

  /// Whether |P(u, v)| is within rounding of zero, given its bound polynomial Pa.
  static bool vanishes(const Poly2& P, const Poly2& Pa, double u, double v) {
    return std::abs(P.eval(u, v)) <=
           kVanishUlps * std::numeric_limits<double>::epsilon() * Pa.eval(std::abs(u), std::abs(v));
  }

  /// Newton's method on (B, L_{k−1}) from the expansion point; the iterate with the smallest
  /// residual (relative to the rounding bounds) is returned in (u, v).
  void solve_derivative_system(int k, double& u, double& v) {
    const Poly2& H = lie(k - 1);
    const Poly2& Ha = lie_abs(k - 1);
    const Poly2 hu = derivative(H, 0), hv = derivative(H, 1);
    u = 0.0, v = 0.0;
    double best = HUGE_VAL, bu = 0.0, bv = 0.0;
    for (int it = 0; it < 60; ++it) {
      const double b = base_.eval(u, v), h = H.eval(u, v);
      const double au = std::abs(u), av = std::abs(v);
      const double residual =
          std::max(std::abs(b) / base_abs_.eval(au, av), std::abs(h) / Ha.eval(au, av));
      if (residual < best) best = residual, bu = u, bv = v;
      if (residual == 0.0) break;
      const double j00 = bu_.eval(u, v), j01 = bv_.eval(u, v);
      const double j10 = hu.eval(u, v), j11 = hv.eval(u, v);
      const double det = j00 * j11 - j01 * j10;
      if (!(std::abs(det) > 0.0)) break;
      const double du = (j11 * b - j01 * h) / det, dv = (j00 * h - j10 * b) / det;
      u -= du;
      v -= dv;
      // Below this a step is rounding noise (t is in (0, 1)); far steps leave the cluster.
      if (!(std::abs(du) + std::abs(dv) > 1e-17) || !(std::abs(u) + std::abs(v) < 1e-2)) break;
    }
    u = bu, v = bv;
  }

  /// The flow vector X = (−B_v, B_u) at (u, v).
  void flow(double u, double v, double& xu, double& xv) const {
    xu = -bv_.eval(u, v);
    xv = bu_.eval(u, v);
  }

  double x0() const { return x0_; }
  double y0() const { return y0_; }

 private:
  void extend(int j) {
    while (static_cast<int>(lie_.size()) <= j) {
      const Poly2& L = lie_.back();
      const Poly2& La = lie_abs_.back();
      lie_.push_back(bu_ * derivative(L, 1) - bv_ * derivative(L, 0));
      lie_abs_.push_back(bua_ * derivative(La, 1) + bva_ * derivative(La, 0));
    }
  }

  double x0_, y0_;
  Poly2 base_{0, 0}, base_abs_{0, 0}, bu_{0, 0}, bv_{0, 0}, bua_{0, 0}, bva_{0, 0};
  std::vector<Poly2> lie_, lie_abs_;
};

/// The real roots s ∈ [−S, S] of c[0] + c[1] s + … + c[k] s^k (starts, not results).
detail::BernsteinRoots model_roots(const double* c, int k, double S) {
  // τ ∈ [0, 1], s = S(2τ − 1): coefficients e_j = c_j S^j of (2τ − 1)^j, expanded in τ, then to
  // Bernstein form b_m = Σ_{i≤m} C(m, i)/C(k, i) a_i.
  double a[kMaxContact + 1] = {}, scale = 0.0;
  double e[kMaxContact + 1];
  for (int j = 0; j <= k; ++j) {
    e[j] = c[j] * std::pow(S, j);
    scale = std::max(scale, std::abs(e[j]));
  }
  for (int j = 0; j <= k; ++j) {
    // (2τ − 1)^j = Σ_i C(j, i) 2^i τ^i (−1)^{j−i}
    double binom = 1.0;
    for (int i = 0; i <= j; ++i) {
      a[i] += e[j] / scale * binom * std::ldexp(1.0, i) * ((j - i) % 2 == 0 ? 1.0 : -1.0);
      binom = binom * (j - i) / (i + 1);
    }
  }
  detail::BernsteinPoly poly;
  poly.degree = k;
  for (int m = 0; m <= k; ++m) {
    double s = 0.0, cm = 1.0, ck = 1.0;  // C(m, i), C(k, i)
    for (int i = 0; i <= m; ++i) {
      s += cm / ck * a[i];
      cm = cm * (m - i) / (i + 1);
      ck = ck * (k - i) / (i + 1);
    }
    poly.b[m] = s;
  }
  detail::BernsteinRoots roots = detail::bernstein_roots(poly, 1e-12);
  for (int i = 0; i < roots.count; ++i) roots.items[i].u = S * (2.0 * roots.items[i].u - 1.0);
  return roots;
}

/// Resolves the cluster of roots of (F, G) around (x0, y0), where Newton on (F, G) met a singular
/// Jacobian, into roots with their multiplicities (appended to `out`); returns the region it
/// covered. The cluster size k is the smallest 2 ≤ k ≤ max_order for which the Taylor model of
/// degree k along the flow, taken at the root of (B, L_{k−1}), holds well beyond the cluster
/// (kClusterGap). If L_0 … L_{k−1} vanish there within rounding, the cluster is one root of
/// multiplicity k at that point, to full precision. Otherwise the model's real roots start Newton
/// on (F, G): distinct close roots (or none, where rounding was not what made the curves touch).
ClusterRegion resolve_cluster(const ClearedSystem& sys, const Magnitudes& mag, double x0, double y0,
                              int max_order, std::vector<Root>& out,
                              std::vector<ClusterRegion>& inner_done) {
  Cluster cl(sys, mag, x0, y0);
  for (int k = 2; k <= max_order; ++k) {
    double u = 0.0, v = 0.0;
    cl.solve_derivative_system(k, u, v);
    // Taylor coefficients c_j = L_j / j! of H along the flow at (u, v), j = 0..k + 2.
    double c[kMaxContact + 3];
    bool exact = true;  // L_0 … L_{k−1} vanish within rounding
    double factorial = 1.0;
    for (int j = 0; j <= k + 2; ++j) {
      if (j > 0) factorial *= j;
      const Poly2& L = cl.lie(j);
      c[j] = L.eval(u, v) / factorial;
      if (j < k) exact = exact && Cluster::vanishes(L, cl.lie_abs(j), u, v);
    }
    if (!(c[k] != 0.0) || !std::isfinite(c[k])) continue;
    double inner = 0.0, outer = HUGE_VAL;  // the Newton polygon's radii left and right of k
    for (int j = 0; j < k; ++j) {
      inner = std::max(inner, std::pow(std::abs(c[j] / c[k]), 1.0 / (k - j)));
    }
    for (int j = k + 1; j <= k + 2; ++j) {
      if (c[j] != 0.0) outer = std::min(outer, std::pow(std::abs(c[k] / c[j]), 1.0 / (j - k)));
    }
    // The values as computed, rounding noise included: near a root of higher order, where Newton
    // on (B, L_{k−1}) stalls, they show a cluster as wide as the model's range.
    if (!(inner <= kClusterGap * outer)) continue;
    const double cx = x0 + u, cy = y0 + v;
    if (exact) {
      out.push_back({cx, cy, k, 1e-9});
      return {cx, cy, 0.0};
    }
    // Distinct roots (or none): the model's real roots, all within twice the inner radius
    // (Fujiwara's bound), start Newton on (F, G).
    double xu = 0.0, xv = 0.0;
    cl.flow(u, v, xu, xv);
    const double speed = std::hypot(xu, xv);  // t-distance per unit of the flow parameter
    const detail::BernsteinRoots starts = model_roots(c, k, 2.0 * inner);
    double spacing = 2.0 * inner;
    for (int i = 1; i < starts.count; ++i) {
      spacing = std::min(spacing, starts.items[i].u - starts.items[i - 1].u);
    }
    const double same = std::max(1e-10, 0.25 * spacing * speed);
    for (int i = 0; i < starts.count; ++i) {
      double x = cx + starts.items[i].u * xu, y = cy + starts.items[i].u * xv;
      bool singular = false;
      if (!polish(sys, x, y, singular, false)) continue;
      // A simple root of the model is a simple root, however close to the others (its Jacobian
      // may still look singular). Model roots that the model itself cannot separate are a
      // smaller cluster inside this one.
      if (starts.items[i].count != 1 && singular && k > 2) {
        // Several starts polish into the same smaller cluster: resolved once (each resolving
        // it again branched again, k! times: a 9-point request took 8 s, issue 18's stress).
        const bool seen = std::any_of(inner_done.begin(), inner_done.end(), [&](const auto& c) {
          return std::hypot(x - c.t1, y - c.t2) <= std::max(c.radius, same);
        });
        if (!seen) inner_done.push_back(resolve_cluster(sys, mag, x, y, k - 1, out, inner_done));
      } else {
        out.push_back({x, y, 1, same});
      }
    }
    return {cx, cy, 3.0 * inner * speed};
  }
  // No order up to max_order shows a cluster (roots at comparable distances, none multiple;
  // not seen in tests): the root Newton reaches, as a simple one.
  double x = x0, y = y0;
  bool singular = false;
  if (polish(sys, x, y, singular, false)) out.push_back({x, y, 1});
  return {x0, y0, 0.0};
}

}  // namespace

namespace {

/// Power of two that brings the largest coordinate of the vectors to size ~1 (exact scaling).
double unit_scale(std::initializer_list<Vec2> vs) {
  double m = 0.0;
  for (Vec2 v : vs) m = std::max({m, std::abs(v.x), std::abs(v.y)});
  int e = 0;
  std::frexp(m, &e);
  return std::ldexp(1.0, -e);
}

KozakKrajncSolutions solve_unit(Point T0, Point T1, Point T2, Point T3, Vec2 d0, Vec2 d3);

}  // namespace

KozakKrajncSolutions kozak_krajnc_solve(Point T0, Point T1, Point T2, Point T3, Vec2 d0, Vec2 d3) {
  for (Vec2 v : {T0, T1, T2, T3, d0, d3}) {
    if (!is_finite(v)) throw Error(ErrorCode::kNonFinite, "kozak-krajnc: non-finite data");
  }
  // The constants (2.6) multiply chord coordinates: solve on data scaled by powers of two
  // (exact) so that nothing overflows or underflows, then scale α and the energy back.
  // Coordinates are scaled with the chords unless that would overflow them.
  double k = unit_scale({T1 - T0, T2 - T1, T3 - T2});
  const double kc = unit_scale({T0, T1, T2, T3});
  if (k > kc * 0x1p1000) k = kc * 0x1p1000;
  const double kd0 = unit_scale({d0}), kd3 = unit_scale({d3});
  KozakKrajncSolutions out = solve_unit(k * T0, k * T1, k * T2, k * T3, kd0 * d0, kd3 * d3);
  // P'(0) = α0·d0: the scaled problem has α̃0·(kd0 d0) = k α0 d0.
  for (int i = 0; i < out.count; ++i) {
    out.items[i].alpha0 *= kd0 / k;
    out.items[i].alpha3 *= kd3 / k;
    out.items[i].energy = out.items[i].energy / k / k;  // k² alone may over/underflow
  }
  return out;
}

namespace {

KozakKrajncSolutions solve_unit(Point T0, Point T1, Point T2, Point T3, Vec2 d0, Vec2 d3) {
  const KozakKrajncConstants k = kozak_krajnc_constants(T0, T1, T2, T3, d0, d3);
  const Vec2 e0 = T1 - T0, e1 = T2 - T1, e2 = T3 - T2;
  const double d01 = cross(e0, e1), d12 = cross(e1, e2);
  const ClearedSystem sys{k.mu1, k.mu2, 1.0 + k.mu1 * (1.0 + k.lambda1) - d12 / d01,
                          1.0 + k.mu2 * (1.0 + k.lambda2) - d01 / d12};

  // Resultant R(t2) = det Bézout(F, G; t1) = t2³(1−t2)³·Q(t2), deg Q ≤ 9: Q's Bernstein
  // coefficients by interpolation at Chebyshev nodes.
  const Interpolation& ip = interpolation();
  double values[kNodes];
  for (int i = 0; i < kNodes; ++i) {
    double f[4], g[4], B[3][3];
    sys.coefficients(ip.node[i], f, g);
    bezout(f, g, B);
    values[i] = det3(B) * ip.weight[i];
  }
  detail::BernsteinPoly q;
  q.degree = kQDegree;
  double qmax = 0.0;
  for (int i = 0; i < kNodes; ++i) {
    double s = 0.0;
    for (int j = 0; j < kNodes; ++j) s += ip.to_bernstein[i][j] * values[j];
    q.b[i] = s;
    qmax = std::max(qmax, std::abs(s));
  }
  if (!(qmax > 0.0) || !std::isfinite(qmax)) {
    throw Error(ErrorCode::kInvalidArgument,
                "kozak-krajnc: the equations (2.3) are degenerate for these data (their "
                "resultant vanishes identically)");
  }
  // Where Q comes within this (relative to its largest coefficient) of zero without changing
  // sign it may have a double root that rounding lifted off the axis: such near tangencies are
  // clusters too (resolved below, where rounding is accounted for). Q's own error reaches
  // ~2e-11 of it at constructed double solutions; 1e-10 here missed 3 more of 3000 of them.
  constexpr double kTouch = 1e-9;
  const detail::BernsteinRoots roots = detail::bernstein_roots(q, 1e-7, kTouch * qmax);

  KozakKrajncSolutions out;
  Root found[detail::BernsteinRoots::kCapacity];
  int nfound = 0;
  // Keeps admissible roots not found before.
  auto keep = [&](const Root& r) {
    if (!(r.t1 > 0.0 && r.t1 < r.t2 && r.t2 < 1.0)) return;
    for (int i = 0; i < nfound; ++i) {
      const double tol = std::max(r.same, found[i].same);
      if (std::abs(found[i].t1 - r.t1) <= tol && std::abs(found[i].t2 - r.t2) <= tol) return;
    }
    if (nfound < detail::BernsteinRoots::kCapacity) found[nfound++] = r;
  };
  std::vector<ClusterRegion> regions;  // clusters resolved so far (rare)
  // Newton from (x, y). A singular Jacobian at the end means a cluster of roots there (a
  // multiple root, or roots Newton cannot separate): resolved into roots with multiplicities,
  // once (other starts that end in it find nothing new).
  auto try_start = [&](double x, double y) {
    bool singular = false;
    if (!polish(sys, x, y, singular)) return;
    if (!singular) return keep({x, y, 1});
    // Clusters are narrow (below 1e-3 even for contact of order 9): one clearly outside the
    // triangle holds no admissible root.
    constexpr double kClusterMargin = 1e-2;
    if (!(x > -kClusterMargin && x < y + kClusterMargin && y < 1.0 + kClusterMargin)) return;
    for (const ClusterRegion& c : regions) {
      if (std::hypot(x - c.t1, y - c.t2) <= c.radius) return;
    }
    std::vector<Root> resolved;
    const Magnitudes mag = magnitudes(k, e0, e1, e2, d0, d3);
    std::vector<ClusterRegion> inner;
    regions.push_back(resolve_cluster(sys, mag, x, y, kMaxContact, resolved, inner));
    for (const Root& r : resolved) keep(r);
  };
  // Q's roots closer than this to a neighbour are treated as a cluster.
  constexpr double kSeparation = 1e-4;
  for (int r = 0; r < roots.count; ++r) {
    const double y0 = roots.items[r].u;
    // Only t1 ∈ (0, t2) can be admissible. At a simple, separated root of Q the common root t1
    // of F(·, t2), G(·, t2) is unique and the Bézout null vector gives it: one Newton start, or
    // none when t1 is clearly outside (0, t2) (most roots of Q). Otherwise (clusters, several
    // common roots) Newton starts at every root of F(·, t2) in [0, t2]: F's own roots do not mix
    // neighbouring roots of Q as the null vector does there.
    const bool separated = roots.items[r].count == 1 &&
                           (r == 0 || y0 - roots.items[r - 1].u > kSeparation) &&
                           (r + 1 == roots.count || roots.items[r + 1].u - y0 > kSeparation);
    double x0 = 0.0;
    if (separated && common_root(sys, y0, x0)) {
      // t1 inherits the error of the root of Q (up to ~1e-8 where Q is ill-conditioned)
      // amplified by up to 1e4 (the rows' angle): a wide margin, the rest is left to Newton.
      constexpr double kMargin = 1e-2;
      if (x0 > -kMargin && x0 < y0 + kMargin) try_start(x0, y0);
      continue;
    }
    const detail::BernsteinRoots starts = fibre_roots(sys, y0);
    for (int s = 0; s < starts.count; ++s) try_start(starts.items[s].u, y0);
  }

  // The residual test compares squared norms (hypot is slow) while the squares of the data can
  // neither overflow nor underflow, else the norms themselves.
  const double size2 = std::max({norm2(e0), norm2(e1), norm2(e2)});
  auto interpolates = [&](Vec2 r1, Vec2 r2) {
    if (size2 > 1e-280 && size2 < 1e280) return std::max(norm2(r1), norm2(r2)) <= 1e-18 * size2;
    return std::max(norm(r1), norm(r2)) <= 1e-9 * std::max({norm(e0), norm(e1), norm(e2)});
  };
  for (int i = 0; i < nfound && out.count < KozakKrajncSolutions::kCapacity; ++i) {
    const double t1 = found[i].t1, t2 = found[i].t2;
    // (2.4), (2.5)
    const double alpha0 =
        k.delta1 * t1 * t2 / (t2 - t1) *
        (1.0 / (t2 * t2 * (1.0 - t2)) - (t2 - t1) / ((1.0 - t1) * (1.0 - t2)) * (1.0 + k.lambda1));
    const double alpha3 =
        k.delta2 * (1.0 - t1) * (1.0 - t2) / (t2 - t1) *
        (1.0 / (t1 * (1.0 - t1) * (1.0 - t1)) - (t2 - t1) / (t1 * t2) * (1.0 + k.lambda2));
    if (!(alpha0 > 0.0 && alpha3 > 0.0)) continue;
    KozakKrajncSolution s;
    s.t1 = t1;
    s.t2 = t2;
    s.alpha0 = alpha0;
    s.alpha3 = alpha3;
    s.multiplicity = found[i].multiplicity;
    const CubicBezier c = kozak_krajnc_bezier(T0, T3, d0, d3, s);
    // Verification by the interpolation residual. The cleared system also vanishes on the
    // boundary of D (e.g. at t1 = t2 = 0), so roots rounding pushed just inside are caught here.
    if (!interpolates(c.eval(t1) - T1, c.eval(t2) - T2)) continue;
    const Vec2 a = c.d2(0.0), b = c.d2(1.0);
    s.energy = (dot(a, a) + dot(a, b) + dot(b, b)) / 3.0;
    out.items[out.count++] = s;
  }
  std::sort(out.items.begin(), out.items.begin() + out.count,
            [](const auto& a, const auto& b) { return a.t1 < b.t1; });
  for (int i = 0; i < out.count; ++i) {
    if (out.chosen < 0 || out.items[i].energy < out.items[out.chosen].energy) out.chosen = i;
  }
  return out;
}

}  // namespace

namespace detail {

std::vector<double> kozak_krajnc_lie_derivatives(double mu1, double mu2, double a1, double a2,
                                                 double t1, double t2, int n) {
  const ClearedSystem sys{mu1, mu2, a1, a2};
  Cluster cl(sys, Magnitudes{1.0, 1.0, 1.0, 1.0}, t1, t2, 0);
  std::vector<double> out;
  for (int j = 0; j <= n; ++j) out.push_back(cl.lie(j).eval(0.0, 0.0));
  return out;
}

}  // namespace detail

}  // namespace fairspline
