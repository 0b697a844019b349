#include "fairspline/io/csv.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "test_util.hpp"

#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::io {
namespace {

using fairspline::testing::expect_error;

std::vector<Point> pts(std::initializer_list<Point> p) {
  return p;
}

TEST(CsvParse, PlainPairs) {
  EXPECT_EQ(parse_csv_points("1,2\n3,4\n"), pts({{1, 2}, {3, 4}}));
  EXPECT_EQ(parse_csv_points("1,2\n3,4"), pts({{1, 2}, {3, 4}}));  // no final newline
  EXPECT_TRUE(parse_csv_points("").empty());
  EXPECT_TRUE(parse_csv_points("\n\n# only comments\n").empty());
}

TEST(CsvParse, HeaderCommentsBlankLinesAndWhitespace) {
  const std::string text =
      "\xEF\xBB\xBF# a comment, with a comma\n"
      "  x , y  \n"
      "\n"
      "  1.5 ,  -2e3   # trailing comment\n"
      "\t\n"
      "+3,.25\r\n"
      "4,5.\n";
  EXPECT_EQ(parse_csv_points(text), pts({{1.5, -2000}, {3, 0.25}, {4, 5}}));
}

TEST(CsvParse, LineEndings) {
  EXPECT_EQ(parse_csv_points("1,2\r\n3,4\r\n"), pts({{1, 2}, {3, 4}}));
  EXPECT_EQ(parse_csv_points("1,2\r3,4\r"), pts({{1, 2}, {3, 4}}));
  const Error e = expect_error([] { parse_csv_points("1,2\r\n\r\n3,4\rbad\n"); });
  EXPECT_EQ(e.index(), 4u);
}

TEST(CsvParse, SemicolonAndWhitespaceSeparators) {
  EXPECT_EQ(parse_csv_points("1;2\n3 ; 4\n"), pts({{1, 2}, {3, 4}}));
  EXPECT_EQ(parse_csv_points("1 2\n3\t4\n  5   6  \n"), pts({{1, 2}, {3, 4}, {5, 6}}));
  EXPECT_EQ(parse_csv_points("x y\n1 2\n"), pts({{1, 2}}));
}

TEST(CsvParse, FixtureFile) {
  const auto p = read_csv_points(FAIRSPLINE_TEST_DATA_DIR "/io-points.csv");
  EXPECT_EQ(p, pts({{0, 0}, {1, 1}, {2, 0.5}, {3, -0.1}, {4.5, 2}}));
}

TEST(CsvParse, MalformedLineNamesTheLine) {
  const Error e = expect_error([] { parse_csv_points("x,y\n1,2\n\n# c\n3,4\n5,6\nabc\n"); });
  EXPECT_EQ(e.code(), ErrorCode::kParseError);
  EXPECT_EQ(e.index(), 7u);
  EXPECT_STREQ(e.what(), "line 7: expected two numbers 'x,y', got 'abc'");
}

TEST(CsvParse, EveryMalformedShape) {
  struct Case {
    const char* text;
    std::size_t line;
  };
  for (const Case& c :
       {Case{"1,2\n3\n", 2}, Case{"1,2\n3,4,5\n", 2}, Case{"1,2\n1,,2\n", 2},
        Case{"1,2\n1,2x\n", 2}, Case{"1,2\n,\n", 2}, Case{"1,2\n1;\n", 2}, Case{"1,2\nx,y\n", 2},
        Case{"1,abc\n", 1}, Case{"0x10,1\n", 1}, Case{"1,2\n1 2 3\n", 2}, Case{"1,2\n--1,2\n", 2},
        Case{"1,2\n+-1,2\n", 2}, Case{"1,2\n1e,2\n", 2}, Case{"1,2\n\"1\",2\n", 2}}) {
    const Error e = expect_error([&] { parse_csv_points(c.text); });
    EXPECT_EQ(e.code(), ErrorCode::kParseError) << c.text;
    EXPECT_EQ(e.index(), c.line) << c.text;
    const std::string prefix = "line " + std::to_string(c.line) + ": expected two numbers";
    EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
  }
}

TEST(CsvParse, OnlyATwoColumnTextLineIsAHeader) {
  for (const char* text : {"abc\n1,2\n", "x,y,z\n1,2\n", "x,\n1,2\n", "\x01\x02,y\n1,2\n"}) {
    const Error e = expect_error([&] { parse_csv_points(text); });
    EXPECT_EQ(e.code(), ErrorCode::kParseError) << text;
    EXPECT_EQ(e.index(), 1u) << text;
  }
  const Error e = expect_error([] { parse_csv_points(std::string("\0\x01\xff\xfe", 4)); });
  EXPECT_EQ(e.code(), ErrorCode::kParseError);
  EXPECT_STREQ(e.what(), "line 1: expected two numbers 'x,y', got '\\x00\\x01\\xff\\xfe'");
  EXPECT_EQ(parse_csv_points("Longitude;Latitude\n1;2\n"), pts({{1, 2}}));
}

TEST(CsvParse, NonFiniteTextNamesTheLineAndThePoint) {
  for (const char* bad : {"nan", "NaN", "inf", "-Infinity", "1e999", "-1e400"}) {
    const std::string text = "x,y\n1,2\n3," + std::string(bad) + "\n";
    const Error e = expect_error([&] { parse_csv_points(text); });
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite) << bad;
    EXPECT_EQ(e.index(), 1u) << bad;  // the second point (the CLI says "at point 1")
    EXPECT_NE(std::string(e.what()).find("line 3 (point 1)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

TEST(CsvParse, UnderflowReadsAsZeroAndSubnormalsSurvive) {
  const auto p = parse_csv_points("1e-400,-1e-400\n4e-320,1\n");
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].x, 0.0);
  EXPECT_EQ(p[0].y, 0.0);
  EXPECT_GT(p[1].x, 0.0);
}

TEST(CsvParse, UnreadableFileIsIoError) {
  const Error e = expect_error([] { read_csv_points("/nonexistent/dir/points.csv"); });
  EXPECT_EQ(e.code(), ErrorCode::kIoError);
  EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/points.csv"), std::string::npos);
}

TEST(CsvParse, ParseNumber) {
  double v = 0;
  EXPECT_TRUE(parse_number(" 2.5 ", v));
  EXPECT_EQ(v, 2.5);
  EXPECT_TRUE(parse_number("+7", v));
  EXPECT_EQ(v, 7);
  EXPECT_TRUE(parse_number("-0.125e1", v));
  EXPECT_EQ(v, -1.25);
  EXPECT_FALSE(parse_number("", v));
  EXPECT_FALSE(parse_number("1,2", v));
  EXPECT_FALSE(parse_number("- 1", v));
  EXPECT_THROW(parse_number("nan", v), Error);
}

TEST(CsvFormat, ShortestRoundTrip) {
  EXPECT_EQ(format_double(0.1), "0.1");
  EXPECT_EQ(format_double(-2.0), "-2");
  EXPECT_EQ(format_double(1e300), "1e+300");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> exp(-300, 300);
  for (int i = 0; i < 2000; ++i) {
    const double x = std::ldexp(mant(rng), exp(rng));
    double back = 0;
    ASSERT_TRUE(parse_number(format_double(x), back));
    EXPECT_EQ(back, x) << format_double(x);
  }
}

TEST(CsvWrite, OneRowPerSegmentRoundTripsExactly) {
  FitInput in;
  in.points = {{1, 90}, {3, 105}, {6, 120}, {10, 100}, {12, 85}, {15, 104}, {17, 80}};
  const FitResult r = fit("li-combined", in, nlohmann::json::object(), ReportLevel::kNone);
  const std::string csv = write_csv(r);
  std::istringstream ss(csv);
  std::string line;
  ASSERT_TRUE(std::getline(ss, line));
  EXPECT_EQ(line, "x0,y0,x1,y1,x2,y2,x3,y3");
  std::size_t rows = 0;
  while (std::getline(ss, line)) {
    ASSERT_LT(rows, r.spline.segments.size());
    const auto& b = r.spline.segments[rows].bezier;
    std::vector<double> values;
    std::size_t start = 0;
    while (true) {
      const auto comma = line.find(',', start);
      double v = 0;
      ASSERT_TRUE(parse_number(line.substr(start, comma - start), v)) << line;
      values.push_back(v);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    ASSERT_EQ(values.size(), 8u);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(values[2 * k], b.p[k].x);
      EXPECT_EQ(values[2 * k + 1], b.p[k].y);
    }
    ++rows;
  }
  EXPECT_EQ(rows, r.spline.segments.size());
}

}  // namespace
}  // namespace fairspline::io
