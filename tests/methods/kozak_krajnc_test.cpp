// Tests of the Kozak–Krajnc building blocks (src/methods/kozak_krajnc.cpp): Table 3.1's
// constants, the withheld φ values of Section 3, Lemmas 2.1–2.3 as properties, the existence
// predicates of Theorems 2.4 and 2.5 on the paper's data, and the single-piece solver (all
// solutions, multiple ones to full precision with exact multiplicities).
#include "fairspline/methods/kozak_krajnc.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "fairspline/error.hpp"
#include "fairspline/methods/kozak_krajnc_spline.hpp"
#include "fairspline/registry.hpp"
#include "methods/kozak_krajnc_detail.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

// Section 3, Step 1: T0 = (−4, −4), T1 = (0, 0), T2 = (4, 0), T3 = (9 + (−1)^s, (−1)^s 4).
struct PaperData {
  Vec2 d0, d3;
  int s;
};
const PaperData kData[] = {{{2, 3}, {2, -3}, 1}, {{-2, 2}, {-2, -2}, 1}, {{-2, 2}, {-1, 2}, 0}};

KozakKrajncConstants constants_of(const PaperData& d) {
  const double sign = d.s == 1 ? -1.0 : 1.0;
  return kozak_krajnc_constants({-4, -4}, {0, 0}, {4, 0}, {9 + sign, 4 * sign}, d.d0, d.d3);
}

/// The two equations (2.3) and α0 of (2.4), α3 of (2.5), written out independently.
struct System {
  double lambda1, lambda2, mu1, mu2, delta1, delta2;
  double f1(double t1, double t2) const {
    return 1 / (t1 * t1 * (1 - t1)) - (1 + mu1) / (t2 * t2 * (1 - t2)) +
           (t2 - t1) / ((1 - t1) * (1 - t2)) * (1 + mu1 * (1 + lambda1) - lambda1 / lambda2);
  }
  double f2(double t1, double t2) const {
    return 1 / (t2 * (1 - t2) * (1 - t2)) - (1 + mu2) / (t1 * (1 - t1) * (1 - t1)) +
           (t2 - t1) / (t1 * t2) * (1 + mu2 * (1 + lambda2) - lambda2 / lambda1);
  }
  double alpha0(double t1, double t2) const {
    return delta1 * t1 * t2 / (t2 - t1) *
           (1 / (t2 * t2 * (1 - t2)) - (t2 - t1) / ((1 - t1) * (1 - t2)) * (1 + lambda1));
  }
  double alpha3(double t1, double t2) const {
    return delta2 * (1 - t1) * (1 - t2) / (t2 - t1) *
           (1 / (t1 * (1 - t1) * (1 - t1)) - (t2 - t1) / (t1 * t2) * (1 + lambda2));
  }
};

TEST(KozakKrajncConstants, Table31) {
  // λ and μ as printed. δ: the table prints 1 for all data, but δ depends on the length of the
  // tangent (Remark 2.1 says only its sign does not): with the printed d0 = (2, 3),
  // d3 = (2, −3) of data 1, δ1 = D01 / det(d0, ΔT0) = −16 / −4 = 4 (δ = 1 would need
  // d0 = (8, 12)). Data 2 and 3 give δ = 1 as printed. Only the signs enter the theorems.
  const double expected[3][6] = {
      {2, 2, 3, 3, 4, 4}, {2, 2, 0.5, 0.5, 1, 1}, {0.5, -0.5, 0.5, 0.5, 1, 1}};
  for (int k = 0; k < 3; ++k) {
    const KozakKrajncConstants c = constants_of(kData[k]);
    EXPECT_DOUBLE_EQ(c.lambda1, expected[k][0]) << k;
    EXPECT_DOUBLE_EQ(c.lambda2, expected[k][1]) << k;
    EXPECT_DOUBLE_EQ(c.mu1, expected[k][2]) << k;
    EXPECT_DOUBLE_EQ(c.mu2, expected[k][3]) << k;
    EXPECT_DOUBLE_EQ(c.delta1, expected[k][4]) << k;
    EXPECT_DOUBLE_EQ(c.delta2, expected[k][5]) << k;
  }
  // Scaling a tangent scales δ, not μ (Remark 2.1).
  const KozakKrajncConstants c =
      kozak_krajnc_constants({-4, -4}, {0, 0}, {4, 0}, {8, -4}, {8, 12}, {8, -12});
  EXPECT_DOUBLE_EQ(c.delta1, 1.0);
  EXPECT_DOUBLE_EQ(c.mu1, 3.0);
}

