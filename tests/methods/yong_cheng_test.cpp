// Tests of the Yong–Cheng method (src/methods/yong_cheng.cpp): Theorem 2 against a direct
// minimization and quadrature, Theorems 3 and 4 as properties, the Fig. 5, 7 and 13 examples,
// coverage of the whole (θ, φ) torus by the dispatcher with Theorem 4's conditions on every
// piece, the paper's applicable regions of every M_i^s, equivariance under similarity
// transforms, reflection and reversal, and the spline-level method with its options and errors.
#include "fairspline/methods/yong_cheng.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "fairspline/diagnostics.hpp"
#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

using testing::random_walk;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

/// fn throws Error with `code` and a message containing `part`.
template <typename F>
void expect_error(ErrorCode code, F&& fn, const std::string& part = "") {
  testing::expect_error(code, std::forward<F>(fn), {part});
}

// ---- independent references ----

/// ∫_0^1 |Q''|² dt by 5-point Gauss–Legendre (exact for the quadratic integrand) on [t0, t1].
double strain_energy_quadrature(const CubicBezier& b, double h) {
  static const double x[] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                             0.9061798459386640};
  static const double w[] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                             0.2369268850561891, 0.2369268850561891};
  double sum = 0.0;
  for (int k = 0; k < 5; ++k) {
    const Vec2 q = b.d2(0.5 * (x[k] + 1.0)) / (h * h);  // d²/dt² = d²/du² / h²
    sum += 0.5 * w[k] * norm2(q);
  }
  return sum * h;
}

/// Minimizer of the quadratic f(a0, a1) from six samples (finite differences; exact for a
/// quadratic up to rounding), independent of formula (4).
std::pair<double, double> minimize_quadratic(const std::function<double(double, double)>& f) {
  const double s = 0.5;
  const double f00 = f(0, 0), fp0 = f(s, 0), fm0 = f(-s, 0), f0p = f(0, s), f0m = f(0, -s),
               fpp = f(s, s);
  const double gx = (fp0 - fm0) / (2 * s), gy = (f0p - f0m) / (2 * s);
  const double hxx = (fp0 - 2 * f00 + fm0) / (s * s), hyy = (f0p - 2 * f00 + f0m) / (s * s);
  const double hxy = (fpp - fp0 - f0p + f00) / (s * s);
  const double det = hxx * hyy - hxy * hxy;
  return {-(hyy * gx - hxy * gy) / det, -(hxx * gy - hxy * gx) / det};
}

/// min over u ∈ [0, 1] of x'(u) / |chord|² in the piece's chord frame (Theorem 4's x'(t) > 0),
/// exact for the quadratic.
double min_chordwise_speed(const CubicBezier& b) {
  const Vec2 c = b.p[3] - b.p[0];
  const double h0 = dot(b.p[1] - b.p[0], c), h1 = dot(b.p[2] - b.p[1], c),
               h2 = dot(b.p[3] - b.p[2], c);
  double m = std::min(h0, h2);
  const double den = h0 - 2 * h1 + h2;
  if (den != 0.0) {
    const double u = (h0 - h1) / den;
    if (u > 0 && u < 1) m = std::min(m, (1 - u) * (1 - u) * h0 + 2 * u * (1 - u) * h1 + u * u * h2);
  }
  return 3 * m / norm2(c);
}

/// Unit vector at angle a, exact at multiples of 90°.
Vec2 dir(double a) {
  const double q = a / (kPi / 2);
  if (q == std::round(q)) {
    static const Vec2 k[] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    return k[static_cast<int>(((static_cast<long>(std::round(q)) % 4) + 4) % 4)];
  }
  return from_angle(a);
}

/// Checks of one COH curve for end data (P0, P1, V0, V1): interpolation, the given directions
/// at the ends, G1 joints, Theorem 4 on every piece. Returns an empty string or the failure.
std::string check_coh(const CohCurve& c, Point p0, Point p1, Vec2 v0, Vec2 v1) {
  const double scale = norm(p1 - p0);
  // Absolute rounding of the control points grows with the coordinates' magnitude.
  const double mag =
      1e-14 * std::max({scale, std::abs(p0.x), std::abs(p0.y), std::abs(p1.x), std::abs(p1.y)});
  if (!(c.count >= 1 && c.count <= 3)) return "bad count";
  if (!(norm(c.pieces[0].p[0] - p0) <= 1e-12 * scale)) return "start point";
  if (!(norm(c.pieces[c.count - 1].p[3] - p1) <= 1e-12 * scale)) return "end point";
  const Vec2 l0 = c.pieces[0].p[1] - c.pieces[0].p[0];
  const Vec2 l1 = c.pieces[c.count - 1].p[3] - c.pieces[c.count - 1].p[2];
  if (!(std::abs(cross(l0, v0)) <= (1e-12 * norm(l0) + mag) * norm(v0) && dot(l0, v0) > 0)) {
    return "start direction not preserved";
  }
  if (!(std::abs(cross(l1, v1)) <= (1e-12 * norm(l1) + mag) * norm(v1) && dot(l1, v1) > 0)) {
    return "end direction not preserved";
  }
  for (int k = 0; k + 1 < c.count; ++k) {
    if (!(norm(c.pieces[k].p[3] - c.pieces[k + 1].p[0]) <= 1e-12 * scale)) return "joint gap";
    // Directions of legs of length ℓ carry a rounding of about mag/ℓ radians.
    const double leg = std::min(norm(c.pieces[k].p[3] - c.pieces[k].p[2]),
                                norm(c.pieces[k + 1].p[1] - c.pieces[k + 1].p[0]));
    const double tol_deg = 1e-9 + 120 * mag / leg;
    if (!(tangent_angle_jump_deg(c.pieces[k], c.pieces[k + 1]) < tol_deg)) return "G1 joint";
  }
  for (int k = 0; k < c.count; ++k) {
    if (!(c.coefficients[k].a0 > 0 && c.coefficients[k].a1 > 0)) return "coefficient <= 0";
    if (!(min_chordwise_speed(c.pieces[k]) > 0)) return "x'(t) not positive";
  }
  if (!(coh_min_margin(c) > 0)) return "cos <= 1/3";
  if (!c.preserved) return "preserved flag";
  return "";
}

