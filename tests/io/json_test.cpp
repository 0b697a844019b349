#include "fairspline/io/json.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "detail/json_input.hpp"
#include "detail/number_format.hpp"
#include "test_util.hpp"

#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::io {
namespace {

using nlohmann::json;

using fairspline::testing::expect_error;

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::vector<Point> kExample = {{1, 90},  {3, 105},  {6, 120}, {10, 100},
                                     {12, 85}, {15, 104}, {17, 80}};

// ------------------------------------------------------------------ input

TEST(JsonInput, MinimalAndDefaults) {
  const ParsedInput p = parse_json_input(R"({"points": [[0, 0], [1, 2.5], [-3, 4e2]]})");
  ASSERT_EQ(p.input.points.size(), 3u);
  EXPECT_EQ(p.input.points[2], (Point{-3, 400}));
  EXPECT_FALSE(p.input.closed);
  EXPECT_EQ(p.input.alpha, FitInput::kDefaultAlpha);
  EXPECT_TRUE(p.input.knots.empty());
  EXPECT_TRUE(p.input.tangents.empty());
  EXPECT_TRUE(p.input.kinds.empty());
  EXPECT_FALSE(p.input.start_tangent);
  EXPECT_FALSE(p.input.end_tangent);
  EXPECT_FALSE(p.method);
  EXPECT_EQ(p.options, json::object());
}

TEST(JsonInput, EveryFieldFromFixture) {
  const ParsedInput p = parse_json_input(read_file(FAIRSPLINE_TEST_DATA_DIR "/io-request.json"));
  const FitInput& in = p.input;
  ASSERT_EQ(in.points.size(), 5u);
  EXPECT_EQ(in.points[3], (Point{3, -0.1}));
  EXPECT_FALSE(in.closed);
  ASSERT_EQ(in.tangents.size(), 5u);
  EXPECT_FALSE(in.tangents[0]);
  EXPECT_EQ(in.tangents[1], (Vec2{1, 0}));
  ASSERT_EQ(in.kinds.size(), 5u);
  EXPECT_EQ(in.kinds[1], PointKind::kClamped);
  EXPECT_EQ(in.kinds[0], PointKind::kSmooth);
  EXPECT_EQ(p.method, "li-strain");
  EXPECT_EQ(in.alpha, 1.0);
  EXPECT_EQ(in.knots, (std::vector<double>{0, 1, 2, 3, 4}));
  EXPECT_EQ(in.start_tangent, (Vec2{1, 1}));
  EXPECT_EQ(in.end_tangent, (Vec2{0, 1}));
  // And it fits.
  const FitResult r = fit(*p.method, in, p.options);
  EXPECT_EQ(r.spline.segments.size(), 4u);
}

TEST(JsonInput, BareArrayCommentsKindsAndLambdas) {
  EXPECT_EQ(parse_json_input("[[0,0],[1,1]]").input.points.size(), 2u);
  const ParsedInput p = parse_json_input(
      R"({"_note": "ignored", "$schema": "x", "points": [[0,0],[1,1],[2,0]], "closed": true,
          "kinds": ["smooth", "corner", "clamped"], "start_tangent": null,
          "options": {"a": 1}, "lambdas": [0.5, 1]})");
  EXPECT_TRUE(p.input.closed);
  EXPECT_EQ(p.input.kinds[1], PointKind::kCorner);
  EXPECT_EQ(p.input.kinds[2], PointKind::kClamped);
  EXPECT_FALSE(p.input.start_tangent);
  EXPECT_EQ(p.options, (json{{"a", 1}, {"lambdas", {0.5, 1}}}));
}

TEST(JsonInput, FromParsedDocument) {
  const ParsedInput p = input_from_json(json{{"points", {{0, 0}, {1, 1}}}, {"method", "m"}});
  EXPECT_EQ(p.input.points.size(), 2u);
  EXPECT_EQ(p.method, "m");
}

struct BadField {
  const char* text;
  ErrorCode code;
  const char* message_prefix;
  std::optional<std::size_t> index;
};

