// fit()'s one normalization (src/detail/normalize.cpp): every registered method's example
// requests, scaled far outside 2^±24, give the unscaled curve scaled, and their method_report
// maps back by the units each method declares (a scale-dependent number it forgot to declare
// fails here).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>

#include "detail/normalize.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

using nlohmann::json;

/// The declared exponent of 2 by which the report number at `path` (indices as "*") scales.
double declared_exponent(const MethodInfo& m, const std::string& path, int k, double alpha,
                         bool explicit_knots) {
  for (const ReportUnit& u : m.report_units) {
    if (u.path == path) return k * (u.length + (explicit_knots ? 0.0 : alpha * u.knots));
  }
  return 0.0;
}

void compare_reports(const MethodInfo& m, const json& unit, const json& big,
                     const std::string& path, int k, double alpha, bool explicit_knots) {
  SCOPED_TRACE("method_report/" + path);
  if (unit.is_object()) {
    ASSERT_TRUE(big.is_object());
    for (auto it = unit.begin(); it != unit.end(); ++it) {
      ASSERT_TRUE(big.contains(it.key())) << it.key();
      compare_reports(m, *it, big.at(it.key()), path.empty() ? it.key() : path + "/" + it.key(), k,
                      alpha, explicit_knots);
    }
  } else if (unit.is_array()) {
    ASSERT_TRUE(big.is_array());
    ASSERT_EQ(unit.size(), big.size());
    for (std::size_t i = 0; i < unit.size(); ++i) {
      compare_reports(m, unit[i], big[i], path + "/*", k, alpha, explicit_knots);
    }
  } else if (unit.is_number_float() || (unit.is_number() && big.is_number_float())) {
    const double e = declared_exponent(m, path, k, alpha, explicit_knots);
    const double lg = std::log2(std::abs(unit.get<double>())) + e;
    if (lg >= 1024) {
      EXPECT_TRUE(big.is_null()) << "beyond the double range: null";
      return;
    }
    ASSERT_TRUE(big.is_number());
    if (lg < -1000) {
      EXPECT_LE(std::abs(big.get<double>()), 0x1p-1000) << "near the double range's end";
      return;
    }
    const double expected = unit.get<double>() * std::exp2(e);
    const double got = big.get<double>();
    // Converged residuals depend on the last step's rounding, not on the scale.
    const double slack =
        path.find("gradient") != std::string::npos || path.find("residual") != std::string::npos
            ? 1e-9
            : 1e-9 * std::abs(expected);
    EXPECT_NEAR(got, expected, slack) << "declared exponent " << e;
  } else {
    EXPECT_EQ(unit, big);
  }
}

TEST(Normalization, ExtremeScalesMapBackForEveryMethod) {
  for (const MethodInfo& m : methods()) {
    for (const std::string& e : m.capabilities.examples) {
      const io::ParsedInput req = io::parse_json_input(e);
      const FitResult unit = fit(m.name, req.input, req.options, ReportLevel::kBasic);
      double size = 0.0;
      for (const Point& p : unit.points) size = std::max({size, std::abs(p.x), std::abs(p.y)});
      for (int k : {-600, -100, 100, 600}) {
        SCOPED_TRACE(m.name + " " + e + " scaled by 2^" + std::to_string(k));
        FitInput in = req.input;
        for (Point& p : in.points) p = {std::ldexp(p.x, k), std::ldexp(p.y, k)};
        const bool c1 = m.capabilities.continuity == Continuity::kC1;
        // A C1 method's tangents are derivatives with respect to the knots.
        const double te = in.knots.empty() ? k * (1.0 - in.alpha) : k;
        auto scale_tangent = [&](std::optional<Vec2>& v) {
          if (v && c1)
            *v = {std::ldexp(v->x, static_cast<int>(te)), std::ldexp(v->y, static_cast<int>(te))};
        };
        for (auto& v : in.tangents) scale_tangent(v);
        scale_tangent(in.start_tangent);
        scale_tangent(in.end_tangent);
        const FitResult big = fit(m.name, in, req.options, ReportLevel::kBasic);
        ASSERT_EQ(big.spline.segments.size(), unit.spline.segments.size());
        for (std::size_t s = 0; s < unit.spline.segments.size(); ++s) {
          for (int j = 0; j < 4; ++j) {
            const Point a = unit.spline.segments[s].bezier.p[j];
            const Point b = big.spline.segments[s].bezier.p[j];
            EXPECT_NEAR(std::ldexp(b.x, -k), a.x, 1e-12 * size);
            EXPECT_NEAR(std::ldexp(b.y, -k), a.y, 1e-12 * size);
          }
        }
        const double ke = in.knots.empty() ? k * in.alpha : 0.0;
        ASSERT_EQ(big.knots.size(), unit.knots.size());
        for (std::size_t i = 0; i < unit.knots.size(); ++i) {
          EXPECT_NEAR(big.knots[i] * std::exp2(-ke), unit.knots[i],
                      1e-12 * std::abs(unit.knots.back()));
        }
        for (std::size_t i = 0; i < unit.tangents.size(); ++i) {
          EXPECT_NEAR(big.tangents[i].x, unit.tangents[i].x, 1e-12);
          EXPECT_NEAR(big.tangents[i].y, unit.tangents[i].y, 1e-12);
        }
        compare_reports(m, unit.method_report, big.method_report, "", k, in.alpha,
                        !in.knots.empty());
      }
    }
  }
}

