// read_fit_result is the inverse of write_json: for every registered method at every report
// level, read(write(r)) equals r field by field (doubles bit for bit) and write(read(write(r)))
// is write(r) byte for byte; and the other views of the one writer (to_json, the SAX events)
// are the same document.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.hpp"

#include "detail/json_input.hpp"
#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::io {
namespace {

using fairspline::testing::expect_error;
using nlohmann::json;

/// Doubles compared bit for bit (-0.0 is not 0.0).
::testing::AssertionResult same_bits(double a, double b) {
  if (std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << std::hexfloat << a << " != " << b;
}

void expect_same(Vec2 a, Vec2 b, const std::string& what) {
  EXPECT_TRUE(same_bits(a.x, b.x)) << what << ".x";
  EXPECT_TRUE(same_bits(a.y, b.y)) << what << ".y";
}

void expect_same(const std::optional<double>& a, const std::optional<double>& b,
                 const std::string& what) {
  ASSERT_EQ(a.has_value(), b.has_value()) << what;
  if (a) {
    EXPECT_TRUE(same_bits(*a, *b)) << what;
  }
}

void expect_same(const Report& a, const Report& b) {
  expect_same(a.bending_energy, b.bending_energy, "bending_energy");
  EXPECT_TRUE(same_bits(a.linearized_energy, b.linearized_energy));
  expect_same(a.curvature_variation_energy, b.curvature_variation_energy, "cv energy");
  expect_same(a.length, b.length, "length");
  EXPECT_EQ(a.regular, b.regular);
  EXPECT_TRUE(same_bits(a.max_tangent_angle_jump_deg, b.max_tangent_angle_jump_deg));
  EXPECT_TRUE(same_bits(a.max_curvature_jump, b.max_curvature_jump));
  EXPECT_TRUE(same_bits(a.min_relative_speed, b.min_relative_speed));
  EXPECT_TRUE(same_bits(a.max_interpolation_residual, b.max_interpolation_residual));
  EXPECT_EQ(a.energy_singular, b.energy_singular);
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const SegmentReport &s = a.segments[i], &t = b.segments[i];
    EXPECT_TRUE(same_bits(s.linearized_energy, t.linearized_energy)) << i;
    EXPECT_TRUE(same_bits(s.bending_energy, t.bending_energy)) << i;
    EXPECT_TRUE(same_bits(s.curvature_variation_energy, t.curvature_variation_energy)) << i;
    EXPECT_TRUE(same_bits(s.length, t.length)) << i;
    EXPECT_EQ(s.regular, t.regular) << i;
    EXPECT_TRUE(same_bits(s.min_relative_speed, t.min_relative_speed)) << i;
    EXPECT_EQ(s.has_loop, t.has_loop) << i;
    EXPECT_EQ(s.has_cusp, t.has_cusp) << i;
    EXPECT_EQ(s.has_fold, t.has_fold) << i;
  }
  ASSERT_EQ(a.intersections.size(), b.intersections.size());
  for (std::size_t i = 0; i < a.intersections.size(); ++i) {
    const Intersection &x = a.intersections[i], &y = b.intersections[i];
    EXPECT_EQ(x.segment_a, y.segment_a) << i;
    EXPECT_EQ(x.segment_b, y.segment_b) << i;
    EXPECT_TRUE(same_bits(x.u_a, y.u_a)) << i;
    EXPECT_TRUE(same_bits(x.u_b, y.u_b)) << i;
    expect_same(x.point, y.point, "intersection point");
  }
}

/// Every field of a FitResult.
void expect_same(const FitResult& a, const FitResult& b) {
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.closed, b.closed);
  EXPECT_EQ(a.options, b.options);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) expect_same(a.points[i], b.points[i], "point");
  ASSERT_EQ(a.knots.size(), b.knots.size());
  for (std::size_t i = 0; i < a.knots.size(); ++i) EXPECT_TRUE(same_bits(a.knots[i], b.knots[i]));
  ASSERT_EQ(a.tangents.size(), b.tangents.size());
  for (std::size_t i = 0; i < a.tangents.size(); ++i) {
    expect_same(a.tangents[i], b.tangents[i], "tangent");
  }
  EXPECT_EQ(a.spline.closed, b.spline.closed);
  ASSERT_EQ(a.spline.segments.size(), b.spline.segments.size());
  for (std::size_t i = 0; i < a.spline.segments.size(); ++i) {
    const Segment &s = a.spline.segments[i], &t = b.spline.segments[i];
    for (std::size_t k = 0; k < 4; ++k) expect_same(s.bezier.p[k], t.bezier.p[k], "bezier");
    EXPECT_TRUE(same_bits(s.t0, t.t0)) << i;
    EXPECT_TRUE(same_bits(s.t1, t.t1)) << i;
    EXPECT_EQ(s.span, t.span) << i;
  }
  ASSERT_EQ(a.report.has_value(), b.report.has_value());
  if (a.report) expect_same(*a.report, *b.report);
  ASSERT_EQ(a.solver.has_value(), b.solver.has_value());
  if (a.solver) {
    EXPECT_EQ(a.solver->status, b.solver->status);
    EXPECT_EQ(a.solver->iterations, b.solver->iterations);
    EXPECT_TRUE(same_bits(a.solver->residual, b.solver->residual));
    EXPECT_TRUE(same_bits(a.solver->tolerance, b.solver->tolerance));
    EXPECT_EQ(a.solver->active, b.solver->active);
  }
  EXPECT_EQ(a.method_report, b.method_report);
}