TEST(JsonInput, EveryMalformedFieldIsNamed) {
  const BadField cases[] = {
      {R"({})", ErrorCode::kParseError, "missing field 'points'", std::nullopt},
      {R"({"points": 3})", ErrorCode::kParseError, "points: expected an array", std::nullopt},
      {R"({"points": [[0,0],[1,1],[2,2],[3]]})", ErrorCode::kParseError,
       "points[3]: expected [x, y] with two numbers", 3},
      {R"({"points": [[0,0],[1,"a"]]})", ErrorCode::kParseError,
       "points[1]: expected [x, y] with two numbers", 1},
      {R"({"points": [[0,0],{"x":1,"y":2}]})", ErrorCode::kParseError,
       "points[1]: expected [x, y] with two numbers", 1},
      {R"({"points": [[0,0,0]]})", ErrorCode::kParseError,
       "points[0]: expected [x, y] with two numbers", 0},
      {R"({"points": [[0,0],[1,1e999]]})", ErrorCode::kNonFinite, "points[1][1]: number", 1},
      {R"({"points": [[0,0]], "closed": "yes"})", ErrorCode::kParseError,
       "closed: expected true or false", std::nullopt},
      {R"({"points": [[0,0]], "closed": 1})", ErrorCode::kParseError,
       "closed: expected true or false", std::nullopt},
      {R"({"points": [[0,0]], "tangents": {}})", ErrorCode::kParseError,
       "tangents: expected an array", std::nullopt},
      {R"({"points": [[0,0]], "tangents": [null, [1]]})", ErrorCode::kParseError,
       "tangents[1]: expected [x, y] with two numbers or null", 1},
      {R"({"points": [[0,0]], "tangents": [[1e999, 0]]})", ErrorCode::kNonFinite,
       "tangents[0][0]: number", 0},
      {R"({"points": [[0,0]], "kinds": ["smooth", "sharp"]})", ErrorCode::kParseError,
       "kinds[1]: expected \"smooth\", \"clamped\" or \"corner\"", 1},
      {R"({"points": [[0,0]], "kinds": [1]})", ErrorCode::kParseError, "kinds[0]: expected", 0},
      {R"({"points": [[0,0]], "method": 3})", ErrorCode::kParseError,
       "method: expected a method name string", std::nullopt},
      {R"({"points": [[0,0]], "options": [1]})", ErrorCode::kParseError,
       "options: expected an object", std::nullopt},
      {R"({"points": [[0,0]], "alpha": "chordal"})", ErrorCode::kParseError,
       "alpha: expected a number", std::nullopt},
      {R"({"points": [[0,0]], "alpha": -1e999})", ErrorCode::kNonFinite, "alpha: number",
       std::nullopt},
      {R"({"points": [[0,0]], "knots": [0, "1"]})", ErrorCode::kParseError,
       "knots[1]: expected a number", 1},
      {R"({"points": [[0,0]], "knots": [0, 1e999]})", ErrorCode::kNonFinite, "knots[1]: number", 1},
      {R"({"points": [[0,0]], "start_tangent": [1]})", ErrorCode::kParseError,
       "start_tangent: expected [x, y] with two numbers", std::nullopt},
      {R"({"points": [[0,0]], "end_tangent": "up"})", ErrorCode::kParseError,
       "end_tangent: expected [x, y] with two numbers", std::nullopt},
      {R"({"points": [[0,0]], "lambdas": [1, null]})", ErrorCode::kParseError,
       "lambdas[1]: expected a number", 1},
      {R"({"points": [[0,0]], "lambdas": [1], "options": {"lambdas": [2]}})",
       ErrorCode::kParseError, "lambdas: given both", std::nullopt},
      {R"({"pionts": [[0,0]]})", ErrorCode::kParseError, "unknown field 'pionts'", std::nullopt},
      {R"({"points": [[0,0]], "Closed": true})", ErrorCode::kParseError, "unknown field 'Closed'",
       std::nullopt},
      {R"("points")", ErrorCode::kParseError, "expected a JSON object", std::nullopt},
  };
  for (const BadField& c : cases) {
    const Error e = expect_error([&] { parse_json_input(c.text); });
    EXPECT_EQ(e.code(), c.code) << c.text << " -> " << e.what();
    EXPECT_TRUE(starts_with(e.what(), c.message_prefix)) << c.text << " -> " << e.what();
    EXPECT_EQ(e.index(), c.index) << c.text;
  }
}

TEST(JsonInput, SyntaxErrorGivesLineAndColumn) {
  const Error e = expect_error([] { parse_json_input("{\n  \"points\": [[0, 0],\n  [1, x]]\n}"); });
  EXPECT_EQ(e.code(), ErrorCode::kParseError);
  EXPECT_EQ(e.index(), 3u);
  EXPECT_TRUE(starts_with(e.what(), "invalid JSON at line 3, column 7")) << e.what();
  const Error empty = expect_error([] { parse_json_input(""); });
  EXPECT_EQ(empty.code(), ErrorCode::kParseError);
  const Error truncated = expect_error([] { parse_json_input(R"({"points": [[0,0])"); });
  EXPECT_EQ(truncated.code(), ErrorCode::kParseError);
  const Error utf8 = expect_error([] { parse_json_input("{\"points\": \"\xff\"}"); });
  EXPECT_EQ(utf8.code(), ErrorCode::kParseError);
}

// Found by fuzz_json (tests/fuzz/corpus/fuzz_json/bad-utf8-outside.json): nlohmann's syntax
// error quotes the bytes last read, and a message with invalid UTF-8 made error_to_json(e).dump()
// throw, so the web server answered a bad byte with an exception instead of a 400.
TEST(JsonInput, SyntaxErrorQuotingInvalidUtf8IsWritableAsJson) {
  const Error e = expect_error([] { parse_json_input("{\"points\": \xff\xfe}"); });
  EXPECT_EQ(e.code(), ErrorCode::kParseError);
  EXPECT_NE(std::string(e.what()).find("\\xff"), std::string::npos) << e.what();
  EXPECT_NO_THROW((void)error_to_json(e).dump());
}

// Found by fuzz_json (tests/fuzz/corpus/fuzz_json/regression-preview-splits-utf8): the preview
// of a bad value cut a long string at byte 57, inside a two-byte character.
TEST(JsonInput, PreviewOfALongValueCutsAtACharacterBoundary) {
  for (std::size_t pad = 52; pad < 60; ++pad) {  // > 60 bytes; cut at each byte
    SCOPED_TRACE(pad);
    std::string body(1, '"');  // (appended: GCC 12 warns -Wrestrict on "\"" + …)
    body += std::string(pad, 'I');
    body +=
        "\xd5\xa4\xd5\xa4\xd5\xa4"
        "f\"";
    const Error e = expect_error([&] { parse_json_input(body); });
    EXPECT_EQ(e.code(), ErrorCode::kParseError);
    EXPECT_NE(std::string(e.what()).find("..."), std::string::npos) << e.what();
    EXPECT_NO_THROW((void)error_to_json(e).dump());
  }
}

TEST(JsonInput, DeepNestingIsRejectedWithoutCrashing) {
  const std::string deep =
      "{\"points\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  const Error e = expect_error([&] { parse_json_input(deep); });
  EXPECT_EQ(e.code(), ErrorCode::kParseError);
  const Error bare = expect_error([] { parse_json_input("[[0,0],[1e999,1]]"); });
  EXPECT_EQ(bare.code(), ErrorCode::kNonFinite);
  EXPECT_EQ(bare.index(), 1u);
  EXPECT_TRUE(starts_with(bare.what(), "[1][0]: number")) << bare.what();
}

