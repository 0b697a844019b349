// Curve Ensemble's node model (issue 19): per-side states, corner angles, per-side tangents.
// Checked by equivalences that do not use the node model: kinds, splitting the input into
// independent fits, and rotating the data after a corner so that the node becomes smooth; by
// finite-difference KKT checks; and the errors with their points.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/methods/min_energy.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

using testing::expect_error;
using testing::random_walk;

constexpr double kPi = std::numbers::pi;
constexpr SideState R = SideState::kRegular;
constexpr SideState C = SideState::kClamped;
constexpr SideState F = SideState::kFree;

FitInput open_input(std::vector<Point> pts) {
  FitInput in;
  in.points = std::move(pts);
  return in;
}

FitResult fit_min(const FitInput& in, const std::string& method = "quasi-elastic") {
  return fit(method, in, {}, ReportLevel::kNone);
}

double angle_of(Vec2 v) {
  return std::atan2(v.y, v.x);
}

double wrap(double a) {
  return std::remainder(a, 2.0 * kPi);
}

/// Outgoing direction at the start of segment s and incoming at its end.
Vec2 out_dir(const FitResult& r, std::size_t s) {
  const CubicBezier& b = r.spline.segments[s].bezier;
  return b.p[1] - b.p[0];
}
Vec2 in_dir(const FitResult& r, std::size_t s) {
  const CubicBezier& b = r.spline.segments[s].bezier;
  return b.p[3] - b.p[2];
}

TEST(NodeModel, StatesThatKindsExpressGiveTheSameCurve) {
  FitInput kinds = open_input(random_walk(12, 4, 80));
  kinds.kinds.assign(12, PointKind::kSmooth);
  kinds.tangents.assign(12, std::nullopt);
  kinds.kinds[4] = PointKind::kCorner;
  kinds.kinds[7] = PointKind::kClamped;
  kinds.tangents[7] = out_dir(fit_min(open_input(kinds.points)), 7);
  FitInput states = kinds;
  states.kinds.clear();
  states.states.assign(12, NodeState{});
  states.states[4] = {F, F};
  states.states[7] = {C, C};
  for (const std::string method : {"quasi-elastic", "li-strain", "restricted-elastic"}) {
    SCOPED_TRACE(method);
    FitInput a = kinds, b = states;
    if (method == "li-strain") {  // li honours clamped tangents but no corners
      a.kinds[4] = PointKind::kSmooth;
      b.states[4] = {R, R};
    }
    // The same curve and report; only the requests (kinds vs states) differ.
    nlohmann::json ja = io::to_json(fit_min(a, method)), jb = io::to_json(fit_min(b, method));
    ja.erase("request");
    jb.erase("request");
    EXPECT_EQ(ja, jb);
  }
}

TEST(NodeModel, HalfStatesSplitTheCurveIntoIndependentFits) {
  // Clamped in / free out at point 5: the fit of points 0..5 with that end tangent, and the fit
  // of points 5..10 with a free start.
  const std::vector<Point> pts = random_walk(11, 9, 70);
  const Vec2 d = from_angle(angle_of(pts[5] - pts[4]) + 0.3);
  FitInput whole = open_input(pts);
  whole.states.assign(11, NodeState{});
  whole.states[5] = {C, F};
  whole.in_tangents.assign(11, std::nullopt);
  whole.in_tangents[5] = d;
  FitInput left = open_input({pts.begin(), pts.begin() + 6});
  left.end_tangent = d;
  const FitInput right = open_input({pts.begin() + 5, pts.end()});
  const FitResult w = fit_min(whole), l = fit_min(left), r = fit_min(right);
  for (std::size_t s = 0; s < 5; ++s) {
    EXPECT_EQ(w.spline.segments[s].bezier.p, l.spline.segments[s].bezier.p) << s;
  }
  for (std::size_t s = 5; s < 10; ++s) {
    EXPECT_EQ(w.spline.segments[s].bezier.p, r.spline.segments[s - 5].bezier.p) << s;
  }
  EXPECT_NEAR(w.method_report["energy"].get<double>(),
              l.method_report["energy"].get<double>() + r.method_report["energy"].get<double>(),
              1e-12 * w.method_report["energy"].get<double>());
}

