// Curve Ensemble's text files: the format as its source defines it (docs/curve-ensemble.md),
// every node state through a write and a read, and the errors.
#include "fairspline/io/curve_ensemble.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "fairspline/energy.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline::io {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const SideState R = SideState::kRegular, C = SideState::kClamped, F = SideState::kFree;

void expect_direction(const std::optional<Vec2>& v, double degrees) {
  ASSERT_TRUE(v.has_value());
  EXPECT_NEAR(v->x, std::cos(degrees * kDeg), 1e-15);
  EXPECT_NEAR(v->y, std::sin(degrees * kDeg), 1e-15);
}

TEST(CurveEnsemble, ReadsTheFormatAsCurveEnsembleWritesIt) {
  // docs/curve-ensemble.md's example: a clamped start (45°), a regular node with a 30° corner,
  // a clamped end (DIR −60, CORNER 10: incoming −70°); trailing spaces as Curve Ensemble
  // writes them.
  const FitInput in = parse_curve_ensemble(
      "#Curve Ensemble Text File\n"
      "0 0 45 0 3 0.012345678900000000427 \n"
      "100 20 -12.25 30 0 0.00899999999999999932 \n"
      "200 0 -60 10 5 0 \n");
  ASSERT_EQ(in.points.size(), 3u);
  EXPECT_FALSE(in.closed);
  EXPECT_EQ(in.points[1], (Point{100, 20}));
  EXPECT_EQ(in.states[0], (NodeState{F, C}));
  EXPECT_EQ(in.states[1], (NodeState{R, R}));
  EXPECT_EQ(in.states[2], (NodeState{C, F}));
  expect_direction(in.out_tangents[0], 45);
  expect_direction(in.in_tangents[2], -70);
  EXPECT_FALSE(in.out_tangents[2].has_value());
  EXPECT_EQ(in.corners_deg, (std::vector<double>{0, 30, 0}));
  // It fits: the clamped ends keep their directions.
  const FitResult r = fit("quasi-elastic", in);
  EXPECT_NEAR(
      r.spline.segments.front().bezier.d1(0.0).y / r.spline.segments.front().bezier.d1(0.0).x, 1.0,
      1e-12);
}

TEST(CurveEnsemble, OpenOrClosedAsCurveEnsembleDecides) {
  // Open exactly when the first state is 7 or 3 and the last 7 or 5; missing columns are 0,
  // so plain "x y" lines are a closed curve of regular nodes.
  EXPECT_TRUE(parse_curve_ensemble("0 0\n1 0\n1 1\n").closed);
  EXPECT_FALSE(parse_curve_ensemble("0 0 0 0 7\n1 0 0 0 0\n1 1 0 0 5\n").closed);
  EXPECT_FALSE(parse_curve_ensemble("0 0 0 0 3\n1 0 0 0 0\n1 1 90 0 7\n").closed);
  EXPECT_TRUE(parse_curve_ensemble("0 0 0 0 5\n1 0 0 0 0\n1 1 0 0 7\n").closed);
  EXPECT_TRUE(parse_curve_ensemble("0 0 0 0 7\n1 0 0 0 0\n1 1 0 0 3\n").closed);
  // Comments and blank lines; "inf" in the energy column (an infeasible piece) is ignored.
  const FitInput c = parse_curve_ensemble("# a comment\n\n0 0 0 0 0 inf \n4 0 90 0 0 1\n4 4\r\n");
  EXPECT_EQ(c.points.size(), 3u);
  EXPECT_EQ(c.states[0], (NodeState{R, R}));
}