TEST(JsonInput, TheNestingLimitIsSixtyFourLevelsWithStringsSkipped) {
  // The whole document nests `levels` deep: the request object, "options", then arrays around
  // a number; brackets inside strings (escaped quotes included) do not count.
  auto request = [](int levels) {
    return R"({"points": [[0, 0], [1, 1]], "_note": "]]}\"]]]", "options": {"x": )" +
           std::string(static_cast<std::size_t>(levels - 2), '[') + "1" +
           std::string(static_cast<std::size_t>(levels - 2), ']') + "}}";
  };
  EXPECT_NO_THROW(detail::parse_json_input_dom(request(64)));
  const Error e = expect_error([&] { detail::parse_json_input_dom(request(65)); });
  EXPECT_EQ(e.code(), ErrorCode::kParseError);
  EXPECT_NE(std::string(e.what()).find("nested deeper than 64 levels"), std::string::npos)
      << e.what();
  // A fit result is read by the same parser: its segments, each an object in one array, once
  // made that quadratic. The limit still applies to it.
  FitInput in;
  in.points = {{0, 0}, {1, 1}, {2, 0}};
  const FitResult r = fit("jaklic-zagar", in);
  EXPECT_EQ(write_json(read_fit_result(write_json(r))), write_json(r));
  const Error deep =
      expect_error([&] { read_fit_result(std::string(70, '[') + std::string(70, ']')); });
  EXPECT_EQ(deep.code(), ErrorCode::kParseError);
}

// ------------------------------------------------------------------ the fast reader

/// What a reader made of a text: the request as JSON (round-trip digits, so bit for bit, -0.0
/// included), or the error's code, message and index.
std::string outcome(const std::function<ParsedInput()>& read) {
  try {
    const ParsedInput p = read();
    return input_to_json(p.input, p.accuracy).dump() + " alpha " + json(p.input.alpha).dump() +
           " method " + (p.method ? *p.method : "-") + " options " + p.options.dump() +
           " best_effort " + (p.best_effort ? (*p.best_effort ? "true" : "false") : "-");
  } catch (const Error& e) {
    return std::string("error ") + std::string(error_code_name(e.code())) + " " + e.what() +
           " index " + (e.index() ? std::to_string(*e.index()) : "-");
  }
}

void expect_same_as_dom(const std::string& text) {
  EXPECT_EQ(outcome([&] { return parse_json_input(text); }),
            outcome([&] { return detail::parse_json_input_dom(text); }))
      << text;
}

TEST(JsonInput, FastReaderReadsWhatTheDocumentReaderReads) {
  const char* numbers[] = {"0",
                           "-0",
                           "0.0",
                           "-0.0",
                           "1",
                           "-1",
                           "1e5",
                           "1E+5",
                           "1e-5",
                           "-2.5E-3",
                           "0.1",
                           "1.5e-300",
                           "5e-324",
                           "4.9e-324",
                           "1e-400",
                           "1e999",
                           "-1e999",
                           "1.7976931348623157e308",
                           "123456789012345678901234567890",
                           "-9223372036854775809",
                           "18446744073709551616",
                           "9007199254740993",
                           "190.18124141243771",
                           "01",
                           "1.",
                           ".5",
                           "+1",
                           "1e",
                           "-",
                           "nan",
                           "inf",
                           "0x10",
                           "1.5e+",
                           "--1",
                           "2.e3"};
  for (const char* x : numbers) {
    for (const char* y : {"2", "-0.0", "3.25e2"}) {
      expect_same_as_dom(std::string("{\"points\": [[") + x + ", " + y + "], [" + y + "," + x +
                         "]]}");
      expect_same_as_dom(std::string("[[") + x + "," + y + "]]");
    }
  }
  const std::string documents[] = {
      R"({"points": []})",
      R"({"points": [[0,0],[1,1]], "closed": true, "method": "li-strain"})",
      " \t\r\n{ \"points\" : [ [ 0 , 0 ] ,\n[ 1 , 1 ] ] , \"closed\" : false } \n",
      R"({"_note": {"a": [1, "]}\"", {"b": "}"}]}, "points": [[0,0],[1,2]], "$x": null})",
      R"({"points": [[0,0],[1,2],[3,1]], "tangents": [null, [1, 0], null],
          "kinds": ["smooth", "corner", "clamped"], "alpha": 1, "knots": [0, 1, 2.5],
          "options": {"lambda": 0.5, "nested": {"deep": [1, [2, [3]]]}}, "accuracy": 1e-7,
          "best_effort": true, "start_tangent": [1, 0], "end_tangent": null})",
      R"({"points": [[0,0],[1,2]], "lambdas": [0, 0.5]})",
      R"({"points": [[0,0]], "points": [[1,1]]})",  // repeated: the last, as nlohmann
      R"({"closed": true, "closed": false, "points": [[0,0]]})",
      R"({"p\u006fints": [[0,0]]})",                  // an escaped key: the DOM reads it
      "\xEF\xBB\xBF{\"points\": [[0,0]]}",            // a byte-order mark
      R"({"points": [[0,0],[1,1]]} x)",               // text after the document
      R"({"points": [[0,0],[1,1]],})",                // a trailing comma
      R"({"points": [[0,0],[1,1]] "closed": true})",  // a missing comma
      R"({"points": [[0,0],[1,1]], "closed": tru})",
      R"({"points": [[0,0],[1,1]], "options": {"a": [1}]})",
      R"({"points": [[0,0],[1,1]], "options": "unterminated})",
      R"({"points": [[0,0],[1,1]], "request": {}, "segments": []})",
      R"({"points": [[0,0],[1,1]], "method": "\ud800"})",
      R"({"points": [[0,0],[1,1]]})"
      "\x01",
      "{\"points\": [[0,0],[1,1]], \"method\": \"caf\xc3\xa9\"}",
      "{\"points\": [[0,0],[1,1]], \"method\": \"\xff\"}",
      R"({"points": [[0,0],[1, 1, 1]]})",
      R"({"points": [[0,0],[1]]})",
      R"({"points": [[0,0],[1,null]]})",
      R"({"points": [[0,0],[1,1]]])",
      R"({"points": [[0,0],[1,1]})",
      R"({"points": [[0,0],[1,1])",
      R"({"points": [[0,0],[1,1]], "options": )" + std::string(40, '[') + std::string(40, ']') +
          "}",
  };
  for (const std::string& d : documents) expect_same_as_dom(d);

  // -0 is nlohmann's integer 0; -0.0 keeps its sign.
  const ParsedInput p = parse_json_input(R"({"points": [[-0, -0.0], [1e-5, 123456789012345678]]})");
  EXPECT_FALSE(std::signbit(p.input.points[0].x));
  EXPECT_TRUE(std::signbit(p.input.points[0].y));
  EXPECT_EQ(p.input.points[1].x, 1e-5);
  EXPECT_EQ(p.input.points[1].y, 123456789012345678.0);
}