TEST(Normalization, OnlyDataOutsideTheNormalRangeAreScaled) {
  // Within 2^±24 (make_report's rule) nothing is rescaled, so normal data keep their bits.
  auto exponent = [](double size, double alpha, bool knots) -> std::optional<double> {
    FitInput in;
    in.points = {{0.0, 0.0}, {size, 0.5 * size}, {-0.25 * size, size}};
    in.alpha = alpha;
    if (knots) in.knots = {0.0, 1.0, 2.0};
    const auto nz = detail::normalization_for(in);
    if (!nz) return std::nullopt;
    EXPECT_EQ(nz->length_exponent % 2, 0);
    EXPECT_EQ(nz->knot_exponent, knots ? 0.0 : alpha * nz->length_exponent);
    return nz->length_exponent;
  };
  EXPECT_EQ(exponent(0x1p24, 0.5, false), std::nullopt);
  EXPECT_EQ(exponent(0x1.fp24, 0.5, false), std::nullopt);
  EXPECT_EQ(exponent(0x1p-24, 0.5, false), std::nullopt);
  EXPECT_EQ(exponent(0x1p25, 0.5, false), 24.0);  // even, so 2^(e/2) is exact
  EXPECT_EQ(exponent(0x1p26, 1.0, true), 26.0);
  EXPECT_EQ(exponent(0x1p-25, 0.3, false), -26.0);
  EXPECT_EQ(exponent(1e300, 0.0, false), 996.0);
  FitInput nan;
  nan.points = {{0.0, 0.0}, {1e300, std::nan("")}};
  EXPECT_FALSE(detail::normalization_for(nan).has_value()) << "the method reports the NaN";
}

TEST(Normalization, ErrorsQuoteTheUsersCoordinates) {
  FitInput in;
  in.points = {{1e300, 0}, {2e300, 1e300}, {2e300, 1e300}, {3e300, 0}};
  testing::expect_error(ErrorCode::kRepeatedPoint, [&] { fit("quasi-elastic", in); },
                        {"point 2 (2e+300, 1e+300) repeats point 1"});
}

}  // namespace
}  // namespace fairspline

namespace fairspline {
namespace {

TEST(Normalization, FitsWithinTheNormalRangeAreHomogeneous) {
  // Nothing is rescaled within 2^±24, so every method must be exactly homogeneous there: the
  // fit of 2^k·x is the fit of x times 2^k, bit for bit (a held row of min-energy's Newton
  // system with diagonal 1.0 once made this walk take another path at 4e-6 than at 1e-6).
  // A 41-point random walk about 1e-6 in size (Hessian entries beyond 1e14).
  std::ifstream file(std::string(FAIRSPLINE_SOURCE_DIR) + "/tests/data/scale-walk.json");
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::vector<Point> walk = io::parse_json_input(text).input.points;
  ASSERT_EQ(walk.size(), 41u);
  for (const MethodInfo& m : methods()) {
    if (m.capabilities.tangents == TangentUse::kRequired || m.capabilities.needs_clamped_tangent) {
      continue;
    }
    SCOPED_TRACE(m.name);
    auto at = [&](int k) {
      FitInput in;
      for (const Point& p : walk) in.points.push_back({std::ldexp(p.x, k), std::ldexp(p.y, k)});
      return fit(m.name, in, json::object(), ReportLevel::kNone);
    };
    FitResult base;
    try {
      base = at(0);
    } catch (const Error& e) {  // kozak-krajnc: a turn beyond its theorem; the same at any scale
      for (int k : {-8, 2, 6}) testing::expect_error(e.code(), [&] { at(k); });
      continue;
    }
    for (int k : {-8, 2, 6}) {
      const FitResult r = at(k);
      ASSERT_EQ(r.spline.segments.size(), base.spline.segments.size());
      for (std::size_t i = 0; i < r.tangents.size(); ++i) {
        ASSERT_EQ(r.tangents[i].x, base.tangents[i].x) << "point " << i << " at 2^" << k;
        ASSERT_EQ(r.tangents[i].y, base.tangents[i].y) << "point " << i << " at 2^" << k;
      }
      for (std::size_t s = 0; s < r.spline.segments.size(); ++s) {
        for (int j = 0; j < 4; ++j) {
          ASSERT_EQ(std::ldexp(r.spline.segments[s].bezier.p[j].x, -k),
                    base.spline.segments[s].bezier.p[j].x);
        }
      }
    }
  }
}

}  // namespace
}  // namespace fairspline
