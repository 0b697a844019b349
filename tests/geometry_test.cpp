// Tests of the spline geometry: arc length against exact lines and Richardson-extrapolated chord
// sums, its derivative against finite differences, the inverse, flattening within its tolerance
// both ways, exact bounds, the nearest point against a brute-force search, sub-curves, reversal,
// affine maps, frames at a cusp, and the errors.
#include "fairspline/geometry.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

constexpr double kPi = std::numbers::pi;

Segment piece(Point a, Point b, Point c, Point d, double t0, double t1, std::size_t span) {
  return {CubicBezier{{a, b, c, d}}, t0, t1, span};
}

// Two pieces along the x axis with uneven speed: t in [0, 1] covers x in [0, 1], t in [1, 3]
// covers x in [1, 4].
Spline straight() {
  Spline s;
  s.segments.push_back(piece({0, 0}, {0.05, 0}, {0.7, 0}, {1, 0}, 0.0, 1.0, 0));
  s.segments.push_back(piece({1, 0}, {1.2, 0}, {3.9, 0}, {4, 0}, 1.0, 3.0, 1));
  return s;
}

// The default fit of a closed curve through n points of a circle of radius r.
Spline circle_fit(std::size_t n, double r) {
  FitInput in;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2 * kPi * static_cast<double>(i) / static_cast<double>(n);
    in.points.push_back({r * std::cos(a), r * std::sin(a)});
  }
  in.closed = true;
  return fit("quasi-elastic", in).spline;
}

// A wavy open fit with sharp and gentle turns.
Spline wavy() {
  FitInput in;
  in.points = {{1, 90}, {3, 105}, {6, 120}, {10, 100}, {12, 85}, {15, 104}, {17, 80}};
  return fit("quasi-elastic", in).spline;
}

// Chord sum of N equal parameter steps per piece.
double chord_sum(const Spline& s, int n) {
  double total = 0.0;
  for (const Segment& g : s.segments) {
    Point prev = g.bezier.p[0];
    for (int i = 1; i <= n; ++i) {
      const Point p = g.bezier.eval(static_cast<double>(i) / n);
      total += distance(prev, p);
      prev = p;
    }
  }
  return total;
}

TEST(Geometry, LengthOfAStraightLineIsExact) {
  const Spline s = straight();
  EXPECT_NEAR(length(s), 4.0, 1e-14);
  const std::vector<double> parts = segment_lengths(s);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_NEAR(parts[0], 1.0, 1e-15);
  EXPECT_NEAR(parts[1], 3.0, 1e-14);
  // The point at arc length ℓ is (ℓ, 0): the inverse is exact whatever the speed.
  const std::vector<double> at = {0.0, 0.3, 1.0, 2.5, 3.999, 4.0};
  const std::vector<double> t = parameters_at_lengths(s, at);
  for (std::size_t i = 0; i < at.size(); ++i) {
    EXPECT_NEAR(s.eval(t[i]).x, at[i], 1e-11) << at[i];
  }
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_EQ(t.back(), 3.0);
  const std::vector<double> back = lengths_at(s, t);
  for (std::size_t i = 0; i < at.size(); ++i) EXPECT_NEAR(back[i], at[i], 1e-11);
}

TEST(Geometry, LengthMatchesExtrapolatedChordSums) {
  for (const Spline& s : {circle_fit(24, 2.0), wavy()}) {
    // Chord sums err by c·h² + O(h⁴): Richardson's (4 S(2N) − S(N)) / 3 leaves O(h⁴).
    const double s1 = chord_sum(s, 2000), s2 = chord_sum(s, 4000);
    const double reference = (4 * s2 - s1) / 3;
    EXPECT_NEAR(length(s), reference, 1e-10 * reference);
  }
  // The fitted circle is within its approximation error of 4π.
  EXPECT_NEAR(length(circle_fit(64, 2.0)), 4 * kPi, 1e-5);
}

TEST(Geometry, LengthDerivativeIsTheSpeed) {
  const Spline s = wavy();
  const double h = 1e-5;
  for (double f : {0.1, 0.37, 0.5, 0.81}) {
    const double t = s.t_begin() + f * (s.t_end() - s.t_begin());
    const std::vector<double> l = lengths_at(s, {t - h, t + h});
    EXPECT_NEAR((l[1] - l[0]) / (2 * h), norm(s.derivative(t)), 1e-6 * norm(s.derivative(t)));
  }
}