TEST(JsonInput, FastReaderMalformedTextGivesTheSameErrors) {
  // Every prefix and single-byte edit of a request: the fast reader and the DOM agree on the
  // request or on the error's code, message (line and column) and index.
  const std::string base =
      "{\"points\": [[0.5, -1e-3],\n [2, 3E2], [-0, 4]],\n \"closed\": true, \"options\": "
      "{\"a\": [1, \"x\"]}, \"_c\": \"]\\\"\"}";
  for (std::size_t n = 0; n <= base.size(); ++n) expect_same_as_dom(base.substr(0, n));
  const char edits[] = {'[', ']', '{', '}', ',', ':', '"', '-', '.', 'e', '0', ' ', '\n', 'x'};
  for (std::size_t i = 0; i < base.size(); ++i) {
    std::string removed = base;
    removed.erase(i, 1);
    expect_same_as_dom(removed);
    for (const char c : edits) {
      std::string replaced = base;
      replaced[i] = c;
      expect_same_as_dom(replaced);
    }
  }
  const Error e = expect_error([] { parse_json_input("{\"points\": [[0, 0],\n  [1, 2,]]}"); });
  EXPECT_EQ(e.code(), ErrorCode::kParseError);
  EXPECT_EQ(e.index(), 2u);
  EXPECT_TRUE(starts_with(e.what(), "invalid JSON at line 2, column 9 (byte 29)")) << e.what();
}

TEST(JsonInput, FastReaderLongRandomRequests) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-1e6, 1e6);
  for (int round = 0; round < 20; ++round) {
    std::string text = "{\"points\": [";
    std::vector<Point> want;
    for (int i = 0; i < 2000; ++i) {
      const double x = round % 2 ? coordinate(rng) : std::bit_cast<double>(rng());
      const double y = std::ldexp(coordinate(rng), static_cast<int>(rng() % 600) - 300);
      if (!std::isfinite(x)) continue;
      want.push_back({x, y});
      char buf[80];
      std::snprintf(buf, sizeof buf, "%s[%.17g,%.*e]", want.size() > 1 ? ", " : "", x,
                    static_cast<int>(rng() % 20), y);
      text += buf;
    }
    text += "]}";
    const ParsedInput fast = parse_json_input(text);
    ASSERT_EQ(fast.input.points.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(fast.input.points[i].x, want[i].x) << i;
    }
    expect_same_as_dom(text);
  }
}

// ------------------------------------------------------------------ output

void expect_number_or_null(const json& j, const char* key) {
  ASSERT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j[key].is_number() || j[key].is_null()) << key << " = " << j[key];
}

void expect_pair(const json& j) {
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  EXPECT_TRUE(j[0].is_number());
  EXPECT_TRUE(j[1].is_number());
}