TEST(NodeModel, ACornerAngleIsTheSmoothFitOfTheDataTurnedAfterIt) {
  // Turning every point after node i about p_i by −c keeps every span's end angles and makes
  // node i smooth: the energies agree and the directions map back by the rotation.
  for (const double corner_deg : {35.0, -60.0, 120.0}) {
    SCOPED_TRACE(corner_deg);
    const std::vector<Point> pts = random_walk(9, 21, 50);
    const std::size_t i = 4;
    const double c = corner_deg * kPi / 180.0;
    FitInput cornered = open_input(pts);
    cornered.corners_deg.assign(9, 0.0);
    cornered.corners_deg[i] = corner_deg;
    FitInput turned = open_input(pts);
    for (std::size_t j = i + 1; j < pts.size(); ++j) {
      turned.points[j] = pts[i] + rotate(pts[j] - pts[i], -c);
    }
    const FitResult a = fit_min(cornered), b = fit_min(turned);
    EXPECT_NEAR(a.method_report["energy"].get<double>(), b.method_report["energy"].get<double>(),
                1e-10 * b.method_report["energy"].get<double>());
    // The corner is kept exactly as asked.
    EXPECT_NEAR(wrap(angle_of(out_dir(a, i)) - angle_of(in_dir(a, i - 1))), c, 1e-12);
    for (std::size_t s = 0; s < 8; ++s) {
      const double turn = s >= i ? c : 0.0;
      EXPECT_NEAR(wrap(angle_of(out_dir(a, s)) - angle_of(out_dir(b, s)) - turn), 0.0, 1e-9) << s;
    }
  }
}

TEST(NodeModel, RegularNodesWithCornersAreStationary) {
  // KKT by central differences of Σ E_1/L: turning both directions of a regular node together
  // (the corner kept) does not lower the energy to first order.
  const std::vector<Point> pts = random_walk(10, 5, 40);
  FitInput in = open_input(pts);
  in.corners_deg = {0, 20, -15, 0, 40, 0, -30, 10, 0, 0};
  const FitResult r = fit_min(in);
  const BasicCurveMethod qe;
  std::vector<double> al, be, len;
  for (const Segment& s : r.spline.segments) {
    const Vec2 c = s.bezier.p[3] - s.bezier.p[0];
    al.push_back(wrap(angle_of(s.bezier.p[1] - s.bezier.p[0]) - angle_of(c)));
    be.push_back(wrap(angle_of(s.bezier.p[3] - s.bezier.p[2]) - angle_of(c)));
    len.push_back(norm(c));
  }
  for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
    auto local = [&](double d) {
      return basic_energy(qe, al[i] + d, be[i]).e / len[i] +
             basic_energy(qe, al[i - 1], be[i - 1] + d).e / len[i - 1];
    };
    const double h = 1e-6, g = (local(h) - local(-h)) / (2 * h);
    const bool bound = std::abs(std::abs(al[i]) - kPi / 2) < 1e-9 ||
                       std::abs(std::abs(be[i - 1]) - kPi / 2) < 1e-9;
    if (!bound) {
      EXPECT_NEAR(g, 0.0, 1e-6) << i;
    }
  }
}

TEST(NodeModel, OneClampedDirectionAndACornerGiveTheOther) {
  const std::vector<Point> pts = random_walk(8, 2, 40);
  FitInput in = open_input(pts);
  const Vec2 d = from_angle(angle_of(pts[4] - pts[3]) + 0.1);
  in.states.assign(8, NodeState{});
  in.states[3] = {C, C};
  in.tangents.assign(8, std::nullopt);
  in.tangents[3] = d;
  in.corners_deg.assign(8, 0.0);
  in.corners_deg[3] = 25.0;
  const FitResult r = fit_min(in);
  EXPECT_NEAR(wrap(angle_of(in_dir(r, 2)) - angle_of(d)), 0.0, 1e-12);
  EXPECT_NEAR(wrap(angle_of(out_dir(r, 3)) - angle_of(d) - 25.0 * kPi / 180.0), 0.0, 1e-12);
  // Two different clamped directions (in_tangents, out_tangents): a clamped corner.
  FitInput two = open_input(pts);
  two.states.assign(8, NodeState{});
  two.states[3] = {C, C};
  two.in_tangents.assign(8, std::nullopt);
  two.out_tangents.assign(8, std::nullopt);
  two.in_tangents[3] = d;
  two.out_tangents[3] = rotate(d, 25.0 * kPi / 180.0);
  EXPECT_NEAR(fit_min(two).method_report["energy"].get<double>(),
              r.method_report["energy"].get<double>(),
              1e-12 * r.method_report["energy"].get<double>());
}

