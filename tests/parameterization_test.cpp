#include "fairspline/parameterization.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fairspline/error.hpp"

namespace fairspline {
namespace {

const std::vector<Point> kPts = {{0, 0}, {3, 4}, {3, 5}, {0, 1}};

TEST(Parameterization, AlphaKnotsMatchDefinition) {
  for (double alpha : {0.0, 0.25, 0.5, 2.0 / 3.0, 1.0}) {
    const auto t = alpha_knots(kPts, alpha, false);
    ASSERT_EQ(t.size(), 4u);
    EXPECT_EQ(t[0], 0.0);
    EXPECT_NEAR(t[1] - t[0], std::pow(5.0, alpha), 1e-15);
    EXPECT_NEAR(t[2] - t[1], std::pow(1.0, alpha), 1e-15);
    EXPECT_NEAR(t[3] - t[2], std::pow(std::hypot(3.0, 4.0), alpha), 1e-15);
  }
}

TEST(Parameterization, ClosedCurveHasClosingSpan) {
  const auto t = alpha_knots(kPts, 1.0, true);
  ASSERT_EQ(t.size(), 5u);
  EXPECT_DOUBLE_EQ(t[4] - t[3], 1.0);  // |P0 - P3| = 1
  EXPECT_DOUBLE_EQ(t[4], 5 + 1 + 5 + 1);
}

TEST(Parameterization, FastPathsAgreeWithPow) {
  const std::vector<Point> pts = {{0.1, 0.2}, {1.7, -3.1}, {2.9, 8.5}};
  for (double alpha : {0.5, 1.0}) {
    const auto t = alpha_knots(pts, alpha, false);
    EXPECT_NEAR(t[2] - t[1], std::pow(std::hypot(1.2, 11.6), alpha), 1e-14);
  }
}

TEST(Parameterization, Errors) {
  EXPECT_THROW(alpha_knots(kPts, -0.1, false), Error);
  EXPECT_THROW(alpha_knots(kPts, 1.1, false), Error);
  EXPECT_THROW(alpha_knots(kPts, NAN, false), Error);
  const std::vector<Point> one = {{0, 0}};
  EXPECT_THROW(alpha_knots(one, 0.5, false), Error);
  try {
    validate_knots(std::vector<double>{0, 1, 1, 2}, 4, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.index(), 2u);
  }
  EXPECT_THROW(validate_knots(std::vector<double>{0, 1, 2}, 4, false), Error);
  EXPECT_THROW(validate_knots(std::vector<double>{0, 1, 2, 3}, 4, true), Error);
  EXPECT_NO_THROW(validate_knots(std::vector<double>{0, 1, 2, 3, 4}, 4, true));
}

}  // namespace
}  // namespace fairspline