TEST(JsonOutput, SchemaAtFullLevel) {
  FitInput in;
  in.points = kExample;
  const FitResult r = fit("li-combined", in, json::object(), ReportLevel::kFull);
  const json j = json::parse(write_json(r));
  for (const char* key : {"method", "closed", "options", "points", "knots", "tangents", "segments",
                          "report", "method_report"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["method"], "li-combined");
  EXPECT_EQ(j["closed"], false);
  EXPECT_TRUE(j["options"].is_object());
  EXPECT_TRUE(j["method_report"].is_object());
  ASSERT_EQ(j["points"].size(), 7u);
  for (const auto& p : j["points"]) expect_pair(p);
  ASSERT_EQ(j["tangents"].size(), 7u);
  for (const auto& t : j["tangents"]) {
    expect_pair(t);
    EXPECT_NEAR(std::hypot(t[0].get<double>(), t[1].get<double>()), 1.0, 1e-12);
  }
  ASSERT_EQ(j["knots"].size(), 7u);
  ASSERT_EQ(j["segments"].size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    const json& s = j["segments"][k];
    ASSERT_EQ(s["bezier"].size(), 4u);
    for (const auto& p : s["bezier"]) expect_pair(p);
    EXPECT_TRUE(s["t0"].is_number());
    EXPECT_TRUE(s["t1"].is_number());
    EXPECT_TRUE(s["span"].is_number_unsigned());
    EXPECT_EQ(s["span"], k);
  }
  const json& rep = j["report"];
  for (const char* key : {"bending_energy", "linearized_energy", "curvature_variation_energy",
                          "length", "max_tangent_angle_jump_deg", "max_curvature_jump",
                          "min_relative_speed", "max_interpolation_residual"}) {
    expect_number_or_null(rep, key);
  }
  EXPECT_TRUE(rep["regular"].is_boolean());
  EXPECT_TRUE(rep["energy_singular"].is_boolean());
  EXPECT_TRUE(rep["bending_energy"].is_number());
  EXPECT_TRUE(rep["length"].is_number());
  ASSERT_TRUE(rep.contains("segment_reports"));
  ASSERT_TRUE(rep.contains("intersections"));
  EXPECT_TRUE(rep["intersections"].is_array());
  for (const auto& s : rep["segment_reports"]) {
    for (const char* key : {"linearized_energy", "bending_energy", "curvature_variation_energy",
                            "length", "min_relative_speed"}) {
      EXPECT_TRUE(s[key].is_number()) << key;
    }
    for (const char* key : {"regular", "has_loop", "has_cusp", "has_fold"}) {
      EXPECT_TRUE(s[key].is_boolean()) << key;
    }
  }
}

TEST(JsonOutput, IntersectionsAndSegmentReportsAreSerialized) {
  FitResult r;
  r.method = "m";
  Report rep;
  rep.bending_energy = 1.0;
  rep.segments.resize(2);
  rep.segments[1].has_loop = true;
  rep.intersections.push_back({0, 1, 0.25, 0.75, {1.5, -2.5}});
  r.report = rep;
  const json j = to_json(r);
  ASSERT_EQ(j["report"]["segment_reports"].size(), 2u);
  EXPECT_EQ(j["report"]["segment_reports"][1]["has_loop"], true);
  const json& x = j["report"]["intersections"][0];
  EXPECT_EQ(x["segment_a"], 0);
  EXPECT_EQ(x["segment_b"], 1);
  EXPECT_EQ(x["u_a"], 0.25);
  EXPECT_EQ(x["u_b"], 0.75);
  EXPECT_EQ(x["point"], json({1.5, -2.5}));
}

TEST(JsonOutput, ReportAbsentOrPartialByLevel) {
  FitInput in;
  in.points = kExample;
  const json none = to_json(fit("li-strain", in, json::object(), ReportLevel::kNone));
  EXPECT_FALSE(none.contains("report"));
  EXPECT_TRUE(none.contains("method_report"));
  Report basic;  // what a basic level leaves unset
  basic.linearized_energy = 2.0;
  const json rb = to_json(basic);
  EXPECT_TRUE(rb["bending_energy"].is_null());
  EXPECT_TRUE(rb["curvature_variation_energy"].is_null());
  EXPECT_TRUE(rb["length"].is_null());
  EXPECT_EQ(rb["linearized_energy"], 2.0);
  EXPECT_FALSE(rb.contains("segment_reports"));
  EXPECT_FALSE(rb.contains("intersections"));
}

TEST(JsonOutput, DoublesRoundTripExactly) {
  FitInput in;
  in.points = {{0.1, 0.7}, {1.0 / 3.0, 2.0 / 7.0}, {2.718281828459045, 1e-17}, {3.3, -1e5}};
  in.closed = true;
  const FitResult r = fit("li-combined", in);
  for (int indent : {-1, 2}) {
    const json j = json::parse(write_json(r, indent));
    for (std::size_t k = 0; k < r.spline.segments.size(); ++k) {
      const Segment& s = r.spline.segments[k];
      const json& js = j["segments"][k];
      EXPECT_EQ(js["t0"].get<double>(), s.t0);
      EXPECT_EQ(js["t1"].get<double>(), s.t1);
      for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(js["bezier"][i][0].get<double>(), s.bezier.p[i].x);
        EXPECT_EQ(js["bezier"][i][1].get<double>(), s.bezier.p[i].y);
      }
    }
    for (std::size_t i = 0; i < r.knots.size(); ++i) {
      EXPECT_EQ(j["knots"][i].get<double>(), r.knots[i]);
    }
    for (std::size_t i = 0; i < r.tangents.size(); ++i) {
      EXPECT_EQ(j["tangents"][i][0].get<double>(), r.tangents[i].x);
      EXPECT_EQ(j["tangents"][i][1].get<double>(), r.tangents[i].y);
    }
    EXPECT_EQ(j["report"]["linearized_energy"].get<double>(), r.report->linearized_energy);
    EXPECT_EQ(j["report"]["bending_energy"].get<double>(), *r.report->bending_energy);
  }
}

// ------------------------------------------------------------------ numbers

std::string formatted(double v) {
  char buf[detail::kJsonNumberChars];
  return std::string(buf, detail::format_json_number(buf, v));
}

/// The doubles of the number test: every binade and sign through random bit patterns, the
/// subnormals, integers up to and past 2^53, powers of two and ten and their neighbours, the
/// edges of fixed notation (1e-4, 1e15), short decimals, and the special values.
std::vector<double> adversarial_doubles() {
  std::vector<double> v = {0.0,
                           -0.0,
                           1.0,
                           -1.0,
                           0.1,
                           0.5,
                           1e-7,
                           1e300,
                           -1e-300,
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::lowest(),
                           std::numeric_limits<double>::min(),
                           std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::epsilon(),
                           9007199254740992.0,  // 2^53
                           9007199254740993.0,
                           123456789012345.0,
                           1234567890123456.0,
                           190.18124141243771};  // Grisu2's digits differ from to_chars's here
  const auto around = [&](double x) {
    for (double y : {x, -x}) {
      v.push_back(y);
      v.push_back(std::nextafter(y, 0.0));
      v.push_back(std::nextafter(y, std::numeric_limits<double>::infinity()));
    }
  };
  for (int e = -1074; e <= 1023; ++e) around(std::ldexp(1.0, e));
  for (int e = -323; e <= 308; ++e) around(std::pow(10.0, e));
  for (double x :
       {1e-5, 1e-4, 1e15, 1e16, 1e17, 1e21, 1e22, 1e23, 5e-324, 1.7976931348623157e308}) {
    around(x);
  }
  std::mt19937_64 rng(20240613);
  for (int i = 0; i < 40000; ++i) {  // any bit pattern: all exponents, both signs
    const double x = std::bit_cast<double>(rng());
    if (std::isfinite(x)) v.push_back(x);
  }
  for (int i = 0; i < 10000; ++i) {  // subnormals
    v.push_back(std::bit_cast<double>(rng() & 0x800FFFFFFFFFFFFFu));
  }
  for (int i = 0; i < 10000; ++i) {  // integers of every size
    v.push_back(static_cast<double>(rng() >> (rng() % 64)));
  }
  std::uniform_real_distribution<double> coordinate(-1000.0, 1000.0);
  for (int i = 0; i < 20000; ++i) v.push_back(coordinate(rng));  // what fits write
  for (int i = 0; i < 10000; ++i) {                              // short decimals k / 10^j
    v.push_back(static_cast<double>(rng() % 100000) / std::pow(10.0, static_cast<int>(rng() % 12)));
  }
  // Their neighbours: the last digit's rounding towards the value (closed form since
  // 2026-11-29) decides between candidates a rounding unit apart there.
  for (int i = 0; i < 10000; ++i) {
    const double x =
        static_cast<double>(rng() % 10000000) / std::pow(10.0, static_cast<int>(rng() % 9));
    v.push_back(std::nextafter(x, 0.0));
    v.push_back(std::nextafter(x, std::numeric_limits<double>::infinity()));
  }
  return v;
}