// ---- Theorem 2 ----

TEST(YongChengOgh, Fig5ExampleCoefficientsAndShape) {
  // t ∈ [0, 2], P0 = (−1, 1), P1 = (1, 1), V0 = (3, −2), V1 = (3, 2). By (4):
  // d·V0 = d·V1 = 6, V0·V1 = 5, |V0|² = |V1|² = 13: a* = (6·6·13 − 3·6·5)/((4·169 − 25)·2) = 9/31.
  const Point p0{-1, 1}, p1{1, 1};
  const Vec2 v0{3, -2}, v1{3, 2};
  const OghCoefficients a = ogh_coefficients(p0, p1, v0, v1, 0, 2);
  EXPECT_NEAR(a.a0, 9.0 / 31.0, 1e-15);
  EXPECT_NEAR(a.a1, 9.0 / 31.0, 1e-15);
  const CubicBezier ogh = ogh_segment(p0, p1, v0, v1, 0, 2);
  EXPECT_TRUE(certify_regularity(ogh).regular);
  EXPECT_FALSE(has_cusp(ogh));
  EXPECT_FALSE(has_fold(ogh));
  EXPECT_GT(min_chordwise_speed(ogh), 0);
  // The ordinary Hermite curve (a0 = a1 = 1) has a cusp: its hodograph vanishes at u = 1/2.
  const CubicBezier hermite = hermite_bezier(p0, p1, v0, v1, 0, 2);
  EXPECT_NEAR(norm(hermite.d1(0.5)), 0.0, 1e-14);
  EXPECT_FALSE(certify_regularity(hermite).regular);
  // The geometry does not depend on the parameter interval or the tangent lengths.
  const CubicBezier other = ogh_segment(p0, p1, 0.1 * v0, 7.0 * v1, 3, 3.5);
  for (int k = 0; k < 4; ++k) EXPECT_LT(norm(other.p[k] - ogh.p[k]), 1e-14);
}

TEST(YongChengOgh, MinimumOfStrainEnergyOverCoefficients) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3, 3), ang(-kPi, kPi), len(0.2, 5), t(-2, 2);
  for (int trial = 0; trial < 500; ++trial) {
    const Point p0{u(rng), u(rng)}, p1{u(rng), u(rng)};
    const Vec2 v0 = len(rng) * from_angle(ang(rng)), v1 = len(rng) * from_angle(ang(rng));
    const double t0 = t(rng), t1 = t0 + len(rng);
    auto f = [&](double a0, double a1) {
      return hermite_strain_energy(p0, p1, a0 * v0, a1 * v1, t0, t1);
    };
    const auto [b0, b1] = minimize_quadratic(f);
    const OghCoefficients a = ogh_coefficients(p0, p1, v0, v1, t0, t1);
    const double scale = 1 + std::abs(a.a0) + std::abs(a.a1);
    ASSERT_NEAR(a.a0, b0, 1e-7 * scale) << trial;
    ASSERT_NEAR(a.a1, b1, 1e-7 * scale) << trial;
    // The closed form of f matches quadrature, and the OGH energy is f at the minimum.
    const CubicBezier q = hermite_bezier(p0, p1, a.a0 * v0, a.a1 * v1, t0, t1);
    const double e = f(a.a0, a.a1);
    ASSERT_NEAR(e, strain_energy_quadrature(q, t1 - t0), 1e-10 * (1 + e));
    ASSERT_NEAR(ogh_strain_energy(p0, p1, v0, v1, t0, t1), e, 1e-10 * (1 + e));
    // Every perturbation increases the energy.
    for (double da : {-1e-3, 1e-3}) {
      ASSERT_GT(f(a.a0 + da, a.a1), e);
      ASSERT_GT(f(a.a0, a.a1 + da), e);
    }
  }
}

TEST(YongChengOgh, UnitEnergyMatchesThePrintedFormAndIsAccurateWhenStraight) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  for (int trial = 0; trial < 1000; ++trial) {
    const double th = ang(rng), ph = ang(rng);
    const double c0 = std::cos(th), c1 = std::cos(ph), c = std::cos(th - ph);
    const double printed = 12 - 36 * (c0 * c0 + c1 * c1 - c0 * c1 * c) / (4 - c * c);
    ASSERT_NEAR(ogh_unit_energy(th, ph), printed, 1e-12);
    ASSERT_NEAR(ogh_unit_energy(th, ph),
                ogh_strain_energy({0, 0}, {1, 0}, from_angle(th), from_angle(ph)), 1e-12);
  }
  // Nearly straight: E ≈ 4(θ² + θφ + φ²) to leading order (the sine form keeps the digits
  // that 12 − 36N/(4 − c²) cancels away).
  const double th = 1e-7, ph = -3e-7;
  const double leading = 4 * (th * th + th * ph + ph * ph);
  EXPECT_NEAR(ogh_unit_energy(th, ph), leading, 1e-12 * leading);
  EXPECT_EQ(ogh_unit_energy(0, 0), 0.0);
}

