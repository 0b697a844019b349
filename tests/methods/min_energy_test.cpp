// Tests of Johnson & Johnson's minimal-energy framework (src/methods/min_energy.cpp): the basic
// curves and energies of Examples 1.1, 4.1, 4.2 and Theorem 4.4 against quadrature, (4.1)'s end
// curvatures and (3.1); derivatives against finite differences and Remark 4.5's Hessian;
// Theorem 3.3 (conditional G2, natural ends), Example 5.2 (no active bound), Proposition 6.3
// (green zone: unique, G2 minimum, reached from random starts); the projected Newton solver
// against the slow coordinate-descent reference on open / closed / clamped / cornered data; the
// errors; and invariance of the minimum under similarities, mirroring and reversal.
#include "fairspline/methods/min_energy.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/methods/yong_cheng.hpp"
#include "fairspline/registry.hpp"
#include "methods/data_balls.hpp"
#include "methods/min_energy_options.hpp"
#include "stress/kkt.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

using testing::random_walk;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

using testing::expect_error;

BasicCurveMethod cond_g2(double lambda, double omega = kPi / 2) {
  return {MinEnergyBasis::kCondG2, lambda, omega};
}
BasicCurveMethod jaklic_zagar(double omega = 80 * kDeg) {
  return {MinEnergyBasis::kJaklicZagar, 1.0, omega};
}
BasicCurveMethod yong_cheng(double omega = 60 * kDeg) {
  return {MinEnergyBasis::kYongCheng, 1.0, omega};
}

/// ∫_0^1 |c''(u)|² du by 3-point Gauss–Legendre (exact: the integrand is a quadratic).
double strain_quadrature(const CubicBezier& b) {
  static const double x[] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  static const double w[] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) sum += 0.5 * w[k] * norm2(b.d2(0.5 * (x[k] + 1.0)));
  return sum;
}

double wrap(double a) {
  a = std::remainder(a, 2 * kPi);
  return a <= -kPi ? a + 2 * kPi : a;
}

/// Chord angles (α, β) and chord length of a Bézier piece, read off its control polygon.
struct ChordAngles {
  double alpha, beta, length;
};
ChordAngles chord_angles(const CubicBezier& b) {
  const Vec2 c = b.p[3] - b.p[0];
  return {signed_angle(c, b.p[1] - b.p[0]), signed_angle(c, b.p[3] - b.p[2]), norm(c)};
}

/// Σ E_1(α_i, β_{i+1}) / L_i over the output pieces (independent of the solver's bookkeeping).
double recomputed_energy(const FitResult& r, const BasicCurveMethod& m) {
  double e = 0.0;
  for (const Segment& s : r.spline.segments) {
    const ChordAngles a = chord_angles(s.bezier);
    e += basic_energy(m, a.alpha, a.beta).e / a.length;
  }
  return e;
}

/// Stencil angles ψ_i (0 at the ends of an open polygon).
std::vector<double> stencil_angles(const std::vector<Point>& p, bool closed) {
  const std::size_t n = p.size();
  std::vector<double> psi(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!closed && (i == 0 || i + 1 == n)) continue;
    psi[i] = signed_angle(p[i] - p[(i + n - 1) % n], p[(i + 1) % n] - p[i]);
  }
  return psi;
}

nlohmann::json options_of(const BasicCurveMethod& m) {
  switch (m.basis) {
    case MinEnergyBasis::kCondG2:
      return {{"basis", "cond-g2"}, {"lambda", m.lambda}, {"omega_deg", m.omega / kDeg}};
    case MinEnergyBasis::kJaklicZagar:
      return {{"basis", "jaklic-zagar"}, {"omega_deg", m.omega / kDeg}};
    case MinEnergyBasis::kYongCheng:
      return {{"basis", "yong-cheng"}, {"omega_deg", m.omega / kDeg}};
    case MinEnergyBasis::kRestrictedElastic:
      return {{"basis", "restricted-elastic"}, {"omega_deg", m.omega / kDeg}};
    case MinEnergyBasis::kElastic:
      return {{"basis", "elastic"}, {"omega_deg", m.omega / kDeg}};
  }
  return {};
}

FitResult fit_with(const BasicCurveMethod& m, const FitInput& in) {
  return fit("min-energy", in, options_of(m), ReportLevel::kBasic);
}

FitInput input_of(std::vector<Point> pts, bool closed = false) {
  FitInput in;
  in.points = std::move(pts);
  in.closed = closed;
  return in;
}

/// A closed polygon near an ellipse: n points at jittered parameters and radii (gentle turns
/// everywhere, including the closing node).
std::vector<Point> wobbly_ellipse(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), radius(0.9, 1.1);
  std::vector<Point> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 2 * kPi * (static_cast<double>(i) + jitter(rng)) / static_cast<double>(n);
    pts.push_back({2 * radius(rng) * std::cos(t), radius(rng) * std::sin(t)});
  }
  return pts;
}

std::vector<std::size_t> active_of(const FitResult& r) {
  return r.method_report.at("active").get<std::vector<std::size_t>>();
}

/// Relative curvature jump at every G1 node (not at corners, not at the ends of an open curve):
/// |κ_left(1) − κ_right(0)| / max(|κ|, 1/L). Indexed by point; −1 where not a joint.
std::vector<double> curvature_jumps(const FitResult& r, const FitInput& in) {
  const auto& segs = r.spline.segments;
  const std::size_t n = r.points.size();
  std::vector<double> jump(n, -1.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!r.closed && (i == 0 || i + 1 == n)) continue;
    if (i < in.kinds.size() && in.kinds[i] == PointKind::kCorner) continue;
    const CubicBezier& left = segs[(i + n - 1) % n].bezier;
    const CubicBezier& right = segs[i].bezier;
    const double kl = left.curvature(1.0), kr = right.curvature(0.0);
    const double len = std::min(norm(left.p[3] - left.p[0]), norm(right.p[3] - right.p[0]));
    jump[i] = std::abs(kl - kr) / std::max({std::abs(kl), std::abs(kr), 1.0 / len});
  }
  return jump;
}

// ---- basic curves and energies (Examples 1.1, 4.1, 4.2, Theorem 4.4) ----

TEST(MinEnergyBasic, CondG2EnergyIsHalfTheStrainOfItsCurve) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ang(-kPi / 2, kPi / 2);
  for (double lambda : {0.5, 1.0, 1.7, 2.5}) {
    const BasicCurveMethod m = cond_g2(lambda);
    for (int trial = 0; trial < 500; ++trial) {
      const double a = ang(rng), b = ang(rng);
      const CubicBezier c = basic_curve(m, {0, 0}, {1, 0}, a, b);
      const double e = basic_energy(m, a, b).e;
      ASSERT_NEAR(e, 0.5 * strain_quadrature(c), 1e-12 * (1 + e)) << lambda << " " << a << " " << b;
      // Speeds λ at both ends in the end directions (4.1).
      ASSERT_NEAR(norm(c.d1(0) - lambda * from_angle(a)), 0, 1e-14);
      ASSERT_NEAR(norm(c.d1(1) - lambda * from_angle(b)), 0, 1e-14);
      const BasicSpeeds s = basic_speeds(m, a, b);
      ASSERT_EQ(s.s0, lambda);
      ASSERT_EQ(s.s1, lambda);
    }
    // E_1(0, 0) = 6(λ − 1)² (Remark 4.5).
    EXPECT_NEAR(basic_energy(m, 0, 0).e, 6 * (lambda - 1) * (lambda - 1), 1e-13);
  }
}

TEST(MinEnergyBasic, QuasiElasticIsExample11) {
  // Example 1.1 prints the curve and half of E_1 for λ = 1: 5 + cos(α−β) − 3(cos α + cos β).
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> ang(-kPi / 2, kPi / 2), len(0.1, 10), u(-5, 5);
  const BasicCurveMethod m = cond_g2(1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const double a = ang(rng), b = ang(rng), L = len(rng), rot = 3 * u(rng);
    const double printed = 5 + std::cos(a - b) - 3 * (std::cos(a) + std::cos(b));
    ASSERT_NEAR(basic_energy(m, a, b).e, 2 * printed, 1e-13);
    // c_L(α, β) = L c_1 rotated and translated onto the chord.
    const Point p0{u(rng), u(rng)};
    const Point p1 = p0 + L * from_angle(rot);
    const CubicBezier c = basic_curve(m, p0, p1, a, b);
    for (double t : {0.0, 0.2, 0.5, 0.7, 1.0}) {
      const double x =
          L * (t * (1 - t) * (1 - t) * std::cos(a) + t * t * (3 - 2 * t + (t - 1) * std::cos(b)));
      const double y = L * (t * (1 - t) * (1 - t) * std::sin(a) + t * t * (t - 1) * std::sin(b));
      ASSERT_LT(norm(c.eval(t) - (p0 + rotate(Vec2{x, y}, rot))), 1e-13 * (1 + L + 5)) << t;
    }
  }
}

TEST(MinEnergyBasic, YongChengIsTheOghCurveWithItsFullStrain) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ang(-kPi / 2, kPi / 2);
  const BasicCurveMethod m = yong_cheng();
  for (int trial = 0; trial < 1000; ++trial) {
    const double a = ang(rng), b = ang(rng);
    const CubicBezier c = basic_curve(m, {0, 0}, {1, 0}, a, b);
    const double e = basic_energy(m, a, b).e;
    // No ½ here (Example 4.1): E_1 = ∫|c''|².
    ASSERT_NEAR(e, strain_quadrature(c), 1e-12 * (1 + e)) << a << " " << b;
    ASSERT_NEAR(e, ogh_unit_energy(a, b), 1e-12 * (1 + e));
    // Speeds of Example 4.1, and Yong–Cheng's own optimal coefficients (4).
    const double cd = std::cos(a - b);
    const double s0 = (6 * std::cos(a) - 3 * std::cos(b) * cd) / (4 - cd * cd);
    const double s1 = (6 * std::cos(b) - 3 * std::cos(a) * cd) / (4 - cd * cd);
    const BasicSpeeds s = basic_speeds(m, a, b);
    ASSERT_NEAR(s.s0, s0, 1e-14);
    ASSERT_NEAR(s.s1, s1, 1e-14);
    const OghCoefficients oc = ogh_coefficients({0, 0}, {1, 0}, from_angle(a), from_angle(b));
    ASSERT_NEAR(s.s0, oc.a0, 1e-13);
    ASSERT_NEAR(s.s1, oc.a1, 1e-13);
    ASSERT_NEAR(norm(c.d1(0) - s0 * from_angle(a)), 0, 1e-13);
    ASSERT_NEAR(norm(c.d1(1) - s1 * from_angle(b)), 0, 1e-13);
  }
  EXPECT_EQ(basic_energy(m, 0, 0).e, 0.0);
}

TEST(MinEnergyBasic, JaklicZagarEnergyAndSpeeds) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> ang(-kPi / 2, kPi / 2);
  const BasicCurveMethod m = jaklic_zagar();
  for (int trial = 0; trial < 1000; ++trial) {
    const double a = ang(rng), b = ang(rng);
    const double e = basic_energy(m, a, b).e;
    ASSERT_NEAR(e, std::sin(a) * std::sin(a) + std::sin(b) * std::sin(b), 1e-15);
    const BasicSpeeds s = basic_speeds(m, a, b);
    ASSERT_NEAR(s.s0, std::cos(a), 1e-16);
    ASSERT_NEAR(s.s1, std::cos(b), 1e-16);
    // The speeds minimize Jaklič–Žagar's functional, whose minimum is E_1 (Example 4.2).
    auto f = [&](double q0, double q1) {
      return (1 - q0 * std::cos(a)) * (1 - q0 * std::cos(a)) +
             (q0 * std::sin(a)) * (q0 * std::sin(a)) +
             (q1 * std::cos(b) - 1) * (q1 * std::cos(b) - 1) +
             (q1 * std::sin(b)) * (q1 * std::sin(b));
    };
    ASSERT_NEAR(f(s.s0, s.s1), e, 1e-14);
    for (double d : {-1e-4, 1e-4}) {
      ASSERT_GT(f(s.s0 + d, s.s1), e);
      ASSERT_GT(f(s.s0, s.s1 + d), e);
    }
    const CubicBezier c = basic_curve(m, {0, 0}, {1, 0}, a, b);
    ASSERT_NEAR(norm(c.d1(0) - std::cos(a) * from_angle(a)), 0, 1e-14);
    ASSERT_NEAR(norm(c.d1(1) - std::cos(b) * from_angle(b)), 0, 1e-14);
  }
}

