// Numeric extremes for every registered method (hardening): coordinates near 1e-300 and 1e300,
// mixed scales, nearly collinear and nearly repeated points, exact reversals, 0° turns, long
// straight runs, points exactly on a circle, 10^6 points and iteration caps. Each input gives a
// regular curve — the report certifies it and the checks below confirm it — or a clear
// fairspline::Error naming a valid index; never NaN, Inf, a crash or a hang.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "capability_inputs.hpp"
#include "fairspline/energy.hpp"
#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/methods/min_energy.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

using nlohmann::json;
using testing::scale_of;

/// What a case may give for one method.
enum class Outcome {
  kCurve,         ///< a regular curve, nothing else
  kCurveOrError,  ///< a regular curve or an Error with one of the allowed codes
};

struct Case {
  std::string name;
  std::vector<Point> points;
  bool closed = false;
  ReportLevel level = ReportLevel::kFull;
  Outcome outcome = Outcome::kCurve;
  std::set<ErrorCode> allowed;  ///< for kCurveOrError
  /// Largest tangent-angle jump at a joint that counts as G1: directions of a piece 1e-15 long
  /// (relative) come from control points a few ulps apart and are known only to ~1e-1 rad.
  double g1_tolerance_deg = 1e-6;
  /// An error with this code must name this point.
  std::optional<std::pair<ErrorCode, std::size_t>> error_index;
};

const Capabilities& caps(const std::string& method) {
  return find_method(method).capabilities;
}

/// C1 methods do not promise regularity (a C1 curve may stop at a reversal); their report must
/// then say so, with the cusp located. Every other method promises a regular curve.
bool promises_regularity(const std::string& method) {
  return caps(method).regular;
}

/// Inputs a method cannot take by construction, as its capabilities declare; everything else
/// must meet the case.
bool structurally_excluded(const std::string& method, const Case& c, ErrorCode code) {
  const Capabilities& k = caps(method);
  if (c.closed && !k.closed && code == ErrorCode::kInvalidArgument) return true;
  if (!k.needs_turns) return false;
  return (c.name.find("straight") != std::string::npos && code == ErrorCode::kInvalidArgument) ||
         (c.name.find("collinear") != std::string::npos &&
          (code == ErrorCode::kInvalidArgument || code == ErrorCode::kInfeasible));
}

/// A gentle wave with 3m + 1 = 19 points (every method accepts it, kozak-krajnc included).
std::vector<Point> wave(double scale = 1.0) {
  std::vector<Point> p;
  for (int i = 0; i < 19; ++i) {
    const double x = i;
    p.push_back({scale * x, scale * 2.0 * std::sin(x / 3.0)});
  }
  return p;
}

json options_for(const std::string& method) {
  return testing::options_for_any_points(find_method(method));
}

FitInput input_for(const std::string& method, const Case& c) {
  FitInput in;
  in.points = c.points;
  in.closed = c.closed;
  testing::clamp_if_needed(find_method(method), in);
  return in;
}

/// The registered methods, or those named in FAIRSPLINE_EXTREMES_METHODS (comma-separated; the
/// plug-in test runs the suite on its throw-away method alone).
std::vector<const MethodInfo*> under_test() {
  std::vector<const MethodInfo*> v;
  const char* only = std::getenv("FAIRSPLINE_EXTREMES_METHODS");
  std::string list = ",";
  if (only) list.append(only).append(",");
  for (const MethodInfo& m : methods()) {
    if (!only || list.find(',' + m.name + ',') != std::string::npos) v.push_back(&m);
  }
  return v;
}

std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

Case make_case(std::string name, std::vector<Point> points) {
  Case c;
  c.name = std::move(name);
  c.points = std::move(points);
  return c;
}

/// A case that may also end in an Error with one of `allowed`.
Case curve_or_error(std::string name, std::vector<Point> points, std::set<ErrorCode> allowed) {
  Case c = make_case(std::move(name), std::move(points));
  c.outcome = Outcome::kCurveOrError;
  c.allowed = std::move(allowed);
  return c;
}

FitInput input_of(std::vector<Point> points) {
  FitInput in;
  in.points = std::move(points);
  return in;
}

bool finite(Point p) {
  return std::isfinite(p.x) && std::isfinite(p.y);
}

void expect_finite_json(const json& j, const std::string& where) {
  if (j.is_number_float()) {
    EXPECT_TRUE(std::isfinite(j.get<double>())) << where;
  } else if (j.is_structured()) {
    for (const auto& [key, value] : j.items()) expect_finite_json(value, where + "/" + key);
  }
}

