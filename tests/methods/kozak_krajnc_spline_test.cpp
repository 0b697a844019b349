// Tests of the Kozak–Krajnc spline (src/methods/kozak_krajnc_spline.cpp): the parameterization
// (4.1)–(4.3), the maps R1, R2, the sweeps against a brute force over a fine ξ grid, the method's
// output properties, options and errors.
#include "fairspline/methods/kozak_krajnc_spline.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "fairspline/error.hpp"
#include "fairspline/methods/kozak_krajnc.hpp"
#include "fairspline/registry.hpp"
#include "stress/kkt.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

double D(const std::vector<Point>& T, std::size_t i, std::size_t j) {
  return cross(T[i + 1] - T[i], T[j + 1] - T[j]);
}
double sgn(double x) {
  return x > 0 ? 1.0 : -1.0;
}

/// A gently turning walk of 3m+1 points (convex stretches and inflections).
std::vector<Point> wavy(std::size_t m, std::uint64_t seed, double max_turn_deg = 50) {
  return testing::random_walk(3 * m + 1, seed, max_turn_deg);
}

TEST(KozakKrajncSpline, ParameterizationMatches42And43) {
  // μ and δ of (2.6) computed from the directions (4.1) agree with the closed forms (4.2),
  // (4.3) as functions of ξ.
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const auto T = wavy(3, seed, 80);
    const std::size_t m = 3;
    for (double xi : {0.1, 0.37, 0.5, 0.81}) {
      for (std::size_t l = 1; l <= m; ++l) {
        const std::size_t k = 3 * l - 3;
        const Vec2 dl = kozak_krajnc_direction(T, l - 1, xi), dr = kozak_krajnc_direction(T, l, xi);
        const KozakKrajncConstants c =
            kozak_krajnc_constants(T[k], T[k + 1], T[k + 2], T[k + 3], dl, dr);
        // Left end of piece ℓ: breakpoint ℓ−1.
        if (l == 1) {
          EXPECT_NEAR(c.mu1, xi / (1 - xi), 1e-12 * (1 + std::abs(c.mu1)));
          EXPECT_NEAR(c.delta1, 1 / (1 - xi), 1e-12 * (1 + c.delta1));
        } else {
          const double sigma = sgn(D(T, k - 2, k - 1) / D(T, k - 1, k));  // σ3ℓ−4
          const double delta = std::abs(D(T, k, k + 1) / D(T, k - 1, k)) / (1 - xi);
          EXPECT_NEAR(c.delta1, delta, 1e-12 * (1 + delta));
          const double mu = sigma * xi * delta + D(T, k - 1, k + 1) / D(T, k - 1, k);
          EXPECT_NEAR(c.mu1, mu, 1e-11 * (1 + std::abs(mu)));
        }
        // Right end: breakpoint ℓ.
        if (l == m) {
          EXPECT_NEAR(c.mu2, (1 - xi) / xi, 1e-12 * (1 + c.mu2));
          EXPECT_NEAR(c.delta2, 1 / xi, 1e-12 * (1 + c.delta2));
        } else {
          const std::size_t j = 3 * l;
          const double sigma = sgn(D(T, j - 1, j) / D(T, j, j + 1));  // σ3ℓ
          const double delta = std::abs(D(T, j - 2, j - 1) / D(T, j - 1, j)) / xi;
          EXPECT_NEAR(c.delta2, delta, 1e-12 * (1 + delta));
          const double mu = sigma * (1 - xi) * delta + D(T, j - 2, j) / D(T, j - 1, j);
          EXPECT_NEAR(c.mu2, mu, 1e-11 * (1 + std::abs(mu)));
        }
        EXPECT_GT(c.delta1, 0);
        EXPECT_GT(c.delta2, 0);
      }
      // kozak_krajnc_xi_of inverts (4.1).
      for (std::size_t l = 0; l <= m; ++l) {
        const auto back = kozak_krajnc_xi_of(T, l, 3.0 * kozak_krajnc_direction(T, l, xi));
        ASSERT_TRUE(back);
        EXPECT_NEAR(*back, xi, 1e-12);
      }
    }
  }
}