/// (4.1)'s end curvatures of c_1(α, β) with speeds s0, s1.
std::pair<double, double> end_curvatures(const BasicCurveMethod& m, double a, double b) {
  const BasicSpeeds s = basic_speeds(m, a, b);
  return {(2 * s.s1 * std::sin(a - b) - 6 * std::sin(a)) / (s.s0 * s.s0),
          (2 * s.s0 * std::sin(a - b) + 6 * std::sin(b)) / (s.s1 * s.s1)};
}

TEST(MinEnergyBasic, EndCurvaturesAndConsistency) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ang(-kPi / 3, kPi / 3), len(0.2, 5), rot(-kPi, kPi);
  const std::vector<BasicCurveMethod> methods = {cond_g2(0.5), cond_g2(1), cond_g2(2.5),
                                                 jaklic_zagar(), yong_cheng()};
  for (const BasicCurveMethod& m : methods) {
    for (int trial = 0; trial < 300; ++trial) {
      const double a = ang(rng), b = ang(rng), L = len(rng);
      // The printed formulas agree with the curvature of the Bézier, scaled by 1/L.
      const CubicBezier c = basic_curve(m, {1, 2}, Point{1, 2} + L * from_angle(rot(rng)), a, b);
      const auto [ka, kb] = end_curvatures(m, a, b);
      ASSERT_NEAR(c.curvature(0.0) * L, ka, 1e-10 * (1 + std::abs(ka)));
      ASSERT_NEAR(c.curvature(1.0) * L, kb, 1e-10 * (1 + std::abs(kb)));
      if (m.basis == MinEnergyBasis::kCondG2) {
        // (3.1) with μ = λ⁻³: the energy is consistent with end curvatures (Theorem 4.4).
        const BasicEnergy e = basic_energy(m, a, b);
        const double mu = 1 / (m.lambda * m.lambda * m.lambda);
        ASSERT_NEAR(-ka, mu * e.ea, 1e-12 * (1 + std::abs(ka)));
        ASSERT_NEAR(kb, mu * e.eb, 1e-12 * (1 + std::abs(kb)));
      }
    }
  }
  // Corollary 3.7's Q(α, 0) = ∂κ_a/∂β + ∂κ_b/∂α: 0 for the conditionally G2 cubic, negative
  // for Jaklič–Žagar (0 < α < π/2) and Yong–Cheng (0 < α ≤ π/3), Examples 4.1, 4.2.
  auto q = [](const BasicCurveMethod& m, double a) {
    const double h = 1e-5;
    return (end_curvatures(m, a, h).first - end_curvatures(m, a, -h).first) / (2 * h) +
           (end_curvatures(m, a + h, 0).second - end_curvatures(m, a - h, 0).second) / (2 * h);
  };
  for (double a = 1 * kDeg; a <= 60 * kDeg + 1e-12; a += 1 * kDeg) {
    EXPECT_NEAR(q(cond_g2(1.3), a), 0, 1e-8) << a;
    EXPECT_LT(q(yong_cheng(), a), 0) << a;
    EXPECT_LT(q(jaklic_zagar(), a), 0) << a;
  }
  for (double a = 61 * kDeg; a < 90 * kDeg; a += 1 * kDeg) EXPECT_LT(q(jaklic_zagar(), a), 0) << a;
}

// ---- derivatives and Remark 4.5 ----

TEST(MinEnergyBasic, DerivativesMatchFiniteDifferences) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> ang(-kPi / 2 + 0.01, kPi / 2 - 0.01);
  const std::vector<BasicCurveMethod> methods = {cond_g2(0.5), cond_g2(1),     cond_g2(1.7),
                                                 cond_g2(2.5), jaklic_zagar(), yong_cheng()};
  for (const BasicCurveMethod& m : methods) {
    auto E = [&](double a, double b) { return basic_energy(m, a, b).e; };
    for (int trial = 0; trial < 200; ++trial) {
      const double a = ang(rng), b = ang(rng);
      const BasicEnergy e = basic_energy(m, a, b);
      auto tol = [](double v) { return 1e-6 * std::max(1.0, std::abs(v)); };
      const double h = 1e-5;
      const double ga = (E(a + h, b) - E(a - h, b)) / (2 * h);
      const double gb = (E(a, b + h) - E(a, b - h)) / (2 * h);
      ASSERT_NEAR(e.ea, ga, tol(ga)) << a << " " << b;
      ASSERT_NEAR(e.eb, gb, tol(gb)) << a << " " << b;
      // Second derivatives: Richardson-extrapolated central differences of E.
      auto second = [&](auto&& d2) {
        const double k = 2e-3;
        return (4 * d2(k / 2) - d2(k)) / 3;
      };
      const double haa =
          second([&](double k) { return (E(a + k, b) - 2 * E(a, b) + E(a - k, b)) / (k * k); });
      const double hbb =
          second([&](double k) { return (E(a, b + k) - 2 * E(a, b) + E(a, b - k)) / (k * k); });
      const double hab = second([&](double k) {
        return (E(a + k, b + k) - E(a + k, b - k) - E(a - k, b + k) + E(a - k, b - k)) /
               (4 * k * k);
      });
      ASSERT_NEAR(e.eaa, haa, tol(haa)) << a << " " << b;
      ASSERT_NEAR(e.ebb, hbb, tol(hbb)) << a << " " << b;
      ASSERT_NEAR(e.eab, hab, tol(hab)) << a << " " << b;
      // Symmetry E_1(α, β) = E_1(β, α) of all three methods.
      ASSERT_NEAR(E(b, a), e.e, 1e-12 * (1 + e.e));
      ASSERT_NEAR(E(-a, -b), e.e, 1e-12 * (1 + e.e));
    }
  }
}

TEST(MinEnergyBasic, HessianOfRemark45AndTheSection6Typo) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ang(-kPi / 2, kPi / 2);
  for (double lambda : {0.5, 1.0, 1.5, 2.0, 2.9}) {
    const BasicCurveMethod m = cond_g2(lambda);
    for (int trial = 0; trial < 200; ++trial) {
      const double a = ang(rng), b = ang(rng), cd = std::cos(a - b);
      const BasicEnergy e = basic_energy(m, a, b);
      ASSERT_NEAR(e.eaa, 2 * lambda * (-lambda * cd + 3 * std::cos(a)), 1e-13);
      ASSERT_NEAR(e.ebb, 2 * lambda * (-lambda * cd + 3 * std::cos(b)), 1e-13);
      ASSERT_NEAR(e.eab, 2 * lambda * lambda * cd, 1e-13);
      // Proposition 6.2's determinant.
      const double det =
          4 * lambda * lambda *
          (9 * std::cos(a) * std::cos(b) - 3 * lambda * cd * (std::cos(a) + std::cos(b)));
      ASSERT_NEAR(e.eaa * e.ebb - e.eab * e.eab, det, 1e-11 * (1 + std::abs(det)));
    }
    // At (0, 0): zero gradient, H_1(0,0) = 2λ[[3−λ, λ], [λ, 3−λ]], eigenvalues d ± e of the
    // symmetric Toeplitz matrix: 6λ and 2λ(3 − 2λ) — positive definite iff λ < 3/2.
    const BasicEnergy z = basic_energy(m, 0, 0);
    EXPECT_EQ(z.ea, 0.0);
    EXPECT_EQ(z.eb, 0.0);
    EXPECT_NEAR(z.eaa, 2 * lambda * (3 - lambda), 1e-13);
    EXPECT_NEAR(z.ebb, 2 * lambda * (3 - lambda), 1e-13);
    EXPECT_NEAR(z.eab, 2 * lambda * lambda, 1e-13);
    EXPECT_NEAR(z.eaa + z.eab, 6 * lambda, 1e-13);
    EXPECT_NEAR(z.eaa - z.eab, 2 * lambda * (3 - 2 * lambda), 1e-13);
  }
  // Section 6 restates H_1(0,0) as 2λ[[3−λ, 1], [1, 3−λ]] with eigenvalues 6 − 4λ and 6. That is
  // a typo: the off-diagonal entry is 2λ·λ (Remark 4.5), and 6 − 4λ, 6 are the eigenvalues of
  // H_1(0,0)/λ (the conclusion "positive definite iff λ < 3/2" is unaffected). At λ = 2 the
  // printed off-diagonal would be 2λ·1 = 4; the true one is 8, and the true eigenvalues are
  // 12 and −4 (the printed matrix would have 8 and 0).
  const BasicEnergy z2 = basic_energy(cond_g2(2.0), 0, 0);
  EXPECT_NEAR(z2.eab, 8.0, 1e-13);
  EXPECT_GT(std::abs(z2.eab - 4.0), 3.9);
  EXPECT_NEAR(z2.eaa + z2.eab, 12.0, 1e-13);
  EXPECT_NEAR(z2.eaa - z2.eab, -4.0, 1e-13);
  // Proposition 6.2: E_1 strictly convex on [−Ω_conv, Ω_conv]², Ω_conv = acos(2λ/3).
  for (double lambda : {0.5, 1.0, 1.2, 1.45}) {
    const double oc = std::acos(2 * lambda / 3);
    std::uniform_real_distribution<double> in(-oc, oc);
    for (int trial = 0; trial < 2000; ++trial) {
      const BasicEnergy e = basic_energy(cond_g2(lambda), in(rng), in(rng));
      ASSERT_GT(e.eaa, 0);
      ASSERT_GT(e.eaa * e.ebb - e.eab * e.eab, 0);
    }
    // ... and not beyond: at the corner (Ω_conv + δ, Ω_conv + δ) the determinant is negative.
    const BasicEnergy out = basic_energy(cond_g2(lambda), oc + 0.02, oc + 0.02);
    EXPECT_LT(out.eaa * out.ebb - out.eab * out.eab, 0) << lambda;
  }
}

// ---- Theorem 3.3: conditional G2 ----

