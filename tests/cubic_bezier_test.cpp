// Tests of CubicBezier: evaluation, derivatives and curvature against finite differences,
// split/subsegment/reversed reproduce the curve, tight bounding boxes, arc length.
#include "fairspline/cubic_bezier.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fairspline {
namespace {

CubicBezier bez(Point a, Point b, Point c, Point d) {
  return {{a, b, c, d}};
}

const CubicBezier kS = bez({0.0, 0.0}, {1.0, 2.0}, {3.0, -1.0}, {4.0, 1.0});  // S-shaped
const CubicBezier kLoop = bez({0.0, 0.0}, {2.0, 1.0}, {-1.0, 1.0}, {1.0, 0.0});
const double kArcK = 4.0 / 3.0 * (std::numbers::sqrt2 - 1.0);
const CubicBezier kQuarter = bez({1.0, 0.0}, {1.0, kArcK}, {kArcK, 1.0}, {0.0, 1.0});

void expect_near(Vec2 a, Vec2 b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
}

CubicBezier random_cubic() {
  CubicBezier b;
  for (auto& q : b.p)
    q = {*rc::gen::inRange(-1000, 1001) / 100.0, *rc::gen::inRange(-1000, 1001) / 100.0};
  return b;
}

TEST(CubicBezier, EvalInterpolatesEndsAndMatchesDeCasteljau) {
  expect_near(kS.eval(0.0), kS.p[0], 0.0);
  expect_near(kS.eval(1.0), kS.p[3], 0.0);
  for (double u : {0.1, 0.37, 0.5, 0.9}) {
    const Point a = lerp(kS.p[0], kS.p[1], u), b = lerp(kS.p[1], kS.p[2], u),
                c = lerp(kS.p[2], kS.p[3], u);
    expect_near(kS.eval(u), lerp(lerp(a, b, u), lerp(b, c, u), u), 1e-14);
  }
}

TEST(CubicBezier, DerivativesMatchCentralDifferences) {
  // Central differences with step h have error h²/6·|f'''| (+ rounding eps/h): with h = 1e-4
  // and derivatives of size ~10-100, errors are below 1e-6.
  const double h = 1e-4;
  for (const CubicBezier& b : {kS, kLoop, kQuarter}) {
    for (double u : {0.05, 0.3, 0.5, 0.71, 0.95}) {
      expect_near(b.d1(u), (b.eval(u + h) - b.eval(u - h)) / (2.0 * h), 1e-6);
      expect_near(b.d2(u), (b.d1(u + h) - b.d1(u - h)) / (2.0 * h), 1e-9);
      expect_near(b.d3(), (b.d2(u + h) - b.d2(u - h)) / (2.0 * h), 1e-9);
      // Second derivative directly from points: (f(u+h) - 2f(u) + f(u-h)) / h².
      expect_near(b.d2(u), (b.eval(u + h) - 2.0 * b.eval(u) + b.eval(u - h)) / (h * h), 1e-4);
      expect_near(b.hodograph().eval(u), b.d1(u), 1e-12);
    }
  }
}

TEST(CubicBezier, CurvatureMatchesFiniteDifferencesOfThePoints) {
  const double h = 1e-4;
  for (const CubicBezier& b : {kS, kLoop, kQuarter}) {
    for (double u : {0.1, 0.3, 0.5, 0.8}) {
      const Vec2 x1 = (b.eval(u + h) - b.eval(u - h)) / (2.0 * h);
      const Vec2 x2 = (b.eval(u + h) - 2.0 * b.eval(u) + b.eval(u - h)) / (h * h);
      const double fd = cross(x1, x2) / std::pow(norm(x1), 3);
      EXPECT_NEAR(b.curvature(u), fd, 1e-5 * std::max(1.0, std::abs(fd))) << "u=" << u;
    }
  }
  // A counter-clockwise arc of the unit circle turns left: κ ≈ +1 (the cubic approximation's
  // curvature stays within [0.978, 1.009], computed densely with SciPy).
  for (double u = 0.0; u <= 1.0; u += 0.125) {
    EXPECT_GT(kQuarter.curvature(u), 0.978);
    EXPECT_LT(kQuarter.curvature(u), 1.009);
    EXPECT_NEAR(kQuarter.reversed().curvature(u), -kQuarter.curvature(1.0 - u), 1e-12);
  }
  // Zero speed: defined as 0, never NaN.
  const CubicBezier cusp = bez({0.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}, {1.0, 0.0});
  EXPECT_EQ(norm(cusp.d1(0.5)), 0.0);
  EXPECT_EQ(cusp.curvature(0.5), 0.0);
}

TEST(CubicBezier, SplitAndSubsegmentReproduceTheCurve) {
  for (double u : {0.0, 0.25, 0.6, 1.0}) {
    const auto [left, right] = kS.split(u);
    for (double v = 0.0; v <= 1.0; v += 0.05) {
      expect_near(left.eval(v), kS.eval(u * v), 1e-13);
      expect_near(right.eval(v), kS.eval(u + (1.0 - u) * v), 1e-13);
    }
  }
  for (auto [u0, u1] : {std::pair{0.2, 0.7}, std::pair{0.9, 0.1}, std::pair{0.0, 1.0}}) {
    const CubicBezier sub = kLoop.subsegment(u0, u1);
    for (double v = 0.0; v <= 1.0; v += 0.05)
      expect_near(sub.eval(v), kLoop.eval(u0 + (u1 - u0) * v), 1e-13);
  }
  const CubicBezier r = kS.reversed();
  for (double v = 0.0; v <= 1.0; v += 0.1) expect_near(r.eval(v), kS.eval(1.0 - v), 1e-13);
}

// Found by fuzz_fit (tests/fuzz/corpus/fuzz_fit/regression-kozak-krajnc-huge-handles): a piece
// whose inner control points are 10^10 times its chord lost its end point to rounding in
// subsegment(t2, 1), so the spline missed the last point by 2e-6 of its size.
TEST(CubicBezier, SubsegmentKeepsTheEndPointsExactly) {
  const CubicBezier b = bez({1765.9375, 3391.875}, {3.8e8, 7.4e8}, {4.4e13, 8.4e13},
                            {1765.9648590087891, 3391.8847694396973});
  EXPECT_EQ(b.subsegment(0.25, 1.0).p[3], b.p[3]);
  EXPECT_EQ(b.subsegment(0.0, 0.5).p[0], b.p[0]);
  EXPECT_EQ(b.subsegment(1.0, 0.0).p[0], b.p[3]);
  EXPECT_EQ(b.subsegment(1.0, 0.0).p[3], b.p[0]);
}

RC_GTEST_PROP(CubicBezier, SplitReproducesRandomCurves, ()) {
  const CubicBezier b = random_cubic();
  const double u = *rc::gen::inRange(1, 1000) / 1000.0;
  const auto [left, right] = b.split(u);
  RC_ASSERT(left.p[3] == right.p[0]);
  for (double v : {0.0, 0.3, 0.5, 0.77, 1.0}) {
    RC_ASSERT(distance(left.eval(v), b.eval(u * v)) <= 1e-11);
    RC_ASSERT(distance(right.eval(v), b.eval(u + (1.0 - u) * v)) <= 1e-11);
  }
}

TEST(CubicBezier, BoundingBoxIsTight) {
  for (const CubicBezier& b : {kS, kLoop, kQuarter}) {
    const BBox box = b.bbox(), cbox = b.control_bbox();
    EXPECT_LE(cbox.min.x, box.min.x);
    EXPECT_LE(cbox.min.y, box.min.y);
    EXPECT_GE(cbox.max.x, box.max.x);
    EXPECT_GE(cbox.max.y, box.max.y);
    BBox seen{b.p[0], b.p[0]};
    const int n = 100000;
    for (int i = 0; i <= n; ++i) {
      const Point q = b.eval(static_cast<double>(i) / n);
      EXPECT_GE(q.x, box.min.x - 1e-12);
      EXPECT_GE(q.y, box.min.y - 1e-12);
      EXPECT_LE(q.x, box.max.x + 1e-12);
      EXPECT_LE(q.y, box.max.y + 1e-12);
      seen.min = {std::min(seen.min.x, q.x), std::min(seen.min.y, q.y)};
      seen.max = {std::max(seen.max.x, q.x), std::max(seen.max.y, q.y)};
    }
    // Dense samples reach the box sides to O(Δu²·|b''|) = 1e-10·|b''|.
    EXPECT_NEAR(seen.min.x, box.min.x, 1e-8);
    EXPECT_NEAR(seen.min.y, box.min.y, 1e-8);
    EXPECT_NEAR(seen.max.x, box.max.x, 1e-8);
    EXPECT_NEAR(seen.max.y, box.max.y, 1e-8);
  }
  // The S curve's box is strictly inside its control box (interior extrema in y).
  EXPECT_GT(kS.bbox().min.y, kS.control_bbox().min.y);
  EXPECT_LT(kS.bbox().max.y, kS.control_bbox().max.y);
}

TEST(CubicBezier, ArcLengthOfAStraightCubicIsTheChord) {
  // Control points on a line at uneven positions 0, 0.1, 2.5, 3 (monotone: the hodograph's
  // coefficients 0.3, 7.2, 1.5 are positive), so the length is exactly the chord 3·|d|.
  const Vec2 d{0.6, 0.8};
  const Point o{2.0, -1.0};
  const CubicBezier line{{o, o + 0.1 * d, o + 2.5 * d, o + 3.0 * d}};
  EXPECT_NEAR(line.arc_length(), 3.0, 3e-10 * 3.0);
  EXPECT_NEAR(line.arc_length(1e-14), 3.0, 1e-13);
}

TEST(CubicBezier, ArcLengthMatchesCompositeSimpson) {
  for (const CubicBezier& b : {kS, kLoop, kQuarter}) {
    // Composite Simpson with 20000 panels: error ~ h⁴·|f''''|/180 ~ 1e-18 relative.
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
      const double a = static_cast<double>(i) / n, h = 1.0 / n;
      sum += h / 6.0 * (norm(b.d1(a)) + 4.0 * norm(b.d1(a + h / 2)) + norm(b.d1(a + h)));
    }
    EXPECT_NEAR(b.arc_length(1e-12), sum, 1e-11 * sum);
    EXPECT_NEAR(b.arc_length(), sum, 1e-9 * sum);
  }
  // Circle approximation: length within 1.5e-4 of the quarter circle (SciPy: +1.403e-4).
  EXPECT_NEAR(kQuarter.arc_length() / (std::numbers::pi / 2) - 1.0, 1.4029e-4, 1e-8);
}

}  // namespace
}  // namespace fairspline