TEST(KozakKrajncSpline, R1AndR2AreTheUnionsOfTheorem25Bands) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> pos(0.1, 5), neg(-5, -0.1), mu(0.0, 6), unit(0, 1);
  for (int trial = 0; trial < 300; ++trial) {
    const double l1 = pos(rng), l2 = neg(rng);
    double a = mu(rng), b = a + mu(rng);
    // R1: μ2 has a partner μ1 ∈ (a, b) with φ3(μ1) < μ2 < φ4(μ1).
    const auto r1 = kozak_krajnc_r1({a, b, false}, l1, l2);
    ASSERT_TRUE(r1);
    for (int s = 0; s < 50; ++s) {
      const double m1 = a + (b - a) * (0.001 + 0.998 * unit(rng));
      const double lo = kozak_krajnc_phi3(l1, l2, m1), hi = kozak_krajnc_phi4(l1, l2, m1);
      const double m2 = lo + (hi - lo) * unit(rng);
      EXPECT_TRUE(r1->lo <= m2 && m2 <= r1->hi);
    }
    EXPECT_NEAR(r1->lo, kozak_krajnc_phi3(l1, l2, a), 1e-12);
    EXPECT_NEAR(r1->hi, kozak_krajnc_phi4(l1, l2, b), 1e-12 * (1 + r1->hi));
    // R2: every μ1 in R2((a2, b2)) has a partner μ2 ∈ (a2, b2), and no μ1 outside does.
    const double a2 = 0.5 * mu(rng) / l1, b2 = a2 + 0.5 * mu(rng) / l1;
    const auto r2 = kozak_krajnc_r2({a2, b2, false}, l1, l2);
    for (int s = 0; s < 200; ++s) {
      const double m1 = 0.01 + 20 * unit(rng);
      const double lo = kozak_krajnc_phi3(l1, l2, m1), hi = kozak_krajnc_phi4(l1, l2, m1);
      const bool partner = std::max(lo, a2) < std::min(hi, b2);
      const bool in = r2 && r2->lo < m1 && m1 < r2->hi;
      const double margin = r2 ? std::min(std::abs(m1 - r2->lo), std::abs(m1 - r2->hi)) : 1;
      if (margin > 1e-9) {
        EXPECT_EQ(partner, in) << l1 << " " << l2 << " " << a2 << " " << b2;
      }
    }
  }
  EXPECT_FALSE(kozak_krajnc_r1({-1, 0, false}, 1, -1));
  EXPECT_FALSE(kozak_krajnc_r2({3.5, 4, false}, 1, -1));  // a ≥ (1 + 2λ1)/λ1² = 3
}

/// Brute force over a ξ grid: does an admissible choice (ξ0, ..., ξm) exist on the grid? Uses
/// only the theorem predicates on directions (no Möbius maps, no R1/R2, no sweeps).
bool grid_has_solution(const std::vector<Point>& T, int N) {
  const std::size_t m = (T.size() - 1) / 3;
  std::vector<double> grid(N);
  for (int i = 0; i < N; ++i) grid[i] = (i + 0.5) / N;
  std::vector<char> reach(N, 1);
  for (std::size_t l = 1; l <= m; ++l) {
    std::vector<char> next(N, 0);
    for (int i = 0; i < N; ++i) {
      if (!reach[i]) continue;
      for (int j = 0; j < N; ++j) {
        if (next[j]) continue;
        if (kozak_krajnc_piece_admissible(T, l, grid[i], grid[j])) next[j] = 1;
      }
    }
    reach.swap(next);
  }
  for (char r : reach) {
    if (r) return true;
  }
  return false;
}

TEST(KozakKrajncSpline, SweepsAgreeWithBruteForceOnAGrid) {
  // Small inflecting data: the sweeps either succeed with a choice that the theorems admit on
  // every piece, or declare the data infeasible, in which case a 60×60 grid has no admissible
  // choice either.
  int feasible = 0, infeasible = 0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    const auto T = testing::random_walk(7, 1000 + seed, 100);
    try {
      const KozakKrajncSweep s = kozak_krajnc_sweep(T);
      const std::vector<double> xi = kozak_krajnc_select(T, s, 0.5);
      for (std::size_t l = 1; l <= 2; ++l) {
        EXPECT_TRUE(kozak_krajnc_piece_admissible(T, l, xi[l - 1], xi[l])) << seed << " " << l;
      }
      ++feasible;
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kInfeasible) continue;  // assumptions of Theorem 4.1 fail
      EXPECT_FALSE(grid_has_solution(T, 60)) << seed << ": " << e.what();
      ++infeasible;
    }
  }
  EXPECT_GT(feasible, 10);
  EXPECT_GT(infeasible, 3);
}

TEST(KozakKrajncSpline, EveryChoiceFromTheSweptSetsIsAdmissibleInTheConvexCase) {
  // Corollary 4.2: for convex data any ξℓ ∈ Ξℓ of one branch is admissible. With branches
  // merged, the selection step keeps the choice consistent; check random γ.
  const auto T = testing::ellipse(13);
  std::vector<Point> open(T.begin(), T.begin() + 10);
  const KozakKrajncSweep s = kozak_krajnc_sweep(open);
  for (double gamma : {0.05, 0.3, 0.5, 0.77, 0.95}) {
    const std::vector<double> xi = kozak_krajnc_select(open, s, gamma);
    for (std::size_t l = 1; l <= 3; ++l) {
      EXPECT_TRUE(kozak_krajnc_piece_admissible(open, l, xi[l - 1], xi[l]));
    }
  }
}