TEST(MinEnergyFit, ConditionalG2AtEveryInactiveNodeAndNaturalEnds) {
  int checked = 0, active_total = 0, active_jumps = 0, free_ends = 0;
  auto run = [&](const std::string& name, double lambda, const FitInput& in) {
    const nlohmann::json opt =
        name == "quasi-elastic" ? nlohmann::json::object() : nlohmann::json{{"lambda", lambda}};
    const FitResult r = fit(name, in, opt, ReportLevel::kBasic);
    const std::vector<std::size_t> active = active_of(r);
    const std::vector<double> jump = curvature_jumps(r, in);
    for (std::size_t i = 0; i < jump.size(); ++i) {
      const bool is_active = std::find(active.begin(), active.end(), i) != active.end();
      if (jump[i] < 0) continue;
      if (is_active) {
        ++active_total;
        active_jumps += jump[i] > 1e-6;
      } else {
        ++checked;
        ASSERT_LT(jump[i], 1e-8) << name << " lambda " << lambda << " point " << i << " of "
                                 << jump.size() << (in.closed ? " closed" : " open");
      }
    }
    // Free ends: ∂E/∂α = 0 there, so κ = −μ ∂E/∂α = 0 (natural end condition).
    if (!r.closed) {
      const auto& segs = r.spline.segments;
      const std::size_t n = r.points.size();
      for (std::size_t i : {std::size_t{0}, n - 1}) {
        if (std::find(active.begin(), active.end(), i) != active.end()) continue;
        const CubicBezier& b = i == 0 ? segs.front().bezier : segs.back().bezier;
        const double k = b.curvature(i == 0 ? 0.0 : 1.0) * norm(b.p[3] - b.p[0]);
        ASSERT_LT(std::abs(k), 1e-8) << name << " end " << i;
        ++free_ends;
      }
    }
  };
  for (std::uint64_t seed = 0; seed < 6; ++seed) {
    const std::vector<Point> gentle = random_walk(30 + 5 * seed, seed, 60);
    const std::vector<Point> wild = random_walk(30, 100 + seed, 150);
    for (const FitInput& in : {input_of(gentle), input_of(wild), input_of(wild, true)}) {
      run("quasi-elastic", 1.0, in);
      run("cond-g2", 0.7, in);
      run("cond-g2", 1.8, in);
    }
  }
  for (std::size_t n : {5, 12, 40}) {
    run("quasi-elastic", 1.0, input_of(testing::ellipse(n), true));
    run("cond-g2", 1.8, input_of(testing::ellipse(n, 3, 0.5), true));
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(free_ends, 20);
  // Where a bound is active the curvature does jump: the condition is not vacuous.
  EXPECT_GT(active_total, 10);
  EXPECT_GT(active_jumps, active_total / 2);
}

// ---- Example 5.2: Ω = 90°, |ψ_i| ≤ atan(√(9−λ²)/λ) ⇒ no active bound ----

TEST(MinEnergyFit, Example52NoActiveBoundBelowPsi) {
  for (double lambda : {1.0, 2.0}) {
    const double psi_max = std::atan(std::sqrt(9 - lambda * lambda) / lambda);
    for (std::uint64_t seed = 0; seed < 10; ++seed) {
      const std::vector<Point> pts = random_walk(40, 200 + seed, 0.999 * psi_max / kDeg);
      for (double psi : stencil_angles(pts, false)) ASSERT_LE(std::abs(psi), psi_max);
      const FitResult r = fit_with(cond_g2(lambda), input_of(pts));
      EXPECT_TRUE(active_of(r).empty()) << lambda << " seed " << seed;
      for (double j : curvature_jumps(r, input_of(pts))) ASSERT_LT(j, 1e-8);
    }
    // A turn at exactly Ψ (the extreme of Example 5.2) still leaves the direction interior.
    const std::vector<Point> edge = {{-1, 0}, {0, 0}, from_angle(psi_max)};
    EXPECT_TRUE(active_of(fit_with(cond_g2(lambda), input_of(edge))).empty());
  }
  // Sharper turns do activate bounds (λ = 2: Ψ ≈ 48.2°), so the check above can fail.
  EXPECT_FALSE(active_of(fit_with(cond_g2(2.0), input_of(random_walk(30, 100, 150)))).empty());
}

// ---- Proposition 6.3: the green zone ----

/// An independent minimizer of the total energy: cyclic coordinate Newton (each node's angle
/// relative to the bisector of its chords, within its feasible box) from a given start.
/// Returns the absolute direction angles.
struct Problem {
  std::vector<double> phi, len, ref, bound;
  bool closed = false;
};
Problem make_problem(const std::vector<Point>& p, bool closed, double omega) {
  Problem pr;
  pr.closed = closed;
  const std::size_t n = p.size(), segs = closed ? n : n - 1;
  for (std::size_t s = 0; s < segs; ++s) {
    pr.phi.push_back(angle(p[(s + 1) % n] - p[s]));
    pr.len.push_back(norm(p[(s + 1) % n] - p[s]));
  }
  const std::vector<double> psi = stencil_angles(p, closed);
  for (std::size_t i = 0; i < n; ++i) {
    const bool has_prev = closed || i > 0, has_next = closed || i + 1 < n;
    const double prev = has_prev ? pr.phi[(i + segs - 1) % segs] : pr.phi[0];
    pr.ref.push_back(has_next && has_prev ? prev + 0.5 * psi[i] : has_next ? pr.phi[i] : prev);
    pr.bound.push_back(omega - 0.5 * std::abs(psi[i]));
  }
  return pr;
}
/// Energy of segment s at node angles x (relative to ref).
BasicEnergy segment_energy(const Problem& pr, const BasicCurveMethod& m,
                           const std::vector<double>& x, std::size_t s) {
  const std::size_t j = (s + 1) % x.size();
  BasicEnergy be =
      basic_energy(m, wrap(pr.ref[s] + x[s] - pr.phi[s]), wrap(pr.ref[j] + x[j] - pr.phi[s]));
  for (double* v : {&be.e, &be.ea, &be.eb, &be.eaa, &be.eab, &be.ebb}) *v /= pr.len[s];
  return be;
}
double problem_energy(const Problem& pr, const BasicCurveMethod& m, const std::vector<double>& x) {
  double e = 0.0;
  for (std::size_t s = 0; s < pr.phi.size(); ++s) e += segment_energy(pr, m, x, s).e;
  return e;
}
std::vector<double> coordinate_newton(const Problem& pr, const BasicCurveMethod& m,
                                      std::vector<double> x) {
  const std::size_t n = x.size(), segs = pr.phi.size();
  for (int sweep = 0; sweep < 5000; ++sweep) {
    double change = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      for (int it = 0; it < 30; ++it) {
        double g = 0.0, h = 0.0;
        if (i < segs) {  // the segment starting at i
          const BasicEnergy e = segment_energy(pr, m, x, i);
          g += e.ea, h += e.eaa;
        }
        if (pr.closed || i > 0) {  // the segment ending at i
          const BasicEnergy e = segment_energy(pr, m, x, (i + segs - 1) % segs);
          g += e.eb, h += e.ebb;
        }
        const double next = std::clamp(x[i] - g / h, -pr.bound[i], pr.bound[i]);
        const double step = std::abs(next - x[i]);
        change = std::max(change, step);
        x[i] = next;
        if (step < 1e-15) break;
      }
    }
    if (change < 1e-14) break;
  }
  return x;
}

TEST(MinEnergyFit, Proposition63GreenZoneIsUniqueAndG2) {
  std::mt19937_64 rng(8);
  int cases = 0;
  for (double lambda : {1.0, 1.2}) {
    const double omega = std::acos(2 * lambda / 3);
    // Ψ = Ω − atan f(Ω), f(α) = sin α / (3/λ − cos α), as the proof derives it:
    // atan(λ√(9−4λ²)/(9−2λ²)). The statement prints atan(√(9−4λ²)/(9−2λ)), equal only at
    // λ = 1 (30.47°); at λ = 1.2 it gives 21.61° where the bound is 17.43° (an erratum).
    const double psi_max =
        omega - std::atan(lambda * std::sqrt(9 - 4 * lambda * lambda) / (9 - 2 * lambda * lambda));
    if (lambda == 1.0) {
      EXPECT_NEAR(psi_max / kDeg, 30.5, 0.05);  // the introduction's 30.5°
    }
    MinEnergyOptions opt;
    opt.method = cond_g2(lambda, omega);
    for (std::uint64_t seed = 0; seed < 4; ++seed) {
      std::vector<FitInput> inputs = {
          input_of(random_walk(25, 300 + seed, 0.999 * psi_max / kDeg))};
      if (seed < 2) inputs.push_back(input_of(testing::ellipse(32 + 8 * seed, 2, 1.5), true));
      for (const FitInput& in : inputs) {
        for (double psi : stencil_angles(in.points, in.closed)) ASSERT_LE(std::abs(psi), psi_max);
        const FitResult r = fit("cond-g2", in, {{"lambda", lambda}, {"omega_deg", omega / kDeg}},
                                ReportLevel::kBasic);
        EXPECT_TRUE(active_of(r).empty());
        for (double j : curvature_jumps(r, in)) ASSERT_LT(j, 1e-8);
        const double e = r.method_report["energy"].get<double>();
        // The slow reference reaches the same minimum.
        const MinEnergyReference ref = min_energy_reference(in, opt);
        EXPECT_NEAR(ref.energy, e, 1e-9 * e) << lambda << " " << seed;
        for (std::size_t i = 0; i < in.points.size(); ++i) {
          EXPECT_NEAR(wrap(ref.angles[i] - angle(r.tangents[i])), 0, 1e-4) << i;
        }
        // Cyclic coordinate Newton from random feasible starts reaches the same directions.
        const Problem pr = make_problem(in.points, in.closed, omega);
        for (int start = 0; start < 3; ++start) {
          std::vector<double> x0;
          for (double b : pr.bound)
            x0.push_back(std::uniform_real_distribution<double>(-b, b)(rng));
          const std::vector<double> x = coordinate_newton(pr, opt.method, x0);
          EXPECT_NEAR(problem_energy(pr, opt.method, x), e, 1e-12 * e);
          for (std::size_t i = 0; i < x.size(); ++i) {
            ASSERT_NEAR(wrap(pr.ref[i] + x[i] - angle(r.tangents[i])), 0, 1e-8)
                << i << " start " << start;
          }
        }
        ++cases;
      }
    }
  }
  EXPECT_EQ(cases, 12);
}

// ---- the projected Newton solver against the reference ----

struct Case {
  std::string what;
  BasicCurveMethod method;
  FitInput input;
};

/// Direction at point i (interior) rotated by `frac` of its feasible half-width from the bisector.
Vec2 feasible_direction(const std::vector<Point>& p, std::size_t i, double omega, double frac) {
  const std::size_t n = p.size();
  const Vec2 in = p[i] - p[(i + n - 1) % n], out = p[(i + 1) % n] - p[i];
  const double psi = signed_angle(in, out);
  return from_angle(angle(in) + 0.5 * psi + frac * (omega - 0.5 * std::abs(psi)));
}

std::vector<Case> reference_cases() {
  std::vector<Case> cases;
  const BasicCurveMethod qe = cond_g2(1.0), g2 = cond_g2(1.8), jz = jaklic_zagar(),
                         yc = yong_cheng();
  auto walk = [](std::size_t n, std::uint64_t seed, double turn) {
    return random_walk(n, seed, turn);
  };
  cases.push_back({"open qe", qe, input_of(walk(40, 11, 120))});
  cases.push_back({"closed qe", qe, input_of(walk(30, 12, 120), true)});
  cases.push_back({"open cond-g2 1.8", g2, input_of(walk(25, 13, 120))});
  {
    FitInput in = input_of(walk(35, 14, 120));
    in.start_tangent = from_angle(angle(in.points[1] - in.points[0]) + 40 * kDeg);
    in.end_tangent = from_angle(angle(in.points[34] - in.points[33]) - 70 * kDeg);
    cases.push_back({"start/end tangents qe", qe, in});
  }
  {
    FitInput in = input_of(walk(30, 15, 120));
    in.kinds.assign(30, PointKind::kSmooth);
    in.kinds[9] = in.kinds[20] = PointKind::kCorner;
    cases.push_back({"corners qe", qe, in});
  }
  {
    FitInput in = input_of(walk(30, 16, 120), true);
    in.kinds.assign(30, PointKind::kSmooth);
    in.kinds[7] = PointKind::kCorner;
    cases.push_back({"closed one corner qe", qe, in});
  }
  {
    FitInput in = input_of(walk(30, 17, 90));
    in.kinds.assign(30, PointKind::kSmooth);
    in.tangents.assign(30, std::nullopt);
    in.kinds[12] = PointKind::kClamped;
    in.tangents[12] = feasible_direction(in.points, 12, qe.omega, 0.6);
    in.kinds[13] = PointKind::kClamped;
    in.tangents[13] = feasible_direction(in.points, 13, qe.omega, -0.999999);  // at the bound
    cases.push_back({"clamped qe", qe, in});
  }
  cases.push_back({"open jz", jz, input_of(walk(30, 18, 60))});
  cases.push_back({"closed jz", jz, input_of(wobbly_ellipse(24, 19), true)});
  {
    FitInput in = input_of(walk(20, 20, 60));
    in.start_tangent = from_angle(angle(in.points[1] - in.points[0]) - 30 * kDeg);
    in.kinds.assign(20, PointKind::kSmooth);
    in.kinds[10] = PointKind::kCorner;
    cases.push_back({"corner + start jz", jz, in});
  }
  cases.push_back({"open yc", yc, input_of(walk(20, 21, 60))});
  {
    FitInput in = input_of(wobbly_ellipse(20, 22), true);
    in.kinds.assign(20, PointKind::kSmooth);
    in.tangents.assign(20, std::nullopt);
    in.kinds[5] = PointKind::kClamped;
    in.tangents[5] = feasible_direction(in.points, 5, yc.omega, 0.3);
    cases.push_back({"closed clamped yc", yc, in});
  }
  return cases;
}

