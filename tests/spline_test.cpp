// Tests of Spline: segment lookup, local parameters, global evaluation and derivatives
// (chain rule checked against finite differences), curvature, sampling, errors.
#include "fairspline/spline.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fairspline/error.hpp"

namespace fairspline {
namespace {

CubicBezier bez(Point a, Point b, Point c, Point d) {
  return {{a, b, c, d}};
}

// Two pieces of unequal parameter length joining C0 at (3, 0): [0, 1] and [1, 3].
Spline two_pieces() {
  Spline s;
  s.segments.push_back({bez({0, 0}, {1, 1}, {2, 1}, {3, 0}), 0.0, 1.0, 0});
  s.segments.push_back({bez({3, 0}, {4, -1}, {5, 2}, {6, 0}), 1.0, 3.0, 1});
  return s;
}

TEST(Spline, SegmentIndexAndLocalParameter) {
  const Spline s = two_pieces();
  EXPECT_EQ(s.t_begin(), 0.0);
  EXPECT_EQ(s.t_end(), 3.0);
  EXPECT_EQ(s.segment_index(-5.0), 0u);
  EXPECT_EQ(s.segment_index(0.5), 0u);
  EXPECT_EQ(s.segment_index(1.0), 1u);  // joints go to the later piece
  EXPECT_EQ(s.segment_index(2.0), 1u);
  EXPECT_EQ(s.segment_index(3.0), 1u);
  EXPECT_EQ(s.segment_index(9.0), 1u);
  EXPECT_DOUBLE_EQ(s.local_parameter(1, 2.0), 0.5);
  EXPECT_DOUBLE_EQ(s.local_parameter(1, 2.5), 0.75);
  EXPECT_DOUBLE_EQ(s.local_parameter(0, -1.0), 0.0);  // clamped
  EXPECT_THROW(Spline{}.segment_index(0.0), Error);
}

TEST(Spline, EvalMatchesPiecesAndIsContinuous) {
  const Spline s = two_pieces();
  EXPECT_EQ(s.eval(0.25), s.segments[0].bezier.eval(0.25));
  EXPECT_EQ(s.eval(2.0), s.segments[1].bezier.eval(0.5));
  EXPECT_LT(distance(s.eval(1.0 - 1e-12), s.eval(1.0)), 1e-10);
  EXPECT_EQ(s.eval(3.0), (Point{6, 0}));
}

TEST(Spline, DerivativesFollowTheChainRule) {
  const Spline s = two_pieces();
  const double h = 1e-5;
  for (double t : {0.3, 0.7, 1.4, 2.2, 2.9}) {
    const Vec2 fd1 = (s.eval(t + h) - s.eval(t - h)) / (2.0 * h);
    const Vec2 fd2 = (s.derivative(t + h, 1) - s.derivative(t - h, 1)) / (2.0 * h);
    const Vec2 fd3 = (s.derivative(t + h, 2) - s.derivative(t - h, 2)) / (2.0 * h);
    EXPECT_NEAR(s.derivative(t, 1).x, fd1.x, 1e-7);
    EXPECT_NEAR(s.derivative(t, 1).y, fd1.y, 1e-7);
    EXPECT_NEAR(s.derivative(t, 2).x, fd2.x, 1e-7);
    EXPECT_NEAR(s.derivative(t, 2).y, fd2.y, 1e-7);
    EXPECT_NEAR(s.derivative(t, 3).x, fd3.x, 1e-7);
    EXPECT_NEAR(s.derivative(t, 3).y, fd3.y, 1e-7);
  }
  // The second piece spans dt = 2: d/dt = (1/2) d/du.
  EXPECT_EQ(s.derivative(2.0, 1), 0.5 * s.segments[1].bezier.d1(0.5));
  EXPECT_EQ(s.derivative(2.0, 2), 0.25 * s.segments[1].bezier.d2(0.5));
  EXPECT_EQ(s.derivative(2.0, 4), (Vec2{0, 0}));
  EXPECT_THROW(s.derivative(2.0, 0), Error);
}

TEST(Spline, CurvatureIsParameterizationIndependent) {
  const Spline s = two_pieces();
  for (double t : {0.2, 1.5, 2.7}) {
    const Vec2 v = s.derivative(t, 1), a = s.derivative(t, 2);
    EXPECT_NEAR(s.curvature(t), cross(v, a) / std::pow(norm(v), 3), 1e-12);
    const std::size_t k = s.segment_index(t);
    EXPECT_NEAR(s.curvature(t), s.segments[k].bezier.curvature(s.local_parameter(k, t)), 1e-12);
  }
}

// One policy for every evaluation: outside [t_begin, t_end], or NaN, is an error naming t and
// the range; the range's own ends are inside.
TEST(Spline, ParametersOutsideTheRangeAreErrors) {
  const Spline s = two_pieces();
  for (double t : {-1e-12, 3.0 + 1e-12, -5.0, 9.0, std::nan(""), HUGE_VAL}) {
    EXPECT_THROW(s.eval(t), Error) << t;
    EXPECT_THROW(s.derivative(t), Error) << t;
    EXPECT_THROW(s.curvature(t), Error) << t;
  }
  try {
    s.eval(3.5);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_STREQ(e.what(), "parameter t = 3.5 is outside the curve's range [0, 3]");
  }
  EXPECT_NO_THROW(s.eval(0.0));
  EXPECT_NO_THROW(s.curvature(3.0));
}

TEST(Spline, SampleIsEquallySpacedInTheParameter) {
  const Spline s = two_pieces();
  const auto pts = s.sample(7);
  ASSERT_EQ(pts.size(), 7u);
  EXPECT_EQ(pts.front(), s.eval(0.0));
  EXPECT_EQ(pts.back(), s.eval(3.0));
  EXPECT_LT(distance(pts[2], s.eval(1.0)), 1e-14);
  EXPECT_LT(distance(pts[4], s.eval(2.0)), 1e-14);
  EXPECT_THROW(s.sample(1), Error);
}

}  // namespace
}  // namespace fairspline