TEST(Geometry, EqualLengthParametersSplitTheLengthEvenly) {
  const Spline s = wavy();
  const std::vector<double> t = equal_length_parameters(s, 41);
  ASSERT_EQ(t.size(), 41u);
  EXPECT_EQ(t.front(), s.t_begin());
  EXPECT_EQ(t.back(), s.t_end());
  const std::vector<double> l = lengths_at(s, t);
  const double step = length(s) / 40;
  for (std::size_t i = 1; i < l.size(); ++i) EXPECT_NEAR(l[i] - l[i - 1], step, 1e-10 * step);
}

TEST(Geometry, FlattenHonoursItsToleranceBothWays) {
  for (const Spline& s : {wavy(), circle_fit(12, 5.0)}) {
    std::size_t previous = 0;
    for (double tol : {1e-1, 1e-3, 1e-5}) {
      const Polyline line = flatten(s, tol);
      ASSERT_EQ(line.points.size(), line.parameters.size());
      EXPECT_GT(line.points.size(), previous);
      previous = line.points.size();
      // Vertices on the curve, in parameter order, from end to end.
      for (std::size_t i = 0; i < line.points.size(); ++i) {
        EXPECT_LE(distance(line.points[i], s.eval(line.parameters[i])), 1e-12 * 200);
        if (i > 0) {
          EXPECT_GT(line.parameters[i], line.parameters[i - 1]);
        }
      }
      EXPECT_EQ(line.parameters.front(), s.t_begin());
      EXPECT_EQ(line.parameters.back(), s.t_end());
      // Curve to polyline.
      double worst = 0.0;
      for (const Segment& g : s.segments) {
        for (int k = 0; k <= 200; ++k) {
          worst =
              std::max(worst, testing::distance_to_polyline(g.bezier.eval(k / 200.0), line.points));
        }
      }
      EXPECT_LE(worst, tol);
      EXPECT_GT(worst, tol / 16);  // adaptive halving: not far finer than asked
      // Polyline to curve.
      double back = 0.0;
      for (std::size_t i = 0; i + 1 < line.points.size(); i += 7) {
        for (int k = 1; k < 8; ++k) {
          const Point q = line.points[i] + (k / 8.0) * (line.points[i + 1] - line.points[i]);
          back = std::max(back, project(s, q).distance);
        }
      }
      EXPECT_LE(back, tol);
    }
  }
  // A closed curve's polyline comes back to its start.
  const Polyline ring = flatten(circle_fit(12, 5.0), 1e-3);
  EXPECT_EQ(ring.points.front().x, ring.points.back().x);
  EXPECT_EQ(ring.points.front().y, ring.points.back().y);
}

TEST(Geometry, BoundsAreTheExtremaOfTheCurve) {
  const Spline s = wavy();
  const BBox box = bounds(s);
  BBox sampled{{HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL}};
  for (const Segment& g : s.segments) {
    for (int k = 0; k <= 20000; ++k) {
      const Point p = g.bezier.eval(k / 20000.0);
      sampled.min = {std::min(sampled.min.x, p.x), std::min(sampled.min.y, p.y)};
      sampled.max = {std::max(sampled.max.x, p.x), std::max(sampled.max.y, p.y)};
    }
  }
  // The sampled box is inside the exact one and reaches it to the sampling's O(h²).
  for (auto [exact, seen, sign] : {std::tuple{box.min.x, sampled.min.x, -1.0},
                                   {box.min.y, sampled.min.y, -1.0},
                                   {box.max.x, sampled.max.x, 1.0},
                                   {box.max.y, sampled.max.y, 1.0}}) {
    EXPECT_GE(sign * (exact - seen), -1e-12);
    EXPECT_LE(std::abs(exact - seen), 1e-6);
  }
  // The data's extremes in y are exceeded by the curve (it overshoots between the points).
  EXPECT_GT(box.max.y, 120.0);
  const BBox ring = bounds(circle_fit(64, 2.0));
  EXPECT_NEAR(ring.max.x, 2.0, 1e-6);
  EXPECT_NEAR(ring.min.y, -2.0, 1e-6);
}