TEST(MinEnergyFit, NewtonIsAtLeastAsGoodAsTheReference) {
  for (const Case& c : reference_cases()) {
    SCOPED_TRACE(c.what);
    const FitInput& in = c.input;
    const std::size_t n = in.points.size();
    MinEnergyOptions opt;
    opt.method = c.method;
    FitResult r;
    MinEnergyReport rep;
    fit_min_energy(in, opt, ReportLevel::kBasic, r, &rep);
    const MinEnergyReference ref = min_energy_reference(in, opt);
    EXPECT_LE(rep.energy, ref.energy * (1 + 1e-12) + 1e-15);
    // Not wildly different either (the reference is a real minimizer).
    EXPECT_GE(rep.energy, ref.energy * (1 - 1e-3));
    // The reported energy is that of the output pieces.
    EXPECT_NEAR(recomputed_energy(r, c.method), rep.energy, 1e-12 * rep.energy);
    EXPECT_EQ(r.method_report["energy"].get<double>(), rep.energy);
    EXPECT_EQ(r.method_report["status"], "converged");
    EXPECT_EQ(r.method_report["iterations"].get<int>(), rep.iterations);
    EXPECT_EQ(active_of(r), rep.active);
    EXPECT_LE(rep.projected_gradient, opt.tolerance);
    // Newton with the exact (cyclic) tridiagonal Hessian: a handful of iterations (3 to 8 here).
    EXPECT_LE(rep.iterations, 15);
    // One piece per corner-separated chain.
    std::size_t corners = 0;
    for (std::size_t i = 0; i < in.kinds.size(); ++i) {
      corners += in.kinds[i] == PointKind::kCorner && (in.closed || (i > 0 && i + 1 < n));
    }
    EXPECT_EQ(static_cast<std::size_t>(rep.pieces),
              in.closed ? std::max<std::size_t>(corners, 1) : corners + 1);
    // Interpolation, feasibility, G1 at smooth nodes, clamped directions kept.
    const auto& segs = r.spline.segments;
    ASSERT_EQ(segs.size(), in.closed ? n : n - 1);
    for (std::size_t s = 0; s < segs.size(); ++s) {
      EXPECT_EQ(segs[s].bezier.p[0], in.points[s]);
      EXPECT_EQ(segs[s].bezier.p[3], in.points[(s + 1) % n]);
      const ChordAngles a = chord_angles(segs[s].bezier);
      EXPECT_LE(std::abs(a.alpha), c.method.omega + 1e-12) << s;
      EXPECT_LE(std::abs(a.beta), c.method.omega + 1e-12) << s;
      // Each piece is the basic curve of its end angles (speeds included).
      const CubicBezier b =
          basic_curve(c.method, in.points[s], in.points[(s + 1) % n], a.alpha, a.beta);
      for (int j = 1; j < 3; ++j) {
        EXPECT_LT(norm(b.p[j] - segs[s].bezier.p[j]), 1e-12 * (1 + testing::scale_of(in.points)))
            << s;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const bool corner = i < in.kinds.size() && in.kinds[i] == PointKind::kCorner;
      const Vec2 leg = i < segs.size() ? segs[i].bezier.p[1] - segs[i].bezier.p[0]
                                       : segs.back().bezier.p[3] - segs.back().bezier.p[2];
      EXPECT_LT(std::abs(signed_angle(r.tangents[i], leg)), 1e-12) << "tangent " << i;
      if ((in.closed || (i > 0 && i + 1 < n)) && !corner) {
        const CubicBezier& left = segs[(i + n - 1) % n].bezier;
        EXPECT_LT(std::abs(signed_angle(left.p[3] - left.p[2], r.tangents[i])), 1e-12)
            << "G1 " << i;
      }
      if (i < in.kinds.size() && in.kinds[i] == PointKind::kClamped) {
        EXPECT_LT(std::abs(signed_angle(*in.tangents[i], r.tangents[i])), 1e-14) << i;
        // A given direction is not a free variable at a bound, even where it sits on one.
        EXPECT_EQ(std::count(rep.active.begin(), rep.active.end(), i), 0) << i;
      }
    }
    if (in.start_tangent) {
      EXPECT_LT(std::abs(signed_angle(*in.start_tangent, r.tangents[0])), 1e-14);
      EXPECT_EQ(std::count(rep.active.begin(), rep.active.end(), 0), 0);
    }
    if (in.end_tangent) {
      EXPECT_LT(std::abs(signed_angle(*in.end_tangent, r.tangents[n - 1])), 1e-14);
      EXPECT_EQ(std::count(rep.active.begin(), rep.active.end(), n - 1), 0);
    }
    // The reference's own energy is that of its angles (no corners: one angle per point).
    if (std::find(in.kinds.begin(), in.kinds.end(), PointKind::kCorner) == in.kinds.end()) {
      double e = 0.0;
      for (std::size_t s = 0; s < segs.size(); ++s) {
        const Vec2 chord = in.points[(s + 1) % n] - in.points[s];
        e += basic_energy(c.method, wrap(ref.angles[s] - angle(chord)),
                          wrap(ref.angles[(s + 1) % n] - angle(chord)))
                 .e /
             norm(chord);
      }
      EXPECT_NEAR(e, ref.energy, 1e-12 * ref.energy);
    }
  }
}

/// The fit started at the bisectors (x = 0 at every node: the start before the quadratic model's),
/// through the warm-start entry with the chord bisectors as span directions.
MinEnergyReport fit_from_bisectors(const FitInput& in, const MinEnergyOptions& opt, FitResult& r) {
  const std::vector<Point>& p = in.points;
  const std::size_t n = p.size(), segs = in.closed ? n : n - 1;
  auto unit = [&](std::size_t s) { return normalized(p[(s + 1) % n] - p[s]); };
  auto bisector = [&](std::size_t i) {
    const bool inner = in.closed || (i > 0 && i + 1 < n);
    if (!inner) return i == 0 ? unit(0) : unit(n - 2);
    return normalized(unit((i + n - 1) % n) + unit(i));
  };
  detail::SpanDirections warm(segs);
  for (std::size_t s = 0; s < segs; ++s) warm[s] = {bisector(s), bisector((s + 1) % n)};
  MinEnergyReport rep;
  detail::fit_min_energy_at(in, opt, ReportLevel::kNone, r, &rep, &warm, nullptr);
  return rep;
}

// The default start (the minimizer of the energy's quadratic model about straight spans, for
// quasi-elastic with stencil angles within ±120°) reaches the bisector start's minimum, in fewer
// iterations; elsewhere (sharper stencils, λ >= 3/2) the start is the bisectors', bit for bit.
TEST(MinEnergyFit, QuadraticModelStartReachesTheBisectorMinimumFaster) {
  int fewer = 0, total_model = 0, total_bisector = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    for (double turn : {30.0, 90.0, 120.0}) {
      SCOPED_TRACE(::testing::Message() << "seed " << seed << " turn " << turn);
      FitInput in;
      in.points = random_walk(300, seed, turn);
      in.closed = seed % 4 == 0;
      MinEnergyOptions opt;
      FitResult a, b;
      MinEnergyReport model;
      fit_min_energy(in, opt, ReportLevel::kNone, a, &model);
      const MinEnergyReport bis = fit_from_bisectors(in, opt, b);
      EXPECT_NEAR(model.energy, bis.energy, 1e-12 * bis.energy);
      for (std::size_t i = 0; i < a.tangents.size(); ++i) {
        EXPECT_NEAR(a.tangents[i].x, b.tangents[i].x, 1e-8);
        EXPECT_NEAR(a.tangents[i].y, b.tangents[i].y, 1e-8);
      }
      fewer += model.iterations < bis.iterations;
      EXPECT_LE(model.iterations, bis.iterations + 1);
      total_model += model.iterations;
      total_bisector += bis.iterations;
    }
  }
  // Measured: 120 walks of 300 points, 558 iterations in all from the bisectors and 471 from
  // the model; 68 walks took fewer (none more than one more).
  EXPECT_GE(fewer, 55);
  EXPECT_LE(total_model * 10, total_bisector * 9);
  for (const auto& [turn, lambda] : {std::pair{175.0, 1.0}, std::pair{90.0, 1.6}}) {
    SCOPED_TRACE(::testing::Message() << "turn " << turn << " lambda " << lambda);
    FitInput in;
    in.points = random_walk(200, 7, turn);
    MinEnergyOptions opt;
    opt.method = cond_g2(lambda);
    FitResult a, b;
    MinEnergyReport model;
    fit_min_energy(in, opt, ReportLevel::kNone, a, &model);
    const MinEnergyReport bis = fit_from_bisectors(in, opt, b);
    // (The warm start's bisectors differ from the chain's by rounding.)
    EXPECT_NEAR(model.energy, bis.energy, 1e-14 * bis.energy);
    EXPECT_EQ(model.iterations, bis.iterations);
  }
}

TEST(MinEnergyFit, RegistryNamesAndOptions) {
  EXPECT_EQ(default_method_name(), "quasi-elastic");
  const std::vector<Point> pts = random_walk(20, 30, 100);
  const FitInput in = input_of(pts);
  const FitResult qe = fit("quasi-elastic", in, {}, ReportLevel::kBasic);
  const FitResult me = fit("min-energy", in, {}, ReportLevel::kBasic);
  const FitResult g1 = fit("cond-g2", in, {{"lambda", 1.0}}, ReportLevel::kBasic);
  const FitResult g = fit("cond-g2", in, {{"lambda", 1.7}}, ReportLevel::kBasic);
  const FitResult mg =
      fit("min-energy", in, {{"basis", "cond-g2"}, {"lambda", 1.7}}, ReportLevel::kBasic);
  for (std::size_t s = 0; s < qe.spline.segments.size(); ++s) {
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(qe.spline.segments[s].bezier.p[k], me.spline.segments[s].bezier.p[k]);
      EXPECT_EQ(qe.spline.segments[s].bezier.p[k], g1.spline.segments[s].bezier.p[k]);
      EXPECT_EQ(g.spline.segments[s].bezier.p[k], mg.spline.segments[s].bezier.p[k]);
    }
  }
  EXPECT_GT(
      std::abs(g.method_report["energy"].get<double>() - qe.method_report["energy"].get<double>()),
      1e-3);
  // quasi-elastic is λ = 1: it lists no lambda option (front ends show the options a method
  // lists; issue 20, bug 4), and basis=quasi-elastic with another lambda is a bad option, not
  // silently ignored, with the option that gets past it as a hint.
  const Error unknown = testing::expect_error([&] { fit("quasi-elastic", in, {{"lambda", 2.0}}); });
  EXPECT_EQ(unknown.code(), ErrorCode::kUnknownOption);
  for (const OptionSpec& o : find_method("quasi-elastic").options) EXPECT_NE(o.name, "lambda");
  const Error bad = testing::expect_error(ErrorCode::kBadOption,
                                          [&] {
                                            fit("min-energy", in, {{"lambda", 2.0}});
                                          },
                                          {"lambda = 1"});
  ASSERT_TRUE(bad.hint());
  EXPECT_EQ(bad.hint()->name, "basis");
  EXPECT_EQ(bad.hint()->value, "cond-g2");
  EXPECT_EQ(std::string(bad.what()).find("--"), std::string::npos) << bad.what();
  // basis=yong-cheng beyond acos(1/3): speeds could turn negative.
  EXPECT_EQ(testing::expect_error([&] {
              fit("min-energy", in, {{"basis", "yong-cheng"}, {"omega_deg", 75}});
            }).code(),
            ErrorCode::kBadOption);
  // Default Ω per basis, reported.
  EXPECT_EQ(qe.method_report["omega_deg"].get<double>(), 90.0);
  EXPECT_NEAR(fit("min-energy", input_of(random_walk(10, 1, 60)), {{"basis", "jaklic-zagar"}})
                  .method_report["omega_deg"]
                  .get<double>(),
              80.0, 1e-12);
  EXPECT_NEAR(fit("min-energy", input_of(random_walk(10, 1, 60)), {{"basis", "yong-cheng"}})
                  .method_report["omega_deg"]
                  .get<double>(),
              60.0, 1e-12);
  EXPECT_EQ(BasicCurveMethod::default_omega(MinEnergyBasis::kCondG2), kPi / 2);
  // A smaller Ω can only raise the minimum; with Ω at 60° some bound is active here.
  const FitResult small = fit("min-energy", in, {{"omega_deg", 60}}, ReportLevel::kBasic);
  EXPECT_GE(small.method_report["energy"].get<double>(),
            qe.method_report["energy"].get<double>() * (1 - 1e-12));
  EXPECT_FALSE(active_of(small).empty());
  // kNone reports no active list but the same curve.
  const FitResult none = fit("quasi-elastic", in, {}, ReportLevel::kNone);
  EXPECT_FALSE(none.method_report.contains("active"));
  EXPECT_EQ(none.method_report["energy"], qe.method_report["energy"]);
}

// KNOWN BUG (fails): fit_min_energy ignores FitInput::start_tangent on a closed curve
// (build_chains: `if (!closed && input.start_tangent) given[0] = ...`). The input checks tell the
// user to "clamp a point with kinds/tangents or use the start tangent" on a closed curve, and the
// Jaklič–Žagar, Li, Kozák–Krajnc and Yong–Cheng methods honour it there.
TEST(MinEnergyFit, ClosedCurveHonoursStartTangent) {
  const std::vector<Point> pts = testing::ellipse(12);
  FitInput in = input_of(pts, true);
  const Vec2 t0 = feasible_direction(pts, 0, kPi / 2, 0.5);
  in.start_tangent = t0;
  const FitResult r = fit("quasi-elastic", in, {}, ReportLevel::kBasic);
  EXPECT_LT(std::abs(signed_angle(t0, r.tangents[0])), 1e-14)
      << "start_tangent ignored on a closed curve";
  const CubicBezier& first = r.spline.segments.front().bezier;
  EXPECT_LT(std::abs(signed_angle(t0, first.p[1] - first.p[0])), 1e-14);
  // The same clamp given through kinds/tangents works.
  FitInput k = input_of(pts, true);
  k.kinds.assign(pts.size(), PointKind::kSmooth);
  k.tangents.assign(pts.size(), std::nullopt);
  k.kinds[0] = PointKind::kClamped;
  k.tangents[0] = t0;
  EXPECT_LT(std::abs(signed_angle(t0, fit("quasi-elastic", k).tangents[0])), 1e-14);
}