TEST(KozakKrajncConstants, WithheldPhiValuesOfSection3) {
  // Data 1 and 2 (λ1 = λ2 = 2): φ1 = φ2 = 2.80828202755131...; data 1 has μ > φ (second case
  // of Theorem 2.4), data 2 has μ < φ (first case).
  for (int k : {0, 1}) {
    const KozakKrajncConstants c = constants_of(kData[k]);
    const double p1 = *kozak_krajnc_phi1(c.lambda1, c.lambda2);
    const double p2 = *kozak_krajnc_phi2(c.lambda1, c.lambda2);
    EXPECT_NEAR(p1, 2.80828202755131, 1e-13);
    EXPECT_NEAR(p2, 2.80828202755131, 1e-13);
    EXPECT_TRUE(kozak_krajnc_theorem_2_4(c));
    EXPECT_FALSE(kozak_krajnc_theorem_2_5(c));
  }
  // Data 3: φ3(1/2, −1/2, 1/2) = 0.25 / (0.5 (1.25 + √1.5)) = 0.2020410288672882 and
  // φ4 = 0.25 · 1.5 / (0.25 · 1.5625) = 0.96, so φ3 < μ2 = 1/2 < φ4 (Theorem 2.5).
  const KozakKrajncConstants c = constants_of(kData[2]);
  EXPECT_NEAR(kozak_krajnc_phi3(c.lambda1, c.lambda2, c.mu1),
              0.25 / (0.5 * (1.25 + std::sqrt(1.5))), 1e-15);
  EXPECT_NEAR(kozak_krajnc_phi4(c.lambda1, c.lambda2, c.mu1), 0.96, 1e-15);
  EXPECT_TRUE(kozak_krajnc_theorem_2_5(c));
  EXPECT_FALSE(kozak_krajnc_theorem_2_4(c));
}

TEST(KozakKrajncLemmas, BoundarySolutionsSolveTheSystemWithAVanishingAlpha) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> lam(0.05, 20), mu(0.1, 10);
  for (int trial = 0; trial < 2000; ++trial) {
    const double l1 = lam(rng), l2 = lam(rng);
    // Lemma 2.1: (t̃1, t̃2) solves (2.7); with μ2 = φ2 it solves (2.3) for every μ1, α0 = 0.
    const ParameterPair s = *kozak_krajnc_boundary_alpha0(l1, l2);
    ASSERT_TRUE(0 < s.t1 && s.t1 < s.t2 && s.t2 < 1) << l1 << " " << l2;
    const double t1 = s.t1, t2 = s.t2;
    ASSERT_NEAR((1 - t1) / (t2 * t2 * (t2 - t1)), 1 + l1, 1e-9 * (1 + l1));
    ASSERT_NEAR((1 - t2) / (t1 * t1 * (t2 - t1)), l1 / l2 * (1 + l2),
                1e-9 * (1 + l1 / l2 * (1 + l2)));
    const System sys{l1, l2, mu(rng), *kozak_krajnc_phi2(l1, l2), 1, 1};
    const double scale = 1 / (t1 * t1 * (1 - t1)) + 1 / (t2 * (1 - t2) * (1 - t2));
    ASSERT_NEAR(sys.f1(t1, t2), 0, 1e-9 * scale);
    ASSERT_NEAR(sys.f2(t1, t2), 0, 1e-9 * scale);
    ASSERT_NEAR(sys.alpha0(t1, t2), 0, 1e-9 * scale);
    // Lemma 2.2: the twin, α3 = 0 with μ1 = φ1.
    const ParameterPair r = *kozak_krajnc_boundary_alpha3(l1, l2);
    ASSERT_TRUE(0 < r.t1 && r.t1 < r.t2 && r.t2 < 1);
    const System twin{l1, l2, *kozak_krajnc_phi1(l1, l2), mu(rng), 1, 1};
    const double scale2 = 1 / (r.t1 * r.t1 * (1 - r.t1)) + 1 / (r.t2 * (1 - r.t2) * (1 - r.t2));
    ASSERT_NEAR(twin.f1(r.t1, r.t2), 0, 1e-9 * scale2);
    ASSERT_NEAR(twin.f2(r.t1, r.t2), 0, 1e-9 * scale2);
    ASSERT_NEAR(twin.alpha3(r.t1, r.t2), 0, 1e-9 * scale2);
    // The symmetry t ↦ 1 − t exchanges the roles: φ1(λ1, λ2) = φ2(λ2, λ1).
    ASSERT_NEAR(*kozak_krajnc_phi1(l1, l2), *kozak_krajnc_phi2(l2, l1),
                1e-12 * (1 + std::abs(*kozak_krajnc_phi1(l1, l2))));
  }
  EXPECT_FALSE(kozak_krajnc_phi2(1, -1));
  EXPECT_FALSE(kozak_krajnc_phi1(-1, 1));
}

TEST(KozakKrajncLemmas, Lemma23Properties) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(0.05, 10), neg(-10, -0.05), mu(0.01, 50);
  for (int trial = 0; trial < 5000; ++trial) {
    const double l1 = pos(rng), l2 = neg(rng), m1 = mu(rng), dm = 1e-3 * m1;
    const double p3 = kozak_krajnc_phi3(l1, l2, m1), p4 = kozak_krajnc_phi4(l1, l2, m1);
    ASSERT_LT(p3, p4);
    ASSERT_GT(kozak_krajnc_phi3(l1, l2, m1 + dm), p3);  // increasing
    ASSERT_GT(kozak_krajnc_phi4(l1, l2, m1 + dm), p4);
    // φ3(λ1, λ2, μ1) = μ2 iff φ4(λ2, λ1, μ2) = μ1 (and the twin).
    ASSERT_NEAR(kozak_krajnc_phi4(l2, l1, p3), m1, 1e-8 * (1 + m1));
    ASSERT_NEAR(kozak_krajnc_phi3(l2, l1, p4), m1, 1e-8 * (1 + m1));
  }
  EXPECT_NEAR(kozak_krajnc_phi3(2, -1, 1e12), 0.5, 1e-5);
  EXPECT_NEAR(kozak_krajnc_phi4(2, -1, 1e12), (1 + 4.0) / 4, 1e-5);
}