TEST(Geometry, ProjectionIsNoFartherThanABruteForceSearch) {
  const Spline s = wavy();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-5, 25), y(60, 140);
  for (int rep = 0; rep < 60; ++rep) {
    const Point q{x(rng), y(rng)};
    const Projection p = project(s, q);
    EXPECT_NEAR(distance(p.point, s.eval(p.t)), 0.0, 1e-12);
    EXPECT_NEAR(p.distance, distance(p.point, q), 1e-12);
    // Dense samples, then golden-section refinement around the best.
    double best = HUGE_VAL, at = 0;
    const int n = 20000;
    for (int k = 0; k <= n; ++k) {
      const double t = s.t_begin() + (s.t_end() - s.t_begin()) * (static_cast<double>(k) / n);
      const double d = distance(s.eval(t), q);
      if (d < best) best = d, at = t;
    }
    double lo = std::max(s.t_begin(), at - (s.t_end() - s.t_begin()) / n),
           hi = std::min(s.t_end(), at + (s.t_end() - s.t_begin()) / n);
    for (int it = 0; it < 100; ++it) {
      const double m1 = lo + (hi - lo) * 0.382, m2 = hi - (hi - lo) * 0.382;
      (distance(s.eval(m1), q) < distance(s.eval(m2), q) ? hi : lo) = (m1 + m2) / 2;
    }
    best = std::min(best, distance(s.eval((lo + hi) / 2), q));
    EXPECT_LE(p.distance, best + 1e-12 * (1 + best));
    // Inside a piece the offset is normal to the curve.
    if (p.t > s.t_begin() && p.t < s.t_end()) {
      const Vec2 d = s.derivative(p.t);
      EXPECT_LE(std::abs(dot(q - p.point, d)) / (norm(d) * (1 + p.distance)), 1e-9);
    }
  }
  // From the centre of the fitted circle, the nearest point is at its least radius (the fit's
  // radial error, 1.5e-6, is the difference to 2).
  const Spline ring = circle_fit(64, 2.0);
  double least = HUGE_VAL;
  for (const Segment& g : ring.segments) {
    for (int k = 0; k <= 400; ++k) least = std::min(least, norm(g.bezier.eval(k / 400.0)));
  }
  EXPECT_NEAR(project(ring, {0, 0}).distance, least, 1e-11);
  EXPECT_NEAR(least, 2.0, 2e-6);
}

TEST(Geometry, SubcurvesSplitAndReversalKeepThePoints) {
  const Spline s = wavy();
  const double a = s.t_begin(), b = s.t_end();
  const double t = a + 0.4321 * (b - a);
  const auto [left, right] = split(s, t);
  EXPECT_EQ(left.t_begin(), a);
  EXPECT_EQ(left.t_end(), t);
  EXPECT_EQ(right.t_begin(), t);
  EXPECT_EQ(right.t_end(), b);
  for (int k = 0; k <= 50; ++k) {
    const double tl = a + (t - a) * (k / 50.0), tr = t + (b - t) * (k / 50.0);
    EXPECT_LE(distance(left.eval(tl), s.eval(tl)), 1e-12 * 200);
    EXPECT_LE(distance(right.eval(tr), s.eval(tr)), 1e-12 * 200);
  }
  EXPECT_NEAR(length(left) + length(right), length(s), 1e-11 * length(s));
  const Spline middle = subcurve(s, a + 0.1 * (b - a), a + 0.2 * (b - a));
  EXPECT_FALSE(middle.closed);
  EXPECT_LE(distance(middle.eval(a + 0.15 * (b - a)), s.eval(a + 0.15 * (b - a))), 1e-10);

  const Spline r = reversed(s);
  EXPECT_EQ(r.t_begin(), a);
  EXPECT_EQ(r.t_end(), b);
  for (int k = 0; k <= 50; ++k) {
    const double tk = a + (b - a) * (k / 50.0);
    EXPECT_LE(distance(r.eval(a + b - tk), s.eval(tk)), 1e-12 * 200);
  }
  const Spline rr = reversed(r);
  for (std::size_t i = 0; i < s.segments.size(); ++i) {
    EXPECT_EQ(rr.segments[i].bezier.p, s.segments[i].bezier.p);
    // a + b − (a + b − t) is t to rounding.
    EXPECT_NEAR(rr.segments[i].t0, s.segments[i].t0, 4e-16 * (a + b));
    EXPECT_NEAR(rr.segments[i].t1, s.segments[i].t1, 4e-16 * (a + b));
  }
  EXPECT_NEAR(length(r), length(s), 1e-12 * length(s));
}