/// Checks the properties every kozak-krajnc result must have: the segments of span i run from
/// point i to point i+1 (one segment, or several for a composite remainder span), G1 joins
/// everywhere, a regular curve.
void expect_valid(const FitResult& r, double tol = 1e-12) {
  const std::size_t n = r.points.size();
  const auto& segs = r.spline.segments;
  ASSERT_GE(segs.size(), n - 1);
  const double size = testing::scale_of(r.points);
  for (std::size_t k = 0; k < segs.size(); ++k) {
    const std::size_t i = segs[k].span;
    const CubicBezier& c = segs[k].bezier;
    if (k == 0 || segs[k - 1].span != i) {
      EXPECT_LT(norm(c.p[0] - r.points[i]), tol * size) << k;
    }
    if (k + 1 == segs.size() || segs[k + 1].span != i) {
      EXPECT_LT(norm(c.p[3] - r.points[i + 1]), tol * size) << k;
    }
    if (k > 0) {  // G1: same direction at the joint
      const Vec2 a = segs[k - 1].bezier.d1(1.0), b = c.d1(0.0);
      EXPECT_LT(std::abs(cross(a, b)) / (norm(a) * norm(b)), 1e-9) << k;
      EXPECT_GT(dot(a, b), 0) << k;
    }
  }
  EXPECT_EQ(segs.back().span, n - 2);
  EXPECT_TRUE(r.report->regular);
}

TEST(KozakKrajncSpline, PropertyPiecesInterpolateAndJoinG1) {
  int fitted = 0;
  for (std::uint64_t seed = 1; seed <= 150; ++seed) {
    FitInput in;
    in.points = wavy(1 + seed % 6, seed, 45);
    FitResult r;
    try {
      r = fit("kozak-krajnc", in);
    } catch (const Error& e) {
      EXPECT_TRUE(e.code() == ErrorCode::kInfeasible || e.code() == ErrorCode::kInvalidArgument)
          << e.what();
      continue;
    }
    ++fitted;
    expect_valid(r);
    const auto& segs = r.method_report.at("segments");
    for (const auto& s : segs) {
      EXPECT_GT(s.at("alpha0").get<double>(), 0);
      EXPECT_GT(s.at("alpha3").get<double>(), 0);
      const double t1 = s.at("t1").get<double>(), t2 = s.at("t2").get<double>();
      EXPECT_TRUE(0 < t1 && t1 < t2 && t2 < 1);
      EXPECT_GE(s.at("solutions").size(), 1u);
    }
    EXPECT_LT(r.report->max_interpolation_residual, 1e-12 * testing::scale_of(r.points));
  }
  EXPECT_GT(fitted, 60);
}

TEST(KozakKrajncSpline, SinglePieceWithClampedEndsIsTheSolver) {
  // m = 1 with both ends clamped is the single-piece problem: paper data 3 (s = 0).
  FitInput in;
  in.points = {{-4, -4}, {0, 0}, {4, 0}, {10, 4}};
  in.start_tangent = Vec2{-2, 2};
  in.end_tangent = Vec2{-1, 2};
  const FitResult r = fit("kozak-krajnc", in);
  const auto& seg = r.method_report.at("segments").at(0);
  const KozakKrajncSolutions direct =
      kozak_krajnc_solve(in.points[0], in.points[1], in.points[2], in.points[3], {-2, 2}, {-1, 2});
  ASSERT_EQ(direct.count, 1);
  EXPECT_NEAR(seg.at("t1").get<double>(), direct.items[0].t1, 1e-14);
  EXPECT_NEAR(seg.at("t2").get<double>(), direct.items[0].t2, 1e-14);
  // α relative to unit directions: |d0| = 2√2.
  EXPECT_NEAR(seg.at("alpha0").get<double>(), direct.items[0].alpha0 * 2 * std::sqrt(2.0), 1e-10);
  expect_valid(r);
}

TEST(KozakKrajncSpline, AllDirectionsPrescribedSolvesEachPieceExactly) {
  // With every breakpoint direction given there are no sweeps: the piece is solved whatever the
  // direction, even outside the cone (4.1) (then the theorems say nothing, the solver decides).
  const std::vector<Point> T{{0, 0}, {1, 1}, {2, 1.5}, {3, 1}};
  const Vec2 d3{1, -2};
  int outside = 0;
  for (int k = 0; k < 360 && outside == 0; ++k) {
    const Vec2 d0 = from_angle(k * std::numbers::pi / 180);
    if (kozak_krajnc_xi_of(T, 0, d0)) continue;
    const KozakKrajncSolutions s = kozak_krajnc_solve(T[0], T[1], T[2], T[3], d0, d3);
    FitInput in;
    in.points = T;
    in.start_tangent = d0;
    in.end_tangent = d3;
    if (s.count == 0) {
      const Error e = testing::expect_error([&] { fit("kozak-krajnc", in); });
      EXPECT_EQ(e.code(), ErrorCode::kInfeasible);
      EXPECT_NE(std::string(e.what()).find("piece 1"), std::string::npos);
      continue;
    }
    ++outside;
    const FitResult r = fit("kozak-krajnc", in);
    expect_valid(r);
    EXPECT_FALSE(r.method_report.at("sweeps").get<bool>());
    EXPECT_NEAR(r.method_report.at("segments").at(0).at("t1").get<double>(), s.items[s.chosen].t1,
                1e-14);
  }
  EXPECT_EQ(outside, 1);  // found such a direction
}