/// Everything a successful fit promises.
void check_curve(const std::string& where, const Case& c, const FitResult& r) {
  const bool regular_promised = promises_regularity(r.method);
  SCOPED_TRACE(where);
  ASSERT_FALSE(r.spline.segments.empty());
  const double scale = scale_of(c.points);
  for (const Segment& g : r.spline.segments) {
    for (const Point& p : g.bezier.p) ASSERT_TRUE(finite(p));
    ASSERT_TRUE(std::isfinite(g.t0) && std::isfinite(g.t1) && g.t1 > g.t0);
    // No piece stops at an end (a zero-length arm has zero speed there): the failure mode of
    // Theorem 6's right-angle rule that this suite found in jaklic-zagar.
    if (regular_promised) {
      const double chord = norm(g.bezier.p[3] - g.bezier.p[0]);
      EXPECT_GT(norm(g.bezier.p[1] - g.bezier.p[0]), 1e-12 * chord);
      EXPECT_GT(norm(g.bezier.p[3] - g.bezier.p[2]), 1e-12 * chord);
    }
  }
  for (const Vec2& t : r.tangents) EXPECT_NEAR(norm(t), 1.0, 1e-12);
  expect_finite_json(r.method_report, "method_report");
  if (!r.report) return;
  const Report& rep = *r.report;
  if (regular_promised) {
    EXPECT_TRUE(rep.regular) << "the report does not certify the curve regular";
    EXPECT_GT(rep.min_relative_speed, 0.0);
  } else if (!rep.regular && c.level == ReportLevel::kFull) {
    bool located = false;
    for (const SegmentReport& g : rep.segments) located = located || (!g.regular && g.has_cusp);
    EXPECT_TRUE(located) << "not regular, but no piece is flagged";
  }
  EXPECT_LE(rep.max_interpolation_residual, 1e-9 * scale);
  EXPECT_LT(rep.max_tangent_angle_jump_deg, c.g1_tolerance_deg);  // G1: no corners are given
  EXPECT_TRUE(std::isfinite(rep.linearized_energy));
  EXPECT_GE(rep.linearized_energy, 0.0);
  for (const auto& v : {rep.bending_energy, rep.curvature_variation_energy, rep.length}) {
    if (v) {
      EXPECT_TRUE(std::isfinite(*v) && *v >= 0.0);
    }
  }
  if (rep.length) {
    EXPECT_GT(*rep.length, 0.0);
  }
  // Optimizers cap their iterations and say whether they converged.
  if (r.method_report.contains("iterations") && r.options.contains("max_iterations")) {
    EXPECT_LE(r.method_report.at("iterations").get<int>(),
              r.options.at("max_iterations").get<int>());
  }
}

/// A clear error: a known code, a sentence without NaN/Inf in it, an index inside the input.
void check_error(const std::string& where, const Case& c, const Error& e) {
  SCOPED_TRACE(where);
  const std::string msg = e.what();
  EXPECT_GE(msg.size(), 20u) << msg;
  EXPECT_LE(msg.size(), 600u) << msg;
  for (const char* bad : {"nan", "-inf", " inf"})
    EXPECT_EQ(msg.find(bad), std::string::npos) << msg;
  if (e.index()) {
    EXPECT_LT(*e.index(), c.points.size()) << msg;
  }
}

void run_case(const Case& c) {
  for (const MethodInfo* mp : under_test()) {
    const MethodInfo& m = *mp;
    const std::string where = m.name + " on " + c.name;
    try {
      const FitResult r = fit(m.name, input_for(m.name, c), options_for(m.name), c.level);
      check_curve(where, c, r);
    } catch (const Error& e) {
      check_error(where, c, e);
      if (c.error_index && e.code() == c.error_index->first) {
        EXPECT_EQ(e.index(), c.error_index->second) << where << ": " << e.what();
      }
      if (structurally_excluded(m.name, c, e.code())) continue;
      const bool allowed = c.outcome == Outcome::kCurveOrError && c.allowed.count(e.code()) > 0;
      EXPECT_TRUE(allowed) << where << ": unexpected " << error_code_name(e.code()) << ": "
                           << e.what();
    }
  }
}

Case closed_copy(Case c) {
  c.closed = true;
  c.name += " (closed)";
  return c;
}

// ---- scale ----

