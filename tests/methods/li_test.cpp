// Tests of the Li methods (src/methods/li.cpp): the paper's systems for uniform knots, the
// non-uniform derivation via finite differences of an independently computed energy,
// C2 / natural end conditions, the singular curvature-variation case, clamping, errors and
// metamorphic properties.
#include "fairspline/methods/li.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <numbers>

#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

using testing::ellipse;
using testing::hermite_tangents;
using testing::random_walk;
using testing::scale_of;

const std::vector<Point> kLiExample1 = {{1, 90},  {3, 105},  {6, 120}, {10, 100},
                                        {12, 85}, {15, 104}, {17, 80}};

FitInput input_of(std::vector<Point> pts, double alpha, bool closed = false) {
  FitInput in;
  in.points = std::move(pts);
  in.alpha = alpha;
  in.closed = closed;
  return in;
}

// Residual of the paper's uniform systems (2.13)/(2.17) (open) and (2.20)/(2.21) (closed)
// with coefficients (a = off-diagonal, b = interior diagonal, e = end diagonal, r = rhs factor).
double paper_system_residual(const std::vector<Point>& p, const std::vector<Vec2>& m, bool closed,
                             double a, double b, double e, double r) {
  const std::size_t n = p.size();
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Vec2 lhs, rhs;
    if (closed) {
      const std::size_t prev = (i + n - 1) % n, next = (i + 1) % n;
      lhs = a * m[prev] + b * m[i] + a * m[next];
      rhs = r * (p[next] - p[prev]);
    } else if (i == 0) {
      lhs = e * m[0] + a * m[1];
      rhs = r * (p[1] - p[0]);
    } else if (i + 1 == n) {
      lhs = a * m[n - 2] + e * m[n - 1];
      rhs = r * (p[n - 1] - p[n - 2]);
    } else {
      lhs = a * m[i - 1] + b * m[i] + a * m[i + 1];
      rhs = r * (p[i + 1] - p[i - 1]);
    }
    worst = std::max(worst, norm(lhs - rhs));
  }
  return worst;
}

TEST(Li, StrainUniformSolvesPaperSystem213) {
  const FitResult r = fit("li-strain", input_of(kLiExample1, 0.0), {}, ReportLevel::kNone);
  EXPECT_LT(paper_system_residual(kLiExample1, hermite_tangents(r), false, 1, 4, 2, 3),
            1e-12 * 120);
  // knots are 0..n-1 for alpha = 0
  for (std::size_t i = 0; i < r.knots.size(); ++i) EXPECT_EQ(r.knots[i], double(i));
}

TEST(Li, CombinedUniformSolvesPaperSystem217) {
  const FitResult r = fit("li-combined", input_of(kLiExample1, 0.0), {}, ReportLevel::kNone);
  EXPECT_LT(paper_system_residual(kLiExample1, hermite_tangents(r), false, 19, 40, 20, 39),
            1e-11 * 120);
}

TEST(Li, ClosedUniformSolvesPaperSystems220And221) {
  const auto pts = ellipse(9);
  const FitResult s = fit("li-strain", input_of(pts, 0.0, true), {}, ReportLevel::kNone);
  EXPECT_LT(paper_system_residual(pts, hermite_tangents(s), true, 1, 4, 0, 3), 1e-13);
  const FitResult c = fit("li-combined", input_of(pts, 0.0, true), {}, ReportLevel::kNone);
  EXPECT_LT(paper_system_residual(pts, hermite_tangents(c), true, 19, 40, 0, 39), 1e-12);
  EXPECT_EQ(s.spline.segments.size(), 9u);
  EXPECT_EQ(s.knots.size(), 10u);
  EXPECT_EQ(s.spline.segments.back().bezier.p[3], pts[0]);
}