TEST(YongChengOgh, EnergyScalesLikeChordSquaredOverIntervalCubed) {
  const Vec2 v0{1, 2}, v1{2, -1};
  const double e = ogh_strain_energy({0, 0}, {1, 0.5}, v0, v1, 0, 1);
  EXPECT_NEAR(ogh_strain_energy({0, 0}, {3, 1.5}, v0, v1, 0, 2), e * 9 / 8, 1e-12 * e);
}

TEST(YongChengOgh, EqualRatioIsTheOneDimensionalMinimum) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-3, 3), ang(-kPi, kPi), len(0.2, 5);
  for (int trial = 0; trial < 300; ++trial) {
    const Point p0{u(rng), u(rng)}, p1{u(rng), u(rng)};
    const double r0 = len(rng), r1 = len(rng);
    const Vec2 v0 = r0 * from_angle(ang(rng)), v1 = r1 * from_angle(ang(rng));
    const double h = len(rng);
    auto g = [&](double a) { return hermite_strain_energy(p0, p1, a * v0, a * v1, 0, h); };
    const double s = 0.5;
    const double ref = -s * (g(s) - g(-s)) / (2 * (g(s) - 2 * g(0) + g(-s)));
    const double a = ogh_equal_ratio_coefficient(p0, p1, v0, v1, 0, h);
    ASSERT_NEAR(a, ref, 1e-7 * (1 + std::abs(a)));
    // a* > 0 iff r0 cos θ + r1 cos φ > 0.
    const TangentAngles ta = tangent_angles(p0, p1, v0, v1);
    ASSERT_EQ(a > 0, r0 * std::cos(ta.theta) + r1 * std::cos(ta.phi) > 0);
  }
}

// ---- Theorems 3 and 4 ----

TEST(YongChengOgh, Theorem3ConditionsAreTheSignsOfTheCoefficients) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ang(-kPi, kPi), len(0.1, 10);
  int both = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double th = ang(rng), ph = ang(rng);
    const OghCoefficients a = ogh_coefficients({0, 0}, {2, 0}, len(rng) * from_angle(th),
                                               len(rng) * from_angle(ph), 0, 3);
    const bool lhs0 = 3 * std::cos(th) > std::cos(th - 2 * ph);
    const bool lhs1 = 3 * std::cos(ph) > std::cos(ph - 2 * th);
    if (std::abs(3 * std::cos(th) - std::cos(th - 2 * ph)) < 1e-12) continue;
    if (std::abs(3 * std::cos(ph) - std::cos(ph - 2 * th)) < 1e-12) continue;
    ASSERT_EQ(a.a0 > 0, lhs0) << th << " " << ph;
    ASSERT_EQ(a.a1 > 0, lhs1) << th << " " << ph;
    ASSERT_EQ(ogh_preserves_directions(th, ph), lhs0 && lhs1);
    both += lhs0 && lhs1;
  }
  EXPECT_GT(both, 1000);
}

TEST(YongChengOgh, Theorem4ConditionsGiveIncreasingChordwiseCoordinate) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> ang(-std::acos(1.0 / 3), std::acos(1.0 / 3));
  for (int trial = 0; trial < 20000; ++trial) {
    const double th = ang(rng), ph = ang(rng);
    ASSERT_TRUE(ogh_geometrically_smooth(th, ph));
    ASSERT_TRUE(ogh_preserves_directions(th, ph));  // (6) implies (5)
    const CubicBezier b = ogh_segment({0, 0}, {1, 0}, from_angle(th), from_angle(ph));
    ASSERT_GT(min_chordwise_speed(b), 0) << th << " " << ph;
  }
  EXPECT_FALSE(ogh_geometrically_smooth(std::acos(1.0 / 3) + 1e-9, 0));
}

TEST(YongChengOgh, Fig7DirectionReversedBySingleOgh) {
  // θ = π/6, φ = 2π/3: 3 cos φ = −3/2 < cos(φ − 2θ) = 1/2, so a1* < 0.
  const double th = kPi / 6, ph = 2 * kPi / 3;
  EXPECT_FALSE(ogh_preserves_directions(th, ph));
  const OghCoefficients a = ogh_coefficients({0, 0}, {1, 0}, from_angle(th), from_angle(ph));
  EXPECT_GT(a.a0, 0);
  EXPECT_LT(a.a1, 0);
  const CohCurve c = coh_curve({0, 0}, {1, 0}, from_angle(th), from_angle(ph));
  EXPECT_EQ(coh_name(c.method, c.symmetry), "M1");
  EXPECT_EQ(check_coh(c, {0, 0}, {1, 0}, from_angle(th), from_angle(ph)), "");
}

// ---- COH ----