TEST(Geometry, AffineMapsMapEveryPoint) {
  const Spline s = wavy();
  const double c = std::cos(0.7), sn = std::sin(0.7);
  const Affine m{2 * c, 2 * sn, -2 * sn, 2 * c, 5, -3};  // rotate by 0.7, scale 2, translate
  const Spline ms = transformed(s, m);
  for (int k = 0; k <= 50; ++k) {
    const double t = s.t_begin() + (s.t_end() - s.t_begin()) * (k / 50.0);
    EXPECT_LE(distance(ms.eval(t), m(s.eval(t))), 1e-12 * 400);
  }
  EXPECT_NEAR(length(ms), 2 * length(s), 1e-11 * length(s));
  const Affine shear{1, 0, 0.5, 1, 0, 0};
  EXPECT_LE(distance(transformed(s, shear).eval(2.0), shear(s.eval(2.0))), 1e-12 * 200);
  EXPECT_THROW(transformed(s, Affine{NAN, 0, 0, 1, 0, 0}), Error);
  try {
    transformed(s, Affine{1e307, 0, 0, 1e307, 0, 0});
    FAIL() << "overflow accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite);
  }
}

TEST(Geometry, FramesAreUnitTangentAndNormalAlsoAtACusp) {
  const Spline s = wavy();
  for (int k = 0; k <= 20; ++k) {
    const double t = s.t_begin() + (s.t_end() - s.t_begin()) * (k / 20.0);
    const Frame f = frame_at(s, t);
    const Vec2 d = s.derivative(t);
    EXPECT_NEAR(norm(f.tangent), 1.0, 1e-15);
    EXPECT_NEAR(cross(f.tangent, d), 0.0, 1e-12 * norm(d));
    EXPECT_GT(dot(f.tangent, d), 0.0);
    EXPECT_NEAR(dot(f.tangent, f.normal), 0.0, 1e-15);
    EXPECT_NEAR(cross(f.tangent, f.normal), 1.0, 1e-15);  // turned +90°
  }
  // A cubic with a cusp at u = 1/2: the tangent there is the limit from the right, (0, −1).
  Spline cusp;
  cusp.segments.push_back(piece({0, 0}, {1, 1}, {0, 1}, {1, 0}, 0.0, 1.0, 0));
  const Frame f = frame_at(cusp, 0.5);
  EXPECT_NEAR(f.tangent.x, 0.0, 1e-15);
  EXPECT_NEAR(f.tangent.y, -1.0, 1e-15);
  const Vec2 after = normalized(cusp.derivative(0.5 + 1e-7));
  EXPECT_NEAR(dot(after, f.tangent), 1.0, 1e-6);
}

// Curves near 1e±180 (whose squares leave the double range) give the unit curve's results
// scaled by the same power of two, bit for bit; a length beyond the range is an error.
TEST(Geometry, ExtremeScalesGiveScaledResultsExactly) {
  const Spline s = wavy();
  for (int e : {600, -600}) {
    Spline big = s;
    for (Segment& g : big.segments) {
      for (Point& p : g.bezier.p) p = {std::scalbn(p.x, e), std::scalbn(p.y, e)};
    }
    EXPECT_EQ(length(big), std::scalbn(length(s), e));
    const std::vector<double> at = {0.0, std::scalbn(10.0, e), length(big)};
    EXPECT_EQ(parameters_at_lengths(big, at), parameters_at_lengths(s, {0.0, 10.0, length(s)}));
    const Polyline a = flatten(s, 1e-3), b = flatten(big, std::scalbn(1e-3, e));
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_EQ(b.points[7].x, std::scalbn(a.points[7].x, e));
    EXPECT_EQ(bounds(big).max.y, std::scalbn(bounds(s).max.y, e));
    const Projection p = project(s, {5, 110});
    const Projection q = project(big, {std::scalbn(5.0, e), std::scalbn(110.0, e)});
    EXPECT_EQ(q.t, p.t);
    EXPECT_EQ(q.distance, std::scalbn(p.distance, e));
    EXPECT_TRUE(std::isfinite(q.distance) && q.distance > 0);
  }
  Spline huge;
  huge.segments.push_back(
      piece({-1.5e308, 0}, {-0.5e308, 1e308}, {0.5e308, -1e308}, {1.5e308, 0}, 0.0, 1.0, 0));
  try {
    (void)length(huge);
    FAIL() << "an overflowing length returned";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite);
  }
}