/// A JSON tree from SAX events (what json::parse builds from the text).
class TreeBuilder : public JsonSax {
 public:
  json tree;

  bool null() override { return value(nullptr); }
  bool boolean(bool v) override { return value(v); }
  bool number_integer(number_integer_t v) override { return value(v); }
  bool number_unsigned(number_unsigned_t v) override { return value(v); }
  bool number_float(number_float_t v, const string_t&) override { return value(v); }
  bool string(string_t& v) override { return value(v); }
  bool binary(binary_t&) override { return value(nullptr); }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool key(string_t& k) override {
    key_ = k;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const json::exception&) override {
    return false;
  }

 private:
  json* add(json v) {
    if (stack_.empty()) {
      tree = std::move(v);
      return &tree;
    }
    json& top = *stack_.back();
    if (top.is_object()) return &(top[key_] = std::move(v));
    top.push_back(std::move(v));
    return &top.back();
  }
  bool value(json v) {
    add(std::move(v));
    return true;
  }
  bool open(json v) {
    stack_.push_back(add(std::move(v)));
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }

  std::string key_;
  std::vector<json*> stack_;
};

/// write_json's views of `r` agree, and read_fit_result inverts it.
void check_round_trip(const FitResult& r) {
  const std::string text = write_json(r);
  const json tree = json::parse(text);
  EXPECT_EQ(tree.dump(), text);  // keys in order, numbers as dump()
  EXPECT_EQ(write_json(r, 2), tree.dump(2));
  EXPECT_EQ(to_json(r), tree);
  TreeBuilder whole, report, method_report;
  write_json(r, whole);
  EXPECT_EQ(whole.tree, tree);
  write_method_report(r, method_report);
  EXPECT_EQ(method_report.tree, tree["method_report"]);
  if (r.report) {
    write_json(*r.report, report);
    EXPECT_EQ(report.tree, tree["report"]);
    EXPECT_EQ(to_json(*r.report), tree["report"]);
  }

  const FitResult back = read_fit_result(text);
  expect_same(r, back);
  EXPECT_TRUE(write_json(back) == text) << "write(read(write(r))) != write(r)";
  expect_same(fit_result_from_json(tree), back);
}

/// The inputs a method is checked on: its own examples (capabilities) and 7 points (3m+1 for
/// Kozak–Krajnc) with a loop, open and closed, when it accepts them.
std::vector<FitInput> inputs_for(const MethodInfo& m) {
  std::vector<FitInput> out;
  for (const std::string& example : m.capabilities.examples) {
    out.push_back(parse_json_input(example).input);
  }
  FitInput seven;
  seven.points = {{0, 0}, {4, 3}, {1, 5}, {-1, 2}, {3, 0}, {7, 1}, {8, 4}};
  out.push_back(seven);
  seven.closed = true;
  out.push_back(seven);
  return out;
}