TEST(YongChengCoh, Fig13IsG2WithJointCurvatureMinusEightThirds) {
  // P0 = (0, 0), P1 = (1, 0), V0 = (0, 1), V1 = (0, −1): M2 gives the joint T = (1/2, 1/2) with
  // V_t = (1, 0); each piece is the OGH with a* = 3/4 (unit chord (1/2, 1/2), unit directions
  // at 45° to it), control points (0, 0), (0, 1/4), (1/4, 1/2), (1/2, 1/2), and the curvature
  // at the joint is (2/3)·|(b1 − b2) × (b3 − b2)| / |b3 − b2|³ = (2/3)·(1/16)/(1/64) = 8/3,
  // clockwise, so −8/3 on both sides (G2).
  const CohCurve c = coh_curve({0, 0}, {1, 0}, {0, 1}, {0, -1});
  EXPECT_EQ(coh_name(c.method, c.symmetry), "M2");
  ASSERT_EQ(c.count, 2);
  EXPECT_NEAR(c.pieces[0].p[3].x, 0.5, 1e-15);
  EXPECT_NEAR(c.pieces[0].p[3].y, 0.5, 1e-15);
  EXPECT_NEAR(c.pieces[0].p[1].y, 0.25, 1e-15);
  EXPECT_NEAR(c.pieces[0].curvature(1.0), -8.0 / 3.0, 1e-12);
  EXPECT_NEAR(c.pieces[1].curvature(0.0), -8.0 / 3.0, 1e-12);
  EXPECT_NEAR(curvature_jump(c.pieces[0], c.pieces[1]), 0.0, 1e-12);
}

TEST(YongChengCoh, GridCoversTheTorusWithTheorem4OnEveryPiece) {
  // 720 × 720 grid of (θ, φ) ∈ [0, 2π)², every pair: the chosen construction is applicable by
  // the paper's regions (Theorem 7), no construction with fewer pieces is, and every piece
  // satisfies (6), positive coefficients and x'(t) > 0.
  const Point p0{0, 0}, p1{1, 0};
  int fewer_available = 0;
  double worst = 1;
  for (int i = 0; i < 720; ++i) {
    for (int j = 0; j < 720; ++j) {
      const double th = i * kPi / 360, ph = j * kPi / 360;
      const Vec2 v0 = dir(th), v1 = dir(ph);
      const CohCurve c = coh_curve(p0, p1, v0, v1);
      const std::string bad = check_coh(c, p0, p1, v0, v1);
      ASSERT_EQ(bad, "") << "theta " << i * 0.5 << " phi " << j * 0.5 << " "
                         << coh_name(c.method, c.symmetry);
      if (c.count > 1) worst = std::min(worst, coh_min_margin(c));
      ASSERT_TRUE(coh_applicable(c.method, c.symmetry, th, ph))
          << i * 0.5 << " " << j * 0.5 << " " << coh_name(c.method, c.symmetry);
      for (int m = 0; m < 8; ++m) {
        const auto method = static_cast<CohMethod>(m);
        if (coh_piece_count(method) >= c.count) continue;
        for (int s = 0; s < 4; ++s) {
          fewer_available += coh_applicable(method, static_cast<CohSymmetry>(s), th, ph);
        }
      }
    }
  }
  EXPECT_EQ(fewer_available, 0);
  // M0's margin is (6) itself; the constructions' tightest corners reach cos 70° − 1/3 ≈ 0.0087.
  EXPECT_GT(worst, 0.008);
}

TEST(YongChengCoh, RandomPairsAndScalesAreCovered) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> ang(0, 2 * kPi), u(-100, 100), len(1e-3, 1e3);
  for (int trial = 0; trial < 200000; ++trial) {
    const Point p0{u(rng), u(rng)};
    const Point p1 = p0 + len(rng) * from_angle(ang(rng));
    const Vec2 v0 = len(rng) * from_angle(ang(rng)), v1 = len(rng) * from_angle(ang(rng));
    const CohCurve c = coh_curve(p0, p1, v0, v1);
    ASSERT_EQ(check_coh(c, p0, p1, v0, v1), "") << trial;
  }
}

TEST(YongChengCoh, EveryMethodSatisfiesTheorem4OnItsPaperRegion) {
  // Theorems 5, 6 and 7: for each M_i^s, a 121 × 121 grid over each applicable box of the
  // paper (after mapping by s) gives pieces satisfying (6). The reconstructed M2 and M3 pass.
  struct Box {
    CohMethod m;
    double a, b, c, d;
  };
  const Box boxes[] = {{CohMethod::kM1, 0, 30, 60, 120},     {CohMethod::kM2, 0, 60, 180, 300},
                       {CohMethod::kM2, 60, 120, 240, 300},  {CohMethod::kM3, 0, 60, 60, 180},
                       {CohMethod::kM4, 60, 120, 0, 120},    {CohMethod::kM5, 60, 120, 180, 240},
                       {CohMethod::kM5, 120, 180, 180, 300}, {CohMethod::kM6, 120, 180, 30, 120},
                       {CohMethod::kM7, 120, 180, 120, 180}};
  for (const Box& box : boxes) {
    for (int s = 0; s < 4; ++s) {
      const auto sym = static_cast<CohSymmetry>(s);
      for (int i = 0; i <= 120; ++i) {
        for (int j = 0; j <= 120; ++j) {
          double th = (box.a + (box.b - box.a) * i / 120) * kDeg;
          double ph = (box.c + (box.d - box.c) * j / 120) * kDeg;
          // The region of M^s is s applied to the box: T (−θ, −φ), R (−φ, −θ), RT (φ, θ).
          if (sym == CohSymmetry::kT) std::tie(th, ph) = std::pair(-th, -ph);
          if (sym == CohSymmetry::kR) std::tie(th, ph) = std::pair(-ph, -th);
          if (sym == CohSymmetry::kRT) std::tie(th, ph) = std::pair(ph, th);
          ASSERT_TRUE(coh_applicable(box.m, sym, th, ph));
          const CohCurve c = coh_construct(box.m, sym, {0, 0}, {1, 0}, dir(th), dir(ph));
          ASSERT_EQ(check_coh(c, {0, 0}, {1, 0}, dir(th), dir(ph)), "")
              << coh_name(box.m, sym) << " theta " << th / kDeg << " phi " << ph / kDeg;
          ASSERT_EQ(c.count, coh_piece_count(box.m));
        }
      }
    }
  }
}