TEST(KozakKrajncSpline, ConvexIsReportedWhenEveryDirectionIsGiven) {
  // Regression: segments[].convex (λ1, λ2 > 0) was false whenever every direction was given (no
  // sweeps), even for convex data. λ from the points alone (D02/D01, D02/D12).
  auto convex_of = [](const std::vector<Point>& T, std::size_t k) {
    return D(T, k, k + 2) / D(T, k, k + 1) > 0 && D(T, k, k + 2) / D(T, k + 1, k + 2) > 0;
  };
  FitInput in;
  // The paper's data 1 (λ = 2, 2: convex) and data 3 (λ = 1/2, −1/2: an inflection), one piece.
  in.points = {{-4, -4}, {0, 0}, {4, 0}, {8, -4}};
  in.start_tangent = Vec2{2, 3};
  in.end_tangent = Vec2{2, -3};
  FitResult r = fit("kozak-krajnc", in);
  EXPECT_FALSE(r.method_report.at("sweeps").get<bool>());
  EXPECT_TRUE(r.method_report.at("segments").at(0).at("convex").get<bool>());
  in.points = {{-4, -4}, {0, 0}, {4, 0}, {10, 4}};
  in.start_tangent = Vec2{-2, 2};
  in.end_tangent = Vec2{-1, 2};
  r = fit("kozak-krajnc", in);
  EXPECT_FALSE(r.method_report.at("segments").at(0).at("convex").get<bool>());
  // Three pieces of a walk turning left by 0.3 rad at T1..T7 and right by 0.6 at T8 (pieces 1, 2
  // convex, an inflection in piece 3), with the directions the sweeps chose given at every
  // breakpoint: the same flags with and without sweeps.
  std::vector<Point> T{{0, 0}};
  for (int i = 0; i < 9; ++i)
    T.push_back(T.back() + from_angle(0.3 * std::min(i, 7) - (i == 8 ? 0.6 : 0.0)));
  in = FitInput{};
  in.points = T;
  const FitResult swept = fit("kozak-krajnc", in);
  in.tangents.assign(T.size(), std::nullopt);
  for (std::size_t i = 0; i < T.size(); i += 3) in.tangents[i] = swept.tangents[i];
  const FitResult given = fit("kozak-krajnc", in);
  EXPECT_FALSE(given.method_report.at("sweeps").get<bool>());
  for (std::size_t l = 0; l < 3; ++l) {
    const bool expected = convex_of(T, 3 * l);
    EXPECT_EQ(expected, l < 2) << l;
    EXPECT_EQ(given.method_report.at("segments").at(l).at("convex").get<bool>(), expected) << l;
    EXPECT_EQ(swept.method_report.at("segments").at(l).at("convex").get<bool>(), expected) << l;
  }
}

TEST(KozakKrajncSpline, ExtremeScalesGiveTheSameCurveScaled) {
  // The constants (2.6) multiply chord coordinates; the method and the solver work on data
  // scaled by powers of two, so 1e±300 data give the same curve (and α ∝ scale).
  const std::vector<Point> base{{0, 0}, {1, 1}, {2, 1.5}, {3, 1.6}, {4, 1.5}, {5, 1}, {6, 0}};
  FitInput in;
  in.points = base;
  const FitResult ref = fit("kozak-krajnc", in, {}, ReportLevel::kNone);
  for (double sc : {1e-300, 1e-150, 1e150, 1e300}) {
    in.points.clear();
    for (Point p : base) in.points.push_back(sc * p);
    const FitResult r = fit("kozak-krajnc", in, {}, ReportLevel::kNone);
    ASSERT_EQ(r.spline.segments.size(), ref.spline.segments.size());
    for (std::size_t k = 0; k < r.spline.segments.size(); ++k) {
      for (int j = 0; j < 4; ++j) {
        const Point a = r.spline.segments[k].bezier.p[j], b = ref.spline.segments[k].bezier.p[j];
        EXPECT_NEAR(a.x / sc, b.x, 1e-12) << sc;
        EXPECT_NEAR(a.y / sc, b.y, 1e-12) << sc;
      }
    }
    const KozakKrajncSolutions a = kozak_krajnc_solve(sc * base[0], sc * base[1], sc * base[2],
                                                      sc * base[3], {1, 2}, {1, -0.3});
    const KozakKrajncSolutions b =
        kozak_krajnc_solve(base[0], base[1], base[2], base[3], {1, 2}, {1, -0.3});
    ASSERT_GE(b.count, 1);
    ASSERT_EQ(a.count, b.count) << sc;
    for (int i = 0; i < a.count; ++i) {
      EXPECT_NEAR(a.items[i].t1, b.items[i].t1, 1e-14);
      EXPECT_NEAR(a.items[i].alpha0 / sc, b.items[i].alpha0, 1e-12 * b.items[i].alpha0);
    }
  }
}