TEST(JsonRoundTrip, EveryMethodAtEveryReportLevel) {
  ASSERT_FALSE(methods().empty());
  for (const MethodInfo& m : methods()) {
    std::size_t fitted = 0;
    for (const FitInput& in : inputs_for(m)) {
      for (ReportLevel level : {ReportLevel::kNone, ReportLevel::kBasic, ReportLevel::kFull}) {
        FitResult r;
        try {
          r = fit(m.name, in, json::object(), level);
        } catch (const Error&) {
          continue;  // the method does not accept this input (closed, count, tangents)
        } catch (const std::exception& e) {  // a bug: named, and the other methods still run
          ADD_FAILURE() << m.name << ": " << e.what();
          continue;
        }
        SCOPED_TRACE(m.name + " level " + std::string(report_level_name(level)) +
                     (in.closed ? " closed" : " open"));
        check_round_trip(r);
        ++fitted;
        // The same result with a solver report, as an iterative method gives it.
        if (!r.solver) {
          r.solver =
              SolverReport{SolverStatus::kIterationLimit, 200, 3.5e-9, 1e-12, {0, r.points.size()}};
          check_round_trip(r);
        }
      }
    }
    EXPECT_GE(fitted, 3u) << m.name << ": fitted at fewer than three levels";
  }
}

TEST(JsonRoundTrip, HandMadeResults) {
  FitResult empty;  // nothing fitted: every list empty, no report
  check_round_trip(empty);

  FitResult r;
  r.method = "hand-made";
  r.closed = true;
  r.options = {{"lambda", 0.5}, {"list", {1, 2.0, "three"}}, {"nested", {{"x", nullptr}}}};
  r.points = {{-0.0, 1e-310}, {std::numeric_limits<double>::max(), -1e-7}};
  r.knots = {0.0, 1e15, 1.0000000000000002e15};
  r.tangents = {{1, 0}, {0.6, -0.8}};
  Segment s;
  s.bezier.p = {Point{1, 2}, Point{3, 4}, Point{5.5, -6.25}, Point{1e300, 1e-300}};
  s.t0 = 0.1;
  s.t1 = 0.30000000000000004;
  s.span = 7;
  r.spline.segments = {s, s};
  r.spline.closed = true;
  Report rep;
  rep.bending_energy = 2.5;
  rep.curvature_variation_energy = std::nullopt;  // singular
  rep.energy_singular = true;
  rep.length = 12.0;
  rep.regular = false;
  rep.segments.resize(2);
  rep.segments[1].has_cusp = true;
  rep.segments[1].min_relative_speed = -0.0;
  rep.intersections.push_back({0, 1, 0.25, 0.75, {1.5, -2.5}});
  r.report = rep;
  r.solver = SolverReport{SolverStatus::kStalled, 0, 0.0, 1e-10, {}};
  r.method_report = {{"energy", 1.25}, {"segments", json::array({{{"k", 1}}})}};
  check_round_trip(r);

  Report basic;  // what the basic level gives: no full-level parts
  basic.linearized_energy = 3.0;
  r.report = basic;
  r.solver.reset();
  check_round_trip(r);
}