TEST(CurveEnsemble, EveryStateSurvivesAWriteAndARead) {
  // A closed curve with every state code at interior positions, and an open one with clamped
  // ends: fit, write, read, and the states, corners, clamped directions and points come back,
  // and the read input fits the same curve.
  FitInput closed;
  closed.closed = true;
  closed.points = {{0, 0}, {4, -1}, {8, 0}, {10, 4}, {8, 8}, {4, 9}, {0, 8}, {-2, 4}};
  closed.states = {{R, R}, {C, C}, {R, R}, {F, C}, {R, R}, {C, F}, {F, F}, {R, R}};
  closed.in_tangents = {std::nullopt, Vec2{1, -0.1}, std::nullopt, std::nullopt,
                        std::nullopt, Vec2{-1, 0.2}, std::nullopt, std::nullopt};
  closed.out_tangents = {std::nullopt, Vec2{1, 0.2}, std::nullopt, Vec2{-0.2, 1},
                         std::nullopt, std::nullopt, std::nullopt, std::nullopt};
  closed.corners_deg = {0, 0, 12.5, 0, -20, 0, 0, 0};
  FitInput open;
  open.points = {{0, 0}, {3, 2}, {6, 1}, {9, 3}};
  open.states = {{F, C}, {R, R}, {R, R}, {C, F}};
  open.out_tangents = {Vec2{1, 1}, std::nullopt, std::nullopt, std::nullopt};
  open.in_tangents = {std::nullopt, std::nullopt, std::nullopt, Vec2{1, -1}};
  open.corners_deg = {0, 15, 0, 0};
  for (const FitInput* in : {&closed, &open}) {
    for (const char* method : {"quasi-elastic", "restricted-elastic"}) {
      SCOPED_TRACE(std::string(method) + (in->closed ? " closed" : " open"));
      const FitResult r = fit(method, *in);
      const std::string text = write_curve_ensemble(r);
      EXPECT_EQ(text.rfind("#Curve Ensemble Text File\n", 0), 0u);
      const FitInput back = parse_curve_ensemble(text);
      EXPECT_EQ(back.closed, in->closed);
      ASSERT_EQ(back.points, in->points);
      for (std::size_t i = 0; i < in->points.size(); ++i) {
        SCOPED_TRACE("node " + std::to_string(i));
        NodeState want = in->states[i];
        if (!in->closed && i == 0) want.in = F;  // the side before an open curve's start
        if (!in->closed && i + 1 == in->points.size()) want.out = F;
        EXPECT_EQ(back.states[i], want);
        const double corner = i < back.corners_deg.size() ? back.corners_deg[i] : 0.0;
        if (want == NodeState{R, R}) {
          EXPECT_EQ(corner, in->corners_deg[i]);
        }
        for (bool side_in : {true, false}) {
          const auto& given = side_in ? in->in_tangents : in->out_tangents;
          const auto& read = side_in ? back.in_tangents : back.out_tangents;
          if (i < given.size() && given[i]) {
            ASSERT_LT(i, read.size());
            ASSERT_TRUE(read[i].has_value());
            EXPECT_NEAR(cross(*read[i], *given[i]), 0.0, 1e-15);
            EXPECT_GT(dot(*read[i], *given[i]), 0.0);
          }
        }
      }
      // Directions pass through degrees (a few ulp), so the refit agrees to the optimizer's
      // tolerance rather than bit for bit (the JSON request is the bit-exact path).
      const FitResult again = fit(method, back);
      ASSERT_EQ(again.spline.segments.size(), r.spline.segments.size());
      for (std::size_t s = 0; s < r.spline.segments.size(); ++s) {
        for (int j = 0; j < 4; ++j) {
          EXPECT_NEAR(again.spline.segments[s].bezier.p[j].x, r.spline.segments[s].bezier.p[j].x,
                      1e-7);
          EXPECT_NEAR(again.spline.segments[s].bezier.p[j].y, r.spline.segments[s].bezier.p[j].y,
                      1e-7);
        }
      }
    }
  }
}

TEST(CurveEnsemble, WritesKindsAsStatesAndAQuarterOfTheBendingEnergy) {
  FitInput in;
  in.points = {{0, 0}, {2, 2}, {4, 0}, {6, 2}, {8, 0}};
  in.kinds = {PointKind::kSmooth, PointKind::kClamped, PointKind::kCorner, PointKind::kSmooth,
              PointKind::kSmooth};
  in.tangents = {std::nullopt, Vec2{1, 0}, std::nullopt, std::nullopt, std::nullopt};
  const FitResult r = fit("restricted-elastic", in);
  const FitInput back = parse_curve_ensemble(write_curve_ensemble(r));
  EXPECT_EQ(back.states[1], (NodeState{C, C}));
  EXPECT_EQ(back.states[2], (NodeState{F, F}));
  EXPECT_EQ(back.states[3], (NodeState{R, R}));
  // Column 6: ¼∫κ² ds of the piece from the node (Curve Ensemble's energy); against the exact
  // elastica energies of the method report, to the Béziers' accuracy.
  const std::string text = write_curve_ensemble(r);
  std::vector<double> be;
  std::size_t pos = text.find('\n') + 1;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    const std::string line = text.substr(pos, end - pos);
    be.push_back(std::stod(line.substr(line.rfind(' ', line.size() - 2) + 1)));
    pos = end + 1;
  }
  ASSERT_EQ(be.size(), 5u);
  const auto& spans = r.method_report.at("spans");
  for (std::size_t i = 0; i < 4; ++i) {
    const double exact = spans[i].at("energy").get<double>() / 4.0;
    EXPECT_NEAR(be[i], exact, 1e-5 * exact + 1e-12) << i;
  }
  EXPECT_EQ(be[4], 0.0) << "the last node of an open curve starts no piece";
}