// The weighted energy computed independently of the implementation: for every span a Hermite
// cubic with the given tangents, ∫|s''|² dt by 2-point Gauss–Legendre (exact for the quadratic
// |s''|²) and ∫|s'''|² dt (constant).
double weighted_energy(const std::vector<Point>& p, const std::vector<double>& t,
                       const std::vector<Vec2>& m, bool closed, double w1, double w2) {
  const std::size_t n = p.size(), spans = closed ? n : n - 1;
  const double H = (t.back() - t.front()) / double(spans);
  double e2 = 0, e3 = 0;
  const double g = 0.5 / std::sqrt(3.0);
  for (std::size_t i = 0; i < spans; ++i) {
    const std::size_t j = (i + 1) % n;
    const double h = t[i + 1] - t[i];
    const CubicBezier b{{p[i], p[i] + h / 3 * m[i], p[j] - h / 3 * m[j], p[j]}};
    for (double u : {0.5 - g, 0.5 + g}) e2 += 0.5 * norm2(b.d2(u)) / (h * h * h);
    e3 += norm2(b.d3()) / (h * h * h * h * h);
  }
  return w1 * e2 + w2 * H * H * e3;
}

void expect_stationary(const FitResult& r, double w1, double w2,
                       const std::vector<std::size_t>& fixed = {}) {
  auto m = hermite_tangents(r);
  const double e0 = weighted_energy(r.points, r.knots, m, r.closed, w1, w2);
  // The energy is quadratic in m, so central differences are exact up to rounding.
  double mscale = 0;
  for (const Vec2& v : m) mscale = std::max(mscale, norm(v));
  const double eps = 1e-3 * mscale;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (std::find(fixed.begin(), fixed.end(), i) != fixed.end()) continue;
    for (int c = 0; c < 2; ++c) {
      auto mp = m, mm = m;
      (c == 0 ? mp[i].x : mp[i].y) += eps;
      (c == 0 ? mm[i].x : mm[i].y) -= eps;
      const double ep = weighted_energy(r.points, r.knots, mp, r.closed, w1, w2);
      const double em = weighted_energy(r.points, r.knots, mm, r.closed, w1, w2);
      const double grad = (ep - em) / (2 * eps);
      EXPECT_LT(std::abs(grad) * mscale, 1e-8 * std::max(e0, 1e-300) + 1e-9 * (ep + em))
          << "node " << i << " component " << c;
      EXPECT_GE(ep + em - 2 * e0, -1e-12 * e0) << "not a minimum at node " << i;
    }
  }
}

TEST(Li, NonUniformStrainIsStationaryForTheTrueEnergy) {
  for (double alpha : {0.5, 2.0 / 3.0, 1.0}) {
    const FitResult r =
        fit("li-strain", input_of(random_walk(12, 7), alpha), {}, ReportLevel::kNone);
    expect_stationary(r, 1, 0);
  }
}

TEST(Li, NonUniformCombinedIsStationaryForTheTrueEnergy) {
  for (auto [w1, w2] : {std::pair{1.0, 1.0}, {1.0, 0.1}, {0.2, 5.0}}) {
    for (bool closed : {false, true}) {
      FitInput in = input_of(random_walk(11, 3), 0.5, closed);
      const FitResult r = fit("li-combined", in, {{"weights", {w1, w2}}}, ReportLevel::kNone);
      expect_stationary(r, w1, w2);
    }
  }
}

TEST(Li, StrainIsC2WithNaturalEnds) {
  const FitResult r = fit("li-strain", input_of(random_walk(20, 11), 0.5), {}, ReportLevel::kNone);
  const auto& segs = r.spline.segments;
  for (std::size_t k = 0; k + 1 < segs.size(); ++k) {
    const double ha = segs[k].t1 - segs[k].t0, hb = segs[k + 1].t1 - segs[k + 1].t0;
    const Vec2 a = segs[k].bezier.d2(1) / (ha * ha), b = segs[k + 1].bezier.d2(0) / (hb * hb);
    EXPECT_LT(norm(a - b), 1e-10 * std::max(norm(a), 1.0)) << "joint " << k;
  }
  EXPECT_LT(norm(segs.front().bezier.d2(0)), 1e-12);
  EXPECT_LT(norm(segs.back().bezier.d2(1)), 1e-12);
}

TEST(Li, ClosedStrainIsPeriodicC2) {
  const FitResult r =
      fit("li-strain", input_of(random_walk(15, 5, 60), 1.0, true), {}, ReportLevel::kNone);
  const auto& segs = r.spline.segments;
  for (std::size_t k = 0; k < segs.size(); ++k) {
    const auto& A = segs[k];
    const auto& B = segs[(k + 1) % segs.size()];
    const double ha = A.t1 - A.t0, hb = B.t1 - B.t0;
    EXPECT_LT(norm(A.bezier.d1(1) / ha - B.bezier.d1(0) / hb), 1e-10);
    EXPECT_LT(norm(A.bezier.d2(1) / (ha * ha) - B.bezier.d2(0) / (hb * hb)), 1e-9);
  }
}