TEST(NodeModel, ClosedCurvesWithEveryNodeRegularAndCorners) {
  FitInput in;
  in.points = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  in.closed = true;
  in.corners_deg = {10, 10, 10, 10};
  const FitResult r = fit_min(in);
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t prev = (i + 3) % 4;
    EXPECT_NEAR(wrap(angle_of(out_dir(r, i)) - angle_of(in_dir(r, prev))), 10 * kPi / 180, 1e-12);
  }
}

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

TEST(NodeModel, Errors) {
  const std::vector<Point> pts = random_walk(6, 1, 40);
  auto with = [&](auto edit) {
    FitInput in = open_input(pts);
    edit(in);
    return in;
  };
  auto err = [&](ErrorCode code, const FitInput& in, std::size_t index, const std::string& part,
                 const std::string& method = "quasi-elastic") {
    const Error e = expect_error(code, [&] { (void)fit_min(in, method); }, {part});
    if (index == kNone) {
      EXPECT_FALSE(e.index().has_value()) << e.what();
    } else {
      EXPECT_EQ(e.index(), std::optional<std::size_t>(index)) << e.what();
    }
  };
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) {
        in.kinds.assign(6, PointKind::kSmooth);
        in.states.assign(6, NodeState{});
      }),
      kNone, "given twice");
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) {
        in.states.assign(6, NodeState{});
        in.states[2] = {C, F};
      }),
      2, "clamped on its incoming side but has no direction");
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) {
        in.states.assign(6, NodeState{});
        in.states[3] = {F, R};
        in.corners_deg.assign(6, 0.0);
        in.corners_deg[3] = 10;
      }),
      3, "has a corner angle, but a side of it is free");
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) {
        in.corners_deg.assign(6, 0.0);
        in.corners_deg[0] = 10;
      }),
      0, "an end of the open curve");
  err(ErrorCode::kNonFinite, with([](FitInput& in) {
        in.corners_deg.assign(6, 0.0);
        in.corners_deg[4] = std::nan("");
      }),
      4, "not finite");
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) {
        in.corners_deg.assign(6, 0.0);
        in.corners_deg[4] = 180;
      }),
      4, "strictly between -180");
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) {
        in.tangents.assign(6, std::nullopt);
        in.in_tangents.assign(6, std::nullopt);
        in.tangents[1] = Vec2{1, 0};
        in.in_tangents[1] = Vec2{1, 0};
      }),
      1, "tangents sets both sides");
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) { in.corners_deg.assign(4, 0.0); }), kNone,
      "corners_deg has 4 entries");
  // A method that honours only kinds refuses what kinds cannot express, naming the point.
  err(ErrorCode::kInvalidArgument, with([](FitInput& in) {
        in.corners_deg.assign(6, 0.0);
        in.corners_deg[2] = 15;
      }),
      2, "honours only the node kinds", "li-strain");
  // A corner angle that turns a stencil beyond 2Ω is infeasible at that point.
  FitInput sharp = open_input({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}});
  sharp.corners_deg = {0, 0, 150, 0, 0};
  const Error e =
      expect_error(ErrorCode::kInfeasible,
                   [&] {
                     (void)fit("quasi-elastic", sharp, {{"omega_deg", 60}}, ReportLevel::kNone);
                   },
                   {"after the corner angle"});
  EXPECT_EQ(e.index(), std::optional<std::size_t>(2));
}

}  // namespace
}  // namespace fairspline