TEST(KozakKrajncSpline, G2NewtonRemovesTheCurvatureJumps) {
  // Ten points on an ellipse x = 3 cos, y = sin, sampled every 24 or 30 degrees.
  for (std::size_t n : {12u, 15u}) {
    const auto E = testing::ellipse(n, 3, 1);
    FitInput in;
    in.points.assign(E.begin(), E.begin() + 10);
    const FitResult g1 = fit("kozak-krajnc", in, {{"tangents", "local-quadratic-uniform"}});
    const FitResult g2 =
        fit("kozak-krajnc", in, {{"tangents", "local-quadratic-uniform"}, {"g2", true}});
    const auto& rep = g2.method_report.at("g2");
    ASSERT_TRUE(rep.at("converged").get<bool>()) << rep.dump();
    EXPECT_EQ(rep.at("start"), "g1");
    expect_valid(g2);
    for (std::size_t l = 1; l < 3; ++l) {
      const std::size_t i = 3 * l;
      const double kl = g2.spline.segments[i - 1].bezier.curvature(1.0);
      const double kr = g2.spline.segments[i].bezier.curvature(0.0);
      EXPECT_NEAR(kl, kr, 1e-8 * std::abs(kl)) << l;
      // (1.4) as printed, with unit directions: the same condition.
      const auto& s1 = g2.method_report.at("segments").at(l - 1);
      const auto& s2 = g2.method_report.at("segments").at(l);
      const Vec2 dm = g2.tangents[i - 3], d = g2.tangents[i], dp = g2.tangents[i + 3];
      const double a3 = s1.at("alpha3").get<double>(), a0 = s2.at("alpha0").get<double>();
      const double lhs =
          cross(3.0 * (in.points[i] - in.points[i - 3]) - s1.at("alpha0").get<double>() * dm, d) /
          (a3 * a3);
      const double rhs =
          cross(d, 3.0 * (in.points[i + 3] - in.points[i]) - s2.at("alpha3").get<double>() * dp) /
          (a0 * a0);
      EXPECT_NEAR(lhs, rhs, 1e-8 * std::abs(lhs)) << l;
    }
    EXPECT_GT(g1.report->max_curvature_jump, 1e3 * g2.report->max_curvature_jump);
    // From the paper's γ = 1/2 choice Newton fails here; the next start is then used.
    const FitResult other = fit("kozak-krajnc", in, {{"g2", true}});
    EXPECT_TRUE(other.method_report.at("g2").at("converged").get<bool>());
  }
}

TEST(KozakKrajncSpline, G2RootBeyondDoublePrecisionIsAConditioningLimit) {
  // Two pieces and a near-repeated pair (T3, T4): the scaled jump at T3 changes sign between
  // two adjacent doubles of ξ1, from 8e-9 to −4e-9, so 1e-10 cannot be met. The curve comes
  // back with status conditioning_limit instead of an error (issue 18, stress case c19147).
  FitInput in;
  in.points = {{0.0, 0.0},
               {270.70865618691096, -620.2183919110814},
               {989.3641611928101, -1153.3384024894929},
               {1439.6006218291102, -1200.9159884410951},
               {1439.600956585169, -1200.9164482550611},
               {1469.5596186967953, -1269.057134533418},
               {2744.769342556417, -1329.571348811363},
               {2794.9098066403435, -1257.1088945231702}};
  const FitResult r = fit("kozak-krajnc", in, {{"g2", true}, {"remainder", "hermite"}});
  const auto& rep = r.method_report.at("g2");
  EXPECT_EQ(rep.at("status"), "conditioning_limit") << rep.dump();
  EXPECT_FALSE(rep.at("converged").get<bool>());
  EXPECT_LE(rep.at("max_scaled_curvature_jump").get<double>(), 1e-6);
  ASSERT_TRUE(r.solver.has_value());
  EXPECT_EQ(r.solver->status, SolverStatus::kConditioningLimit);
  // The jump itself, from the Béziers: within the same bound, scaled by the mean chord.
  const double kl = r.spline.segments[2].bezier.curvature(1.0);
  const double kr = r.spline.segments[3].bezier.curvature(0.0);
  const double chord =
      0.5 * (norm(in.points[3] - in.points[2]) + norm(in.points[4] - in.points[3]));
  EXPECT_LE(std::abs(kl - kr) * chord, 1e-6);
}