// Random fits (open or closed random walks with sharp turns, loops and cusps allowed by some
// methods) and tolerances: the polyline within the tolerance both ways (against the
// projection), the nearest point no farther than dense samples, and split + reversal keeping
// the curve and its length.
RC_GTEST_PROP(GeometryProps, FlattenProjectSplitAndReverseOnRandomFits, ()) {
  const auto n = static_cast<std::size_t>(*rc::gen::inRange(3, 12));
  const bool closed = *rc::gen::arbitrary<bool>();
  const auto seed = static_cast<std::uint64_t>(*rc::gen::inRange(0, 1 << 30));
  const char* method = *rc::gen::element("quasi-elastic", "li-strain", "jaklic-zagar");
  FitInput in;
  in.points = testing::random_walk(n, seed, 150);
  in.closed = closed;
  FitResult r;
  try {
    r = fit(method, in, nlohmann::json::object(), FitOptions{.level = ReportLevel::kNone});
  } catch (const Error&) {
    RC_SUCCEED("no fit");
  }
  const Spline& s = r.spline;
  const double size =
      std::hypot(bounds(s).max.x - bounds(s).min.x, bounds(s).max.y - bounds(s).min.y);
  const double tol = size * std::pow(10.0, -*rc::gen::inRange(1, 5));
  const Polyline line = flatten(s, tol);
  for (std::size_t i = 0; i + 1 < line.points.size(); ++i) {
    const Point mid = 0.5 * (line.points[i] + line.points[i + 1]);
    RC_ASSERT(project(s, mid).distance <= tol * (1 + 1e-12));
    const double tm = 0.5 * (line.parameters[i] + line.parameters[i + 1]);
    RC_ASSERT(testing::distance_to_polyline(s.eval(tm), line.points) <= tol * (1 + 1e-12));
  }
  const Point q{*rc::gen::inRange(-20, 20) * 0.5, *rc::gen::inRange(-20, 20) * 0.5};
  const Projection p = project(s, q);
  for (int k = 0; k <= 2000; ++k) {
    const double t = s.t_begin() + (s.t_end() - s.t_begin()) * (k / 2000.0);  // k = 2000: t_end
    RC_ASSERT(p.distance <= distance(s.eval(t), q) + 1e-12 * (1 + p.distance));
  }
  const double t = s.t_begin() + (s.t_end() - s.t_begin()) * *rc::gen::inRange(1, 99) / 100;
  const auto [left, right] = split(s, t);
  const double total = length(s);
  RC_ASSERT(std::abs(length(left) + length(right) - total) <= 1e-10 * total);
  const Spline back = reversed(s);
  RC_ASSERT(std::abs(length(back) - total) <= 1e-12 * total);
  RC_ASSERT(distance(back.eval(back.t_begin()), s.eval(s.t_end())) <= 1e-12 * size);
}

TEST(Geometry, BadArgumentsAreErrors) {
  const Spline s = straight();
  auto code_of = [](auto&& call) {
    try {
      call();
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::kIoError;  // (no error: fails every expectation below)
  };
  EXPECT_EQ(code_of([&] { frame_at(s, 3.5); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { frame_at(s, NAN); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { length(Spline{}); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { length(s, 0.0); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { parameters_at_lengths(s, {-1.0}); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { parameters_at_lengths(s, {4.1}); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { equal_length_parameters(s, 1); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { flatten(s, 0.0); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { flatten(s, NAN); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { flatten(wavy(), 1e-9, 1000); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { subcurve(s, 2.0, 1.0); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { split(s, 3.0); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_of([&] { project(s, {NAN, 0}); }), ErrorCode::kNonFinite);
  try {
    lengths_at(s, {1.0, 7.0});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.index(), 1u);  // the offending entry
    EXPECT_NE(std::string(e.what()).find("outside the curve's range [0, 3]"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace fairspline