TEST(KozakKrajncConstants, DegenerateDataThrows) {
  const Error e = testing::expect_error([] {
    kozak_krajnc_constants({0, 0}, {1, 0}, {2, 0}, {3, 1}, {1, 1}, {1, 1});
  });
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  const Error f = testing::expect_error([] {
    kozak_krajnc_constants({0, 0}, {1, 0}, {2, 1}, {3, 1}, {1, 0}, {1, 1});
  });
  EXPECT_EQ(f.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(std::string(f.what()).find("d0"), std::string::npos);
}

// T2, T3, T4 on the line y = x/3 up to the rounding of their coordinates: the sign of
// det(ΔT2, ΔT3), which sets σ and the tangent cone (4.1) at T3, is noise. The stress inputs
// kozak-krajnc-internal-non_finite-* (walks with such runs) got a cone whose admissible part
// was narrower than an ulp of ξ, and a NaN direction; now they are collinear data.
TEST(KozakKrajncSpline, PointsCollinearToRoundingAreCollinear) {
  auto input = [](double lift) {
    FitInput in;
    in.points = {
        {-1.0, 1.0}, {-0.5, 0.6}, {0.1, 0.1 / 3.0}, {0.7, 0.7 / 3.0}, {1.3, 1.3 / 3.0 + lift},
        {1.9, 0.2},  {2.5, 0.9}};
    return in;
  };
  const std::vector<Point> pts = input(0.0).points;
  const Vec2 a = pts[3] - pts[2], b = pts[4] - pts[3];
  ASSERT_NE(cross(a, b), 0.0);  // not exactly collinear as doubles
  ASSERT_LT(std::abs(cross(a, b)) / (norm(a) * norm(b)), 1e-15);
  const Error e = testing::expect_error([&] { fit("kozak-krajnc", input(0.0), {}); });
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(e.index(), std::optional<std::size_t>(3));
  EXPECT_NE(std::string(e.what()).find("T2, T3, T4 are collinear to within rounding"),
            std::string::npos)
      << e.what();
  // A turn of 1e-9 rad at T3 is resolved: the sweeps run, and the directions (4.1) there come
  // out as unit vectors even where (1 − ξ)u + ξv nearly cancels.
  const FitInput turned = input(1e-9);
  const KozakKrajncSweep sw = kozak_krajnc_sweep(turned.points);
  ASSERT_EQ(sw.xi.size(), 3u);
  const Vec2 u = kozak_krajnc_direction(turned.points, 1, 0.0);
  const Vec2 v = kozak_krajnc_direction(turned.points, 1, 1.0);
  // Where |(1 − ξ)u + ξv| is least: the direction there is normal to u − v.
  const double foot = -dot(u, v - u) / norm2(v - u);
  const Vec2 d = kozak_krajnc_direction(turned.points, 1, foot);
  ASSERT_GT(norm(d), 0.0);
  EXPECT_LT(std::abs(dot(d, v - u)) / (norm(d) * norm(v - u)), 1e-6);
}

/// Largest distance of the piece from T1, T2 at its parameters, relative to the data size.
double interpolation_residual(Point T0, Point T1, Point T2, Point T3, Vec2 d0, Vec2 d3,
                              const KozakKrajncSolution& s) {
  const CubicBezier c = kozak_krajnc_bezier(T0, T3, d0, d3, s);
  const double size = std::max({norm(T1 - T0), norm(T2 - T1), norm(T3 - T2)});
  return std::max(norm(c.eval(s.t1) - T1), norm(c.eval(s.t2) - T2)) / size;
}

TEST(KozakKrajncSolve, Table32) {
  // The withheld Table 3.2, computed here and independently (exact resultants in SymPy,
  // tests/py/test_kozak_krajnc.py). Data 1: the uniform cubic through the symmetric points,
  // a single solution where the curves (2.3) touch with contact order 3 (α for the printed
  // d0 = (2, 3); the table's δ = 1 would divide them by 4), refined to full precision although
  // Newton on (2.3) reaches only ~1e-5 there. Data 2: t = (1 − 1/√3, 1/√3), α = 3 + 3√3.
  // Data 3: one simple solution.
  struct Row {
    double t1, t2, alpha0, alpha3;
    int multiplicity;
    double tol;
  };
  const double r3 = std::sqrt(3.0);
  const Row rows[3] = {
      {1.0 / 3, 2.0 / 3, 6, 6, 3, 1e-14},
      {1 - 1 / r3, 1 / r3, 3 + 3 * r3, 3 + 3 * r3, 1, 1e-13},
      {0.450046590620398, 0.583424586275439, 12.164220336736625, 12.182770956783598, 1, 1e-12}};
  for (int k = 0; k < 3; ++k) {
    const double sign = kData[k].s == 1 ? -1.0 : 1.0;
    const Point T0{-4, -4}, T1{0, 0}, T2{4, 0}, T3{9 + sign, 4 * sign};
    const KozakKrajncSolutions sol = kozak_krajnc_solve(T0, T1, T2, T3, kData[k].d0, kData[k].d3);
    ASSERT_EQ(sol.count, 1) << k;
    const KozakKrajncSolution& s = sol.items[0];
    const Row& r = rows[k];
    EXPECT_NEAR(s.t1, r.t1, r.tol) << k;
    EXPECT_NEAR(s.t2, r.t2, r.tol) << k;
    EXPECT_NEAR(s.alpha0, r.alpha0, r.tol * 100) << k;
    EXPECT_NEAR(s.alpha3, r.alpha3, r.tol * 100) << k;
    EXPECT_EQ(s.multiplicity, r.multiplicity) << k;
    EXPECT_EQ(sol.total_multiplicity() % 2, 1) << k;  // odd, as Step 1 of Section 3 says
    EXPECT_EQ(sol.chosen, 0);
    EXPECT_LT(interpolation_residual(T0, T1, T2, T3, kData[k].d0, kData[k].d3, s), r.tol) << k;
  }
}

/// Relative error of a solution against the constructed one (t1, t2, α0 = α3 = 1).
double constructed_error(const KozakKrajncSolution& s, double t1, double t2) {
  return std::max({std::abs(s.t1 / t1 - 1), std::abs(s.t2 / t2 - 1), std::abs(s.alpha0 - 1),
                   std::abs(s.alpha3 - 1)});
}

/// The solution nearest to (t1, t2), or nullptr when none is within 1e-3.
const KozakKrajncSolution* nearest(const KozakKrajncSolutions& sol, double t1, double t2) {
  const KozakKrajncSolution* best = nullptr;
  for (const KozakKrajncSolution& s : sol) {
    const double d = std::abs(s.t1 - t1) + std::abs(s.t2 - t2);
    if (d < 1e-3 && (!best || d < std::abs(best->t1 - t1) + std::abs(best->t2 - t2))) best = &s;
  }
  return best;
}

TEST(KozakKrajncSolve, LieDerivativesOfTheClearedSystem) {
  // The polynomials the solver forms at multiple solutions, checked numerically: L_0 = G, L_1 =
  // F_t1 G_t2 − F_t2 G_t1, and L_{j+1} the derivative of L_j along X = (−F_t2, F_t1), by central
  // differences of F and G written out here and of L_j itself.
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> c(-3, 3), t(0.1, 0.9);
  for (int trial = 0; trial < 200; ++trial) {
    const double m1 = c(rng), m2 = c(rng), a1 = c(rng), a2 = c(rng);
    auto F = [&](double x, double y) {
      return y * y * (1 - y) - (1 + m1) * x * x * (1 - x) + a1 * (y - x) * x * x * y * y;
    };
    auto G = [&](double x, double y) {
      return x * (1 - x) * (1 - x) - (1 + m2) * y * (1 - y) * (1 - y) +
             a2 * (y - x) * (1 - x) * (1 - x) * (1 - y) * (1 - y);
    };
    const double x = t(rng), y = t(rng), h = 1e-6;
    const std::vector<double> L = detail::kozak_krajnc_lie_derivatives(m1, m2, a1, a2, x, y, 4);
    ASSERT_EQ(L.size(), 5u);
    EXPECT_NEAR(L[0], G(x, y), 1e-14 * (1 + std::abs(L[0])));
    const double Fx = (F(x + h, y) - F(x - h, y)) / (2 * h),
                 Fy = (F(x, y + h) - F(x, y - h)) / (2 * h);
    const double Gx = (G(x + h, y) - G(x - h, y)) / (2 * h),
                 Gy = (G(x, y + h) - G(x, y - h)) / (2 * h);
    EXPECT_NEAR(L[1], Fx * Gy - Fy * Gx, 1e-7 * (1 + std::abs(L[1]))) << trial;
    // Along the flow: a step s·X with |s·X| = 1e-5.
    const double s = 1e-5 / std::hypot(Fx, Fy);
    const std::vector<double> Lp =
        detail::kozak_krajnc_lie_derivatives(m1, m2, a1, a2, x - s * Fy, y + s * Fx, 3);
    const std::vector<double> Lm =
        detail::kozak_krajnc_lie_derivatives(m1, m2, a1, a2, x + s * Fy, y - s * Fx, 3);
    for (int j = 0; j < 4; ++j) {
      EXPECT_NEAR((Lp[j] - Lm[j]) / (2 * s), L[j + 1], 1e-6 * (1 + std::abs(L[j + 1])))
          << trial << " j " << j;
    }
  }
  // At paper data 1 (a parabola): L_0 = L_1 = L_2 = 0 ≠ L_3 at (1/3, 2/3), contact of order 3.
  const KozakKrajncConstants k =
      kozak_krajnc_constants({-4, -4}, {0, 0}, {4, 0}, {8, -4}, {2, 3}, {2, -3});
  const std::vector<double> L = detail::kozak_krajnc_lie_derivatives(
      k.mu1, k.mu2, 1 + k.mu1 * (1 + k.lambda1) - k.lambda1 / k.lambda2,
      1 + k.mu2 * (1 + k.lambda2) - k.lambda2 / k.lambda1, 1.0 / 3, 2.0 / 3, 3);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(L[j], 0.0, 1e-13) << j;  // rounding; L_3 = 1024/81
  EXPECT_GT(std::abs(L[3]), 1e-3);
}

TEST(KozakKrajncSolve, TripleRootsOfParabolasToFullPrecision) {
  // Four points of a parabola at parameters 0 < t1 < t2 < 1 with its end derivatives: (t1, t2)
  // solves (2.3) with α0 = α3 = 1, and the curves (2.3) have contact of order exactly 3 there for
  // every 0 < t1 < t2 < 1 (SymPy, exactly, for P(t) = (t, t²): the Lie derivatives L0 = L1 = L2 =
  // 0 and L3 = −48 t1⁴ t2⁷ (t1 − 1)⁴ (t1 − t2)⁹ (t2 − 1)⁵ (t1 − t2 − 1)⁴ · const ≠ 0; the
  // constants (2.6) are affine invariants, so every parabola gives the same system). Data 1 is
  // one. Random parabolas: integer affine images of P(t) = (3t, 3t²) (control points (0, 0),
  // (1, 0), (2, 1), (3, 3)), t = k/64: every coordinate is exact in double.
  std::mt19937_64 rng(29);
  std::uniform_int_distribution<int> coef(-9, 9), offset(-500, 500), k(4, 60);
  const int base[4][2] = {{0, 0}, {1, 0}, {2, 1}, {3, 3}};
  double worst = 0;
  int cases = 0;
  while (cases < 400) {
    const int a = coef(rng), b = coef(rng), c = coef(rng), d = coef(rng);
    if (a * d - b * c == 0) continue;
    const int ox = offset(rng), oy = offset(rng);
    int k1 = k(rng), k2 = k(rng);
    if (k1 == k2) continue;
    if (k1 > k2) std::swap(k1, k2);
    long long ctrl[4][2];
    for (int i = 0; i < 4; ++i) {
      ctrl[i][0] = a * base[i][0] + b * base[i][1] + ox;
      ctrl[i][1] = c * base[i][0] + d * base[i][1] + oy;
    }
    // P(j/64) = Σ C(3,i) j^i (64 − j)^(3−i) b_i / 64³, in integers.
    auto at = [&](int j) {
      const long long w[4] = {(64 - j) * (64 - j) * (64 - j), 3LL * j * (64 - j) * (64 - j),
                              3LL * j * j * (64 - j), 1LL * j * j * j};
      long long x = 0, y = 0;
      for (int i = 0; i < 4; ++i) x += w[i] * ctrl[i][0], y += w[i] * ctrl[i][1];
      return Point{static_cast<double>(x) / 262144, static_cast<double>(y) / 262144};
    };
    const Point T0 = at(0), T1 = at(k1), T2 = at(k2), T3 = at(64);
    const Vec2 d0{3.0 * (ctrl[1][0] - ctrl[0][0]), 3.0 * (ctrl[1][1] - ctrl[0][1])};
    const Vec2 d3{3.0 * (ctrl[3][0] - ctrl[2][0]), 3.0 * (ctrl[3][1] - ctrl[2][1])};
    const double t1 = k1 / 64.0, t2 = k2 / 64.0;
    const KozakKrajncSolutions sol = kozak_krajnc_solve(T0, T1, T2, T3, d0, d3);
    const KozakKrajncSolution* s = nearest(sol, t1, t2);
    ASSERT_NE(s, nullptr) << "parabola " << a << " " << b << " " << c << " " << d << ", t = " << t1
                          << ", " << t2 << ": the triple solution is missing";
    EXPECT_EQ(s->multiplicity, 3) << t1 << " " << t2;
    const double e = constructed_error(*s, t1, t2);
    EXPECT_LE(e, 1e-12) << "parabola " << a << " " << b << " " << c << " " << d << ", t = " << t1
                        << ", " << t2;
    worst = std::max(worst, e);
    ++cases;
  }
  std::printf("triple roots: worst relative error of t1, t2, alpha0, alpha3: %.2g\n", worst);
}

TEST(KozakKrajncSolve, DoubleRootsToFullPrecision) {
  // Data of cubics built to make (t1, t2) a root of multiplicity exactly 2 (checked in exact
  // arithmetic by tests/py/make_kozak_krajnc_double_roots.py, which generated the table).
  struct Case {
    Vec2 v[6];  // T0..T3, d0, d3
    double t1, t2;
  };
  const Case cases[] = {
#include "methods/kozak_krajnc_double_roots.inc"
  };
  double worst = 0;
  for (const Case& c : cases) {
    const KozakKrajncSolutions sol =
        kozak_krajnc_solve(c.v[0], c.v[1], c.v[2], c.v[3], c.v[4], c.v[5]);
    const KozakKrajncSolution* s = nearest(sol, c.t1, c.t2);
    ASSERT_NE(s, nullptr) << "t = " << c.t1 << ", " << c.t2 << ": the double solution is missing";
    EXPECT_EQ(s->multiplicity, 2) << c.t1 << " " << c.t2;
    const double e = constructed_error(*s, c.t1, c.t2);
    EXPECT_LE(e, 1e-12) << "t = " << c.t1 << ", " << c.t2;
    worst = std::max(worst, e);
  }
  std::printf("double roots: worst relative error of t1, t2, alpha0, alpha3: %.2g\n", worst);
}

TEST(KozakKrajncSolve, CloseSolutionsAreToldApartFromADoubleOne) {
  // Paper data 1 with d0 = (2, 3.05), d3 = (2, −3.0302332169562578) lies next to a fold: two
  // simple solutions 4.3e-6 apart (exact SymPy reference, 60 digits), besides a third one. A
  // solver that sees only a singular Jacobian reports them as one double solution.
  const KozakKrajncSolutions sol =
      kozak_krajnc_solve({-4, -4}, {0, 0}, {4, 0}, {8, -4}, {2, 3.05}, {2, -3.0302332169562578});
  const double ref[3][2] = {{0.24361305761751832, 0.5331846203292666},
                            {0.39426073826876264, 0.71487955541881104},
                            {0.39426507649803838, 0.71488251180839987}};
  ASSERT_EQ(sol.count, 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(sol.items[i].multiplicity, 1) << i;
    // The pair is ill-conditioned (sine of the curves' angle 8.5e-7): ε / 8.5e-7 ≈ 3e-10.
    EXPECT_NEAR(sol.items[i].t1, ref[i][0], 1e-9) << i;
    EXPECT_NEAR(sol.items[i].t2, ref[i][1], 1e-9) << i;
  }
}

/// Random four points and end directions near a smooth curve, so that admissible data are common.
struct RandomPiece {
  Point T[4];
  Vec2 d0, d3;
};
RandomPiece random_piece(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  RandomPiece p;
  double angle = u(rng) * 3.14159, x = 0, y = 0;
  const double turn = 1.2 * u(rng);
  for (int i = 0; i < 4; ++i) {
    p.T[i] = {x, y};
    const double len = 0.3 + std::abs(u(rng));
    angle += turn + 0.6 * u(rng);
    x += len * std::cos(angle);
    y += len * std::sin(angle);
  }
  const Vec2 c0 = p.T[1] - p.T[0], c2 = p.T[3] - p.T[2];
  auto rotate = [](Vec2 v, double a) {
    return Vec2{v.x * std::cos(a) - v.y * std::sin(a), v.x * std::sin(a) + v.y * std::cos(a)};
  };
  p.d0 = rotate(c0, 1.2 * u(rng));
  p.d3 = rotate(c2, 1.2 * u(rng));
  return p;
}

/// The constants of a sample, or nullopt when they are undefined (collinear chords etc.).
std::optional<KozakKrajncConstants> try_constants(const RandomPiece& p) {
  try {
    return kozak_krajnc_constants(p.T[0], p.T[1], p.T[2], p.T[3], p.d0, p.d3);
  } catch (const Error&) {
    return std::nullopt;
  }
}

TEST(KozakKrajncSolve, EverySolutionInterpolatesAndTheoremsGiveAnOddCount) {
  std::mt19937_64 rng(11);
  int with_theorem = 0, multiple = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const RandomPiece p = random_piece(rng);
    const auto constants = try_constants(p);
    if (!constants) continue;  // degenerate sample
    const KozakKrajncConstants& c = *constants;
    const KozakKrajncSolutions sol = kozak_krajnc_solve(p.T[0], p.T[1], p.T[2], p.T[3], p.d0, p.d3);
    for (const KozakKrajncSolution& s : sol) {
      ASSERT_TRUE(0 < s.t1 && s.t1 < s.t2 && s.t2 < 1 && s.alpha0 > 0 && s.alpha3 > 0);
      ASSERT_LT(interpolation_residual(p.T[0], p.T[1], p.T[2], p.T[3], p.d0, p.d3, s), 1e-12)
          << trial << " " << c.lambda1 << " " << c.lambda2 << " " << c.mu1 << " " << c.mu2 << " "
          << c.delta1 << " " << c.delta2 << " t " << s.t1 << " " << s.t2 << " a " << s.alpha0 << " "
          << s.alpha3 << " m " << s.multiplicity;
    }
    if (sol.count > 1) ++multiple;
    if (kozak_krajnc_theorem_2_4(c) || kozak_krajnc_theorem_2_5(c)) {
      ++with_theorem;
      ASSERT_GE(sol.count, 1) << trial << " " << c.lambda1 << " " << c.lambda2 << " " << c.mu1
                              << " " << c.mu2 << " " << c.delta1 << " " << c.delta2;
      ASSERT_EQ(sol.total_multiplicity() % 2, 1)
          << trial << " " << c.lambda1 << " " << c.lambda2 << " " << c.mu1 << " " << c.mu2
          << " count " << sol.count << " t " << sol.items[0].t1 << " " << sol.items[0].t2 << " m "
          << sol.items[0].multiplicity << " t' " << sol.items[1].t1 << " " << sol.items[1].t2
          << " m " << sol.items[1].multiplicity;
    }
  }
  EXPECT_GT(with_theorem, 3000);
  EXPECT_GT(multiple, 10);  // several admissible solutions do occur; all are reported
}