TEST(YongChengCoh, PaperM2AsPrintedFailsToCloseTheTurn) {
  // The printed ϕ = (2π − φ + φ1)/3 with φ1 = θ − π/18 (θ < π/9) makes the three angles at T
  // inconsistent: the direction of P0T would have to be both θ − φ1 = π/18 and φ + 3ϕ = φ1.
  // With the corrected ϕ = (2π − φ + β)/3, β = ∠P0T, the construction closes; e.g. θ = 5°,
  // φ = 200°: β = 10°, ϕ = 56.67°, and V_t makes ϕ with both chords.
  const double th = 5 * kDeg, ph = 200 * kDeg;
  const double phi1 = th - kPi / 18;
  EXPECT_GT(std::abs((th - phi1) - phi1), 0.1);  // printed version inconsistent
  const CohCurve c = coh_construct(CohMethod::kM2, CohSymmetry::kNone, {0, 0}, {1, 0},
                                   from_angle(th), from_angle(ph));
  const Point t = c.pieces[0].p[3];
  EXPECT_NEAR(std::atan2(t.y, t.x), 10 * kDeg, 1e-12);
  const double expected = (2 * kPi - ph + 10 * kDeg) / 3;
  const Vec2 vt = c.pieces[1].p[1] - c.pieces[1].p[0];
  EXPECT_NEAR(signed_angle(Vec2{1, 0} - t, vt), expected, 1e-12);
  EXPECT_NEAR(signed_angle(vt, t), expected, 1e-12);
}

TEST(YongChengCoh, ChoiceNamesAndCounts) {
  EXPECT_EQ(coh_name(CohMethod::kM4, CohSymmetry::kRT), "M4^RT");
  EXPECT_EQ(coh_name(CohMethod::kM0, CohSymmetry::kT), "M0");
  EXPECT_EQ(coh_piece_count(CohMethod::kM0), 1);
  EXPECT_EQ(coh_piece_count(CohMethod::kM2), 2);
  EXPECT_EQ(coh_piece_count(CohMethod::kM7), 3);
  const CohChoice c = coh_choose(100 * kDeg, 10 * kDeg);
  EXPECT_EQ(coh_name(c.method, c.symmetry), "M1^RT");
  const CohChoice d = coh_choose(10 * kDeg, 100 * kDeg);
  EXPECT_EQ(coh_name(d.method, d.symmetry), "M1");
  EXPECT_EQ(coh_piece_count(coh_choose(10 * kDeg, -20 * kDeg).method), 1);
}

TEST(YongChengCoh, BatchEqualsSingleCallsBitForBit) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> ang(0, 2 * kPi), u(-5, 5), len(0.1, 3);
  std::vector<HermiteEnds> ends(1000);
  for (HermiteEnds& e : ends) {
    e.p0 = {u(rng), u(rng)};
    e.p1 = e.p0 + len(rng) * from_angle(ang(rng));
    e.v0 = len(rng) * from_angle(ang(rng));
    e.v1 = len(rng) * from_angle(ang(rng));
  }
  std::vector<CohCurve> out(ends.size());
  coh_curves(ends, out);
  for (std::size_t i = 0; i < ends.size(); ++i) {
    const CohCurve one = coh_curve(ends[i].p0, ends[i].p1, ends[i].v0, ends[i].v1);
    ASSERT_EQ(out[i].count, one.count);
    ASSERT_EQ(out[i].method, one.method);
    ASSERT_EQ(out[i].symmetry, one.symmetry);
    for (int k = 0; k < one.count; ++k) {
      for (int j = 0; j < 4; ++j) ASSERT_EQ(out[i].pieces[k].p[j], one.pieces[k].p[j]);
    }
  }
  // An error names the offending span of the batch.
  ends[77].v1 = {0, 0};
  const Error e = testing::expect_error([&] { coh_curves(ends, out); });
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(e.index(), 77u);
  std::vector<CohCurve> shorter(3);
  expect_error(ErrorCode::kInvalidArgument, [&] { coh_curves(ends, shorter); });
}

TEST(YongChengOgh, TinyAndHugeTangentsUseTheRescaledPath) {
  const Point p0{0, 0}, p1{2, 1};
  const OghCoefficients ref = ogh_coefficients(p0, p1, {1, 2}, {3, -1});
  for (double s : {1e-200, 1e-160, 1e160, 1e200}) {
    const OghCoefficients a = ogh_coefficients(p0, p1, s * Vec2{1, 2}, s * Vec2{3, -1});
    EXPECT_NEAR(a.a0 * s, ref.a0, 1e-14 * std::abs(ref.a0)) << s;
    EXPECT_NEAR(a.a1 * s, ref.a1, 1e-14 * std::abs(ref.a1)) << s;
  }
  expect_error(ErrorCode::kNonFinite, [&] { ogh_coefficients(p0, p1, {1e-310, 0}, {0, 1e-310}); });
}