// KNOWN BUG (fails): with a corner at the last point of a closed curve, FitResult::tangents
// reports the corner's incoming direction instead of its outgoing one (every other corner, and
// every other method, report the direction of the piece starting there). In fit_min_energy the
// condition `ch.closed || t + 1 < k || ch.node[t] == n - 1` meant for the last point of an open
// curve also fires for the closing node of the (open) chain of a closed curve, overwriting the
// outgoing angle; `(!out.closed && ch.node[t] == n - 1)` would fix it. The spline is right.
TEST(MinEnergyFit, ClosedCurveCornerAtTheLastPointReportsOutgoingTangent) {
  const std::vector<Point> pts = testing::ellipse(12);
  for (std::size_t corner : {std::size_t{4}, pts.size() - 1}) {
    FitInput c = input_of(pts, true);
    c.kinds.assign(pts.size(), PointKind::kSmooth);
    c.kinds[corner] = PointKind::kCorner;
    const FitResult r = fit("quasi-elastic", c, {}, ReportLevel::kBasic);
    const CubicBezier& out = r.spline.segments[corner].bezier;
    const CubicBezier& in = r.spline.segments[(corner + pts.size() - 1) % pts.size()].bezier;
    EXPECT_GT(std::abs(signed_angle(in.p[3] - in.p[2], out.p[1] - out.p[0])), 0.1);  // a corner
    EXPECT_LT(std::abs(signed_angle(out.p[1] - out.p[0], r.tangents[corner])), 1e-12)
        << "corner " << corner << ": the tangent is the incoming direction";
  }
}

// KNOWN BUG (fails): the default method throws Error(kNotConverged) on about 6% of 3-point and
// 3% of 4-point open random walks (random_walk(n, seed, 90)), e.g. quasi-elastic on
// {(0,0), (1,0), (1.8,0.1)}. After two Newton steps the relative projected gradient is ~1.5e-10,
// just above the tolerance 1e-10, but E_1 = 2cos(α−β) − 6(cos α + cos β) + 10 is evaluated with
// cancellation (terms ~12/L, absolute rounding ~1e-15/L) while the remaining decrease is ~1e-20:
// the Armijo test sees only rounding noise, rejects the Newton and the gradient steps, and the
// solver gives up. The "rounding-level" acceptance of a full Newton step (en <= energy +
// 1e-14·|energy|·√k) does not help: it is relative to the total energy (here 0.013), not to the
// size of the terms that cancel. Only λ = 1 is affected (for λ ≠ 1 the energy ≥ 6(λ−1)²/L is
// large enough for that slack to cover the noise). A cancellation-free E_1 (e.g. 6(λ−1)²
// + 12λ(sin²(α/2) + sin²(β/2)) − 4λ² sin²((α−β)/2)) or a slack relative to Σ(|terms|)/L would
// fix it. The error message also prints the gradient with std::to_string: "projected gradient
// 0.000000 (relative), above the tolerance".
TEST(MinEnergyFit, ConvergesOnShortNearlyStraightData) {
  for (double y : {0.1, -0.1, 0.2, -0.2}) {
    const FitInput in = input_of({{0, 0}, {1, 0}, {1.8, y}});
    try {
      const FitResult r = fit("quasi-elastic", in, {}, ReportLevel::kNone);
      EXPECT_LE(r.method_report["projected_gradient"].get<double>(), 1e-10);
    } catch (const Error& e) {
      ADD_FAILURE() << "y = " << y << ": " << e.what();
    }
  }
  int failures = 0;
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    for (std::size_t n : {3, 4, 6}) {
      try {
        (void)fit("quasi-elastic", input_of(random_walk(n, seed, 90)), {}, ReportLevel::kNone);
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::kNotConverged);
        ++failures;
      }
    }
  }
  EXPECT_EQ(failures, 0);
}

/// The stress suite's seed 18 case 809 (cond-g2, λ = 2.79, an end tangent): the coordinate
/// search's basin (14.44, where Curve Ensemble's optimizer lands too) is above Newton's from the
/// quadratic model's start (13.18); search = coordinate returns the lower.
TEST(MinEnergyFit, CoordinateSearchKeepsNewtonsLowerMinimum) {
  FitInput in = input_of({{0.0, 0.0},
                          {-4.476822666514581, -3.389584067116368},
                          {-11.539346192453545, -7.692667163142648},
                          {-22.929661742719635, -9.627988462796731},
                          {-37.51099991057951, -14.758276304092446},
                          {-44.60774299548056, -17.606308479295265},
                          {-47.402561824308926, -17.33230797766663}});
  in.end_tangent = Vec2{-0.9215057820423046, 0.38836464007759597};
  MinEnergyOptions opt;
  opt.method = cond_g2(2.7912494486443484);
  const testing::Searches s = testing::fit_both_searches(in, opt);
  const MinEnergyReference ref = min_energy_reference(in, opt);
  EXPECT_GT(ref.energy, s.newton.energy * 1.05);
  EXPECT_NEAR(s.coordinate.energy, s.newton.energy, 1e-12 * s.newton.energy);
}

/// Which minimum (issue 18): beyond Ω_conv the energy has several local minima, and Newton from
/// the bisectors misses Curve Ensemble's (the coordinate search's) on many walks for the
/// Yong–Cheng basis and cond-g2 with λ = 1.8. search = coordinate starts Newton from that
/// search's point and keeps search = newton's minimum where that is lower: never above the
/// reference nor newton, and below Newton's local minimum on some walk.
TEST(MinEnergyFit, CoordinateSearchIsNeverAboveTheReference) {
  int below_newton = 0;
  for (const BasicCurveMethod& m : {yong_cheng(), cond_g2(1.8)}) {
    for (std::uint64_t seed = 0; seed < 6; ++seed) {
      SCOPED_TRACE(seed);
      const FitInput in = input_of(random_walk(40, 900 + seed, 110));
      MinEnergyOptions opt;
      opt.method = m;
      const testing::Searches s = testing::fit_both_searches(in, opt, ReportLevel::kBasic);
      const FitResult &a = s.newton_fit, &b = s.coordinate_fit;
      const MinEnergyReport &newton = s.newton, &coordinate = s.coordinate;
      opt.search = MinEnergySearch::kCoordinate;
      const MinEnergyReference ref = min_energy_reference(in, opt);
      EXPECT_LE(coordinate.energy, ref.energy * (1 + 1e-12));
      EXPECT_LE(coordinate.energy, newton.energy * (1 + 1e-12));
      EXPECT_EQ(b.method_report.at("search"), "coordinate");
      EXPECT_EQ(a.method_report.at("search"), "newton");
      EXPECT_NEAR(recomputed_energy(b, m), coordinate.energy, 1e-12 * coordinate.energy);
      if (coordinate.energy < newton.energy * (1 - 1e-9)) ++below_newton;
    }
  }
  EXPECT_GE(below_newton, 1);
  // Through the registry, as every front end passes it.
  const FitInput in = input_of(random_walk(12, 3, 100));
  const FitResult r = fit("min-energy", in, {{"basis", "yong-cheng"}, {"search", "coordinate"}},
                          ReportLevel::kBasic);
  EXPECT_EQ(r.options.at("search"), "coordinate");
  EXPECT_EQ(r.method_report.at("search"), "coordinate");
  expect_error(ErrorCode::kBadOption, [&] {
    (void)fit("restricted-elastic", in, {{"search", "random"}});
  });
}

TEST(MinEnergyFit, GlobalSearchReachesTheBruteForceMinimum) {
  // search=global (the least point of a grid of directions by dynamic programming, then
  // Newton) against brute force over two free directions (a 1° grid over both, then pattern
  // moves), for every cubic basis and restricted-elastic. The listed seeds are inputs where
  // search=newton from the bisectors, or search=coordinate too, stops in a higher minimum
  // (cond-g2 λ = 2.6, seed 105: 22.47 for both against 20.43).
  struct Inputs {
    BasicCurveMethod m;
    std::vector<std::uint64_t> seeds;
  };
  const BasicCurveMethod restricted{MinEnergyBasis::kRestrictedElastic, 1.0, kPi / 2};
  const std::vector<Inputs> inputs{{cond_g2(1.0), {0, 1, 2, 3}},
                                   {cond_g2(2.6), {0, 1, 2, 43, 65, 105, 141}},
                                   {jaklic_zagar(), {0, 1, 2, 3}},
                                   {yong_cheng(), {0, 1, 15, 19, 94}},
                                   {restricted, {0, 1}}};
  int newton_above = 0, coordinate_above = 0;
  for (const auto& [m, seeds] : inputs) {
    for (const std::uint64_t seed : seeds) {
      SCOPED_TRACE(::testing::Message()
                   << static_cast<int>(m.basis) << " λ " << m.lambda << " seed " << seed);
      const testing::TwoFreeDirections t =
          testing::two_free_directions(seed, 1.9 * m.omega / kDeg, m.omega / kDeg);
      const double brute = t.brute_force(m);
      ASSERT_TRUE(std::isfinite(brute));
      MinEnergyOptions o;
      o.method = m;
      auto energy = [&](MinEnergySearch search) {
        o.search = search;
        FitResult r;
        MinEnergyReport rep;
        fit_min_energy(t.input(), o, ReportLevel::kNone, r, &rep);
        EXPECT_NEAR(recomputed_energy(r, m), rep.energy, 1e-12 * rep.energy);
        return rep.energy;
      };
      const double global = energy(MinEnergySearch::kGlobal);
      EXPECT_NEAR(global, brute, 1e-9 * brute);
      const double newton = energy(MinEnergySearch::kNewton);
      if (newton > brute * (1 + 1e-6)) ++newton_above;
      // method_report "minimum": the grid's where it is below Newton's.
      o.search = MinEnergySearch::kGlobal;
      FitResult g;
      fit_min_energy(t.input(), o, ReportLevel::kNone, g);
      EXPECT_EQ(g.method_report.at("minimum"), global < newton * (1 - 1e-9) ? "global" : "newton");
      if (energy(MinEnergySearch::kCoordinate) > brute * (1 + 1e-6)) ++coordinate_above;
    }
  }
  // (7 and 3 of the 22 inputs today.)
  EXPECT_GE(newton_above, 1);
  EXPECT_GE(coordinate_above, 1);
}

/// Issue 18's 20-point walk: quasi-elastic stopped at projected gradient 7.78e-9 after 200
/// iterations (and 1000). A node inside the active band (7.8e-9 from its bound, the gradient
/// pushing outwards) was held there instead of moved onto the bound. Checked independently:
/// KKT conditions of the output's directions by central differences of Σ E_1/L.
/// Σ E/L of the (one or two) spans of an open curve at node i, its direction turned by d.
double node_energy(const BasicCurveMethod& qe, const std::vector<ChordAngles>& a, std::size_t i,
                   double d) {
  double e = 0.0;
  if (i < a.size()) e += basic_energy(qe, a[i].alpha + d, a[i].beta).e / a[i].length;
  if (i > 0) e += basic_energy(qe, a[i - 1].alpha, a[i - 1].beta + d).e / a[i - 1].length;
  return e;
}