/// Data with prescribed constants (2.6): T0 = 0, ΔT0 = (1, 0), ΔT1 = (a, 1), ΔT2 = (c, λ1) with
/// c = aλ1 − λ1/λ2, then d0 and d3 solved from μ and δ (the free shear `a` varies the shape).
RandomPiece piece_from_constants(double l1, double l2, double m1, double m2, double de1, double de2,
                                 double a) {
  RandomPiece p;
  const double e = l1, c = a * l1 - l1 / l2, d12 = l1 / l2;
  p.T[0] = {0, 0};
  p.T[1] = {1, 0};
  p.T[2] = p.T[1] + Vec2{a, 1};
  p.T[3] = p.T[2] + Vec2{c, e};
  const double q = -1 / de1;
  p.d0 = {q * (a - m1), q};
  // [−e c; −1 a](r, s) = (K, μ2 K) with K = D12/δ2.
  const double K = d12 / de2, det = c - e * a;
  p.d3 = {(a * K - c * m2 * K) / det, (-e * m2 * K + K) / det};
  return p;
}

TEST(KozakKrajncSolve, PieceFromConstantsRoundTrips) {
  const RandomPiece p = piece_from_constants(1.5, -0.7, 2.5, 0.3, 0.8, -1.9, 0.4);
  const KozakKrajncConstants c = kozak_krajnc_constants(p.T[0], p.T[1], p.T[2], p.T[3], p.d0, p.d3);
  EXPECT_NEAR(c.lambda1, 1.5, 1e-14);
  EXPECT_NEAR(c.lambda2, -0.7, 1e-14);
  EXPECT_NEAR(c.mu1, 2.5, 1e-14);
  EXPECT_NEAR(c.mu2, 0.3, 1e-14);
  EXPECT_NEAR(c.delta1, 0.8, 1e-14);
  EXPECT_NEAR(c.delta2, -1.9, 1e-14);
}