TEST(JsonNumbers, SameTextAsNlohmannDump) {
  const std::vector<double> values = adversarial_doubles();
  ASSERT_GT(values.size(), 100000u);
  std::size_t mismatches = 0;
  for (const double x : values) {
    const std::string want = json(x).dump();
    const std::string got = formatted(x);
    if (got != want && ++mismatches <= 10) {
      ADD_FAILURE() << std::hexfloat << x << ": " << got << " != dump() " << want;
    }
    ASSERT_LE(got.size(), detail::kJsonNumberChars);
  }
  EXPECT_EQ(mismatches, 0u);
}

// The digit generation writes p1's digits two at a time where Grisu2's loop divided by a
// power of ten per digit: the same text on many more doubles than the test above.
TEST(JsonNumbers, SameTextAsNlohmannDumpOnManyRandomDoubles) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> coordinate(-500.0, 500.0);
  std::size_t mismatches = 0;
  for (int i = 0; i < 200000; ++i) {
    const double values[] = {
        std::bit_cast<double>(rng()), coordinate(rng),
        static_cast<double>(rng() % 1000000) / std::pow(10.0, static_cast<int>(rng() % 9)),
        static_cast<double>(rng() >> (rng() % 64)) * 1000.0,  // trailing decimal zeros
        std::ldexp(static_cast<double>(rng() >> 11), static_cast<int>(rng() % 200) - 100)};
    for (const double x : values) {
      if (json(x).dump() != formatted(x) && ++mismatches < 10) {
        ADD_FAILURE() << json(x).dump() << " vs " << formatted(x);
      }
    }
  }
  EXPECT_EQ(mismatches, 0u);
}

TEST(JsonNumbers, Layout) {
  EXPECT_EQ(formatted(0.0), "0.0");
  EXPECT_EQ(formatted(-0.0), "-0.0");
  EXPECT_EQ(formatted(1.0), "1.0");
  EXPECT_EQ(formatted(-2.5), "-2.5");
  EXPECT_EQ(formatted(1e-4), "0.0001");
  EXPECT_EQ(formatted(1e-5), "1e-05");
  EXPECT_EQ(formatted(1e-7), "1e-07");
  EXPECT_EQ(formatted(123456789012345.0), "123456789012345.0");
  EXPECT_EQ(formatted(1e15), "1e+15");
  EXPECT_EQ(formatted(1e300), "1e+300");
  EXPECT_EQ(formatted(1.5e-300), "1.5e-300");
  EXPECT_EQ(formatted(5e-324), "5e-324");
  EXPECT_EQ(formatted(9007199254740993.0), "9.007199254740992e+15");
  // Not std::to_chars's shortest "190.1812414124377": Grisu2, as dump().
  EXPECT_EQ(formatted(190.18124141243771), "190.18124141243771");
  EXPECT_EQ(formatted(std::numeric_limits<double>::quiet_NaN()), "null");
  EXPECT_EQ(formatted(-std::numeric_limits<double>::infinity()), "null");
}

// ------------------------------------------------------------------ the writer

TEST(JsonWriter, SameBytesAsTheTreeDumped) {
  FitInput in;
  in.points = kExample;
  for (ReportLevel level : {ReportLevel::kNone, ReportLevel::kBasic, ReportLevel::kFull}) {
    const FitResult r = fit("li-combined", in, json::object(), level);
    const std::string text = write_json(r);
    EXPECT_EQ(json::parse(text).dump(), text);  // keys in order, numbers as dump()
    for (int indent : {0, 1, 2, 4}) {
      EXPECT_EQ(write_json(r, indent), json::parse(text).dump(indent)) << indent;
    }
    EXPECT_EQ(to_json(r), json::parse(text));
    std::string appended = "prefix";
    write_json(r, appended);
    EXPECT_EQ(appended, "prefix" + text);
  }
}

// The writer copies the text of a number it wrote recently (by its bits) instead of formatting
// it again: repeats, evictions, 0.0 and -0.0, and the non-finite numbers still read as dump().
TEST(JsonWriter, RepeatedNumbersAsDump) {
  std::mt19937_64 rng(5);
  std::vector<double> pool = {0.0,
                              -0.0,
                              std::numeric_limits<double>::quiet_NaN(),
                              std::numeric_limits<double>::infinity(),
                              5e-324,
                              1e300};
  while (pool.size() < 3000) pool.push_back(std::bit_cast<double>(rng()));
  FitResult r;
  std::string want = "\"knots\":[";
  for (int i = 0; i < 50000; ++i) {
    // Mostly a few recent values, sometimes any of the pool (evicting others).
    const std::size_t k = rng() % 4 == 0 ? rng() % pool.size() : rng() % 8;
    r.knots.push_back(pool[k]);
    want += (i ? "," : "") + json(pool[k]).dump();
  }
  want += "]";
  for (int pass = 0; pass < 2; ++pass) {  // the second with the memory of the first
    const std::string text = write_json(r);
    EXPECT_NE(text.find(want), std::string::npos);
  }
}