TEST(Extremes, HugeCoordinates) {
  for (double s : {1e150, 1e300}) {
    Case c = make_case("wave x" + sci(s), wave(s));
    run_case(c);
    run_case(closed_copy(c));
  }
}

TEST(Extremes, TinyCoordinatesBasicReport) {
  // The curve is representable at every scale; only the full report's curvature-variation
  // energy (∝ 1/scale³) is not, below ~1e-103 (next test).
  for (double s : {1e-150, 1e-300}) {
    Case c = make_case("wave x" + sci(s), wave(s));
    c.level = ReportLevel::kBasic;
    run_case(c);
    run_case(closed_copy(c));
  }
}

TEST(Extremes, TinyCoordinatesFullReportSaysWhatOverflows) {
  Case c = make_case("wave x1e-300, full report", wave(1e-300));
  for (const MethodInfo* mp : under_test()) {
    const MethodInfo& m = *mp;
    SCOPED_TRACE(m.name);
    const Error e = testing::expect_error(ErrorCode::kNonFinite, [&] {
      fit(m.name, input_for(m.name, c), options_for(m.name), ReportLevel::kFull);
    });
    EXPECT_NE(std::string(e.what()).find("curvature-variation energy"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("basic report"), std::string::npos);
  }
  // At 1e-90 everything is representable and the energies scale as the theory says.
  const FitResult unit = fit("quasi-elastic", input_of(wave(1.0)));
  const FitInput tiny = input_of(wave(0x1p-300));
  const FitResult small = fit("quasi-elastic", tiny);
  EXPECT_NEAR(*small.report->length, std::ldexp(*unit.report->length, -300),
              1e-12 * std::ldexp(*unit.report->length, -300));
  EXPECT_NEAR(*small.report->bending_energy, std::ldexp(*unit.report->bending_energy, 300),
              1e-12 * std::ldexp(*unit.report->bending_energy, 300));
  EXPECT_NEAR(small.report->min_relative_speed, unit.report->min_relative_speed, 1e-12);
}

TEST(Extremes, ReportIsScaleEquivariant) {
  // Scaling the points by 2^k scales the curve exactly; the report scales as its dimensions:
  // length ∝ s, bending ∝ 1/s, curvature variation ∝ 1/s³, linearized energy ∝ s^(2 − 3α).
  const FitInput base = input_of(wave(1.0));
  const FitResult r1 = fit("li-strain", base, json::object(), ReportLevel::kFull);
  for (int k : {-900, -300, 300, 1000}) {
    SCOPED_TRACE(k);
    FitInput in = base;
    for (Point& p : in.points) p = {std::ldexp(p.x, k), std::ldexp(p.y, k)};
    const ReportLevel level = k < -340 ? ReportLevel::kBasic : ReportLevel::kFull;
    const FitResult r = fit("li-strain", in, json::object(), level);
    const double s = std::ldexp(1.0, k);
    EXPECT_NEAR(r.report->linearized_energy / std::pow(s, 0.5), r1.report->linearized_energy,
                1e-12 * r1.report->linearized_energy);
    EXPECT_NEAR(std::ldexp(*r.report->length, -k), *r1.report->length, 1e-12 * *r1.report->length);
    EXPECT_NEAR(std::ldexp(*r.report->bending_energy, k), *r1.report->bending_energy,
                1e-12 * *r1.report->bending_energy);
    if (level == ReportLevel::kFull) {
      if (k == 300) {  // 2^-3000 at k = 1000 underflows to 0, its nearest double
        EXPECT_NEAR(std::ldexp(*r.report->curvature_variation_energy, 3 * k),
                    *r1.report->curvature_variation_energy,
                    1e-12 * *r1.report->curvature_variation_energy);
      }
    }
    EXPECT_EQ(r.report->regular, r1.report->regular);
    EXPECT_NEAR(r.report->min_relative_speed, r1.report->min_relative_speed, 1e-12);
  }
}

TEST(Extremes, ReportOfPiecesOfVeryDifferentSizes) {
  // Each piece's energies are integrated at its own scale (exactly rescaled by a power of two):
  // in one curve with pieces of size 2^-300 and 2^300, each piece's bending energy, length and
  // curvature variation equal those of the same piece scaled to unit size, scaled back.
  const FitInput in =
      input_of({{0, 0}, {0x1p-300, 0x1p-301}, {0x1p-299, 0}, {0x1p300, 0x1p299}, {0x1p301, 0}});
  const FitResult r = fit("jaklic-zagar", in, json::object(), ReportLevel::kFull);
  ASSERT_TRUE(r.report);
  EXPECT_TRUE(r.report->regular);
  for (std::size_t k : {std::size_t{0}, std::size_t{3}}) {
    SCOPED_TRACE(k);
    const int ex = k == 0 ? -300 : 300;
    CubicBezier unit_piece;
    const CubicBezier& b = r.spline.segments[k].bezier;
    for (int j = 0; j < 4; ++j)
      unit_piece.p[j] = {std::ldexp(b.p[j].x - b.p[0].x, -ex),
                         std::ldexp(b.p[j].y - b.p[0].y, -ex)};
    const SegmentReport& g = r.report->segments[k];
    const double bend = bending_energy(unit_piece).value, len = arc_length(unit_piece).value;
    EXPECT_NEAR(std::ldexp(g.bending_energy, ex), bend, 1e-12 * bend);
    EXPECT_NEAR(std::ldexp(g.length, -ex), len, 1e-12 * len);
    if (k == 3) {
      const double var = curvature_variation_energy(unit_piece).value;
      EXPECT_NEAR(std::ldexp(g.curvature_variation_energy, 3 * ex), var, 1e-12 * var);
    }
  }
}

TEST(Extremes, ChordsBeyondTheDoubleRange) {
  // Chord lengths between ±DBL_MAX overflow (uniform knots do not): a valid curve or a clear
  // Error for every method and knot exponent (min-energy took ilogb(0) = INT_MIN and negated
  // it: undefined behaviour found by fuzz_fit).
  const double big = std::numeric_limits<double>::max();
  for (double alpha : {0.0, 0.5, 1.0}) {
    for (bool closed : {false, true}) {
      Case c =
          make_case("chords beyond DBL_MAX", {{0.2, 13.8}, {big, big}, {0.2, 13.8}, {-big, big}});
      c.closed = closed;
      for (const MethodInfo* mp : under_test()) {
        const MethodInfo& m = *mp;
        SCOPED_TRACE(m.name + " alpha " + sci(alpha) + (closed ? " closed" : ""));
        FitInput in = input_for(m.name, c);
        in.alpha = alpha;
        try {
          check_curve(m.name, c, fit(m.name, in, options_for(m.name)));
        } catch (const Error& e) {
          check_error(m.name, c, e);
        }
      }
    }
  }
}

TEST(Extremes, MixedScales) {
  // Chords from 1e-8 to 1e8 in one input (ratio 1e16).
  std::vector<Point> p;
  for (int i = 0; i < 6; ++i) p.push_back({1e-8 * i, 1e-8 * (i % 2)});
  for (int i = 1; i < 8; ++i) p.push_back({1e8 * i, 1e8 * std::sin(i)});
  const Case c = curve_or_error(
      "chords 1e-8 .. 1e8", p,
      {ErrorCode::kSingularSystem, ErrorCode::kInfeasible, ErrorCode::kNotConverged});
  run_case(c);
  run_case(closed_copy(c));
}

// ---- degenerate geometry ----

TEST(Extremes, NearlyCollinearPoints) {
  // A line with perpendicular offsets of 1e-15 relative to the coordinates.
  std::vector<Point> p;
  for (int i = 0; i < 19; ++i) p.push_back({100.0 * i, (i % 3 == 1 ? 1e-15 * 100.0 * i : 0.0)});
  run_case(make_case("nearly collinear", p));
}

TEST(Extremes, NearlyRepeatedPoints) {
  // Two consecutive points 1e-15 apart relative to the coordinates: a regular curve or
  // Error(repeated_point) naming the second one.
  for (double rel : {1e-15, 1e-13}) {
    std::vector<Point> p = wave(1.0);
    p.insert(p.begin() + 10, p[9] + Vec2{rel * scale_of(p), 0.5 * rel * scale_of(p)});
    Case c = curve_or_error(
        "nearly repeated " + sci(rel), p,
        {ErrorCode::kRepeatedPoint, ErrorCode::kInfeasible, ErrorCode::kSingularSystem});
    c.g1_tolerance_deg = 10.0;
    c.error_index = {ErrorCode::kRepeatedPoint, 10};
    run_case(c);
  }
}

TEST(Extremes, ExactReversal) {
  // (0,0) → (2,0) → (1,0): a 180° turn at point 1. A regular curve or Error(reversal) at 1.
  const std::vector<Point> p{{0, 0}, {2, 0}, {1, 0}, {1, 1}, {2, 2}, {3, 2}, {4, 3}};
  Case c =
      curve_or_error("exact reversal", p,
                     {ErrorCode::kReversal, ErrorCode::kInvalidArgument, ErrorCode::kInfeasible});
  c.error_index = {ErrorCode::kReversal, 1};
  run_case(c);
}

TEST(Extremes, ZeroTurnsGiveAStraightCurve) {
  std::vector<Point> p;
  for (int i = 0; i < 10; ++i) p.push_back({3.0 * i, 2.0 * i});
  const Case c = make_case("straight line", p);
  run_case(c);
  for (const MethodInfo* mp : under_test()) {
    const MethodInfo& m = *mp;
    try {
      const FitResult r = fit(m.name, input_for(m.name, c), options_for(m.name));
      for (const Segment& g : r.spline.segments)
        for (const Point& q : g.bezier.p) EXPECT_NEAR(cross(q, Vec2{3, 2}), 0.0, 1e-12) << m.name;
    } catch (const Error& e) {
      EXPECT_TRUE(structurally_excluded(m.name, c, e.code())) << m.name << ": " << e.what();
    }
  }
}

TEST(Extremes, LongStraightRunsAndRightAngles) {
  // A staircase on the integer grid: runs of 200 collinear points, exact right-angle turns.
  std::vector<Point> p{{0, 0}};
  for (int step = 0; step < 4; ++step) {
    const Vec2 d = step % 2 == 0 ? Vec2{1, 0} : Vec2{0, 1};
    for (int i = 0; i < 200; ++i) p.push_back(p.back() + d);
  }
  run_case(make_case("straight runs", p));
}

TEST(Extremes, PointsExactlyOnACircle) {
  std::vector<Point> p;
  for (int i = 0; i < 24; ++i) p.push_back(from_angle(2.0 * std::numbers::pi * i / 24.0));
  const Case open = make_case("circle", p);
  run_case(open);
  run_case(closed_copy(open));
  // The curves stay close to the circle (15° arcs: every method is within 1% of the radius).
  for (const MethodInfo* mp : under_test()) {
    const MethodInfo& m = *mp;
    for (bool closed : {false, true}) {
      Case c = open;
      c.closed = closed;
      try {
        const FitResult r = fit(m.name, input_for(m.name, c), options_for(m.name));
        for (const Segment& g : r.spline.segments)
          for (double u = 0.0; u <= 1.0; u += 0.125)
            EXPECT_NEAR(norm(g.bezier.eval(u)), 1.0, 0.01) << m.name << (closed ? " closed" : "");
      } catch (const Error& e) {
        EXPECT_TRUE(structurally_excluded(m.name, c, e.code())) << m.name << ": " << e.what();
      }
    }
  }
}

// ---- size and work ----

TEST(Extremes, AMillionPoints) {
  // 10^6 = 3·333333 + 1 points of a gentle wave: every method, basic report. Work is O(n) for
  // every method (bench/scaling_bench.cpp measures the slope); here it must simply finish.
  // Without diagnostics: a million per-point entries in method_report cost up to 15× the fit.
  std::vector<Point> p;
  p.reserve(1000000);
  for (int i = 0; i < 1000000; ++i) p.push_back({0.5 * i, std::sin(0.05 * i)});
  Case c = make_case("10^6 points", p);
  c.level = ReportLevel::kBasic;
  for (const MethodInfo* mp : under_test()) {
    const MethodInfo& m = *mp;
    SCOPED_TRACE(m.name);
    const FitResult r = fit(m.name, input_for(m.name, c), options_for(m.name),
                            FitOptions{.level = c.level, .diagnostics = false});
    EXPECT_EQ(r.points.size(), p.size());
    EXPECT_LT(r.method_report.dump().size(), 2000u);
    EXPECT_TRUE(r.report->regular);
    EXPECT_LE(r.report->max_interpolation_residual, 1e-9 * scale_of(p));
  }
}

TEST(Extremes, IterationCapsStopOptimizers) {
  // Every integer option whose name says it limits iterations, on every example request (and a
  // random walk) whose solver needs more than one iteration: a cap of 1 stops the solver, which
  // says so — Error(not_converged) naming the iterations, or with a best effort the curve with
  // SolverStatus::kIterationLimit in FitResult::solver.
  const std::vector<Point> walk = testing::random_walk(400, 5, 150);
  int checked = 0;
  for (const MethodInfo* mp : under_test()) {
    const MethodInfo& m = *mp;
    std::vector<std::pair<FitInput, json>> requests;
    for (const std::string& e : m.capabilities.examples) {
      const io::ParsedInput p = io::parse_json_input(e);
      requests.emplace_back(p.input, p.options);
    }
    requests.emplace_back(input_of(walk), options_for(m.name));
    for (const OptionSpec& o : m.options) {
      if (o.type != OptionType::kInteger || o.name.find("iterations") == std::string::npos)
        continue;
      for (auto& [in, options] : requests) {
        FitResult full;
        try {
          full = fit(m.name, in, options);
        } catch (const Error&) {
          continue;  // (the walk is not for every method)
        }
        if (!full.solver || full.solver->iterations <= 1) continue;
        SCOPED_TRACE(m.name + " " + o.name + " " + json(options).dump());
        EXPECT_EQ(full.solver->status, SolverStatus::kConverged);
        EXPECT_LE(full.solver->residual, full.solver->tolerance);
        // (max_iterations unset: its default, these requests having no data balls)
        EXPECT_LE(full.solver->iterations, full.options.contains(o.name)
                                               ? full.options.at(o.name).get<int>()
                                               : MinEnergyOptions::kDefaultIterations);
        options[o.name] = 1;
        const Error e =
            testing::expect_error(ErrorCode::kNotConverged, [&] { fit(m.name, in, options); });
        EXPECT_NE(std::string(e.what()).find("after 1 iterations"), std::string::npos) << e.what();
        const FitResult capped =
            fit(m.name, in, options, FitOptions{.level = ReportLevel::kFull, .best_effort = true});
        ASSERT_TRUE(capped.solver.has_value());
        EXPECT_EQ(capped.solver->status, SolverStatus::kIterationLimit);
        EXPECT_EQ(capped.solver->iterations, 1);
        EXPECT_GT(capped.solver->residual, capped.solver->tolerance);
        check_curve(m.name, make_case("capped", in.points), capped);
        ++checked;
        break;
      }
    }
  }
  // Every registered method with an iteration cap was checked on one of its requests.
  if (std::getenv("FAIRSPLINE_EXTREMES_METHODS") == nullptr) {
    EXPECT_GE(checked, 4);
  }
}

// ---- tangents at the extremes (Hermite methods) ----

TEST(Extremes, GivenTangentsOfExtremeLength) {
  // Hermite methods use only the directions; yong-cheng's report rescales the coefficients to
  // the given vectors and must stay finite for lengths from 1e-300 to DBL_MAX (found by
  // fuzz_fit).
  const std::vector<Point> p = wave(1.0);
  for (const MethodInfo* mp : under_test()) {
    if (mp->capabilities.tangents != TangentUse::kRequired) continue;
    for (double len : {1e-300, 1.0, 1e300, std::numeric_limits<double>::max()}) {
      SCOPED_TRACE(mp->name + " " + sci(len));
      FitInput in = input_of(p);
      for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec2 d = p[std::min(i + 1, p.size() - 1)] - p[i > 0 ? i - 1 : 0];
        in.tangents.push_back((d / std::max(std::abs(d.x), std::abs(d.y))) * len);
      }
      const FitResult r = fit(mp->name, in);
      check_curve(mp->name, make_case("tangents", p), r);
      if (!r.method_report.contains("spans")) continue;
      for (const json& span : r.method_report.at("spans")) {
        EXPECT_TRUE(span.at("theta_deg").is_number());
        EXPECT_TRUE(span.at("phi_deg").is_number());
        for (const json& ab : span.at("coefficients"))
          for (const json& a : ab) EXPECT_GT(a.get<double>(), 0.0);
      }
    }
  }
}

// ---- messages ----

TEST(Extremes, ErrorMessagesPrintNumbersShortly) {
  // Numbers in messages are the shortest text that reads back as the same double: 1e308 was
  // 309 digits and 1e-7 "0.000000" with std::to_string.
  const FitInput in = input_of({{0, 0}, {1e308, 1e-7}, {1e308, 1e-7}, {2, 0}});
  const Error e = testing::expect_error(ErrorCode::kRepeatedPoint, [&] { fit("jaklic-zagar", in); },
                                        {"point 2 (1e+308, 1e-07) repeats point 1"});
  EXPECT_LT(std::string(e.what()).size(), 100u) << e.what();
  FitInput bad_alpha = input_of(wave(1.0));
  bad_alpha.alpha = -1e-300;
  testing::expect_error(ErrorCode::kBadOption, [&] { fit("li-strain", bad_alpha); }, {"-1e-300"});
}

}  // namespace
}  // namespace fairspline