/// Fits with g2 (and `options`), expecting a root found by the m = 2 scan with that G2 status and
/// at most `max_jump` as reported, and the output certified from its Béziers alone (the jump
/// within the certificate's tolerance plus the rounding of control points beside short chords).
void expect_scan_root(const FitInput& in, const nlohmann::json& options, const std::string& status,
                      double max_jump) {
  nlohmann::json opts = options;
  opts["g2"] = true;
  opts["remainder"] = "hermite";
  const FitResult r = fit("kozak-krajnc", in, opts);
  const auto& rep = r.method_report.at("g2");
  EXPECT_EQ(rep.at("status"), status) << rep.dump();
  EXPECT_EQ(rep.at("start"), "scan");
  EXPECT_LE(rep.at("max_scaled_curvature_jump").get<double>(), max_jump);
  const stress::KktResult k = stress::check_optimum(in, r);
  EXPECT_TRUE(k.checked && k.pass) << k.what;
}

TEST(KozakKrajncSpline, G2ScanFollowsARootIntoTheGridsFirstCell) {
  // Two pieces and a near-repeated pair (stress case s40-c12221): the jump at T3 changes sign at
  // ξ1 = 1.7e-4, inside the first cell of the scan's 4000-point grid, and is positive (~7800)
  // on the whole grid. Newton crept towards ξ1 = 1; the scan's walk from its first point
  // towards ξ1 = 0 brackets the root (it used to stop there and report not_converged).
  FitInput in;
  in.points = {{0.0, 0.0},
               {8.18955503281589, 0.4457867204268956},
               {37.87060323131593, 9.125021518192167},
               {37.87060341146015, 9.125021631720045},
               {37.87053495108267, 9.125128335842085},
               {32.729603982244036, 15.242482187834907},
               {6.482643020244754, 17.333787439966365}};
  // (Read off the Béziers the jump is 1.4e-5, within the rounding allowance beside the 2e-7
  // chord.)
  expect_scan_root(in, nlohmann::json::object(), "converged", 1e-10);
}

TEST(KozakKrajncSpline, G2ScanFollowsARootToWhereAPieceLosesItsSolutions) {
  // Two pieces (stress case s40-c2132): on the grid's last point the right piece has two
  // solutions, one with a jump of 3.9 and one with −2.3e-4; the first falls to zero at
  // ξ1 = 0.999988, just before the pieces lose their solutions at ~0.999992. The walk towards
  // ξ1 = 1 halves its way to the nearest point without solutions and brackets the root, which
  // lies between two adjacent doubles of ξ1 (a conditioning limit, not an error).
  FitInput in;
  in.points = {{0.0, 0.0},
               {1865.206776822419, -2725.6558079907677},
               {4361.954062565607, -4862.942446630308},
               {4431.189526389016, -4922.209977143222},
               {4431.189868327068, -4922.210269812145},
               {4500.8488508092405, -4981.836838698451},
               {4687.1091680859745, -5141.27061236619},
               {5116.7998883433165, -5509.075664059845}};
  expect_scan_root(in, {{"gamma", 0.4533995309445078}}, "conditioning_limit", 1e-6);
}

TEST(KozakKrajncSpline, G2ScanReadsTheJumpOfEverySolutionOffItsOwnCurve) {
  // Two pieces and a near-repeated pair (stress case s40-c3554 of `--max-points 9`). The right
  // piece has two solutions over part of ξ1; the scan read the jump of every pair off the
  // least-energy pair's curves, saw it negative everywhere (least 5.1e6) and refused the request
  // as infeasible. The other solution's jump changes sign: a G2 spline exists.
  FitInput in;
  in.points = {{0.0, 0.0},
               {11.562280068237941, 819.8832218239519},
               {7.7310685053800166, 872.6589658376206},
               {7.73106821818795, 872.6589723964911},
               {11.35564806294686, 961.4259598788976},
               {-43.414293661301286, 1234.3937738070686},
               {-52.2599249333051, 1286.2042749657671}};
  expect_scan_root(in, nlohmann::json::object(), "converged", 1e-10);
}

TEST(KozakKrajncSpline, G2ChainScanFindsARootNewtonMisses) {
  // Ten points of a perturbed circle, three pieces (stress case s18-c7048): Newton from the
  // G1 spline and from both parabolas' directions stalls at the edge of the admissible ξ; the
  // chain scan's cells bracket a G2 spline elsewhere, and Newton from there reaches it.
  FitInput in;
  in.points = {
      {0.7280395449655364, 0.1440283701178012},    {0.6647729523463161, 0.3285027357914905},
      {0.13730151864198437, 0.7291381171141219},   {-0.10296437699286032, 0.7520597048807133},
      {-0.5480334221214594, 0.4786047956467151},   {-0.7219914343857781, 0.07383590120846635},
      {-0.5902769813007365, -0.44294208143965913}, {-0.07938095032231995, -0.7212726199900144},
      {0.0834913498251977, -0.7432938546785481},   {0.5310477283731693, -0.5010689548990517}};
  const FitResult r = fit("kozak-krajnc", in, {{"g2", true}, {"gamma", 0.026196763819152646}});
  const auto& rep = r.method_report.at("g2");
  ASSERT_TRUE(rep.at("converged").get<bool>()) << rep.dump();
  EXPECT_EQ(rep.at("start"), "chain-scan");
  expect_valid(r);
  for (std::size_t i : {3u, 6u}) {
    const double kl = r.spline.segments[i - 1].bezier.curvature(1.0);
    const double kr = r.spline.segments[i].bezier.curvature(0.0);
    EXPECT_NEAR(kl, kr, 1e-8 * std::abs(kl)) << i;
  }
}