TEST(YongChengCoh, BadEndDataThrows) {
  expect_error(ErrorCode::kRepeatedPoint, [] { coh_curve({1, 1}, {1, 1}, {1, 0}, {1, 0}); });
  expect_error(ErrorCode::kInvalidArgument, [] { coh_curve({0, 0}, {1, 1}, {0, 0}, {1, 0}); });
  expect_error(ErrorCode::kNonFinite, [] { coh_curve({0, 0}, {1, 1}, {NAN, 0}, {1, 0}); });
  expect_error(ErrorCode::kInvalidArgument, [] {
    ogh_coefficients({0, 0}, {1, 1}, {1, 0}, {1, 0}, 1, 1);
  });
  // A construction far outside its region: the joints do not exist.
  expect_error(ErrorCode::kInfeasible, [] {
    coh_construct(CohMethod::kM2, CohSymmetry::kNone, {0, 0}, {1, 0}, from_angle(-3.0),
                  from_angle(-3.0));
  });
}

// ---- equivariance ----

/// Generic angle pairs: away from the lines where two mirror images meet (θ = ±φ, θ or φ ∈
/// {0, π}) and from the dispatcher's thresholds, where rounding may pick another construction.
bool generic(double th, double ph) {
  auto away = [](double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)) > 1e-6; };
  for (double x : {th, ph}) {
    for (double v : {0.0, kPi, std::acos(1.0 / 3), -std::acos(1.0 / 3)}) {
      if (!away(x, v)) return false;
    }
    for (int k = 0; k < 12; ++k) {
      if (!away(x, k * kPi / 6)) return false;
    }
  }
  return away(th, ph) && away(th, -ph);
}

struct Similarity {
  double angle, scale;
  Vec2 shift;
  bool mirror;
  Point map(Point p) const {
    if (mirror) p.y = -p.y;
    return shift + scale * rotate(p, angle);
  }
  Vec2 map_dir(Vec2 v) const {
    if (mirror) v.y = -v.y;
    return scale * rotate(v, angle);
  }
};

RC_GTEST_PROP(YongChengCohProps, EquivariantUnderSimilaritiesAndReversal, ()) {
  const double th = *rc::gen::inRange(0, 3600000) * (2 * kPi / 3600000) + 1.234e-8;
  const double ph = *rc::gen::inRange(0, 3600000) * (2 * kPi / 3600000) + 2.345e-8;
  RC_PRE(generic(th, ph));
  const Point p0{0.3, -0.2}, p1{1.7, 0.4};
  const double base = std::atan2(p1.y - p0.y, p1.x - p0.x);
  const Vec2 v0 = 2.0 * from_angle(base + th), v1 = 0.5 * from_angle(base + ph);
  const Similarity sim{*rc::gen::inRange(-314, 314) * 0.01 + 1e-3,
                       std::pow(10.0, *rc::gen::inRange(-3, 4)) * 1.3,
                       {*rc::gen::inRange(-1000, 1000) * 0.1, *rc::gen::inRange(-1000, 1000) * 0.1},
                       *rc::gen::arbitrary<bool>()};
  const CohCurve a = coh_curve(p0, p1, v0, v1);
  const CohCurve b = coh_curve(sim.map(p0), sim.map(p1), sim.map_dir(v0), sim.map_dir(v1));
  RC_ASSERT(a.count == b.count);
  const double tol = 1e-9 * sim.scale;
  for (int k = 0; k < a.count; ++k) {
    for (int j = 0; j < 4; ++j) {
      RC_ASSERT(norm(sim.map(a.pieces[k].p[j]) - b.pieces[k].p[j]) <= tol + 1e-9 * norm(sim.shift));
    }
  }
  // Reversal: the curve from P1 to P0 with −V1, −V0 is the same curve backwards.
  const CohCurve r = coh_curve(p1, p0, -v1, -v0);
  RC_ASSERT(r.count == a.count);
  for (int k = 0; k < a.count; ++k) {
    for (int j = 0; j < 4; ++j) {
      RC_ASSERT(norm(r.pieces[a.count - 1 - k].p[3 - j] - a.pieces[k].p[j]) <= 1e-12);
    }
  }
}

TEST(YongChengCoh, ExactMirrorAboutTheBaseLineIsTheTScheme) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> ang(0, 2 * kPi);
  for (int trial = 0; trial < 10000; ++trial) {
    const Vec2 v0 = from_angle(ang(rng)), v1 = from_angle(ang(rng));
    const CohCurve a = coh_curve({0, 0}, {1, 0}, v0, v1);
    const CohCurve b = coh_curve({0, 0}, {1, 0}, {v0.x, -v0.y}, {v1.x, -v1.y});
    ASSERT_EQ(a.count, b.count);
    ASSERT_EQ(a.method, b.method);
    for (int k = 0; k < a.count; ++k) {
      for (int j = 0; j < 4; ++j) {
        ASSERT_EQ(a.pieces[k].p[j].x, b.pieces[k].p[j].x);
        ASSERT_EQ(a.pieces[k].p[j].y, -b.pieces[k].p[j].y);
      }
    }
  }
}

// ---- spline level ----

FitInput with_tangents(std::vector<Point> pts, std::vector<Vec2> tangents, bool closed = false) {
  FitInput in;
  in.points = std::move(pts);
  in.closed = closed;
  for (Vec2 t : tangents) in.tangents.emplace_back(t);
  return in;
}