TEST(JsonRoundTrip, AMemberFilterWritesTheKeptMembersOnly) {
  // The filtered text is the whole text's object with only the kept members (byte for byte,
  // extra members always), to a string and to a stream alike.
  FitInput in;
  in.points = {{0, 0}, {1, 2}, {3, 1}, {4, 3}};
  const FitResult r = fit("quasi-elastic", in, json::object(), ReportLevel::kBasic);
  const json extra = {{"line", 7}};
  std::string whole;
  write_json(r, whole, -1, extra);
  const json all = json::parse(whole);
  for (const std::vector<std::string>& kept :
       {std::vector<std::string>{},
        {"segments"},
        {"closed", "tangents"},
        {"report", "request"},
        {"knots", "method", "method_report", "options", "points"}}) {
    const MemberFilter keep = [&](std::string_view key) {
      return std::find(kept.begin(), kept.end(), key) != kept.end();
    };
    json expected = {{"line", 7}};
    for (const std::string& k : kept) expected[k] = all[k];
    std::string text;
    write_json(r, text, -1, extra, keep);
    EXPECT_EQ(text, expected.dump()) << kept.size();
    std::ostringstream stream;
    write_json(r, stream, -1, keep);
    expected.erase("line");
    EXPECT_EQ(stream.str(), expected.dump()) << kept.size();
  }
  // No filter: everything.
  std::string text;
  write_json(r, text, -1, extra, MemberFilter{});
  EXPECT_EQ(text, whole);
}

/// What a result reader made of a text: the result's text, or the error's code, message, index.
std::string result_outcome(const std::function<FitResult()>& read) {
  try {
    return write_json(read());
  } catch (const Error& e) {
    return std::string("error ") + std::string(error_code_name(e.code())) + " " + e.what() +
           " index " + (e.index() ? std::to_string(*e.index()) : "-");
  }
}

TEST(JsonRoundTrip, FastResultReaderReadsWhatTheDocumentReaderReads) {
  // Every prefix and many one-byte edits of results' texts (compact and indented): the fast
  // reader either gives up or gives what the DOM reader gives, errors included.
  FitInput in;
  in.points = {{0, 0}, {1, 2}, {3, 1}, {4, 3}};
  FitInput closed = in;
  closed.closed = true;
  const std::vector<std::string> texts = {
      write_json(fit("quasi-elastic", in, json::object(), ReportLevel::kBasic)),
      write_json(fit("li-strain", closed, json::object(), ReportLevel::kNone)),
      write_json(fit("jaklic-zagar", in, json::object(), ReportLevel::kNone), 1)};
  std::size_t reads = 0;
  for (const std::string& text : texts) {
    auto same = [&](const std::string& t) {
      ++reads;
      EXPECT_EQ(result_outcome([&] { return read_fit_result(t); }),
                result_outcome([&] { return detail::read_fit_result_dom(t); }))
          << t;
    };
    same(text);
    for (std::size_t n = 0; n < text.size(); n += 3) same(text.substr(0, n));
    for (std::size_t i = 0; i < text.size(); ++i) {
      for (const char c : {' ', ',', '0', '"', ']', '}', '-', 'e', '.'}) {
        if (text[i] == c) continue;
        std::string edited = text;
        edited[i] = c;
        same(edited);
      }
    }
  }
  EXPECT_GT(reads, 10000u);
  // Repeated long arrays and segment keys in another order go to the DOM reader too.
  const std::string& t = texts[1];
  const std::size_t at = t.find("\"tangents\"");
  ASSERT_NE(at, std::string::npos);
  std::string twice = t.substr(0, t.size() - 1) + "," + t.substr(at, t.size() - 1 - at) + "}";
  EXPECT_EQ(result_outcome([&] { return read_fit_result(twice); }),
            result_outcome([&] { return detail::read_fit_result_dom(twice); }));
  // The first segment's "t0" and "t1" swapped: the fast reader gives up, the DOM reads it.
  const std::size_t t0 = t.find("\"t0\":"), t1 = t.find(",\"t1\":", t0);
  const std::size_t end = t.find('}', t1);
  ASSERT_TRUE(t0 != std::string::npos && t1 != std::string::npos && end != std::string::npos);
  const std::string swapped = t.substr(0, t0) + t.substr(t1 + 1, end - t1 - 1) + "," +
                              t.substr(t0, t1 - t0) + t.substr(end);
  ASSERT_NE(swapped, t);
  EXPECT_EQ(write_json(read_fit_result(swapped)), t);
}