TEST(KozakKrajncSpline, G2ChainScanProvesThatNoSplineExists) {
  // Ten points of a walk with a near-repeated pair (stress case s18-c10208): over every cell of
  // the chain scan the scaled curvature jumps at T3 and T6 cannot vanish together, so the
  // request is refused as infeasible, naming a breakpoint; a best effort gives the G1 spline.
  FitInput in;
  in.points = {{0.0, 0.0},
               {-2.9545779227655293e-08, 1.2679984817409791e-08},
               {-21.071324557550625, 6.526686311842819},
               {-38.92120663016269, 11.988851867041717},
               {-73.35186127679079, 14.990298740431781},
               {-112.70693863783391, 11.804442366477236},
               {-125.51923607514594, 13.167916413779537},
               {-142.1157780575953, 12.824431115700301},
               {-164.20332000667406, 7.626094508602984},
               {-183.56013334928411, 5.156145378414153}};
  const nlohmann::json options = {{"g2", true}, {"gamma", 0.6487633439299039}};
  try {
    fit("kozak-krajnc", in, options);
    FAIL() << "expected infeasible";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInfeasible) << e.what();
    ASSERT_TRUE(e.index());
    EXPECT_TRUE(*e.index() == 3 || *e.index() == 6) << *e.index();
    EXPECT_NE(std::string(e.what()).find("T" + std::to_string(*e.index())), std::string::npos)
        << e.what();
  }
  const FitResult r = fit("kozak-krajnc", in, options, FitOptions{.best_effort = true});
  EXPECT_FALSE(r.method_report.at("g2").at("converged").get<bool>());
  expect_valid(r);
}

TEST(KozakKrajncSpline, GammaAndTangentOptions) {
  const auto E = testing::ellipse(12, 3, 1);
  FitInput in;
  in.points.assign(E.begin(), E.begin() + 10);
  for (const char* t : {"sweep", "local-quadratic-uniform"}) {
    const FitResult r = fit("kozak-krajnc", in, {{"tangents", t}});
    expect_valid(r);
    EXPECT_EQ(r.method_report.at("tangents"), t);
  }
  // The chord-length parabolas' directions at T3, T6 lie in their swept sets, but piece 2 has
  // no admissible solution for them: a clear error naming the piece.
  const Error e = testing::expect_error([&] {
    fit("kozak-krajnc", in, {{"tangents", "local-quadratic-chordal"}});
  });
  EXPECT_EQ(e.code(), ErrorCode::kInfeasible);
  EXPECT_NE(std::string(e.what()).find("piece"), std::string::npos) << e.what();
  const FitResult a = fit("kozak-krajnc", in, {{"gamma", 0.2}});
  const FitResult b = fit("kozak-krajnc", in, {{"gamma", "auto"}});
  expect_valid(a);
  expect_valid(b);
  EXPECT_NE(a.tangents[3].x, b.tangents[3].x);
  // Every reported ξ lies in its swept set.
  for (const auto& bp : a.method_report.at("breakpoints")) {
    const double x = bp.at("xi").get<double>();
    bool inside = false;
    for (const auto& iv : bp.at("Xi")) inside |= iv[0].get<double>() < x && x < iv[1].get<double>();
    EXPECT_TRUE(inside);
    EXPECT_TRUE(bp.at("in_Xi").get<bool>());
  }
}

TEST(KozakKrajncSpline, RemainderHermite) {
  for (std::size_t n : {5u, 6u, 8u, 9u}) {
    FitInput in;
    in.points = testing::random_walk(n, 40 + n, 30);
    const Error e = testing::expect_error([&] { fit("kozak-krajnc", in); });
    EXPECT_EQ(e.code(), ErrorCode::kWrongPointCount);
    EXPECT_EQ(e.index(), n - 1);
    EXPECT_NE(std::string(e.what()).find("3m+1"), std::string::npos);
    const FitResult r = fit("kozak-krajnc", in, {{"remainder", "hermite"}});
    expect_valid(r);
    EXPECT_EQ(r.method_report.at("remainder").at("spans").get<std::size_t>(), (n - 1) % 3);
  }
}