TEST(YongChengSpline, SpansAreCohCurvesWithSpanIndices) {
  // Span 0 is Fig. 5 (one OGH), span 1 needs M1 (θ = 30°, φ = 120° relative to its chord).
  const Point a{-1, 1}, b{1, 1}, c{3, 1};
  FitInput in = with_tangents({a, b, c}, {{3, -2}, {3, 2}, from_angle(120 * kDeg)});
  in.tangents[1] = from_angle(30 * kDeg);
  in.tangents[0] = from_angle(-30 * kDeg);
  const FitResult r = fit("yong-cheng", in, {}, ReportLevel::kFull);
  ASSERT_EQ(r.spline.segments.size(), 3u);
  EXPECT_EQ(r.spline.segments[0].span, 0u);
  EXPECT_EQ(r.spline.segments[1].span, 1u);
  EXPECT_EQ(r.spline.segments[2].span, 1u);
  EXPECT_EQ(r.method_report["spans"][0]["construction"], "M0");
  EXPECT_EQ(r.method_report["spans"][1]["construction"], "M1");
  EXPECT_EQ(r.method_report["spans"][1]["pieces"], 2);
  EXPECT_TRUE(r.method_report["all_preserved"].get<bool>());
  EXPECT_NEAR(r.method_report["spans"][1]["phi_deg"].get<double>(), 120, 1e-9);
  // Knots: span 1's interval is split at an interior parameter, pieces are contiguous.
  EXPECT_EQ(r.spline.segments[1].t0, r.knots[1]);
  EXPECT_EQ(r.spline.segments[1].t1, r.spline.segments[2].t0);
  EXPECT_EQ(r.spline.segments[2].t1, r.knots[2]);
  EXPECT_GT(r.spline.segments[1].t1, r.knots[1]);
  EXPECT_LT(r.spline.segments[1].t1, r.knots[2]);
  ASSERT_TRUE(r.report);
  EXPECT_TRUE(r.report->regular);
  EXPECT_LT(r.report->max_tangent_angle_jump_deg, 1e-9);
  EXPECT_LT(r.report->max_interpolation_residual, 1e-12);
  // Coefficients are relative to the given vectors on each piece's interval: the first piece
  // of span 1 starts with derivative a0·V1 in t.
  const auto& seg = r.spline.segments[1];
  const double a0 = r.method_report["spans"][1]["coefficients"][0][0].get<double>();
  const Vec2 deriv = 3.0 / (seg.t1 - seg.t0) * (seg.bezier.p[1] - seg.bezier.p[0]);
  EXPECT_LT(norm(deriv - a0 * from_angle(30 * kDeg)), 1e-12);
  // Span 0's coefficients are (4) on [t0, t1] with the given V0 = (cos −30°, sin −30°), V1.
  const OghCoefficients ref =
      ogh_coefficients(a, b, from_angle(-30 * kDeg), from_angle(30 * kDeg), r.knots[0], r.knots[1]);
  EXPECT_NEAR(r.method_report["spans"][0]["coefficients"][0][0].get<double>(), ref.a0, 1e-12);
  EXPECT_NEAR(r.method_report["spans"][0]["coefficients"][0][1].get<double>(), ref.a1, 1e-12);
}

TEST(YongChengSpline, RandomDataGivesRegularG1Curves) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> ang(0, 2 * kPi);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Point> pts = random_walk(30, trial, 170);
    std::vector<Vec2> tan;
    for (std::size_t i = 0; i < pts.size(); ++i) tan.push_back(from_angle(ang(rng)));
    const FitResult r =
        fit("yong-cheng", with_tangents(pts, tan, trial % 2), {}, ReportLevel::kBasic);
    ASSERT_TRUE(r.report->regular) << trial;
    ASSERT_LT(r.report->max_tangent_angle_jump_deg, 1e-8);
    ASSERT_LT(r.report->max_interpolation_residual, 1e-12 * testing::scale_of(pts) + 1e-12);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      ASSERT_NEAR(cross(r.tangents[i], tan[i]), 0, 1e-15);
    }
  }
}

TEST(YongChengSpline, TangentsFromAnotherMethod) {
  const std::vector<Point> pts = random_walk(12, 4, 100);
  FitInput in;
  in.points = pts;
  expect_error(
      ErrorCode::kInvalidArgument, [&] { (void)fit("yong-cheng", in); }, "point 0 has none");
  const FitResult jz = fit("jaklic-zagar", in, {}, ReportLevel::kNone);
  const FitResult r = fit("yong-cheng", in, {{"tangents_from", "jaklic-zagar"}});
  ASSERT_EQ(r.tangents.size(), jz.tangents.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_LT(norm(r.tangents[i] - jz.tangents[i]), 1e-15);
  }
  // Jaklič–Žagar's directions satisfy its Theorem 4 half-plane conditions, which need not be
  // (6): the spans report their constructions either way, all preserving the directions.
  EXPECT_TRUE(r.method_report["all_preserved"].get<bool>());
  // Given tangents win over the other method's.
  in.tangents.assign(pts.size(), std::nullopt);
  in.tangents[3] = Vec2{0, 1};
  const FitResult g = fit("yong-cheng", in, {{"tangents_from", "li-strain"}});
  EXPECT_LT(norm(g.tangents[3] - Vec2{0, 1}), 1e-15);
  expect_error(ErrorCode::kBadOption, [&] {
    (void)fit("yong-cheng", in, {{"tangents_from", "yong-cheng"}});
  });
  expect_error(ErrorCode::kUnknownMethod, [&] {
    (void)fit("yong-cheng", in, {{"tangents_from", "nope"}});
  });
}