// Long arrays of a compact text are written in chunks on several cores (TextSink::array): the
// same bytes as the indented text, which is written in one pass, parsed and dumped compact;
// lengths around the chunk size and the threshold, and odd numbers of chunks.
TEST(JsonWriter, LongArraysOnSeveralCoresAsTheOnePassText) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (const std::size_t n : {16383, 16384, 16385, 1024 * 17 + 1, 70001}) {
    FitResult r;
    r.method = "test";
    for (std::size_t i = 0; i < n; ++i) {
      r.points.push_back({u(rng), u(rng)});
      r.tangents.push_back({u(rng), u(rng)});
      r.knots.push_back(static_cast<double>(i) + u(rng) * 1e-4);
      Segment g;
      for (Point& p : g.bezier.p) p = {u(rng), u(rng)};
      g.span = i;
      g.t0 = u(rng);
      g.t1 = u(rng);
      r.spline.segments.push_back(g);
    }
    const std::string text = write_json(r);
    EXPECT_TRUE(json::parse(write_json(r, 2)).dump() == text) << n;
    std::ostringstream os;
    write_json(r, os);
    EXPECT_TRUE(os.str() == text) << n;
  }
}

// The request is written without its document: its points streamed in their place among the
// keys (before "radii", "start_tangent", "states", "tangents"; after the rest), the other
// members as input_to_json has them. The text must be input_to_json's dumped, every field set.
TEST(JsonWriter, TheRequestIsInputToJsonDumped) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (const std::size_t n : {3, 20000}) {
    FitResult r;
    r.method = "test";
    r.accuracy = 1e-7;
    FitInput& in = r.input;
    in.closed = true;
    in.alpha = 0.25;
    in.start_tangent = Vec2{1.0, u(rng)};
    in.end_tangent = Vec2{u(rng), -1.0};
    for (std::size_t i = 0; i < n; ++i) {
      in.points.push_back({u(rng), u(rng)});
      in.knots.push_back(static_cast<double>(i));
      in.radii.push_back(i % 3 == 0 ? 0.0 : 1e-3 * u(rng) * u(rng));
      in.corners_deg.push_back(i % 2 == 0 ? 0.0 : u(rng));
      in.tangents.push_back(i % 4 == 0 ? std::optional<Vec2>(Vec2{u(rng), u(rng)}) : std::nullopt);
      in.in_tangents.push_back(i % 5 == 0 ? std::optional<Vec2>(Vec2{u(rng), 1.0}) : std::nullopt);
      in.out_tangents.push_back(i % 7 == 0 ? std::optional<Vec2>(Vec2{1.0, u(rng)}) : std::nullopt);
      in.kinds.push_back(static_cast<PointKind>(i % 3));
      in.states.push_back({static_cast<SideState>(i % 3), static_cast<SideState>((i / 3) % 3)});
    }
    const std::string want = "\"request\":" + input_to_json(r.input, r.accuracy).dump();
    EXPECT_NE(write_json(r).find(want), std::string::npos) << n;
    EXPECT_EQ(json::parse(write_json(r, 2)).at("request"), input_to_json(r.input, r.accuracy));
    r.input.points.clear();  // none: no "points" member
    EXPECT_EQ(json::parse(write_json(r)).at("request"), input_to_json(r.input, r.accuracy));
    EXPECT_FALSE(json::parse(write_json(r)).at("request").contains("points"));
  }
}

TEST(JsonWriter, ExtraMembersGoInKeyOrder) {
  FitInput in;
  in.points = kExample;
  const FitResult r = fit("jaklic-zagar", in, json::object(), ReportLevel::kNone);
  std::string text;
  write_json(r, text, -1, json{{"line", 12}, {"a", "first"}, {"zz", nullptr}});
  json expected = to_json(r);
  expected["line"] = 12;
  expected["a"] = "first";
  expected["zz"] = nullptr;
  EXPECT_EQ(text, expected.dump());
  EXPECT_NE(text.find(R"("knots":[)"), std::string::npos);
  EXPECT_LT(text.find(R"("knots":)"), text.find(R"("line":12,"method":)"));
  std::string pretty;
  write_json(r, pretty, 2, json{{"line", 12}, {"a", "first"}, {"zz", nullptr}});
  EXPECT_EQ(pretty, expected.dump(2));
  std::string ignored;
  expect_error(ErrorCode::kInvalidArgument,
               [&] {
                 write_json(r, ignored, -1, json{{"method", "x"}});
               },
               {"'method'"});
  expect_error(ErrorCode::kInvalidArgument, [&] { write_json(r, ignored, -1, json::array()); });
}

TEST(JsonWriter, StringsAndOddValuesAsDump) {
  FitResult r;
  r.method = "quote \" backslash \\ tab \t \x01 caf\xc3\xa9 bad \xff end";
  r.options = {{"s", "\n"}, {"i", -3},      {"u", 7u},
               {"f", 2.0},  {"n", nullptr}, {"e", json::object()}};
  r.method_report = nullptr;  // written as {}
  const std::string text = write_json(r);
  json expected = {{"closed", false},           {"knots", json::array()},
                   {"method", r.method},        {"method_report", json::object()},
                   {"options", r.options},      {"points", json::array()},
                   {"request", json::object()}, {"segments", json::array()},
                   {"tangents", json::array()}};
  EXPECT_EQ(text, expected.dump(-1, ' ', false, json::error_handler_t::replace));
  EXPECT_EQ(write_json(r, 3), expected.dump(3, ' ', false, json::error_handler_t::replace));
}