TEST(Li, DuplicateClosingPointIsDropped) {
  auto pts = ellipse(8);
  pts.push_back(pts.front());
  const FitResult r = fit("li-strain", input_of(pts, 0.5, true), {}, ReportLevel::kNone);
  EXPECT_EQ(r.points.size(), 8u);
  EXPECT_EQ(r.spline.segments.size(), 8u);
}

TEST(Li, CurvatureVariationNeedsAClampedTangent) {
  try {
    fit("li-curvature-variation", input_of(kLiExample1, 0.5));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kSingularSystem);
    EXPECT_NE(std::string(e.what()).find("Give a start tangent"), std::string::npos) << e.what();
  }
  // Closed with an even count is singular too; with an odd count it is unique.
  EXPECT_THROW(fit("li-curvature-variation", input_of(ellipse(8), 0.5, true)), Error);
  const FitResult odd =
      fit("li-curvature-variation", input_of(ellipse(7), 0.5, true), {}, ReportLevel::kNone);
  for (const auto& s : odd.spline.segments) EXPECT_LT(norm(s.bezier.d3()), 1e-12);
}

TEST(Li, CurvatureVariationWithStartTangentIsC1PiecewiseQuadratic) {
  FitInput in = input_of(kLiExample1, 0.5);
  in.start_tangent = Vec2{1, 2};
  const FitResult r = fit("li-curvature-variation", in, {}, ReportLevel::kNone);
  const auto m = hermite_tangents(r);
  EXPECT_LT(norm(m[0] - Vec2{1, 2}), 1e-14);
  for (const auto& s : r.spline.segments) {
    // A cubic with zero third derivative is a degree-elevated quadratic.
    EXPECT_LT(norm(s.bezier.d3()), 1e-9 * 120) << "span " << s.span;
  }
  // Paper (2.16) with non-uniform knots: m_i + m_{i+1} = 2 ΔP_i / h_i.
  for (std::size_t i = 0; i + 1 < m.size(); ++i) {
    const double h = r.knots[i + 1] - r.knots[i];
    EXPECT_LT(norm(m[i] + m[i + 1] - 2.0 / h * (r.points[i + 1] - r.points[i])), 1e-10 * 120);
  }
}

TEST(Li, ClampedEndsAreKeptAndInteriorIsStationary) {
  FitInput in = input_of(random_walk(9, 2), 0.5);
  in.start_tangent = Vec2{0.3, -1.0};
  in.end_tangent = Vec2{2.0, 0.5};
  for (const char* method : {"li-strain", "li-combined"}) {
    const FitResult r = fit(method, in, {}, ReportLevel::kNone);
    const auto m = hermite_tangents(r);
    EXPECT_LT(norm(m.front() - *in.start_tangent), 1e-14);
    EXPECT_LT(norm(m.back() - *in.end_tangent), 1e-14);
    expect_stationary(r, 1, std::string(method) == "li-combined" ? 1 : 0, {0, m.size() - 1});
  }
}

TEST(Li, ClampedInteriorPointOfClosedCurve) {
  FitInput in = input_of(ellipse(10), 0.5, true);
  in.tangents.assign(10, std::nullopt);
  in.kinds.assign(10, PointKind::kSmooth);
  in.tangents[4] = Vec2{-1, 0.5};
  in.kinds[4] = PointKind::kClamped;
  const FitResult r = fit("li-combined", in, {}, ReportLevel::kNone);
  const auto m = hermite_tangents(r);
  EXPECT_LT(norm(m[4] - Vec2{-1, 0.5}), 1e-14);
  expect_stationary(r, 1, 1, {4});
}

TEST(Li, TwoPointsGiveAStraightLine) {
  const FitResult r = fit("li-strain", input_of({{0, 0}, {3, 4}}, 0.5), {}, ReportLevel::kNone);
  ASSERT_EQ(r.spline.segments.size(), 1u);
  const auto& b = r.spline.segments[0].bezier;
  EXPECT_NEAR(cross(b.p[1] - b.p[0], Vec2{3, 4}), 0, 1e-12);
  EXPECT_NEAR(cross(b.p[2] - b.p[0], Vec2{3, 4}), 0, 1e-12);
}