TEST(YongChengSpline, OptionsAndErrors) {
  // Fig. 7 as a one-span spline: composite=false keeps the single OGH and reports the reversal.
  FitInput in = with_tangents({{0, 0}, {1, 0}}, {from_angle(kPi / 6), from_angle(2 * kPi / 3)});
  const FitResult off = fit("yong-cheng", in, {{"composite", false}});
  EXPECT_EQ(off.spline.segments.size(), 1u);
  EXPECT_FALSE(off.method_report["spans"][0]["preserved"].get<bool>());
  EXPECT_FALSE(off.method_report["all_preserved"].get<bool>());
  const FitResult on = fit("yong-cheng", in);
  EXPECT_EQ(on.spline.segments.size(), 2u);
  // Equal ratio: a* = 3 d·(V0 + V1) / (2(|V0|² + V0·V1 + |V1|²) h).
  FitInput eq = with_tangents({{0, 0}, {2, 0}}, {{1, 1}, {2, -1}});
  const FitResult e = fit("yong-cheng", eq, {{"ratio", "equal"}});
  const double h = e.knots[1] - e.knots[0];
  const double a = 3.0 * 2 * 3 / (2.0 * (2 + 1 + 5) * h);
  EXPECT_NEAR(e.method_report["spans"][0]["coefficients"][0][0].get<double>(), a, 1e-14);
  EXPECT_EQ(e.method_report["spans"][0]["construction"], "equal-ratio");
  FitInput back = with_tangents({{0, 0}, {2, 0}}, {{-1, 1}, {-2, -1}});
  expect_error(
      ErrorCode::kInfeasible,
      [&] {
        (void)fit("yong-cheng", back, {{"ratio", "equal"}});
      },
      "span 0");
  // Corners are refused; start/end tangents override.
  FitInput corner = with_tangents({{0, 0}, {1, 0}, {2, 1}}, {{1, 0}, {1, 0}, {1, 0}});
  corner.kinds = {PointKind::kSmooth, PointKind::kCorner, PointKind::kSmooth};
  expect_error(
      ErrorCode::kInvalidArgument, [&] { (void)fit("yong-cheng", corner); }, "corner");
  FitInput ends = with_tangents({{0, 0}, {1, 0}, {2, 1}}, {{1, 0}, {1, 0}, {1, 0}});
  ends.start_tangent = Vec2{0, 1};
  ends.end_tangent = Vec2{0, -1};
  const FitResult o = fit("yong-cheng", ends);
  EXPECT_LT(norm(o.tangents.front() - Vec2{0, 1}), 1e-15);
  EXPECT_LT(norm(o.tangents.back() - Vec2{0, -1}), 1e-15);
  // Bad tangents name the point.
  FitInput zero = with_tangents({{0, 0}, {1, 0}, {2, 1}}, {{1, 0}, {0, 0}, {1, 0}});
  expect_error(
      ErrorCode::kInvalidArgument, [&] { (void)fit("yong-cheng", zero); }, "zero");
  FitInput nan = with_tangents({{0, 0}, {1, 0}, {2, 1}}, {{1, 0}, {NAN, 0}, {1, 0}});
  expect_error(ErrorCode::kNonFinite, [&] { (void)fit("yong-cheng", nan); });
  FitInput few = with_tangents({{0, 0}}, {{1, 0}});
  expect_error(ErrorCode::kTooFewPoints, [&] { (void)fit("yong-cheng", few); });
}

TEST(YongChengSpline, HugeAndTinyCoordinatesStayFinite) {
  for (double s : {1e-150, 1e150, 1e300}) {
    FitInput in = with_tangents({{0, 0}, {s, 0}, {s, s}}, {{s, s}, {0, -s}, {-s, 0}});
    const FitResult r = fit("yong-cheng", in, {}, ReportLevel::kNone);
    for (const Segment& seg : r.spline.segments) {
      for (const Point& p : seg.bezier.p) ASSERT_TRUE(is_finite(p)) << s;
    }
    EXPECT_LT(norm(r.spline.segments.back().bezier.p[3] - Point{s, s}), 1e-12 * s);
  }
}

// Found by fuzz_fit (tests/fuzz/corpus/fuzz_fit/regression-yong-cheng-denormal-tangents): the
// method report rescales each coefficient to the given tangent's length, which was computed as
// sqrt(|v|^2) (0 for |v| = 1e-170) and divided by: Inf in method_report. Short tangents whose
// square underflows now report finite coefficients; a denormal one, whose coefficient would
// overflow, is refused with an Error naming the point.
TEST(YongChengSpline, TinyTangentsGiveFiniteReportsOrAnError) {
  FitInput in = with_tangents({{0, 0}, {1, 0}, {1, 1}}, {{1e-170, 1e-170}, {0, -1}, {-1, 0}});
  const FitResult r = fit("yong-cheng", in, {}, ReportLevel::kBasic);
  for (const auto& span : r.method_report.at("spans")) {
    for (const auto& c : span.at("coefficients")) {
      for (const auto& x : c) EXPECT_TRUE(x.is_number() && std::isfinite(x.get<double>())) << c;
    }
  }
  in.tangents[0] = Vec2{5e-324, 5e-324};
  try {
    fit("yong-cheng", in, {}, ReportLevel::kBasic);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite);
    EXPECT_EQ(e.index(), 0u);
  }
}

}  // namespace
}  // namespace fairspline