TEST(JsonWriter, SolverGoesInsideMethodReportInKeyOrder) {
  FitResult r;
  r.method = "m";
  r.method_report = {{"aa", 1}, {"status", "mine"}, {"zz", {1.5, 2.5}}};
  EXPECT_EQ(to_json(r)["method_report"], r.method_report);  // no solver: as the method wrote it
  r.solver = SolverReport{SolverStatus::kConditioningLimit, 17, 1.25e-13, 1e-14, {2, 5}};
  const json j = to_json(r);
  EXPECT_EQ(j["method_report"]["solver"], (json{{"status", "conditioning_limit"},
                                                {"iterations", 17},
                                                {"residual", 1.25e-13},
                                                {"tolerance", 1e-14},
                                                {"active", {2, 5}}}));
  EXPECT_EQ(j["method_report"]["aa"], 1);
  EXPECT_EQ(j["method_report"]["status"], "mine");
  EXPECT_EQ(json::parse(write_json(r)).dump(), write_json(r));
  // A "solver" of the method's own gives way to the result's.
  r.method_report["solver"] = "stale";
  EXPECT_EQ(to_json(r), j);
  for (SolverStatus s : {SolverStatus::kConverged, SolverStatus::kConditioningLimit,
                         SolverStatus::kIterationLimit, SolverStatus::kStalled}) {
    EXPECT_EQ(parse_solver_status(solver_status_name(s)), s);
  }
  expect_error(ErrorCode::kInvalidArgument, [] { parse_solver_status("Converged"); });
}

TEST(JsonOutput, ErrorToJson) {
  const json with = error_to_json(Error(ErrorCode::kRepeatedPoint, "point 3 repeats", 3));
  EXPECT_EQ(with,
            (json{{"error",
                   {{"code", "repeated_point"}, {"message", "point 3 repeats"}, {"index", 3}}}}));
  const json without = error_to_json(Error(ErrorCode::kUnknownMethod, "nope"));
  EXPECT_TRUE(without["error"]["index"].is_null());
  EXPECT_EQ(without["error"]["code"], "unknown_method");
  EXPECT_FALSE(without["error"].contains("hint"));
  // The option that gets past an error travels as data; each client words it (issue 20).
  const json hinted = error_to_json(Error(ErrorCode::kWrongPointCount, "needs 3m+1 points", 4,
                                          OptionHint{"remainder", "hermite"}));
  EXPECT_EQ(hinted["error"]["hint"], (json{{"option", "remainder"}, {"value", "hermite"}}));
  const json any = error_to_json(
      Error(ErrorCode::kInvalidArgument, "no tangent", 0, OptionHint{"tangents_from", ""}));
  EXPECT_TRUE(any["error"]["hint"]["value"].is_null());
}

TEST(JsonText, WrittenToAStreamAsItIsMade) {
  // 20000 points: about 6 MB of text, flushed a megabyte at a time; the same bytes as the
  // string, compact and indented, and a stream that fails is an io_error.
  FitInput in;
  in.points = testing::random_walk(20000, 3, 100);
  const FitResult r = fit("jaklic-zagar", in, json::object(), ReportLevel::kFull);
  for (int indent : {-1, 2}) {
    std::ostringstream os;
    write_json(r, os, indent);
    const std::string whole = write_json(r, indent);
    EXPECT_GT(whole.size(), std::size_t{3} << 20);
    EXPECT_TRUE(os.str() == whole) << indent;
    EXPECT_TRUE(json::parse(whole).dump(indent) == whole) << indent;
  }
  std::ostringstream broken;
  broken.setstate(std::ios::badbit);
  testing::expect_error(ErrorCode::kIoError, [&] { write_json(r, broken); }, {"writing"});
}

TEST(JsonText, ReportLevelAndPointKindNames) {
  for (ReportLevel l : {ReportLevel::kNone, ReportLevel::kBasic, ReportLevel::kFull}) {
    EXPECT_EQ(parse_report_level(report_level_name(l)), l);
  }
  EXPECT_THROW(parse_report_level("Full"), Error);
  for (PointKind k : {PointKind::kSmooth, PointKind::kClamped, PointKind::kCorner}) {
    EXPECT_EQ(parse_point_kind(point_kind_name(k)), k);
  }
  EXPECT_THROW(parse_point_kind("sharp"), Error);
}

TEST(JsonText, SummaryTable) {
  FitInput in;
  in.points = kExample;
  const std::string full =
      summary_table(fit("li-combined", in, json::object(), ReportLevel::kFull));
  for (const char* row :
       {"method", "segments", "bending energy", "linearized energy", "curvature-variation energy",
        "length", "regular", "max tangent jump", "max curvature jump", "self-intersections"}) {
    EXPECT_NE(full.find(row), std::string::npos) << row;
  }
  // The default (basic) report: no curvature-variation or self-intersection row.
  const std::string basic = summary_table(fit("li-combined", in));
  EXPECT_NE(basic.find("bending energy"), std::string::npos);
  EXPECT_EQ(basic.find("curvature-variation energy"), std::string::npos);
  EXPECT_EQ(basic.find("self-intersections"), std::string::npos);
  EXPECT_NE(full.find("li-combined"), std::string::npos);
  // Aligned: every value starts in the same column.
  std::istringstream ss(full);
  std::string line;
  std::size_t column = std::string::npos;
  while (std::getline(ss, line)) {
    const auto gap = line.find("  ");
    ASSERT_NE(gap, std::string::npos) << line;
    const auto value = line.find_first_not_of(' ', gap);
    if (column == std::string::npos) column = value;
    EXPECT_EQ(value, column) << line;
  }
  const std::string none =
      summary_table(fit("li-combined", in, json::object(), ReportLevel::kNone));
  EXPECT_NE(none.find("not computed"), std::string::npos);
  EXPECT_EQ(full.find("data balls"), std::string::npos);
  // Data balls: how many touch their circle, and the optimizer's status.
  FitInput balls;
  balls.points = {{0, 0}, {3, 1.5}, {6, -0.5}, {9, 1}, {12, 0}};
  balls.radii = {0, 0.6, 0.6, 0.6, 0};
  const FitResult b = fit("quasi-elastic", balls);
  const std::string table = summary_table(b);
  const std::string value = std::to_string(b.method_report.at("balls").at("active").size()) +
                            " of 3 on their circle (converged)";
  const auto at = table.find("data balls");
  ASSERT_NE(at, std::string::npos) << table;
  EXPECT_EQ(table.substr(table.find_first_not_of(' ', at + 10), value.size()), value) << table;
}

}  // namespace
}  // namespace fairspline::io
