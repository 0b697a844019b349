// Tests of energy.hpp: the closed-form linearized energy against Simpson's rule (exact for its
// quadratic integrand), the adaptive quadratures against brute-force composite Simpson and
// independent finite-difference formulas, invariances, and singular pieces.
#include "fairspline/energy.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <functional>
#include <numbers>

#include "detail/quadrature.hpp"
#include "fairspline/error.hpp"

namespace fairspline {
namespace {

CubicBezier bez(Point a, Point b, Point c, Point d) {
  return {{a, b, c, d}};
}

const double kArcK = 4.0 / 3.0 * (std::numbers::sqrt2 - 1.0);
const CubicBezier kQuarter = bez({1.0, 0.0}, {1.0, kArcK}, {kArcK, 1.0}, {0.0, 1.0});
const CubicBezier kS = bez({0.0, 0.0}, {1.0, 2.0}, {3.0, -1.0}, {4.0, 1.0});
const CubicBezier kLoop = bez({0.0, 0.0}, {2.0, 1.0}, {-1.0, 1.0}, {1.0, 0.0});
const CubicBezier kCusp = bez({0.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}, {1.0, 0.0});  // b'(1/2) = 0

/// Composite Simpson on [0,1] with n panels.
double simpson(const std::function<double(double)>& f, int n) {
  double sum = 0.0;
  const double h = 1.0 / n;
  for (int i = 0; i < n; ++i) {
    const double a = i * h;
    sum += h / 6.0 * (f(a) + 4.0 * f(a + 0.5 * h) + f(a + h));
  }
  return sum;
}

double bending_integrand(const CubicBezier& b, double u) {
  const double k = b.curvature(u);
  return k * k * norm(b.d1(u));
}

CubicBezier transform(const CubicBezier& b, double angle, double scale, Vec2 shift) {
  CubicBezier r;
  for (int i = 0; i < 4; ++i) r.p[i] = scale * rotate(b.p[i], angle) + shift;
  return r;
}

CubicBezier random_cubic() {
  CubicBezier b;
  for (auto& q : b.p)
    q = {*rc::gen::inRange(-1000, 1001) / 100.0, *rc::gen::inRange(-1000, 1001) / 100.0};
  return b;
}

// The rule's constants are Boost.Math's 31-point Kronrod and 15-point Gauss rules (to the last
// bit), and the rule integrates polynomials of degree 46 exactly and degree 29 by its Gauss part.
TEST(Quadrature, GaussKronrod31ConstantsAreBoostsAndExactOnPolynomials) {
  using Kronrod = boost::math::quadrature::gauss_kronrod<double, 31>;
  using Gauss = boost::math::quadrature::gauss<double, 15>;
  const auto& x = Kronrod::abscissa();
  const auto& w = Kronrod::weights();
  ASSERT_EQ(x.size(), detail::kGkNodes.size());
  for (std::size_t i = 0; i < x.size(); ++i) {  // Boost: centre first, ascending
    EXPECT_EQ(detail::kGkNodes[15 - i], x[i]) << i;
    EXPECT_EQ(detail::kKronrodWeights[15 - i], w[i]) << i;
  }
  const auto& gx = Gauss::abscissa();
  const auto& gw = Gauss::weights();
  for (std::size_t i = 0; i < gx.size(); ++i) {
    EXPECT_EQ(detail::kGaussWeights[7 - i], gw[i]) << i;
    EXPECT_EQ(detail::kGkNodes[15 - 2 * i], gx[i]) << i;  // the Gauss nodes are every other
  }
  // ∫_0^1 u^d du = 1/(d+1): the Kronrod value exact to rounding up to d = 46; the estimate of a
  // degree-29 integrand (Gauss exact too) is only the round-off floor.
  for (int d : {0, 1, 7, 29, 30, 46}) {
    auto f = [d](double u) { return std::array<double, 1>{std::pow(u, d)}; };
    std::array<double, 1> value{}, error{};
    detail::gauss_kronrod<1>(f, 0.0, 1.0, value, error);
    EXPECT_NEAR(value[0], 1.0 / (d + 1), 4e-16) << d;
    if (d <= 29) {
      EXPECT_LT(error[0], 1e-13) << d;
    }
  }
  // A peak of width 0.1 (∫ = 20·atan(5)): one rule is off by 3e-4, and its estimate covers it.
  auto g = [](double u) { return std::array<double, 1>{1.0 / (0.01 + (u - 0.5) * (u - 0.5))}; };
  std::array<double, 1> value{}, error{};
  detail::gauss_kronrod<1>(g, 0.0, 1.0, value, error);
  const double exact = 20.0 * std::atan(5.0), off = std::abs(value[0] - exact);
  EXPECT_GT(off, 1e-5);
  EXPECT_GT(error[0], off);
}

TEST(Energy, LinearizedLocalMatchesSimpson) {
  // |b''(u)|² is a quadratic polynomial in u: one Simpson panel is exact.
  for (const CubicBezier& b : {kQuarter, kS, kLoop, kCusp}) {
    const double f0 = norm2(b.d2(0.0)), fh = norm2(b.d2(0.5)), f1 = norm2(b.d2(1.0));
    const double exact = (f0 + 4.0 * fh + f1) / 6.0;
    EXPECT_NEAR(linearized_energy_local(b), exact, 1e-13 * exact);
  }
  // Hand value: the S curve has A = 6(p2-2p1+p0) = (6,-30), B = 6(p3-2p2+p1) = (-6,30):
  // (|A|² + A·B + |B|²)/3 = (936 - 936 + 936)/3 = 312.
  EXPECT_DOUBLE_EQ(linearized_energy_local(kS), 312.0);
}

RC_GTEST_PROP(Energy, LinearizedLocalMatchesSimpsonOnRandomCubics, ()) {
  const CubicBezier b = random_cubic();
  const double exact = (norm2(b.d2(0.0)) + 4.0 * norm2(b.d2(0.5)) + norm2(b.d2(1.0))) / 6.0;
  RC_ASSERT(std::abs(linearized_energy_local(b) - exact) <= 1e-12 * (1.0 + exact));
}

TEST(Energy, LinearizedInTheGlobalParameter) {
  // ∫|s''(t)|² dt over a piece spanning dt, computed from Spline::derivative with Simpson
  // (exact: quadratic integrand), equals local / dt³.
  Spline s;
  s.segments.push_back({kS, 0.0, 0.5, 0});
  s.segments.push_back({bez(kS.p[3], {5, 3}, {6, 0}, {8, 1}), 0.5, 2.5, 1});
  double total = 0.0;
  for (const Segment& g : s.segments) {
    const double dt = g.t1 - g.t0;
    const auto f = [&](double t) { return norm2(s.derivative(t, 2)); };
    const double mid = 0.5 * (g.t0 + g.t1);
    // Evaluate just inside the piece so the joint belongs to it.
    const double a = g.t0 + 1e-15 * dt, b = g.t1 - 1e-15 * dt;
    const double ref = dt / 6.0 * (f(a) + 4.0 * f(mid) + f(b));
    EXPECT_NEAR(linearized_energy(g.bezier, dt), ref, 1e-10 * ref);
    EXPECT_DOUBLE_EQ(linearized_energy(g.bezier, dt),
                     linearized_energy_local(g.bezier) / (dt * dt * dt));
    total += linearized_energy(g.bezier, dt);
  }
  EXPECT_DOUBLE_EQ(linearized_energy(s), total);
  EXPECT_DOUBLE_EQ(linearized_energy(kS, 0.5), 312.0 * 8.0);
  EXPECT_THROW(linearized_energy(kS, 0.0), Error);
  EXPECT_THROW(linearized_energy(kS, -1.0), Error);
  s.segments[1].t1 = 0.5;
  try {
    linearized_energy(s);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(e.index(), std::optional<std::size_t>(1));
  }
}

TEST(Energy, BendingOfQuarterCircleApproximation) {
  const Quadrature q = bending_energy(kQuarter);
  EXPECT_FALSE(q.singular);
  // Brute force: composite Simpson of κ²|b'| with 20000 panels (error ~1e-17 relative).
  const double ref = simpson([](double u) { return bending_integrand(kQuarter, u); }, 20000);
  EXPECT_NEAR(q.value, ref, 1e-9 * ref);
  EXPECT_LE(q.error_estimate, 1e-9 * ref);
  // Bracket independent of any quadrature of κ: κ ∈ [κmin, κmax] on the piece, so
  // κmin²·L ≤ ∫κ² ds ≤ κmax²·L.
  double kmin = 1e9, kmax = -1e9;
  for (int i = 0; i <= 10000; ++i) {
    const double k = kQuarter.curvature(i / 10000.0);
    kmin = std::min(kmin, k);
    kmax = std::max(kmax, k);
  }
  const double len = arc_length(kQuarter).value;
  EXPECT_GE(q.value, kmin * kmin * len);
  EXPECT_LE(q.value, kmax * kmax * len);
  // The exact circular arc has θ/R = π/2; the cubic's radial error (2.7e-4) makes the energy
  // differ by -9.54e-5 relative (SciPy quad of the same integrand, epsrel
  // 1e-13: 1.5706464166073046).
  EXPECT_NEAR(q.value, 1.5706464166073046, 1e-12);
  EXPECT_NEAR(q.value / (std::numbers::pi / 2) - 1.0, -9.5436e-5, 1e-8);
}

TEST(Energy, BendingMatchesSimpsonOnCurvedPieces) {
  for (const CubicBezier& b : {kS, kLoop}) {
    const double ref = simpson([&](double u) { return bending_integrand(b, u); }, 40000);
    const Quadrature q = bending_energy(b);
    EXPECT_FALSE(q.singular);
    EXPECT_NEAR(q.value, ref, 2e-9 * ref);
  }
  // A tighter accuracy gives a tighter answer.
  EnergyOptions tight;
  tight.accuracy = 1e-13;
  const double ref = simpson([&](double u) { return bending_integrand(kS, u); }, 40000);
  EXPECT_NEAR(bending_energy(kS, tight).value, ref, 1e-12 * ref);
}

TEST(Energy, BendingIsInvariantUnderRigidMotionsAndScalesAsOneOverLength) {
  const double e = bending_energy(kS).value;
  const CubicBezier moved = transform(kS, 0.7, 1.0, {5.0, -3.0});
  EXPECT_NEAR(bending_energy(moved).value, e, 1e-9 * e);
  EXPECT_NEAR(bending_energy(kS.reversed()).value, e, 1e-9 * e);
  const CubicBezier scaled = transform(kS, -1.1, 4.0, {0.5, 0.5});
  EXPECT_NEAR(bending_energy(scaled).value, e / 4.0, 1e-9 * e);
  // ∫(dκ/ds)² ds scales as 1/λ³, length as λ.
  const double cv = curvature_variation_energy(kS).value;
  EXPECT_NEAR(curvature_variation_energy(scaled).value, cv / 64.0, 1e-9 * cv);
  EXPECT_NEAR(arc_length(scaled).value, 4.0 * arc_length(kS).value, 1e-9);
}

TEST(Energy, CurvatureVariationMatchesFiniteDifferencesOfCurvature) {
  // Independent of the closed-form dκ/du: differentiate CubicBezier::curvature numerically
  // (central difference, h = 1e-5: error ~1e-10·|κ'''|) and integrate (dκ/du)²/|b'| by Simpson.
  for (const CubicBezier& b : {kQuarter, kS}) {
    const double h = 1e-5;
    const auto f = [&](double u) {
      const double dk = (b.curvature(u + h) - b.curvature(u - h)) / (2.0 * h);
      return dk * dk / norm(b.d1(u));
    };
    // The polynomial pieces extend beyond [0,1], so the stencil may straddle the ends.
    const double ref = simpson(f, 4000);
    const Quadrature q = curvature_variation_energy(b);
    EXPECT_FALSE(q.singular);
    EXPECT_NEAR(q.value, ref, 1e-6 * ref);
  }
  // The circle approximation has nearly constant curvature: tiny but non-zero variation.
  const double cv = curvature_variation_energy(kQuarter).value;
  EXPECT_GT(cv, 0.0);
  EXPECT_LT(cv, 1e-2);
}

TEST(Energy, StraightPiecesHaveZeroBendingAndChordLength) {
  // Uneven collinear control points (0.1, 2.5 along a direction with non-representable ratios).
  const Vec2 d = normalized(Vec2{1.0, 3.0});
  const Point o{0.1, 0.7};
  const CubicBezier line{{o, o + 0.1 * d, o + 2.5 * d, o + 3.0 * d}};
  const Quadrature bq = bending_energy(line), cq = curvature_variation_energy(line);
  EXPECT_EQ(bq.value, 0.0);
  EXPECT_FALSE(bq.singular);
  EXPECT_EQ(cq.value, 0.0);
  EXPECT_FALSE(cq.singular);
  EXPECT_NEAR(arc_length(line).value, 3.0, 1e-12);
}

TEST(Energy, CollinearReversalIsSingular) {
  // x'(u) ∝ 6(1-u)² - 18u(1-u) + 6u² changes sign twice: the point stops and goes back.
  const CubicBezier back = bez({0, 0}, {2, 0}, {-1, 0}, {1, 0});
  const Quadrature q = bending_energy(back);
  EXPECT_TRUE(q.singular);
  EXPECT_EQ(q.value, 0.0);
  // Length: ∫|x'| covers 0 -> max -> min -> 1; compare with Simpson of |b'|.
  const double ref = simpson([&](double u) { return norm(back.d1(u)); }, 200000);
  const Quadrature len = arc_length(back);
  EXPECT_FALSE(len.singular);
  EXPECT_NEAR(len.value, ref, 1e-9 * ref);
}

TEST(Energy, CuspIsSingularButFinite) {
  for (const Quadrature& q : {bending_energy(kCusp), curvature_variation_energy(kCusp)}) {
    EXPECT_TRUE(q.singular);
    EXPECT_TRUE(std::isfinite(q.value));
    EXPECT_TRUE(std::isfinite(q.error_estimate));
    EXPECT_GE(q.value, 0.0);
  }
  // The length is fine at a cusp (|b'| is continuous): the kink is a breakpoint of the rule.
  const double ref = simpson([&](double u) { return norm(kCusp.d1(u)); }, 20000);
  EXPECT_NEAR(arc_length(kCusp).value, ref, 1e-9 * ref);
  EXPECT_FALSE(arc_length(kCusp).singular);
  // A zero-length handle: speed 0 at u = 0 and κ ~ 1/u there, ∫κ² ds diverges.
  const CubicBezier handle = bez({0, 0}, {0, 0}, {1, 1}, {2, 0});
  EXPECT_TRUE(bending_energy(handle).singular);
  EXPECT_TRUE(std::isfinite(bending_energy(handle).value));
  // A point.
  const CubicBezier point = bez({1, 1}, {1, 1}, {1, 1}, {1, 1});
  EXPECT_TRUE(bending_energy(point).singular);
  EXPECT_EQ(bending_energy(point).value, 0.0);
  EXPECT_EQ(arc_length(point).value, 0.0);
}

TEST(Energy, NearCuspIsNotSingularAndConverges) {
  // p2 moved by 2e-4 off the cusp cubic: the hodograph misses the origin by 1.5e-4, a sharp but
  // integrable peak of κ²|b'| (width ~2e-5 in u) that Simpson with 2e6 panels resolves.
  const CubicBezier near = bez({0.0, 0.0}, {1.0, 1.0}, {2e-4, 1.0}, {1.0, 0.0});
  const Quadrature q = bending_energy(near);
  EXPECT_FALSE(q.singular);
  const double ref = simpson([&](double u) { return bending_integrand(near, u); }, 2000000);
  EXPECT_NEAR(q.value, ref, 1e-8 * ref);
  EXPECT_NEAR(q.value, 355520025.4180056, 1e-8 * ref);  // SciPy quad, breakpoints at the peak
  // Moved along the tangent instead: the speed minimum is only 7.5e-9 (the x-speed vanishes
  // quadratically), the energy 1.4e17 — huge but finite and above the speed floor, so it is
  // integrated, not flagged. Reference: mpmath quad at 40 digits of the same double control
  // points, breakpoints at u0 ± 10^-k. In double, b'(u) near u0 is O(1) terms cancelling to
  // 7.5e-9: a relative rounding of ~4e-8 in the speed, five times that in κ²|b'| ∝ 1/|b'|⁵ at
  // the peak, so 5e-8 is as close as double evaluation gets (SciPy's quad: 2.8e-9 off, ours
  // 2.2e-8; one ulp more in p2.y moves the value by 1.5e-8).
  const CubicBezier nearer = bez({0.0, 0.0}, {1.0, 1.0}, {0.0, 1.0002}, {1.0, 0.0});
  const Quadrature q2 = bending_energy(nearer);
  EXPECT_FALSE(q2.singular);
  EXPECT_NEAR(q2.value, 1.4229335538119883e+17, 5e-8 * q2.value);
  EXPECT_LE(q2.error_estimate, 1e-8 * q2.value);
}

TEST(Energy, SplineTotalsSumThePieces) {
  Spline s;
  s.segments.push_back({kS, 0.0, 1.0, 0});
  s.segments.push_back({transform(kQuarter, 0.0, 1.0, kS.p[3] - kQuarter.p[0]), 1.0, 2.0, 1});
  EXPECT_DOUBLE_EQ(bending_energy(s).value, bending_energy(s.segments[0].bezier).value +
                                                bending_energy(s.segments[1].bezier).value);
  EXPECT_DOUBLE_EQ(arc_length(s).value,
                   arc_length(s.segments[0].bezier).value + arc_length(s.segments[1].bezier).value);
  EXPECT_DOUBLE_EQ(curvature_variation_energy(s).value,
                   curvature_variation_energy(s.segments[0].bezier).value +
                       curvature_variation_energy(s.segments[1].bezier).value);
  EXPECT_FALSE(bending_energy(s).singular);
  s.segments.push_back({bez(kQuarter.p[3], {1, 2}, {0, 2}, {1, 1}), 2.0, 3.0, 2});
  s.segments.back().bezier = kCusp;
  EXPECT_TRUE(bending_energy(s).singular);
  EXPECT_TRUE(std::isfinite(bending_energy(s).value));
}

RC_GTEST_PROP(Energy, QuadraturesAreFiniteAndNonNegativeOnRandomCubics, ()) {
  const CubicBezier b = random_cubic();
  for (const Quadrature& q : {bending_energy(b), curvature_variation_energy(b), arc_length(b)}) {
    RC_ASSERT(std::isfinite(q.value));
    RC_ASSERT(std::isfinite(q.error_estimate));
    RC_ASSERT(q.value >= 0.0);
  }
  // Arc length lies between the chord and the control polygon length.
  const double len = arc_length(b).value;
  const double poly =
      distance(b.p[0], b.p[1]) + distance(b.p[1], b.p[2]) + distance(b.p[2], b.p[3]);
  RC_ASSERT(len >= distance(b.p[0], b.p[3]) * (1.0 - 1e-9));
  RC_ASSERT(len <= poly * (1.0 + 1e-9) + 1e-12);
}

}  // namespace
}  // namespace fairspline
