// Tests of the path exports: svg_path_data gives back every control point bit for bit (its
// digits read with std::from_chars) and closes only a closed curve; write_geojson's default
// tolerance is 1e-4 of the bounds' diagonal, its LineString stays within the tolerance of the
// curve both ways (fairspline::project one way, the distance to the polyline the other), its
// ends are the curve's, and its properties are there.
#include "fairspline/io/paths.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/geometry.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline::io {
namespace {

using nlohmann::json;

FitResult walk_fit(bool closed, ReportLevel level = ReportLevel::kFull) {
  FitInput in;
  in.points = testing::random_walk(12, 7, 100);  // coordinates that need all 17 digits
  in.closed = closed;
  return fit("quasi-elastic", in, json::object(), level);
}

/// The tokens of path data: a command letter or a number, as written (space separated).
std::vector<std::string_view> tokens(std::string_view d) {
  std::vector<std::string_view> out;
  while (!d.empty()) {
    const std::size_t space = d.find(' ');
    out.push_back(d.substr(0, space));
    d.remove_prefix(space == std::string_view::npos ? d.size() : space + 1);
    // A command letter is glued to its first number ("M0", "C1"): split it off.
    std::string_view& last = out.back();
    if (last.size() > 1 && std::isalpha(static_cast<unsigned char>(last.front()))) {
      const std::string_view number = last.substr(1);
      last = last.substr(0, 1);
      out.push_back(number);
    }
  }
  return out;
}

double read_number(std::string_view text) {
  double v = std::numeric_limits<double>::quiet_NaN();
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  EXPECT_TRUE(ec == std::errc() && end == text.data() + text.size()) << text;
  return v;
}

/// The control points of `s` read back from its path data, and the commands in order.
void read_back(const Spline& s, std::vector<Point>& points, std::string& commands) {
  const std::string d = svg_path_data(s);
  const std::vector<std::string_view> t = tokens(d);
  for (std::size_t i = 0; i < t.size();) {
    if (std::isalpha(static_cast<unsigned char>(t[i].front()))) {
      commands += t[i++];
      continue;
    }
    ASSERT_LT(i + 1, t.size()) << d;
    points.push_back({read_number(t[i]), read_number(t[i + 1])});
    i += 2;
  }
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

TEST(Paths, SvgPathDataGivesBackEveryControlPointBitForBit) {
  for (const bool closed : {false, true}) {
    SCOPED_TRACE(closed ? "closed" : "open");
    const FitResult r = walk_fit(closed);
    std::vector<Point> points;
    std::string commands;
    read_back(r.spline, points, commands);
    const std::size_t n = r.spline.segments.size();
    std::string expected_commands = "M";
    expected_commands.append(n, 'C');
    if (closed) expected_commands += 'Z';
    EXPECT_EQ(commands, expected_commands);
    ASSERT_EQ(points.size(), 1 + 3 * n);
    EXPECT_TRUE(same_bits(points[0].x, r.spline.segments[0].bezier.p[0].x));
    EXPECT_TRUE(same_bits(points[0].y, r.spline.segments[0].bezier.p[0].y));
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t j = 1; j < 4; ++j) {
        const Point want = r.spline.segments[k].bezier.p[j];
        const Point got = points[1 + 3 * k + (j - 1)];
        EXPECT_TRUE(same_bits(got.x, want.x) && same_bits(got.y, want.y))
            << "piece " << k << " point " << j;
      }
    }
  }
}

TEST(Paths, SvgPathDataWritesTheShortestDigitsOfAwkwardNumbers) {
  // Negative zero, the smallest subnormal, 0.1 + 0.2, a huge and a tiny value: each read back
  // exactly, in the fewest digits that do it.
  const double values[] = {-0.0, 5e-324, 0.1 + 0.2, 1.7976931348623157e308, -1e-300, 1.0};
  Spline s;
  s.segments.push_back({CubicBezier{{Point{values[0], values[1]}, Point{values[2], values[3]},
                                     Point{values[4], values[5]}, Point{2.0, 3.0}}},
                        0.0, 1.0, 0});
  std::vector<Point> points;
  std::string commands;
  read_back(s, points, commands);
  EXPECT_EQ(commands, "MC");
  ASSERT_EQ(points.size(), 4u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(same_bits(points[i].x, values[2 * i]));
    EXPECT_TRUE(same_bits(points[i].y, values[2 * i + 1]));
  }
  EXPECT_EQ(svg_path_data(s),
            "M-0 5e-324 C0.30000000000000004 1.7976931348623157e+308 -1e-300 1 2 3");
  testing::expect_error(ErrorCode::kInvalidArgument, [] { (void)svg_path_data(Spline{}); });
}