TEST(CurveEnsemble, DataBallsAsCurveEnsembleWritesThem) {
  // Rows with state −r (and a "marked" ball, 100 + r) are balls at their centres; the corner
  // column (the node's angle on the circle) is not an input: the position is optimized.
  const FitInput in = parse_curve_ensemble(
      "#Curve Ensemble Text File\n0 0 0 0 7 0 \n10 10 0 0 -5 0 \n20 0 14.5 -90 -1.5 0.3 \n"
      "30 9 0 0 102 0 \n40 0 0 0 7 0 \n");
  EXPECT_FALSE(in.closed);
  EXPECT_EQ(in.radii, (std::vector<double>{0, 5, 1.5, 2, 0}));
  EXPECT_EQ(in.points[2], (Point{20, 0}));
  EXPECT_EQ(in.states[2], (NodeState{SideState::kRegular, SideState::kRegular}));
  EXPECT_TRUE(in.corners_deg.empty());
  // Curve Ensemble's three-column data-ball file: x y r on every line (closed, as it loads it).
  const FitInput three = parse_curve_ensemble("# balls\n10 10 5\n60 30 12\n90 -20 0\n");
  EXPECT_TRUE(three.closed);
  EXPECT_EQ(three.radii, (std::vector<double>{5, 12, 0}));
  EXPECT_EQ(three.points[1], (Point{60, 30}));
}

TEST(CurveEnsemble, DataBallsSurviveAWriteAndARead) {
  FitInput in;
  in.points = {{0, 0}, {3, 1.5}, {6, -0.5}, {9, 1}, {12, 0}};
  in.radii = {0, 0.6, 0.6, 0.6, 0};
  const FitResult r = fit("quasi-elastic", in, {}, FitOptions{.level = ReportLevel::kBasic});
  const std::string text = write_curve_ensemble(r);
  const FitInput back = parse_curve_ensemble(text);
  EXPECT_EQ(back.points, in.points);  // the centres
  EXPECT_EQ(back.radii, in.radii);
  EXPECT_FALSE(back.closed);
  // The corner column of a ball holds the angle of the chosen position from its centre.
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);
  for (std::size_t i = 0; i < 5 && std::getline(lines, line); ++i) {
    std::istringstream row(line);
    double x, y, dir, corner, state;
    row >> x >> y >> dir >> corner >> state;
    if (in.radii[i] == 0.0) continue;
    EXPECT_EQ(state, -in.radii[i]);
    const Vec2 off = r.points[i] - in.points[i];
    if (norm(off) > 0) {
      EXPECT_NEAR(corner, std::atan2(off.y, off.x) * 180 / std::numbers::pi, 1e-12) << i;
    }
  }
  // Fitting the read-back file gives the same curve.
  const FitResult again = fit("quasi-elastic", back, {}, FitOptions{.level = ReportLevel::kBasic});
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(again.points[i], r.points[i]);
}

TEST(CurveEnsemble, ErrorsNameTheLineAndTheNode) {
  using testing::expect_error;
  expect_error(ErrorCode::kParseError, [] { parse_curve_ensemble("0 0\n1 x\n"); },
               {"line 2 (node 1)", "'x'"});
  expect_error(ErrorCode::kParseError, [] { parse_curve_ensemble("0 0 0 0 0 0 9\n"); },
               {"at most 6"});
  expect_error(ErrorCode::kParseError, [] { parse_curve_ensemble("0 0\n1 1 0 0 4\n"); },
               {"state 4 is not a Curve Ensemble node state"});
  const Error ball = expect_error(ErrorCode::kInvalidArgument,
                                  [] { parse_curve_ensemble("0 0 1\n5 5 -2\n9 0 0\n"); },
                                  {"node 1", "radius", "negative"});
  EXPECT_EQ(ball.index(), 1u);
  expect_error(ErrorCode::kNonFinite, [] { parse_curve_ensemble("0 0\n1 nan\n2 0\n"); },
               {"node 1"});
  expect_error(ErrorCode::kTooFewPoints, [] { parse_curve_ensemble("# only a comment\n"); });
  expect_error(ErrorCode::kIoError, [] { read_curve_ensemble("/nonexistent/file.txt"); });
}

}  // namespace
}  // namespace fairspline::io