TEST(MinEnergyFit, Issue18WalkConvergesToAKktPoint) {
  const FitInput in =
      input_of({{1.7823, -2.0654}, {3.3194, -2.1738}, {3.4487, -1.8315}, {2.9205, -2.3082},
                {4.4087, -3.3094}, {4.0094, -1.7516}, {6.1072, -0.6796}, {6.6874, -0.8872},
                {5.0868, -0.6063}, {5.4886, 0.852},   {4.9722, 0.12},    {6.3907, -0.7327},
                {9.0581, -1.1198}, {8.6779, -2.0987}, {8.4757, -1.3491}, {8.1541, -2.3829},
                {9.4373, -0.9691}, {9.1433, -1.6915}, {9.5098, -1.2932}, {10.3593, -1.0084}});
  const BasicCurveMethod qe = cond_g2(1.0);
  const FitResult r = fit_with(qe, in);
  ASSERT_TRUE(r.solver.has_value());
  EXPECT_EQ(r.solver->status, SolverStatus::kConverged);
  EXPECT_LT(r.solver->iterations, 30);
  const std::size_t n = in.points.size();
  std::vector<ChordAngles> a;
  for (const Segment& s : r.spline.segments) a.push_back(chord_angles(s.bezier));
  // Energy of the two spans at node i with its direction turned by d.
  auto local = [&](std::size_t i, double d) { return node_energy(qe, a, i, d); };
  const double h = 1e-6;
  for (std::size_t i = 0; i < n; ++i) {
    const double g = (local(i, h) - local(i, -h)) / (2.0 * h);
    // The node's box: |α| <= 90° on the next chord and |β| <= 90° on the previous one.
    const double up =
        std::min(i + 1 < n ? kPi / 2 - a[i].alpha : kPi, i > 0 ? kPi / 2 - a[i - 1].beta : kPi);
    const double down =
        std::min(i + 1 < n ? kPi / 2 + a[i].alpha : kPi, i > 0 ? kPi / 2 + a[i - 1].beta : kPi);
    const double scale = 1.0 / a[std::min(i, n - 2)].length;
    if (up < 1e-9) {
      EXPECT_LE(g, 1e-6 * scale) << "node " << i << " on its upper bound";
    } else if (down < 1e-9) {
      EXPECT_GE(g, -1e-6 * scale) << "node " << i << " on its lower bound";
    } else {
      EXPECT_NEAR(g, 0.0, 1e-6 * scale) << "node " << i;
    }
  }
}

// The open chain's LDLᵀ keeps its pivots as ratios of continuants, rescaled by powers of two:
// on a 3000-point walk whose chords span 10^4 (the continuants, products of the pivots, leave
// 2^±512 many times along it) the fit converges to a stationary point, and the reversed walk
// (the system eliminated from the other end, other continuants) reaches the same energy.
TEST(MinEnergyFit, LongChainOfMixedScalesSolvesFromEitherEnd) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> turn(-kPi / 2, kPi / 2), exponent(-3.0, 1.0);
  std::vector<Point> pts;
  Point p{0, 0};
  double heading = 0;
  for (int i = 0; i < 3000; ++i) {
    pts.push_back(p);
    heading += turn(rng);
    p += std::pow(10.0, exponent(rng)) * from_angle(heading);
  }
  const BasicCurveMethod qe = cond_g2(1.0);
  const FitResult r = fit_with(qe, input_of(pts));
  std::vector<Point> rev(pts.rbegin(), pts.rend());
  const FitResult b = fit_with(qe, input_of(rev));
  ASSERT_TRUE(r.solver && b.solver);
  EXPECT_EQ(r.solver->status, SolverStatus::kConverged);
  EXPECT_EQ(b.solver->status, SolverStatus::kConverged);
  const double e = r.method_report["energy"].get<double>();
  EXPECT_NEAR(b.method_report["energy"].get<double>(), e, 1e-12 * e);
  // Stationary at every node off its bounds: the energy of its two spans, with its direction
  // turned by ±h, by central differences.
  const std::size_t n = pts.size();
  std::vector<ChordAngles> a;
  for (const Segment& s : r.spline.segments) a.push_back(chord_angles(s.bezier));
  auto local = [&](std::size_t i, double d) { return node_energy(qe, a, i, d); };
  const double h = 1e-6;
  int checked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool inside = (i + 1 == n || std::abs(a[i].alpha) < kPi / 2 - 1e-6) &&
                        (i == 0 || std::abs(a[i - 1].beta) < kPi / 2 - 1e-6);
    if (!inside) continue;
    const double scale =
        std::max(1.0 / a[std::min(i, n - 2)].length, i > 0 ? 1.0 / a[i - 1].length : 0.0);
    EXPECT_NEAR((local(i, h) - local(i, -h)) / (2.0 * h), 0.0, 1e-5 * scale) << "node " << i;
    ++checked;
  }
  EXPECT_GT(checked, 2900);
}

/// A saved stress input (tests/data/stress/), parsed as the CLI would.
io::ParsedInput stress_input(const std::string& file) {
  std::ifstream f(std::string(FAIRSPLINE_TEST_DATA_DIR) + "/stress/" + file);
  std::stringstream ss;
  ss << f.rdbuf();
  return io::parse_json_input(ss.str());
}

/// Σ E_1/L from the fit's unit tangents and the exact chords (not from the Béziers' control
/// points, which lose a direction at near-repeated points), with node i turned by d.
double energy_with_turn(const FitResult& r, const BasicCurveMethod& m, std::size_t i, double d) {
  const std::size_t n = r.points.size(), segs = r.closed ? n : n - 1;
  double e = 0.0;
  for (std::size_t s = 0; s < segs; ++s) {
    const std::size_t j = s + 1 == n ? 0 : s + 1;
    const Vec2 c = r.points[j] - r.points[s];
    const double alpha = signed_angle(c, r.tangents[s]) + (s == i ? d : 0.0);
    const double beta = signed_angle(c, r.tangents[j]) + (j == i ? d : 0.0);
    e += basic_energy(m, alpha, beta).e / norm(c);
  }
  return e;
}

/// The largest KKT violation of a fit's directions (boxes |α|, |β| <= Ω), by central differences
/// of energy_with_turn, relative to the largest chord weight (the solver's measure).
double kkt_violation(const FitResult& r, const BasicCurveMethod& m, double h) {
  const std::size_t n = r.points.size();
  const std::size_t segs = r.closed ? n : n - 1;
  double wmax = 0.0;
  for (std::size_t s = 0; s < segs; ++s) {
    wmax = std::max(wmax, 1.0 / norm(r.points[s + 1 == n ? 0 : s + 1] - r.points[s]));
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double g = (energy_with_turn(r, m, i, h) - energy_with_turn(r, m, i, -h)) / (2 * h);
    // The node's angles with its next (α) and previous (β) chords, where they exist.
    double hi = -kPi, lo = kPi;
    if (r.closed || i + 1 < n) {
      const double a = signed_angle(r.points[i + 1 == n ? 0 : i + 1] - r.points[i], r.tangents[i]);
      hi = std::max(hi, a), lo = std::min(lo, a);
    }
    if (r.closed || i > 0) {
      const double b = signed_angle(r.points[i] - r.points[i == 0 ? n - 1 : i - 1], r.tangents[i]);
      hi = std::max(hi, b), lo = std::min(lo, b);
    }
    double v = std::abs(g);
    if (hi > m.omega - 1e-9) v = std::max(0.0, g);  // upper bound: may only pull outwards
    if (lo < -m.omega + 1e-9) v = std::max(0.0, -g);
    worst = std::max(worst, v / wmax);
  }
  return worst;
}

/// Issue 18: a closed 830-point walk with two near-repeated pairs (chords 1.1e-9) cycled between
/// two states 0.0103 apart in energy until the 200-iteration cap (projected gradient 1.48e-10).
/// The line search took a full Newton step that raised the energy whenever the rise was within
/// the rounding allowance of the total (1.3e-2 here, set by the 1e9 chord weights), though the
/// step predicted a decrease of 0.33, far above that rounding: node 1 jumped between its bounds.
TEST(MinEnergyFit, Issue18NearRepeatedWalkDoesNotCycle) {
  const io::ParsedInput p = stress_input("quasi-elastic-not_converged-s18-c430846.json");
  const FitResult r = fit("quasi-elastic", p.input, p.options, ReportLevel::kBasic);
  ASSERT_TRUE(r.solver.has_value());
  EXPECT_EQ(r.solver->status, SolverStatus::kConverged);
  EXPECT_LT(r.solver->iterations, 20);
  const BasicCurveMethod qe = cond_g2(1.0);
  const double energy = r.method_report.at("energy").get<double>();
  EXPECT_NEAR(energy_with_turn(r, qe, 0, 0.0), energy, 1e-13 * energy);
  // Below both states of the cycle (220411267.4039 and .4142); rounding here is ~1e-6.
  EXPECT_LT(energy, 220411267.40387 - 0.05);
  EXPECT_LT(kkt_violation(r, qe, 1e-5), 1e-9);
}

/// The same cycle in restricted-elastic (each with a near-repeated point): an open 10-point walk
/// (stopped at projected gradient 9e-10, energy 68485712643.0848 or more) and a closed 9-point
/// one (5.68e-10, 3596526.1231 or more).
TEST(MinEnergyFit, Issue18RestrictedElasticNearRepeatedWalksDoNotCycle) {
  struct Case {
    const char* file;
    double stalled_energy;
  };
  for (const Case& c : {Case{"restricted-elastic-not_converged-s18-c130322.json", 68485712643.0848},
                        Case{"restricted-elastic-not_converged-s18-c214718.json", 3596526.1231}}) {
    SCOPED_TRACE(c.file);
    const io::ParsedInput p = stress_input(c.file);
    const FitResult r = fit("restricted-elastic", p.input, p.options, ReportLevel::kBasic);
    ASSERT_TRUE(r.solver.has_value());
    EXPECT_EQ(r.solver->status, SolverStatus::kConverged);
    EXPECT_LT(r.solver->iterations, 30);
    const BasicCurveMethod re{MinEnergyBasis::kRestrictedElastic, 1.0, kPi / 2};
    const double energy = r.method_report.at("energy").get<double>();
    EXPECT_NEAR(energy_with_turn(r, re, 0, 0.0), energy, 1e-11 * energy);
    EXPECT_LT(energy, c.stalled_energy - 1e-3);
    EXPECT_LT(kkt_violation(r, re, 1e-5), 1e-9);
  }
}

/// Issue 18: closed 3-point elastic curves with a start tangent stopped at once ("projected
/// gradient 0 … above the tolerance"): the restricted start held node 2, whose box was empty, at
/// the middle of its box and its pair bound with the clamped node 0, which broke that pair
/// constraint (|α − β| > 180°), so the coupled phase started at an infinite energy. Checked
/// independently: no feasible turn of the two free directions (64 directions) lowers Σ E_1/L.
TEST(MinEnergyFit, Issue18ElasticClosedThreePointsWithStartTangent) {
  struct Case {
    std::vector<Point> points;
    Vec2 tangent;
    double energy;
  };
  const std::vector<Case> cases = {{{{0.0, 0.0},
                                     {1.6988986424576447, -38.44691389305743},
                                     {6.985304600164595, -158.08088709661294}},
                                    {0.46165857536172683, -0.8870576981205793},
                                    0.2369544805070628},
                                   {{{0.02291830683460748, 0.0026027542122316113},
                                     {-0.018851045014499825, 0.02818105210254719},
                                     {-0.018110047277175294, -0.019883353548042184}},
                                    {-0.9966327586205304, -0.08199478303179664},
                                    514.3227668916841}};
  const BasicCurveMethod el{MinEnergyBasis::kElastic, 1.0, kPi};
  for (const Case& c : cases) {
    FitInput in = input_of(c.points, true);
    in.start_tangent = c.tangent;
    const FitResult r = fit("elastic", in, {}, ReportLevel::kBasic);
    ASSERT_TRUE(r.solver.has_value());
    EXPECT_TRUE(r.solver->status == SolverStatus::kConverged ||
                r.solver->status == SolverStatus::kConditioningLimit);
    EXPECT_NEAR(cross(r.tangents[0], normalized(c.tangent)), 0.0, 1e-15);
    const double energy = r.method_report.at("energy").get<double>();
    EXPECT_NEAR(energy, c.energy, 1e-9 * c.energy);
    EXPECT_NEAR(energy_with_turn(r, el, 0, 0.0), energy, 1e-9 * energy);
    double wmax = 0.0;
    for (std::size_t s = 0; s < 3; ++s)
      wmax = std::max(wmax, 1.0 / norm(c.points[(s + 1) % 3] - c.points[s]));
    // Σ E_1/L with nodes 1 and 2 turned by (d1, d2); infinite outside the s-curve domain.
    auto turned = [&](double d1, double d2) {
      double e = 0.0;
      for (std::size_t s = 0; s < 3; ++s) {
        const std::size_t j = (s + 1) % 3;
        const Vec2 ch = r.points[j] - r.points[s];
        const double d[] = {0.0, d1, d2};
        e += basic_energy(el, signed_angle(ch, r.tangents[s]) + d[s],
                          signed_angle(ch, r.tangents[j]) + d[j])
                 .e /
             norm(ch);
      }
      return e;
    };
    const double h = 1e-7, e0 = turned(0, 0);
    for (int q = 0; q < 64; ++q) {
      const double phi = 2 * kPi * q / 64;
      const double e = turned(h * std::cos(phi), h * std::sin(phi));
      if (std::isfinite(e)) {
        EXPECT_GE((e - e0) / h, -1e-5 * wmax) << "direction " << q;
      }
    }
  }
}