TEST(Li, BadInputGivesErrorsWithIndex) {
  auto expect_error = [](const FitInput& in, ErrorCode code, std::optional<std::size_t> index,
                         const nlohmann::json& options = nlohmann::json::object()) {
    try {
      fit("li-combined", in, options);
      ADD_FAILURE() << "expected " << error_code_name(code);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), code) << e.what();
      EXPECT_EQ(e.index(), index) << e.what();
      EXPECT_GT(std::string(e.what()).size(), 20u);
    }
  };
  expect_error(input_of({{0, 0}}, 0.5), ErrorCode::kTooFewPoints, std::nullopt);
  expect_error(input_of({{0, 0}, {1, 0}}, 0.5, true), ErrorCode::kTooFewPoints, std::nullopt);
  expect_error(input_of({{0, 0}, {1, NAN}, {2, 0}}, 0.5), ErrorCode::kNonFinite, 1);
  expect_error(input_of({{0, 0}, {1, 0}, {INFINITY, 0}}, 0.5), ErrorCode::kNonFinite, 2);
  expect_error(input_of({{0, 0}, {1, 0}, {1, 0}, {2, 1}}, 0.5), ErrorCode::kRepeatedPoint, 2);
  expect_error(input_of({{0, 0}, {1, 0}, {1, 1}, {1, 1}}, 0.5, true), ErrorCode::kRepeatedPoint, 3);
  expect_error(input_of({{0, 0}, {1, 0}, {2, 1}}, 1.5), ErrorCode::kBadOption, std::nullopt);
  FitInput corner = input_of({{0, 0}, {1, 0}, {2, 1}}, 0.5);
  corner.kinds = {PointKind::kSmooth, PointKind::kCorner, PointKind::kSmooth};
  expect_error(corner, ErrorCode::kInvalidArgument, 1);
  FitInput nan_tangent = input_of({{0, 0}, {1, 0}, {2, 1}}, 0.5);
  nan_tangent.start_tangent = Vec2{NAN, 1};
  expect_error(nan_tangent, ErrorCode::kNonFinite, 0);
  expect_error(input_of(kLiExample1, 0.5), ErrorCode::kBadOption, std::nullopt,
               {{"weights", {-1, 1}}});
  expect_error(input_of(kLiExample1, 0.5), ErrorCode::kBadOption, std::nullopt,
               {{"weights", {1, 2, 3}}});
  expect_error(input_of(kLiExample1, 0.5), ErrorCode::kUnknownOption, std::nullopt,
               {{"weight", {1, 2}}});
  expect_error(input_of(kLiExample1, 0.5), ErrorCode::kBadOption, std::nullopt,
               {{"weights", {0, 0}}});
}

// ---- metamorphic properties ----

struct Similarity {
  double angle, scale;
  Vec2 shift;
  Point operator()(Point p) const { return scale * rotate(p, angle) + shift; }
};

void expect_same_curve(const FitResult& a, const FitResult& b, const Similarity& T, double tol) {
  RC_ASSERT(a.spline.segments.size() == b.spline.segments.size());
  for (std::size_t k = 0; k < a.spline.segments.size(); ++k) {
    for (int j = 0; j < 4; ++j) {
      const Point expected = T(a.spline.segments[k].bezier.p[j]);
      RC_ASSERT(norm(expected - b.spline.segments[k].bezier.p[j]) <= tol);
    }
  }
}

RC_GTEST_PROP(LiProperty, SimilarityEquivariance, ()) {
  const auto n = *rc::gen::inRange<std::size_t>(2, 40);
  const auto seed = *rc::gen::arbitrary<std::uint32_t>();
  const bool closed = n >= 3 && *rc::gen::arbitrary<bool>();
  const double alpha = *rc::gen::element(0.0, 0.5, 2.0 / 3.0, 1.0);
  const char* method = *rc::gen::element("li-strain", "li-combined");
  const Similarity T{*rc::gen::inRange(-314, 314) / 100.0,
                     std::pow(10.0, *rc::gen::inRange(-30, 30) / 10.0),
                     {*rc::gen::inRange(-1000, 1000) * 1.0, *rc::gen::inRange(-1000, 1000) * 1.0}};
  auto pts = random_walk(n, seed, closed ? 60 : 150);
  std::vector<Point> moved;
  for (const Point& p : pts) moved.push_back(T(p));
  const FitResult a = fit(method, input_of(pts, alpha, closed), {}, ReportLevel::kNone);
  const FitResult b = fit(method, input_of(moved, alpha, closed), {}, ReportLevel::kNone);
  const double tol = 1e-9 * (T.scale * scale_of(pts) + norm(T.shift));
  expect_same_curve(a, b, T, tol);
}