TEST(KozakKrajncSolve, TheoremsAndTable33AdmitAnOddNumberOfSolutions) {
  // Theorems 2.4, 2.5 and every row of Table 3.3 (stated without proof in the paper), on data
  // sampled directly in the constants' space.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> lam(0.05, 8), mu(-8, 8), del(0.1, 4), shear(-2, 2),
      coin(0, 1);
  int hits[11] = {};
  for (int trial = 0; trial < 150000; ++trial) {
    const double l1 = lam(rng) * (coin(rng) < 0.5 ? -1 : 1);
    const double l2 = lam(rng) * (coin(rng) < 0.5 ? -1 : 1);
    const double de1 = del(rng) * (coin(rng) < 0.2 ? -1 : 1);
    const double de2 = del(rng) * (coin(rng) < 0.2 ? -1 : 1);
    const RandomPiece p = piece_from_constants(l1, l2, mu(rng), mu(rng), de1, de2, shear(rng));
    const KozakKrajncConstants c =
        kozak_krajnc_constants(p.T[0], p.T[1], p.T[2], p.T[3], p.d0, p.d3);
    int which = kozak_krajnc_table_3_3(c);
    if (kozak_krajnc_theorem_2_4(c)) which = 9;
    if (kozak_krajnc_theorem_2_5(c)) which = 10;
    if (which == 0) continue;
    ++hits[which];
    const KozakKrajncSolutions sol = kozak_krajnc_solve(p.T[0], p.T[1], p.T[2], p.T[3], p.d0, p.d3);
    ASSERT_EQ(sol.total_multiplicity() % 2, 1)
        << "case " << which << ": " << c.lambda1 << " " << c.lambda2 << " " << c.mu1 << " " << c.mu2
        << " " << c.delta1 << " " << c.delta2 << " count " << sol.count;
  }
  for (int which = 1; which <= 10; ++which) {
    EXPECT_GT(hits[which], 50) << which;  // every case exercised
  }
  std::printf("cases hit:");
  for (int which = 1; which <= 10; ++which) std::printf(" %d", hits[which]);
  std::printf("\n");
}

