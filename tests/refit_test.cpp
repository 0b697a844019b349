// A result carries its request (FitResult::input, "request" in JSON): fit(read(write(fit(x))))
// gives the same curve bit for bit, for every method and every kind of input.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"

namespace fairspline {
namespace {

void expect_same_curve(const FitResult& a, const FitResult& b) {
  ASSERT_EQ(a.spline.segments.size(), b.spline.segments.size());
  for (std::size_t s = 0; s < a.spline.segments.size(); ++s) {
    EXPECT_EQ(std::memcmp(&a.spline.segments[s].bezier, &b.spline.segments[s].bezier,
                          sizeof(CubicBezier)),
              0)
        << "segment " << s;
  }
  ASSERT_EQ(a.knots.size(), b.knots.size());
  for (std::size_t i = 0; i < a.knots.size(); ++i) EXPECT_EQ(a.knots[i], b.knots[i]);
}

/// fit -> write_json -> parse_json_input (a result is a request) -> fit.
void check_refit(const std::string& method, const std::string& request) {
  SCOPED_TRACE(method + " " + request);
  const io::ParsedInput req = io::parse_json_input(request);
  const FitResult first = fit(method, req.input, req.options, req.fit_options(ReportLevel::kNone));
  const std::string text = io::write_json(first);
  const io::ParsedInput again = io::parse_json_input(text);
  ASSERT_TRUE(again.method.has_value());
  EXPECT_EQ(*again.method, method);
  EXPECT_EQ(again.accuracy, req.accuracy);
  const FitResult second =
      fit(*again.method, again.input, again.options, again.fit_options(ReportLevel::kNone));
  expect_same_curve(first, second);
  // read_fit_result gives the same request back.
  const FitResult read = io::read_fit_result(text);
  EXPECT_EQ(io::input_to_json(refit_input(read), read.accuracy),
            io::input_to_json(refit_input(first), first.accuracy));
}

TEST(Refit, EveryMethodsExamplesFitTheSameCurveAgain) {
  for (const MethodInfo& m : methods()) {
    for (const std::string& e : m.capabilities.examples) check_refit(m.name, e);
  }
}

TEST(Refit, NodeModelKindsKnotsAndAccuracySurviveTheRoundTrip) {
  const std::string node_model = R"({"points": [[0,0],[2,1],[4,0],[6,2],[8,0],[10,1]],
      "states": ["regular", ["clamped", "free"], "regular", ["free", "clamped"], "regular",
                 "regular"],
      "in_tangents": [null, [1, -0.2], null, null, null, null],
      "out_tangents": [null, null, null, [1, 0.4], null, null],
      "corners_deg": [0, 0, 25, 0, -10, 0], "alpha": 0.3, "accuracy": 1e-8})";
  for (const char* m : {"quasi-elastic", "cond-g2", "restricted-elastic", "elastic"}) {
    check_refit(m, node_model);
  }
  const std::string kinds = R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0],[8,1],[9,3]],
      "kinds": ["smooth", "clamped", "smooth", "corner", "smooth", "smooth", "smooth"],
      "tangents": [null, [1, 0.5], null, null, null, null, null], "alpha": 1})";
  for (const char* m : {"quasi-elastic", "cond-g2", "restricted-elastic"}) check_refit(m, kinds);
  const std::string clamped = R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0]],
      "kinds": ["smooth", "clamped", "smooth", "smooth", "smooth"],
      "tangents": [null, [1, 0.5], null, null, null], "alpha": 0})";
  for (const char* m : {"li-combined", "jaklic-zagar"}) check_refit(m, clamped);
  check_refit("li-strain", R"({"points": [[0,0],[1,2],[3,3],[5,2]], "knots": [0, 1, 3, 4],
      "start_tangent": [1, 1], "end_tangent": [1, -2]})");
  // The closing duplicate is dropped from the result's points; the request keeps it.
  check_refit("quasi-elastic", R"({"points": [[0,0],[4,0],[4,4],[0,4],[0,0]], "closed": true})");
  // Inserted points (reversal=insert) differ from the input: the request keeps the input's.
  check_refit("jaklic-zagar", R"({"points": [[0,0],[2,0],[1,0],[1,2]],
      "options": {"reversal": "insert"}})");
}

TEST(Refit, PlainInputsAddAnEmptyRequest) {
  FitInput in;
  in.points = {{0, 0}, {1, 2}, {3, 3}, {5, 2}};
  const FitResult r = fit("quasi-elastic", in, nlohmann::json::object(), ReportLevel::kNone);
  EXPECT_TRUE(r.input.points.empty()) << "the result's points are the request's";
  EXPECT_EQ(io::to_json(r).at("request"), nlohmann::json::object());
}

}  // namespace
}  // namespace fairspline
