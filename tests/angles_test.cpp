// detail::half_angle, atan2_right, atan2_fast and sincos_taylor (src/detail/angles.hpp); the
// angles against long double atan2l, the sines and cosines against sinl and cosl.
#include "detail/angles.hpp"

#include "detail/numbers.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace fairspline::detail {
namespace {

/// The error of `got` in units in the last place of the exact angle rounded to double.
double ulps(double got, long double exact) {
  const double rounded = static_cast<double>(exact);
  const double ulp = std::nextafter(std::abs(rounded), std::numeric_limits<double>::infinity()) -
                     std::abs(rounded);
  return static_cast<double>(std::abs(static_cast<long double>(got) - exact) / ulp);
}

TEST(Atan2Right, WithinTwoUlpOfTheExactAngleOverTheRightHalfPlane) {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> angle(-kPi / 2.0, kPi / 2.0), decade(-30.0, 30.0);
  double worst = 0.0, worst_libm = 0.0;
  for (int i = 0; i < 2000000; ++i) {
    // Directions all round the half-plane, at every scale; every fourth near an axis or the
    // diagonals, where the reductions switch.
    double t = angle(rng);
    if (i % 4 == 0) t = std::round(t / (kPi / 8.0)) * (kPi / 8.0) + 1e-9 * angle(rng);
    const double r = std::pow(10.0, decade(rng));
    const double x = std::max(0.0, r * std::cos(t)), y = r * std::sin(t);
    const long double exact = std::atan2(static_cast<long double>(y), static_cast<long double>(x));
    worst = std::max(worst, ulps(atan2_right(y, x), exact));
    worst_libm = std::max(worst_libm, ulps(std::atan2(y, x), exact));
  }
  EXPECT_LE(worst, 1.6);
  EXPECT_LE(worst_libm, 1.0);  // the reference itself
}

TEST(Atan2Right, UnitHalfAnglesOfTurnsAsTheStencilsUseThem) {
  // (cos, sin) of half a turn ψ, computed from the turn's cosine and sine as the chains do.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> turn(-kPi, kPi);
  double worst = 0.0;
  for (int i = 0; i < 1000000; ++i) {
    const double psi = turn(rng);
    const HalfAngle h = half_angle(std::cos(psi), std::sin(psi));
    const double hc = h.c, hs = h.s;
    ASSERT_GE(hc, 0.0);
    // The half-angle formulas themselves: within a few rounding units of cos, sin of ψ/2.
    ASSERT_NEAR(hc, std::cos(psi / 2.0), 8e-16);
    ASSERT_NEAR(hs, std::sin(psi / 2.0), 8e-16);
    const long double exact =
        std::atan2(static_cast<long double>(hs), static_cast<long double>(hc));
    worst = std::max(worst, ulps(atan2_right(hs, hc), exact));
  }
  EXPECT_LE(worst, 1.6);
}

TEST(Atan2Right, AxesZerosAndNaN) {
  EXPECT_EQ(atan2_right(0.0, 1.0), 0.0);
  EXPECT_TRUE(std::signbit(atan2_right(-0.0, 1.0)));
  EXPECT_EQ(atan2_right(0.0, 0.0), 0.0);
  EXPECT_TRUE(std::signbit(atan2_right(-0.0, 0.0)));
  EXPECT_DOUBLE_EQ(atan2_right(1.0, 0.0), kPi / 2.0);
  EXPECT_DOUBLE_EQ(atan2_right(-3.0, 0.0), -kPi / 2.0);
  EXPECT_DOUBLE_EQ(atan2_right(2.0, 2.0), kPi / 4.0);
  EXPECT_DOUBLE_EQ(atan2_right(-1e300, 1e300), -kPi / 4.0);
  EXPECT_DOUBLE_EQ(atan2_right(5e-324, 1.0), 5e-324);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(atan2_right(nan, 1.0)));
  EXPECT_TRUE(std::isnan(atan2_right(1.0, nan)));
}

TEST(Atan2Fast, WithinTwoUlpOfTheExactAngleAllRoundTheCircle) {
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> angle(-kPi, kPi), decade(-30.0, 30.0);
  double worst = 0.0;
  for (int i = 0; i < 2000000; ++i) {
    // Every fourth direction near an axis or a diagonal, where the reductions switch (and near
    // ±π, where the left half-plane's subtraction from π is closest to cancelling).
    double t = angle(rng);
    if (i % 4 == 0) t = std::round(t / (kPi / 8.0)) * (kPi / 8.0) + 1e-9 * angle(rng);
    const double r = std::pow(10.0, decade(rng));
    const double x = r * std::cos(t), y = r * std::sin(t);
    const long double exact = std::atan2(static_cast<long double>(y), static_cast<long double>(x));
    worst = std::max(worst, ulps(atan2_fast(y, x), exact));
  }
  EXPECT_LE(worst, 2.0);
}

TEST(Atan2Fast, LeftAxisZerosAndNaN) {
  EXPECT_EQ(atan2_fast(0.0, -1.0), kPi);
  EXPECT_EQ(atan2_fast(-0.0, -1.0), -kPi);
  EXPECT_EQ(atan2_fast(1e-300, -1.0), kPi);
  EXPECT_DOUBLE_EQ(atan2_fast(1.0, -1.0), 3.0 * kPi / 4.0);
  EXPECT_DOUBLE_EQ(atan2_fast(-1.0, -1.0), -3.0 * kPi / 4.0);
  EXPECT_EQ(atan2_fast(3.0, 0.0), atan2_right(3.0, 0.0));
  EXPECT_EQ(atan2_fast(0.0, 2.0), 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(atan2_fast(nan, -1.0)));
  EXPECT_TRUE(std::isnan(atan2_fast(1.0, nan)));
}

TEST(SincosTaylor, WithinThreeRoundingUnitsOfTheExactValuesUpToARightAngle) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> angle(-kPi / 2.0, kPi / 2.0);
  double worst = 0.0;
  for (int i = 0; i < 1000000; ++i) {
    const double x = i % 3 == 0 ? angle(rng) * 1e-6 : angle(rng);
    double s = 0.0, c = 0.0;
    sincos_taylor(x, s, c);
    const long double xl = x;
    // Absolute error in units of 2^-53 (half an ulp of 1): what a unit vector's components
    // carry. The series itself is exact there; the rest is the rounding of its terms.
    worst = std::max({worst, static_cast<double>(std::abs(s - std::sin(xl)) / 0x1p-53L),
                      static_cast<double>(std::abs(c - std::cos(xl)) / 0x1p-53L)});
  }
  EXPECT_LE(worst, 3.0);
  double s = 1.0, c = 0.0;
  sincos_taylor(0.0, s, c);
  EXPECT_EQ(s, 0.0);
  EXPECT_EQ(c, 1.0);
}

}  // namespace
}  // namespace fairspline::detail
