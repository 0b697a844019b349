// Passes over long inputs split in two halves (src/detail/two_threads.hpp): the input copy and
// knots (detail::prepare_input), the normalization scan and the result comparison of the
// registry give what one pass gives, bit for bit, and errors name the first bad point.
#include "detail/two_threads.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "detail/normalize.hpp"
#include "fairspline/error.hpp"
#include "fairspline/parameterization.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

const std::size_t kLong = detail::kTwoThreadPoints + 5;  // odd: halves of different sizes

TEST(TwoThreads, LongInputsGiveTheKnotsOfOnePass) {
  ASSERT_TRUE(detail::split_in_two(kLong) || std::thread::hardware_concurrency() < 2);
  for (bool closed : {false, true}) {
    for (double alpha : {0.5, 1.0, 0.0, 0.3}) {
      SCOPED_TRACE(std::string(closed ? "closed" : "open") + " alpha " + std::to_string(alpha));
      FitInput in;
      in.points = testing::random_walk(kLong, 41, 120);
      in.closed = closed;
      in.alpha = alpha;
      const FitResult r = fit("jaklic-zagar", in, {}, ReportLevel::kNone);
      const std::vector<double> one = alpha_knots(in.points, alpha, closed);
      ASSERT_EQ(r.knots.size(), one.size());
      EXPECT_EQ(0, std::memcmp(r.knots.data(), one.data(), one.size() * sizeof(double)));
      ASSERT_EQ(r.points.size(), in.points.size());
      EXPECT_EQ(0, std::memcmp(r.points.data(), in.points.data(), kLong * sizeof(Point)));
      EXPECT_TRUE(r.input.points.empty());  // the registry's comparison: the same points
    }
  }
}

TEST(TwoThreads, BadPointsInEitherHalfAreNamed) {
  FitInput in;
  in.points = testing::random_walk(kLong, 43, 120);
  const std::size_t late = kLong - 10, early = 10;
  in.points[late].y = std::numeric_limits<double>::quiet_NaN();
  Error e = testing::expect_error(ErrorCode::kNonFinite, [&] { fit("li-strain", in); });
  EXPECT_EQ(e.index(), late);
  in.points[early].x = std::numeric_limits<double>::infinity();
  e = testing::expect_error(ErrorCode::kNonFinite, [&] { fit("li-strain", in); });
  EXPECT_EQ(e.index(), early);
  in.points = testing::random_walk(kLong, 43, 120);
  in.points[late + 1] = in.points[late];
  e = testing::expect_error(ErrorCode::kRepeatedPoint, [&] { fit("jaklic-zagar", in); });
  EXPECT_EQ(e.index(), late + 1);
}

TEST(TwoThreads, TheNormalizationScanSeesBothHalves) {
  // The largest coordinate in the second half only, or in the first: the scale is its power.
  FitInput in;
  in.points = testing::random_walk(kLong, 47, 120);
  for (std::size_t at : {kLong - 3, std::size_t{3}}) {
    FitInput big = in;
    big.points[at] = {std::ldexp(1.5, 70), 0.0};
    const std::optional<detail::Normalization> nz = detail::normalization_for(big);
    ASSERT_TRUE(nz) << at;
    EXPECT_EQ(nz->length_exponent, 70) << at;
    big.points[at ^ 1].y = std::numeric_limits<double>::quiet_NaN();  // left to the checks
    EXPECT_FALSE(detail::normalization_for(big)) << at;
  }
  EXPECT_FALSE(detail::normalization_for(in));  // unit size: none
}

TEST(TwoThreads, TheFirstHalfsErrorWins) {
  auto throw_both = [](int h) { throw std::runtime_error(h == 0 ? "first" : "second"); };
  try {
    detail::on_two_threads(throw_both);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "first");
  }
  try {
    detail::on_two_threads([](int h) {
      if (h == 1) throw std::runtime_error("second");
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "second");
  }
}

}  // namespace
}  // namespace fairspline