RC_GTEST_PROP(LiProperty, ReversalReversesTheCurve, ()) {
  const auto n = *rc::gen::inRange<std::size_t>(2, 40);
  const auto seed = *rc::gen::arbitrary<std::uint32_t>();
  const char* method = *rc::gen::element("li-strain", "li-combined");
  const double alpha = *rc::gen::element(0.0, 0.5, 1.0);
  auto pts = random_walk(n, seed);
  auto rev = std::vector<Point>(pts.rbegin(), pts.rend());
  const FitResult a = fit(method, input_of(pts, alpha), {}, ReportLevel::kNone);
  const FitResult b = fit(method, input_of(rev, alpha), {}, ReportLevel::kNone);
  RC_ASSERT(testing::is_reversed_curve(a, b, 1e-10 * scale_of(pts)));
}

}  // namespace
}  // namespace fairspline

namespace fairspline {
namespace {

// Found by fuzz_fit (tests/fuzz/corpus/fuzz_fit/regression-li-strain-1e300): the method
// report's strain term was expanded in the tangents and chord/h, squaring coordinates of 1e300
// (Inf - Inf = NaN) for a straight piece whose energy is 0. It now comes from the control
// points, as the report's linearized energy does, and an energy that really overflows is an
// Error.
TEST(Li, EnergyTermsOfHugeCoordinatesAreFiniteOrAnError) {
  FitInput in;
  in.points = {{1e300, 1e300}, {1e-8, 811.5625}};
  in.alpha = 0.0;
  const FitResult r = fit("li-strain", in, {}, ReportLevel::kFull);
  const double strain = r.method_report.at("strain_term").get<double>();
  EXPECT_TRUE(std::isfinite(strain));
  EXPECT_DOUBLE_EQ(strain, r.report->linearized_energy);
  EXPECT_TRUE(std::isfinite(r.method_report.at("third_derivative_term").get<double>()));
  EXPECT_TRUE(std::isfinite(r.method_report.at("objective").get<double>()));
  in.points = {{0, 0}, {1e300, 0}, {1e300, 1e300}};
  try {
    const FitResult big = fit("li-strain", in, {}, ReportLevel::kFull);
    EXPECT_TRUE(std::isfinite(big.method_report.at("strain_term").get<double>()));
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite) << e.what();
  }
}

TEST(Li, HugeAndTinyCoordinatesGiveACurveOrAClearError) {
  // Far apart but representable: a curve, finite everywhere.
  for (double s : {1e-300, 1e-160, 1e160, 1e300}) {
    FitInput in;
    in.points = {{0, 0}, {s, 0}, {s, s}, {0, s}};
    const FitResult r = fit("li-combined", in, {}, ReportLevel::kNone);
    for (const auto& seg : r.spline.segments) {
      for (const Point& p : seg.bezier.p) EXPECT_TRUE(is_finite(p)) << s;
    }
    for (const Vec2& d : r.tangents) EXPECT_NEAR(norm(d), 1.0, 1e-15) << s;
  }
  // Control points beyond DBL_MAX: the fused finite check names the span.
  FitInput in;
  in.points = {{0, 0}, {1.7e308, 0}, {1.7e308, 1.7e308}};
  in.alpha = 0.0;
  try {
    const FitResult r = fit("li-strain", in, {}, ReportLevel::kNone);
    for (const auto& seg : r.spline.segments) {
      for (const Point& p : seg.bezier.p) EXPECT_TRUE(is_finite(p));
    }
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite) << e.what();
    EXPECT_TRUE(e.index().has_value());
  }
  // Knot intervals that overflow.
  in.alpha = 1.0;
  in.points = {{-1.7e308, 0}, {1.7e308, 0}, {1.7e308, 1e308}};
  try {
    fit("li-strain", in);
    ADD_FAILURE() << "expected an overflow error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite) << e.what();
  }
}

}  // namespace
}  // namespace fairspline