/// Brute force: Newton on (2.3) from a 24×24 grid of starts in the triangle 0 < t1 < t2 < 1.
std::vector<ParameterPair> brute_force(const KozakKrajncConstants& c) {
  const System sys{c.lambda1, c.lambda2, c.mu1, c.mu2, c.delta1, c.delta2};
  std::vector<ParameterPair> found;
  const int n = 24;
  for (int i = 1; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      double x = double(i) / n, y = double(j) / n;
      bool ok = false;
      for (int it = 0; it < 60; ++it) {
        const double h = 1e-7;
        const double f = sys.f1(x, y), g = sys.f2(x, y);
        const double fx = (sys.f1(x + h, y) - sys.f1(x - h, y)) / (2 * h);
        const double fy = (sys.f1(x, y + h) - sys.f1(x, y - h)) / (2 * h);
        const double gx = (sys.f2(x + h, y) - sys.f2(x - h, y)) / (2 * h);
        const double gy = (sys.f2(x, y + h) - sys.f2(x, y - h)) / (2 * h);
        const double det = fx * gy - fy * gx;
        if (det == 0 || !std::isfinite(det)) break;
        const double dx = (gy * f - fy * g) / det, dy = (fx * g - gx * f) / det;
        x -= dx, y -= dy;
        if (!(x > 1e-6 && x < y - 1e-9 && y < 1 - 1e-6)) break;
        if (std::abs(dx) + std::abs(dy) < 1e-13) {
          ok = true;
          break;
        }
      }
      if (!ok || !(sys.alpha0(x, y) > 1e-9 && sys.alpha3(x, y) > 1e-9)) continue;
      found.push_back({x, y});
    }
  }
  return found;
}