namespace fairspline {
namespace {

/// Unit direction of the span s's Bézier at its start (end = false) or its end.
Vec2 piece_direction(const FitResult& r, std::size_t s, bool end) {
  const CubicBezier& b = r.spline.segments.at(s).bezier;
  return normalized(end ? b.p[3] - b.p[2] : b.p[1] - b.p[0]);
}

double turn_deg(Vec2 a, Vec2 b) {
  return std::atan2(cross(a, b), dot(a, b)) * 180.0 / std::numbers::pi;
}

RC_GTEST_PROP(NodeModel, EveryStateCombinationKeepsItsDirectionsAndReachesTheReference, ()) {
  // Random small curves whose nodes take every side state (regular, clamped, free, on each side
  // independently), corners on regular nodes: the fit keeps every clamped direction and every
  // corner on its Béziers, and its energy is at most the slow coordinate search's (Curve
  // Ensemble's optimizer, min_energy_reference) on the same input.
  const bool closed = *rc::gen::arbitrary<bool>();
  const auto n = static_cast<std::size_t>(*rc::gen::inRange(closed ? 3 : 4, 8));
  FitInput in;
  in.closed = closed;
  double heading = 0.0;
  Point p{0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    in.points.push_back(p);
    heading += *rc::gen::inRange(-50, 51) * std::numbers::pi / 180.0;
    const double step = 0.5 + *rc::gen::inRange(0, 100) / 50.0;
    p = p + step * from_angle(heading);
  }
  const SideState kStates[] = {SideState::kRegular, SideState::kClamped, SideState::kFree};
  in.states.resize(n);
  in.in_tangents.assign(n, std::nullopt);
  in.out_tangents.assign(n, std::nullopt);
  in.corners_deg.assign(n, 0.0);
  auto chord = [&](std::size_t a) {  // unit chord from point a to the next
    return normalized(in.points[(a + 1) % n] - in.points[a]);
  };
  for (std::size_t i = 0; i < n; ++i) {
    NodeState& s = in.states[i];
    s.in = kStates[*rc::gen::inRange(0, 3)];
    s.out = kStates[*rc::gen::inRange(0, 3)];
    const bool has_prev = closed || i > 0, has_next = closed || i + 1 < n;
    if (!has_prev) s.in = s.out == SideState::kClamped ? SideState::kFree : s.out;
    if (!has_next) s.out = s.in == SideState::kClamped ? SideState::kFree : s.in;
    // Clamped directions within 30° of the adjacent chord: feasible for Ω = 90°.
    if (s.in == SideState::kClamped) {
      in.in_tangents[i] =
          rotate(chord(i == 0 ? n - 1 : i - 1), *rc::gen::inRange(-30, 31) * 0.0174533);
    }
    if (s.out == SideState::kClamped) {
      in.out_tangents[i] = rotate(chord(i), *rc::gen::inRange(-30, 31) * 0.0174533);
    }
    if (s.in == SideState::kRegular && s.out == SideState::kRegular && has_prev && has_next &&
        *rc::gen::inRange(0, 3) == 0) {
      in.corners_deg[i] = *rc::gen::inRange(-30, 31);
    }
  }
  FitResult r;
  try {
    r = fit("quasi-elastic", in, nlohmann::json::object(), ReportLevel::kNone);
  } catch (const Error& e) {
    // Only a clamped direction or a stencil beyond the feasible range may refuse the input.
    RC_ASSERT(e.code() == ErrorCode::kInfeasible);
    RC_SUCCEED("infeasible");
  }
  const std::size_t spans = closed ? n : n - 1;
  RC_ASSERT(r.spline.segments.size() == spans);
  for (std::size_t i = 0; i < n; ++i) {
    const bool has_prev = closed || i > 0, has_next = closed || i + 1 < n;
    const std::size_t before = i == 0 ? n - 1 : i - 1;
    if (has_prev && in.in_tangents[i]) {
      RC_ASSERT(std::abs(turn_deg(*in.in_tangents[i], piece_direction(r, before, true))) < 1e-9);
    }
    if (has_next && in.out_tangents[i]) {
      RC_ASSERT(std::abs(turn_deg(*in.out_tangents[i], piece_direction(r, i, false))) < 1e-9);
    }
    if (has_prev && has_next && in.states[i] == NodeState{}) {
      const double turn = turn_deg(piece_direction(r, before, true), piece_direction(r, i, false));
      RC_ASSERT(std::abs(turn - in.corners_deg[i]) < 1e-9);
    }
  }
  MinEnergyOptions o;
  o.method.basis = MinEnergyBasis::kCondG2;
  const MinEnergyReference ref = min_energy_reference(in, o);
  const double e = r.method_report.at("energy").get<double>();
  RC_ASSERT(e <= ref.energy * (1.0 + 1e-9) + 1e-12);
}

}  // namespace
}  // namespace fairspline