std::vector<Point> coordinates(const json& feature) {
  std::vector<Point> out;
  for (const json& c : feature.at("geometry").at("coordinates")) {
    EXPECT_EQ(c.size(), 2u);
    out.push_back({c.at(0).get<double>(), c.at(1).get<double>()});
  }
  return out;
}

TEST(Paths, GeoJsonDefaultToleranceIsATenThousandthOfTheDiagonal) {
  for (const bool closed : {false, true}) {
    SCOPED_TRACE(closed ? "closed" : "open");
    const FitResult r = walk_fit(closed);
    const json f = json::parse(write_geojson(r));
    EXPECT_EQ(f.at("type"), "Feature");
    EXPECT_EQ(f.at("geometry").at("type"), "LineString");
    const BBox box = bounds(r.spline);
    const double diagonal = std::hypot(box.max.x - box.min.x, box.max.y - box.min.y);
    const double tolerance = f.at("properties").at("tolerance").get<double>();
    EXPECT_DOUBLE_EQ(tolerance, 1e-4 * diagonal);
    EXPECT_EQ(tolerance, kDefaultGeoJsonRelativeTolerance * diagonal);
    // The same as asking for it.
    EXPECT_EQ(write_geojson(r, tolerance), write_geojson(r));

    const std::vector<Point> line = coordinates(f);
    ASSERT_GE(line.size(), 2u);
    const Point first = r.spline.segments.front().bezier.p[0];
    const Point last = r.spline.segments.back().bezier.p[3];
    EXPECT_EQ(line.front(), first);
    EXPECT_EQ(line.back(), closed ? first : last);
    // Every vertex on the curve, every edge's midpoint within the tolerance of it, and the
    // curve within the tolerance of the line (both ways: a Hausdorff distance).
    const double slack = tolerance * (1 + 1e-9);
    for (std::size_t i = 0; i < line.size(); ++i) {
      EXPECT_LE(project(r.spline, line[i]).distance, 1e-9 * diagonal) << "vertex " << i;
      if (i + 1 < line.size()) {
        const Point mid = 0.5 * (line[i] + line[i + 1]);
        EXPECT_LE(project(r.spline, mid).distance, slack) << "edge " << i;
      }
    }
    for (const Point& p : r.spline.sample(2000)) {
      EXPECT_LE(testing::distance_to_polyline(p, line), slack);
    }
  }
}

TEST(Paths, GeoJsonPropertiesAndAnExplicitTolerance) {
  const FitResult r = walk_fit(false);
  const json f = json::parse(write_geojson(r));
  const json& p = f.at("properties");
  EXPECT_EQ(p.at("method"), "quasi-elastic");
  EXPECT_EQ(p.at("closed"), false);
  EXPECT_EQ(p.at("length").get<double>(), length(r.spline));
  ASSERT_TRUE(r.report && r.report->bending_energy);
  EXPECT_EQ(p.at("bending_energy").get<double>(), *r.report->bending_energy);
  // Without a computed bending energy (no report) the property is left out, not null.
  const json none = json::parse(write_geojson(walk_fit(false, ReportLevel::kNone)));
  EXPECT_FALSE(none.at("properties").contains("bending_energy"));
  EXPECT_TRUE(none.at("properties").contains("length"));
  // A smaller tolerance, more vertices; the tolerance is echoed as given.
  std::size_t previous = 0;
  for (const double tolerance : {1.0, 0.1, 0.01, 0.001}) {
    const json g = json::parse(write_geojson(r, tolerance));
    EXPECT_EQ(g.at("properties").at("tolerance").get<double>(), tolerance);
    const std::size_t count = g.at("geometry").at("coordinates").size();
    EXPECT_GT(count, previous) << tolerance;
    previous = count;
    for (const Point& q : coordinates(g)) EXPECT_LE(project(r.spline, q).distance, tolerance);
  }
  for (const double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(), HUGE_VAL}) {
    testing::expect_error(ErrorCode::kInvalidArgument, [&] { (void)write_geojson(r, bad); },
                          {"tolerance"});
  }
}

}  // namespace
}  // namespace fairspline::io