TEST(KozakKrajncSpline, Errors) {
  FitInput in;
  in.points = {{0, 0}, {1, 0}, {2, 0}, {3, 1}};  // T0, T1, T2 collinear
  Error e = testing::expect_error([&] { fit("kozak-krajnc", in); });
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(e.index(), 1u);
  in.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0.5}, {0.5, 0.5}, {0.6, 0.2}};
  in.closed = true;
  e = testing::expect_error([&] { fit("kozak-krajnc", in); });
  EXPECT_NE(std::string(e.what()).find("open"), std::string::npos);
  in.closed = false;
  in.points = {{0, 0}, {1, 0}, {1, 1}, {-1, 0.5}};  // λ1, λ2 < 0: turns past a half turn
  e = testing::expect_error([&] { fit("kozak-krajnc", in); });
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  in.points = testing::random_walk(7, 3, 30);
  in.tangents.assign(7, std::nullopt);
  in.tangents[2] = Vec2{1, 0};
  e = testing::expect_error([&] { fit("kozak-krajnc", in); });
  EXPECT_EQ(e.index(), 2u);
  EXPECT_THROW(fit("kozak-krajnc", in, {{"gamma", 2}}), Error);
}

TEST(KozakKrajncSpline, InfeasibleDataNameTheFirstEmptySpan) {
  // Find inflecting data the sweeps reject; the message names a point of the data.
  int found = 0;
  for (std::uint64_t seed = 1; seed <= 200 && found < 5; ++seed) {
    FitInput in;
    in.points = testing::random_walk(10, 5000 + seed, 110);
    try {
      fit("kozak-krajnc", in);
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kInfeasible) continue;
      ASSERT_TRUE(e.index());
      EXPECT_LT(*e.index(), 10u);
      EXPECT_NE(std::string(e.what()).find("T" + std::to_string(*e.index())), std::string::npos)
          << e.what();
      ++found;
    }
  }
  EXPECT_GT(found, 0);
}

RC_GTEST_PROP(KozakKrajncProps, SolverIsEquivariantUnderReversalAndSimilarity, ()) {
  // Four points along a turning walk, end directions near the end chords.
  const auto angle = [](int k) { return k * 1e-3; };
  const double h0 = angle(*rc::gen::inRange(-3142, 3142));
  const double turn1 = angle(*rc::gen::inRange(-1200, 1200)),
               turn2 = angle(*rc::gen::inRange(-1200, 1200));
  std::vector<Point> T{{0, 0}};
  double h = h0;
  for (double turn : {0.0, turn1, turn2}) {
    h += turn;
    T.push_back(T.back() + (0.3 + *rc::gen::inRange(0, 1000) * 1e-3) * from_angle(h));
  }
  const Vec2 d0 = from_angle(h0 + angle(*rc::gen::inRange(-1200, 1200)));
  const Vec2 d3 = from_angle(h + angle(*rc::gen::inRange(-1200, 1200)));
  RC_PRE(std::abs(cross(T[1] - T[0], T[2] - T[1])) > 1e-3 &&
         std::abs(cross(T[2] - T[1], T[3] - T[2])) > 1e-3 &&
         std::abs(cross(d0, T[1] - T[0])) > 1e-3 && std::abs(cross(T[3] - T[2], d3)) > 1e-3);
  const KozakKrajncSolutions a = kozak_krajnc_solve(T[0], T[1], T[2], T[3], d0, d3);
  // Reversed: T3..T0 with −d3, −d0 gives t ↦ 1 − t and swapped α.
  const KozakKrajncSolutions r = kozak_krajnc_solve(T[3], T[2], T[1], T[0], -1.0 * d3, -1.0 * d0);
  RC_ASSERT(a.count == r.count);
  for (const KozakKrajncSolution& x : a) {  // (sorted by t1, so match by value)
    bool matched = false;
    for (const KozakKrajncSolution& y : r) {
      matched =
          matched || (std::abs(x.t1 - (1 - y.t2)) < 1e-9 && std::abs(x.t2 - (1 - y.t1)) < 1e-9 &&
                      std::abs(x.alpha0 - y.alpha3) < 1e-8 * (1 + x.alpha0) &&
                      x.multiplicity == y.multiplicity);
    }
    RC_ASSERT(matched);
  }
  // Similarity: rotate by 0.7 rad, scale by s, shift: t unchanged, α scaled by s.
  const double s = std::pow(10.0, *rc::gen::inRange(-3, 4));
  const auto map = [&](Point p) {
    return Point{0, 0} + s * rotate(p - Point{0, 0}, 0.7) + Vec2{5, -2};
  };
  const KozakKrajncSolutions b = kozak_krajnc_solve(map(T[0]), map(T[1]), map(T[2]), map(T[3]),
                                                    rotate(d0, 0.7), rotate(d3, 0.7));
  RC_ASSERT(a.count == b.count);
  for (int i = 0; i < a.count; ++i) {
    RC_ASSERT(std::abs(a.items[i].t1 - b.items[i].t1) < 1e-9);
    RC_ASSERT(std::abs(a.items[i].alpha3 * s - b.items[i].alpha3) <
              1e-8 * s * (1 + a.items[i].alpha3));
  }
}

}  // namespace
}  // namespace fairspline