TEST(JsonRoundTrip, MalformedResultsNameTheField) {
  FitInput in;
  in.points = {{0, 0}, {1, 1}, {2, 0}, {3, 2}};
  FitResult r = fit("jaklic-zagar", in, json::object(), ReportLevel::kFull);
  r.solver = SolverReport{SolverStatus::kConverged, 3, 1e-14, 1e-12, {1}};
  const json good = to_json(r);
  ASSERT_NO_THROW(fit_result_from_json(good));
  struct Case {
    std::function<void(json&)> edit;
    std::vector<std::string> parts;
    std::optional<std::size_t> index;
  };
  const std::vector<Case> cases = {
      {[](json& j) { j.erase("knots"); }, {"missing field 'knots'"}, std::nullopt},
      {[](json& j) { j["typo"] = 1; }, {"unknown field 'typo'"}, std::nullopt},
      {[](json& j) { j["closed"] = "no"; }, {"closed: expected true or false", "\"no\""}, {}},
      {[](json& j) { j["method"] = 3; }, {"method: expected a method name string"}, {}},
      {[](json& j) { j["options"] = json::array(); }, {"options: expected an object"}, {}},
      {[](json& j) { j["points"][2] = {1}; }, {"points[2]: expected [x, y]"}, 2},
      {[](json& j) { j["knots"][1] = "x"; }, {"knots[1]: expected a number", "\"x\""}, 1},
      {[](json& j) { j["tangents"] = 5; }, {"tangents: expected an array"}, std::nullopt},
      {[](json& j) { j["segments"][1]["span"] = -1; },
       {"segments[1].span: expected a non-negative integer"},
       1},
      {[](json& j) { j["segments"][2]["bezier"].erase(3); },
       {"segments[2].bezier: expected 4 control points"},
       2},
      {[](json& j) {
         j["segments"][0]["bezier"][1] = {1, "a"};
       },
       {"segments[0].bezier[1]: expected [x, y]"},
       0},
      {[](json& j) { j["segments"][0].erase("t1"); }, {"missing field 'segments[0].t1'"}, 0},
      {[](json& j) { j["report"]["length"] = true; }, {"report.length: expected a number"}, {}},
      {[](json& j) { j["report"].erase("regular"); }, {"missing field 'report.regular'"}, {}},
      {[](json& j) { j["report"]["segment_reports"][2]["has_loop"] = 1; },
       {"report.segment_reports[2].has_loop: expected true or false"},
       2},
      {[](json& j) { j["report"]["segment_reports"][1]["extra"] = 1; },
       {"unknown field 'report.segment_reports[1].extra'"},
       1},
      {[](json& j) {
         j["report"]["intersections"] = {{{"point", {0, 0}}}};
       },
       {"missing field 'report.intersections[0].segment_a'"},
       0},
      {[](json& j) { j["method_report"] = nullptr; }, {"method_report: expected an object"}, {}},
      {[](json& j) { j["method_report"]["solver"]["status"] = "done"; },
       {"method_report.solver.status: expected \"converged\"", "\"done\""},
       {}},
      {[](json& j) { j["method_report"]["solver"]["iterations"] = 1.5; },
       {"method_report.solver.iterations: expected a non-negative integer"},
       {}},
      {[](json& j) { j["method_report"]["solver"]["active"][0] = "a"; },
       {"method_report.solver.active[0]: expected a non-negative integer"},
       0},
      {[](json& j) { j["method_report"]["solver"].erase("tolerance"); },
       {"missing field 'method_report.solver.tolerance'"},
       {}},
      {[](json& j) { j = json::array(); }, {"result: expected an object"}, {}},
  };
  for (const Case& c : cases) {
    json j = good;
    c.edit(j);
    const Error e = expect_error(
        ErrorCode::kParseError, [&] { fit_result_from_json(j); }, c.parts);
    EXPECT_EQ(e.index(), c.index) << e.what();
    // From text the same.
    const Error t = expect_error(ErrorCode::kParseError, [&] { read_fit_result(j.dump()); });
    EXPECT_STREQ(t.what(), e.what());
  }
  const Error syntax =
      expect_error(ErrorCode::kParseError, [] { read_fit_result("{\n\"closed\": tru}"); },
                   {"invalid JSON at line 2, column"});
  EXPECT_EQ(syntax.index(), 2u);
}

}  // namespace
}  // namespace fairspline::io