/// Issue 18: closed 3–4-point elastic curves stopped with |α − β| = 180° active on a span
/// whose multiplier had the wrong sign (the stress suite's KKT certificate: residual 0.93, 2.03,
/// 0.44): the coupled active-set Newton stalled on that face with a reduced gradient between
/// its tolerance and kElasticPrecision and returned "conditioning_limit" without ever checking
/// the multipliers, so the constraint was never released. Checked independently: the energy of
/// the old stop is above the new one, the certificate passes, and no feasible turn of any one
/// or two directions (scales 1e-6 … 0.1) lowers Σ E_1/L.
TEST(MinEnergyFit, Issue18ElasticReleasesAPairConstraintWithTheWrongSign) {
  struct Case {
    std::vector<Point> points;
    double energy;   // the optimum (pattern search from the old stop agrees to 1e-12)
    double stopped;  // where the fit stopped before
  };
  const std::vector<Case> cases = {{{{0.0, 0.0},
                                     {-0.9155230786878982, -0.07462921295342947},
                                     {-4.564745586694919, -0.3720970248636773},
                                     {-7.5668995192117565, -0.6168187867760688}},
                                    5.97762132951239,
                                    6.01884590199294},
                                   {{{0.0, 0.0},
                                     {-156.651031857418, -71.7543481556374},
                                     {-202.81645580892413, -59.38712266245961}},
                                    0.0871405064161802,
                                    0.0925257758683788},
                                   {{{0.0, 0.0},
                                     {-108.67058905317167, 29.859139013428635},
                                     {-1612.9922928792282, -900.035790349294}},
                                    0.0085026442637567,
                                    0.00870989710026233}};
  const BasicCurveMethod el{MinEnergyBasis::kElastic, 1.0, kPi};
  for (const Case& c : cases) {
    const FitInput in = input_of(c.points, true);
    const FitResult r = fit("elastic", in, {}, ReportLevel::kBasic);
    ASSERT_TRUE(r.solver.has_value());
    EXPECT_EQ(r.solver->status, SolverStatus::kConverged);
    const double energy = r.method_report.at("energy").get<double>();
    EXPECT_NEAR(energy, c.energy, 1e-9 * c.energy);
    EXPECT_LT(energy, c.stopped * (1.0 - 1e-3));
    const stress::KktResult k = stress::check_optimum(in, r);
    EXPECT_TRUE(k.checked && k.pass) << k.what;
    const std::size_t n = c.points.size();
    // Σ E_1/L with the directions turned by d; infinite outside the s-curve domain.
    auto turned = [&](const std::vector<double>& d) {
      double e = 0.0;
      for (std::size_t s = 0; s < n; ++s) {
        const std::size_t j = (s + 1) % n;
        const Vec2 ch = r.points[j] - r.points[s];
        e += basic_energy(el, signed_angle(ch, r.tangents[s]) + d[s],
                          signed_angle(ch, r.tangents[j]) + d[j])
                 .e /
             norm(ch);
      }
      return e;
    };
    const double e0 = turned(std::vector<double>(n, 0.0));
    EXPECT_NEAR(e0, energy, 1e-9 * energy);
    for (double h : {1e-6, 1e-4, 1e-2, 1e-1}) {
      for (std::size_t u = 0; u < n; ++u) {
        for (std::size_t v = u; v < n; ++v) {
          for (int q = 0; q < 16; ++q) {
            std::vector<double> d(n, 0.0);
            d[u] += h * std::cos(2 * kPi * q / 16);
            d[v] += h * std::sin(2 * kPi * q / 16);
            const double e = turned(d);
            if (std::isfinite(e)) {
              EXPECT_GE(e, e0 * (1.0 - 1e-10)) << "h " << h << " nodes " << u << ", " << v;
            }
          }
        }
      }
    }
  }
}

// ---- errors ----

TEST(MinEnergyFit, InfeasibleMessageGivesTheBasisOmegaLimit) {
  // Issue 18 (part 5): the advice "raise omega_deg (at most 90)" was printed for every basis,
  // but basis=yong-cheng accepts only omega_deg < 70.52 (acos 1/3), jaklic-zagar < 90 and
  // elastic up to 180. Stencil angles 175.4° and −178.7° need 2Ω above them.
  const FitInput in = input_of({{0, 0}, {3, 0}, {0.5, 0.2}, {4, 0}});
  struct Case {
    const char* basis;
    double omega_deg;
    const char* limit;
  };
  for (const Case& c : {Case{"yong-cheng", 60, "below 70.52"}, Case{"jaklic-zagar", 80, "below 90"},
                        Case{"elastic", 45, "at most 180"}, Case{"cond-g2", 45, "at most 90"}}) {
    const Error e = expect_error(ErrorCode::kInfeasible, [&] {
      (void)fit("min-energy", in, {{"basis", c.basis}, {"omega_deg", c.omega_deg}});
    });
    const std::string what = e.what();
    EXPECT_NE(what.find(std::string("Raise omega_deg (") + c.limit), std::string::npos)
        << c.basis << ": " << what;
    if (std::string(c.limit) != "at most 90") {
      EXPECT_EQ(what.find("(at most 90"), std::string::npos) << c.basis << ": " << what;
    }
  }
}

// Issue 20, bug 3: clamping a node of a fit whose direction lies on the bound Ω kept failing
// with "angle of 90.00° with a chord, beyond Ω = 90.00°": the direction read back from the curve
// is a few ulps past Ω. A given direction within kGivenAngleTolerance (1e-9 rad) of Ω counts as
// on the bound; one clearly past it is still infeasible.
TEST(MinEnergyFit, GivenDirectionOnTheBoundIsAccepted) {
  // The README's example: the default fit has its directions on the bound at points 4 and 5.
  const FitInput li =
      input_of({{1, 90}, {3, 105}, {6, 120}, {10, 100}, {12, 85}, {15, 104}, {17, 80}});
  const FitResult free = fit("quasi-elastic", li, {}, ReportLevel::kBasic);
  const std::vector<std::size_t> active = active_of(free);
  ASSERT_NE(std::find(active.begin(), active.end(), 4u), active.end());
  ASSERT_NE(std::find(active.begin(), active.end(), 5u), active.end());
  for (std::size_t i : {4u, 5u}) {
    // Both ways the editor reads a direction back: the result's tangent and the control arm.
    const CubicBezier& after = free.spline.segments[i].bezier;
    for (const Vec2 d : {free.tangents[i], after.p[1] - after.p[0]}) {
      FitInput in = li;
      in.kinds.assign(li.points.size(), PointKind::kSmooth);
      in.tangents.assign(li.points.size(), std::nullopt);
      in.kinds[i] = PointKind::kClamped;
      in.tangents[i] = d;
      const FitResult r = fit("quasi-elastic", in, {}, ReportLevel::kBasic);
      EXPECT_LT(std::abs(signed_angle(d, r.tangents[i])), 1e-14) << "point " << i;
      // Clamping a direction the optimum has keeps the curve.
      for (std::size_t s = 0; s < r.spline.segments.size(); ++s) {
        for (int k = 0; k < 4; ++k) {
          EXPECT_LT(norm(r.spline.segments[s].bezier.p[k] - free.spline.segments[s].bezier.p[k]),
                    1e-9 * 120)
              << "point " << i << ", segment " << s;
        }
      }
    }
  }
  // Exactly Ω and Ω ± 1e-11 rad from a chord, for each basis at its default Ω (a clamped
  // interior point and a start tangent), and 1e-6 rad past Ω refused (index and both angles).
  struct Case {
    const char* basis;
    double omega_deg;
  };
  for (const Case& c : {Case{"quasi-elastic", 90}, Case{"cond-g2", 90}, Case{"jaklic-zagar", 80},
                        Case{"yong-cheng", 60}, Case{"restricted-elastic", 90}}) {
    SCOPED_TRACE(c.basis);
    const nlohmann::json options = {{"basis", c.basis}};
    const double omega = c.omega_deg * kDeg;
    // Points 1..3 on a line at 20°: the chords' direction; the clamp at point 2 turns off it.
    const Vec2 chord = from_angle(20 * kDeg);
    const Point p1{1, 0.5};
    const FitInput line = input_of({{0, 0}, p1, p1 + 1.5 * chord, p1 + 3.0 * chord, {5, 3}});
    for (const double off : {0.0, 1e-11, -1e-11, 1e-6}) {
      for (const double sign : {1.0, -1.0}) {
        const Vec2 d = from_angle(20 * kDeg + sign * (omega + off));
        FitInput in = line;
        in.kinds.assign(5, PointKind::kSmooth);
        in.tangents.assign(5, std::nullopt);
        in.kinds[2] = PointKind::kClamped;
        in.tangents[2] = d;
        FitInput start = input_of({{0, 0}, Point{0, 0} + 2.0 * chord, {3, 0.5}});
        start.start_tangent = from_angle(20 * kDeg + sign * (omega + off));
        if (off > 1e-9) {
          const Error e =
              expect_error(ErrorCode::kInfeasible, [&] { (void)fit("min-energy", in, options); });
          EXPECT_EQ(e.index(), 2u);
          // The angle is printed with the digits that tell it from Ω.
          EXPECT_EQ(
              std::string(e.what()).find("angle of " + std::to_string(int(c.omega_deg)) + ".00°"),
              std::string::npos)
              << e.what();
          EXPECT_EQ(
              expect_error(ErrorCode::kInfeasible, [&] { (void)fit("min-energy", start, options); })
                  .index(),
              0u);
          continue;
        }
        const FitResult r = fit("min-energy", in, options, ReportLevel::kBasic);
        EXPECT_LT(std::abs(signed_angle(d, r.tangents[2])), 1e-14) << off;
        EXPECT_TRUE(r.report && r.report->regular) << off;
        const FitResult s = fit("min-energy", start, options, ReportLevel::kBasic);
        EXPECT_LT(std::abs(signed_angle(*start.start_tangent, s.tangents[0])), 1e-14) << off;
      }
    }
  }
  // The elastic basis's domain ends at 180° (open): a direction opposite to a chord stays
  // refused.
  FitInput back = input_of({{0, 0}, {1, 0}, {2, 1}});
  back.start_tangent = Vec2{-1, 0};
  expect_error(ErrorCode::kInfeasible, [&] { (void)fit("elastic", back); });
}