TEST(KozakKrajncSolve, BruteForceFindsNothingTheSolverMissed) {
  std::mt19937_64 rng(13);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const RandomPiece p = random_piece(rng);
    const auto constants = try_constants(p);
    if (!constants) continue;  // degenerate sample
    const KozakKrajncConstants& c = *constants;
    const KozakKrajncSolutions sol = kozak_krajnc_solve(p.T[0], p.T[1], p.T[2], p.T[3], p.d0, p.d3);
    for (const ParameterPair& b : brute_force(c)) {
      bool matched = false;
      for (const KozakKrajncSolution& s : sol) {
        matched = matched || (std::abs(s.t1 - b.t1) < 1e-6 && std::abs(s.t2 - b.t2) < 1e-6);
      }
      ASSERT_TRUE(matched) << "trial " << trial << ": brute force found (" << b.t1 << ", " << b.t2
                           << "), solver has " << sol.count;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

// Issue 18: a G2 request whose directions are all prescribed has no equation left ((1.4) is not
// asked at a prescribed breakpoint): it is met as it stands, not a solver failure (stress input
// s18-c10785, one piece with both end tangents).
TEST(KozakKrajncG2, EveryDirectionPrescribedIsConvergedWithNothingToSolve) {
  FitInput in;
  in.points = {{0.0, 0.0},
               {2.3975812885594427, -0.056015887274671744},
               {2.4283445390940077, -0.07134440355761573},
               {2.7597342164590533, -0.18841968218413532}};
  in.start_tangent = Vec2{0.41260279825332263, 0.910911044434926};
  in.end_tangent = Vec2{0.926533724753417, 0.3762117181781549};
  const FitResult r = fit("kozak-krajnc", in, {{"g2", true}});
  const auto& g2 = r.method_report.at("g2");
  EXPECT_TRUE(g2.at("converged").get<bool>());
  EXPECT_EQ(g2.at("iterations").get<int>(), 0);
  EXPECT_EQ(g2.at("max_scaled_curvature_jump").get<double>(), 0.0);
  ASSERT_TRUE(r.solver.has_value());
  EXPECT_EQ(r.solver->status, SolverStatus::kConverged);
}

// Issue 18: with m = 2, (1.4) is one equation in ξ1 between the tangent rule's end directions.
// For these stress inputs the scaled curvature jump at T3 keeps one sign over every admissible
// ξ1 (and every pair of piece solutions) and is least where a piece loses its solutions, which is
// where Newton stalled: no G2 spline exists, and the method says so.
TEST(KozakKrajncG2, NoG2SolutionForTheRuleEndsIsInfeasibleAtT3) {
  struct Case {
    std::vector<Point> points;
    std::optional<double> gamma;
    const char* sign;
    double least;  // the smallest |jump| the best effort's Newton reached
  };
  const std::vector<Case> cases = {
      // s18-m60-c10026: jump > 0.0822 over ξ1 ∈ (0.1966, 1).
      {{{16.79260776217467, 4.5224953865183615},
        {14.053155255863352, 13.424506462019568},
        {-10.622292009804795, 16.92347881129812},
        {-16.8057001744249, 9.682971794866532},
        {-27.587191661201164, -8.60098129696809},
        {1.453246430590698, -19.103520270226674},
        {22.15421240336348, -15.20651805137946}},
       0.25068270114528285,
       "positive",
       0.08},
      // s18-m60-c10362: jump < −0.0069 over ξ1 ∈ (0, 0.8216).
      {{{4.037373776042581, 1.4790215691345368},
        {1.7061602396765643, 5.153988170429556},
        {-0.46962532756514275, 5.736252055742903},
        {-3.9449111822866896, 1.6152048450533756},
        {-5.3884002766989525, -1.2469957596820735},
        {0.42064025661080506, -4.411853981702633},
        {3.188472183631618, -3.187197335474888}},
       std::nullopt,
       "negative",
       0.0068},
      // s18-m60-c5065: the left piece nearly cusps at T3, jump ≈ 4.9e16 over ξ1 ∈ (0, 0.014).
      {{{0.0, 0.0},
        {-0.2114327593785952, 1.3966389247475395},
        {-1.2750744579027604, 16.395759799159062},
        {-1.2890247706630324, 16.89951940855364},
        {-1.2557539811100293, 17.04500769345589},
        {4.839657314079917, 43.699347575095},
        {4.856063044916242, 43.77108752266513}},
       0.8394914730501765,
       "positive",
       4e16},
  };
  for (const Case& c : cases) {
    FitInput in;
    in.points = c.points;
    nlohmann::json o = {{"g2", true}};
    if (c.gamma) o["gamma"] = *c.gamma;
    const Error e = testing::expect_error([&] { fit("kozak-krajnc", in, o); });
    EXPECT_EQ(e.code(), ErrorCode::kInfeasible) << e.what();
    EXPECT_EQ(e.index(), std::optional<std::size_t>(3));
    const std::string what = e.what();
    EXPECT_NE(what.find("no G2 spline"), std::string::npos) << what;
    EXPECT_NE(what.find(std::string("keeps ") + c.sign + " sign"), std::string::npos) << what;
    EXPECT_NE(what.find("at the edge of the admissible"), std::string::npos) << what;
    // The best effort returns the G1 spline, its jump at T3 no smaller than the scan's bound.
    const FitResult g1 = fit("kozak-krajnc", in, o, FitOptions{.best_effort = true});
    const auto& g2 = g1.method_report.at("g2");
    EXPECT_FALSE(g2.at("converged").get<bool>());
    EXPECT_GT(g2.at("max_scaled_curvature_jump").get<double>(), c.least);
  }
}

}  // namespace
}  // namespace fairspline