TEST(MinEnergyFit, Errors) {
  // Stencil angles beyond 2Ω (Theorem 2.3): every offending point listed, index() the first.
  const Point p2{2, 0};
  const Point p3 = p2 + from_angle(100 * kDeg);
  const Point p4 = p3 + from_angle(100 * kDeg);
  const Point p5 = p4 + from_angle(-10 * kDeg);
  const FitInput turns = input_of({{0, 0}, {1, 0}, p2, p3, p4, p5, p5 + from_angle(-10 * kDeg)});
  const Error e = expect_error(ErrorCode::kInfeasible,
                               [&] {
                                 (void)fit("quasi-elastic", turns, {{"omega_deg", 45}});
                               },
                               {"point 2 ", "100.00", "point 4 ", "-110.00", "90.00"});
  EXPECT_EQ(e.index(), 2u);
  EXPECT_EQ(std::string(e.what()).find("point 3 "), std::string::npos);
  (void)fit("quasi-elastic", turns, {{"omega_deg", 55.5}});  // 2Ω = 111° > 110°: fine
  // The closing node of a closed curve counts: a square with Ω = 40° (2Ω = 80° < 90°).
  const FitInput square = input_of({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, true);
  const Error sq = expect_error(ErrorCode::kInfeasible,
                                [&] {
                                  (void)fit("quasi-elastic", square, {{"omega_deg", 40}});
                                },
                                {"point 0 ", "point 3 "});
  EXPECT_EQ(sq.index(), 0u);
  // The reference refuses the same data.
  MinEnergyOptions narrow;
  narrow.method = cond_g2(1.0, 40 * kDeg);
  expect_error(ErrorCode::kInfeasible, [&] { (void)min_energy_reference(square, narrow); });

  // A clamped tangent outside its feasible range.
  FitInput clamp = input_of({{0, 0}, {1, 0}, {2, 0}, {3, 0}});
  clamp.kinds = {PointKind::kSmooth, PointKind::kSmooth, PointKind::kClamped, PointKind::kSmooth};
  clamp.tangents = {std::nullopt, std::nullopt, from_angle(95 * kDeg), std::nullopt};
  const Error ce = expect_error(ErrorCode::kInfeasible, [&] { (void)fit("quasi-elastic", clamp); },
                                {"point 2 ", "95.00"});
  EXPECT_EQ(ce.index(), 2u);
  clamp.tangents[2] = from_angle(85 * kDeg);
  (void)fit("quasi-elastic", clamp);
  FitInput start = input_of({{0, 0}, {1, 0}, {2, 1}});
  start.start_tangent = Vec2{-1, 0.1};
  const Error se = expect_error(ErrorCode::kInfeasible, [&] { (void)fit("quasi-elastic", start); },
                                {"point 0 "});
  EXPECT_EQ(se.index(), 0u);
  FitInput end = input_of({{0, 0}, {1, 0}, {2, 0}});
  end.end_tangent = Vec2{0, 1};  // 90°: on the bound, allowed
  (void)fit("quasi-elastic", end);
  end.end_tangent = Vec2{-0.01, 1};
  const Error ee =
      expect_error(ErrorCode::kInfeasible, [&] { (void)fit("quasi-elastic", end); }, {"point 2 "});
  EXPECT_EQ(ee.index(), 2u);

  // Options.
  const FitInput ok = input_of(random_walk(10, 3, 60));
  for (double lambda : {0.0, 3.0, -1.0, 3.5}) {
    expect_error(ErrorCode::kBadOption,
                 [&] {
                   (void)fit("cond-g2", ok, {{"lambda", lambda}});
                 },
                 {"lambda"});
  }
  for (double omega : {0.0, 90.5, -10.0}) {
    expect_error(ErrorCode::kBadOption,
                 [&] {
                   (void)fit("quasi-elastic", ok, {{"omega_deg", omega}});
                 },
                 {"omega_deg"});
  }
  expect_error(ErrorCode::kBadOption,
               [&] {
                 (void)fit("min-energy", ok, {{"basis", "jaklic-zagar"}, {"omega_deg", 90}});
               },
               {"jaklic-zagar"});
  expect_error(ErrorCode::kBadOption, [&] { (void)fit("min-energy", ok, {{"basis", "spiro"}}); });
  expect_error(ErrorCode::kUnknownOption, [&] { (void)fit("quasi-elastic", ok, {{"omega", 10}}); });
  MinEnergyOptions wide;
  wide.method = cond_g2(1.0, 2.0);
  FitResult out;
  expect_error(ErrorCode::kBadOption, [&] { fit_min_energy(ok, wide, ReportLevel::kNone, out); });
  wide.method = jaklic_zagar(kPi / 2);
  expect_error(ErrorCode::kBadOption, [&] { fit_min_energy(ok, wide, ReportLevel::kNone, out); });
  // Iteration limit: a hard problem cannot converge in one Newton step.
  expect_error(ErrorCode::kNotConverged, [&] {
    (void)fit("quasi-elastic", input_of(random_walk(40, 4, 150)), {{"max_iterations", 1}});
  });

  // Input.
  expect_error(ErrorCode::kNonFinite, [] {
    (void)fit("quasi-elastic", input_of({{0, 0}, {NAN, 1}, {2, 0}}));
  });
  expect_error(ErrorCode::kTooFewPoints, [] { (void)fit("quasi-elastic", input_of({{0, 0}})); });
  expect_error(ErrorCode::kTooFewPoints, [] {
    (void)fit("quasi-elastic", input_of({{0, 0}, {1, 0}}, true));
  });
  expect_error(ErrorCode::kRepeatedPoint, [] {
    (void)fit("quasi-elastic", input_of({{0, 0}, {1, 0}, {1, 0}, {2, 0}}));
  });
  // Two points: one straight span, zero energy.
  const FitResult two = fit("quasi-elastic", input_of({{0, 0}, {3, 4}}), {}, ReportLevel::kBasic);
  EXPECT_NEAR(two.method_report["energy"].get<double>(), 0.0, 1e-15);
  EXPECT_LT(norm(two.tangents[0] - Vec2{0.6, 0.8}), 1e-15);
}

// ---- invariance ----

RC_GTEST_PROP(MinEnergyProps, InvariantUnderSimilaritiesMirrorAndReversal, ()) {
  const auto seed = static_cast<std::uint64_t>(*rc::gen::inRange(0, 1000000));
  const auto n = static_cast<std::size_t>(*rc::gen::inRange(3, 25));
  const bool closed = *rc::gen::arbitrary<bool>();
  const int which = *rc::gen::inRange(0, 4);
  const BasicCurveMethod m = which == 0   ? cond_g2(1.0)
                             : which == 1 ? cond_g2(0.6)
                             : which == 2 ? jaklic_zagar()
                                          : yong_cheng();
  const std::vector<Point> pts = random_walk(n, seed, m.basis == MinEnergyBasis::kCondG2 ? 90 : 50);
  const std::vector<double> psi = stencil_angles(pts, closed);
  RC_PRE(std::all_of(psi.begin(), psi.end(),
                     [&](double p) { return std::abs(p) < 2 * m.omega - 1e-6; }));
  const double rot = *rc::gen::inRange(-314, 314) * 0.01 + 1e-3;
  const double scale = std::pow(10.0, *rc::gen::inRange(-3, 4)) * 1.3;
  const Vec2 shift{*rc::gen::inRange(-1000, 1000) * 0.1, *rc::gen::inRange(-1000, 1000) * 0.1};
  const bool mirror = *rc::gen::arbitrary<bool>();
  auto map = [&](Point p) {
    if (mirror) p.y = -p.y;
    return shift + scale * rotate(p, rot);
  };
  std::vector<Point> moved;
  for (Point p : pts) moved.push_back(map(p));
  std::vector<Point> reversed(pts.rbegin(), pts.rend());
  if (closed) std::rotate(reversed.rbegin(), reversed.rbegin() + 1, reversed.rend());  // p0 first

  FitResult a, b, c;
  try {
    a = fit_with(m, input_of(pts, closed));
    b = fit_with(m, input_of(moved, closed));
    c = fit_with(m, input_of(reversed, closed));
  } catch (const Error& e) {
    // The known non-convergence of λ = 1 on short data (MinEnergyFit.
    // ConvergesOnShortNearlyStraightData) is tested there; remove this discard once fixed.
    RC_PRE(!(e.code() == ErrorCode::kNotConverged && m.lambda == 1.0 &&
             m.basis == MinEnergyBasis::kCondG2));
    throw;
  }
  const double ea = a.method_report["energy"].get<double>();
  const double eb = b.method_report["energy"].get<double>();
  const double ec = c.method_report["energy"].get<double>();
  // The moved data's coordinates are rounded to ε·|q|, each chord's angle to ~2ε|q|/ℓ: E moves
  // by about E_1's gradient (at most ~2√(3E_1) near straight, E_1 <= E·L) times that over L.
  // (Scaled by 1.3e-3 and shifted by 141, three points differed by 2.09e-13 at E = 1.06e-4.)
  double q = 0.0;
  for (Point p : moved) q = std::max({q, std::abs(p.x), std::abs(p.y)});
  double slack = 0.0;
  for (std::size_t i = 0; i + 1 < pts.size() + (closed ? 1 : 0); ++i) {
    const double len = distance(pts[i], pts[(i + 1) % pts.size()]);
    slack += 2.0 * std::sqrt(3.0 * ea * len) / len *
             (4.0 * std::numeric_limits<double>::epsilon() * q / (scale * len));
  }
  RC_ASSERT(std::abs(eb * scale - ea) <= 1e-9 * ea + 1e-13 + slack);
  RC_ASSERT(std::abs(ec - ea) <= 1e-9 * ea + 1e-13);
  RC_ASSERT(active_of(a) == active_of(b));
  // The same curve, moved / backwards.
  const double tol = 1e-7 * (1 + testing::scale_of(pts));
  for (std::size_t s = 0; s < a.spline.segments.size(); ++s) {
    for (int k = 0; k < 4; ++k) {
      const Point q = map(a.spline.segments[s].bezier.p[k]);
      RC_ASSERT(norm(q - b.spline.segments[s].bezier.p[k]) <= tol * scale + 1e-12 * norm(shift));
    }
  }
  RC_ASSERT(testing::is_reversed_curve(a, c, tol));
}

/// max_iterations unset: 200 up to 10³ points, then growing with log10 n (long elastic walks
/// needed 208–397 iterations at 10⁴–10⁵ points), with data balls 4·10⁶ / n within [1000, 4000];
/// given, it bounds the data-ball optimizer too.
RC_GTEST_PROP(MinEnergyProps, GlobalSearchIsNeverAboveBruteForceNorNewton, ()) {
  // Two free directions between given end directions, turns up to 1.9 Ω: search=global is
  // never above a brute force on a 2° grid polished by pattern moves, nor above search=newton.
  const auto seed = static_cast<std::uint64_t>(*rc::gen::inRange(0, 1000000));
  const int which = *rc::gen::inRange(0, 4);
  const BasicCurveMethod m = which == 0   ? cond_g2(1.0)
                             : which == 1 ? cond_g2(*rc::gen::inRange(1, 29) * 0.1)
                             : which == 2 ? jaklic_zagar()
                                          : yong_cheng();
  const testing::TwoFreeDirections t =
      testing::two_free_directions(seed, 1.9 * m.omega / kDeg, m.omega / kDeg);
  const double brute = t.brute_force(m, 180);
  RC_PRE(std::isfinite(brute));
  MinEnergyOptions o;
  o.method = m;
  FitResult r;
  MinEnergyReport global, newton;
  o.search = MinEnergySearch::kGlobal;
  fit_min_energy(t.input(), o, ReportLevel::kNone, r, &global);
  o.search = MinEnergySearch::kNewton;
  fit_min_energy(t.input(), o, ReportLevel::kNone, r, &newton);
  RC_ASSERT(global.energy <= brute * (1 + 1e-9));
  RC_ASSERT(global.energy <= newton.energy * (1 + 1e-12));
}

TEST(MinEnergyIterations, TheDefaultLimitGrowsWithThePointsAndDataBalls) {
  constexpr MinEnergyBasis qe = MinEnergyBasis::kCondG2, el = MinEnergyBasis::kElastic;
  EXPECT_EQ(detail::default_iteration_limit(3, false, qe), 200);
  EXPECT_EQ(detail::default_iteration_limit(1000, false, qe), 200);
  EXPECT_EQ(detail::default_iteration_limit(10000, false, qe), 400);
  EXPECT_EQ(detail::default_iteration_limit(100000, false, qe), 600);
  // With data balls 4·10⁶ / n, within [1000, 4000] (short curves creep for longer; seed 19:
  // up to 2714 iterations).
  EXPECT_EQ(detail::default_iteration_limit(20, true, qe), 4000);
  EXPECT_EQ(detail::default_iteration_limit(1000, true, qe), 4000);
  EXPECT_EQ(detail::default_iteration_limit(2000, true, qe), 2000);
  EXPECT_EQ(detail::default_iteration_limit(10000, true, qe), 1000);
  EXPECT_EQ(detail::default_iteration_limit(1000000, true, qe), 1000);
  EXPECT_EQ(detail::default_iteration_limit(100000000, true, qe), 1200);
  // The elastic spline: twice the growth, 400 (log10 n − 2) from 316 points (623 iterations at
  // 10⁵, ±150°).
  EXPECT_EQ(detail::default_iteration_limit(300, false, el), 200);
  EXPECT_EQ(detail::default_iteration_limit(1000, false, el), 400);
  EXPECT_EQ(detail::default_iteration_limit(10000, false, el), 800);
  EXPECT_EQ(detail::default_iteration_limit(100000, false, el), 1200);
  EXPECT_EQ(detail::default_iteration_limit(100000, true, el), 1200);

  FitInput in = input_of(random_walk(12, 7, 90));
  in.radii.assign(in.points.size(), 0.0);
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    double gap = HUGE_VAL;
    if (i > 0) gap = std::min(gap, norm(in.points[i] - in.points[i - 1]));
    if (i + 1 < in.points.size()) gap = std::min(gap, norm(in.points[i + 1] - in.points[i]));
    in.radii[i] = 0.3 * gap;
  }
  const FitResult unset = fit("quasi-elastic", in);
  EXPECT_FALSE(unset.options.contains("max_iterations"));  // a refit gets the same default
  EXPECT_EQ(unset.method_report.at("status"), "converged");
  const Error e = testing::expect_error(ErrorCode::kNotConverged, [&] {
    fit("quasi-elastic", in, {{"max_iterations", 1}});
  });
  EXPECT_NE(std::string(e.what()).find("data-ball optimizer"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace fairspline
