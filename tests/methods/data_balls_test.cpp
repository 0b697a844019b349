// Data balls (src/methods/data_balls.cpp): the minimal-energy curve through discs. Checked
// against what it must be, from outside the optimizer: r = 0 is interpolation bit for bit; the
// returned positions satisfy the KKT conditions, recomputed here from the curve's own end
// directions with span_derivatives (no force left at an inactive ball, only an outward-falling
// radial one at an active ball); no lower energy is found by a derivative-free search over the
// positions; noisy samples of known curves give the known curve's bending energy.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "detail/ball_energy.hpp"
#include "fairspline/error.hpp"
#include "fairspline/methods/min_energy.hpp"
#include "fairspline/registry.hpp"
#include "stress/kkt.hpp"

namespace fairspline {
namespace {

constexpr double kPi = std::numbers::pi;

FitResult fit_balls(const std::string& method, const FitInput& in,
                    const nlohmann::json& options = nlohmann::json::object(),
                    ReportLevel level = ReportLevel::kBasic) {
  return fit(method, in, options, FitOptions{.level = level});
}

// The unit end directions of span s: the first and last cubics of its pieces.
std::pair<Vec2, Vec2> span_directions(const FitResult& r, std::size_t s) {
  const CubicBezier* first = nullptr;
  const CubicBezier* last = nullptr;
  for (const Segment& g : r.spline.segments) {
    if (g.span != s) continue;
    if (!first) first = &g.bezier;
    last = &g.bezier;
  }
  auto unit = [](Vec2 v) { return v / norm(v); };
  const Vec2 a = first->p[1] - first->p[0], b = last->p[3] - last->p[2];
  return {unit(norm(a) > 0 ? a : first->p[2] - first->p[0]),
          unit(norm(b) > 0 ? b : last->p[3] - last->p[1])};
}

BasicCurveMethod basis_of(const std::string& method, const nlohmann::json& options) {
  BasicCurveMethod m;
  if (method == "restricted-elastic") m.basis = MinEnergyBasis::kRestrictedElastic;
  if (method == "elastic") m.basis = MinEnergyBasis::kElastic;
  if (method == "cond-g2") m.basis = MinEnergyBasis::kCondG2;
  const std::string b = options.value("basis", std::string());
  if (b == "jaklic-zagar") m.basis = MinEnergyBasis::kJaklicZagar;
  if (b == "yong-cheng") m.basis = MinEnergyBasis::kYongCheng;
  m.lambda = options.value("lambda", 1.0);
  m.omega = BasicCurveMethod::default_omega(m.basis);
  return m;
}

struct Kkt {
  double inactive = 0.0;    // largest |force| at an inactive ball (relative)
  double tangential = 0.0;  // largest tangential force at an active ball (relative)
  double inward = 0.0;      // largest force pulling an active ball inward (relative)
  double outside = 0.0;     // largest |p − q| − r over r
  std::size_t active = 0;
  std::size_t skipped = 0;
};

// The energy's force on each position at the returned directions (envelope: the directions are
// optimal for the positions), in units of the solver's stopping test: |∂E/∂p|·ℓ over the node's
// own weight 1/ℓ, ℓ the shorter adjacent chord of the centres.
// Balls in `skip` are not judged (the ends of an elastic span on its pair bound |α − β| = π,
// where E_1's partial derivatives are infinite and only the multiplier's sum is known).
Kkt kkt_of(const FitResult& r, const FitInput& in, const BasicCurveMethod& m,
           const std::vector<std::size_t>& skip = {}) {
  const std::size_t n = r.points.size(), spans = r.closed ? n : n - 1;
  std::vector<Vec2> force(n);
  for (std::size_t s = 0; s < spans; ++s) {
    const std::size_t j = s + 1 == n ? 0 : s + 1;
    const Vec2 c = r.points[j] - r.points[s];
    const auto [out, inn] = span_directions(r, s);
    const double phi = std::atan2(c.y, c.x);
    const double a = std::remainder(std::atan2(out.y, out.x) - phi, 2 * kPi);
    const double b = std::remainder(std::atan2(inn.y, inn.x) - phi, 2 * kPi);
    const detail::SpanDerivatives d = detail::span_derivatives(basic_energy(m, a, b), c);
    force[s] -= Vec2{d.g[2], d.g[3]};
    force[j] += Vec2{d.g[2], d.g[3]};
  }
  Kkt k;
  for (std::size_t i = 0; i < n; ++i) {
    const double ri = in.radii[i];
    if (ri == 0.0) continue;
    if (std::find(skip.begin(), skip.end(), i) != skip.end()) {
      ++k.skipped;
      continue;
    }
    double ell = HUGE_VAL;
    if (r.closed || i > 0)
      ell = std::min(ell, distance(in.points[i], in.points[i ? i - 1 : n - 1]));
    if (r.closed || i + 1 < n) ell = std::min(ell, distance(in.points[i], in.points[(i + 1) % n]));
    const Vec2 off = r.points[i] - in.points[i];
    const Vec2 f = force[i] * (ell * ell);
    k.outside = std::max(k.outside, norm(off) / ri - 1.0);
    if (norm(off) >= ri * (1 - 1e-9)) {
      ++k.active;
      const Vec2 u = off / norm(off);
      k.tangential = std::max(k.tangential, std::abs(cross(u, f)));
      k.inward = std::max(k.inward, dot(f, u));
    } else {
      k.inactive = std::max(k.inactive, norm(f));
    }
  }
  return k;
}

std::vector<Point> noisy(std::vector<Point> p, double amplitude, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2 * kPi), radius(0.0, 1.0);
  for (Point& q : p) {
    const double a = angle(rng), d = amplitude * std::sqrt(radius(rng));
    q = q + Vec2{d * std::cos(a), d * std::sin(a)};
  }
  return p;
}

std::vector<Point> circle(std::size_t n, double radius) {
  std::vector<Point> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 2 * kPi * static_cast<double>(i) / static_cast<double>(n);
    p[i] = {radius * std::cos(t), radius * std::sin(t)};
  }
  return p;
}

TEST(DataBalls, RadiusZeroIsInterpolationBitForBit) {
  FitInput in;
  in.points = noisy(circle(30, 2.0), 0.1, 1);
  in.closed = true;
  for (const char* method : {"quasi-elastic", "cond-g2", "restricted-elastic", "elastic"}) {
    const FitResult plain = fit_balls(method, in);
    FitInput zero = in;
    zero.radii.assign(in.points.size(), 0.0);
    const FitResult balls = fit_balls(method, zero);
    ASSERT_EQ(plain.spline.segments.size(), balls.spline.segments.size()) << method;
    for (std::size_t s = 0; s < plain.spline.segments.size(); ++s) {
      for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(plain.spline.segments[s].bezier.p[k].x, balls.spline.segments[s].bezier.p[k].x);
        EXPECT_EQ(plain.spline.segments[s].bezier.p[k].y, balls.spline.segments[s].bezier.p[k].y);
      }
    }
    EXPECT_FALSE(balls.method_report.contains("balls")) << method;
  }
}

TEST(DataBalls, BadRadiiAreRefusedNamingThePoint) {
  FitInput in;
  in.points = {{0, 0}, {1, 1}, {2, 0}, {3, 1}};
  auto code_at = [&](std::vector<double> radii, const std::string& method, ErrorCode& code) {
    FitInput c = in;
    c.radii = std::move(radii);
    try {
      fit_balls(method, c);
    } catch (const Error& e) {
      code = e.code();
      return e.index().value_or(999);
    }
    return std::size_t{12345};
  };
  ErrorCode code{};
  EXPECT_EQ(code_at({0, -0.1, 0, 0}, "quasi-elastic", code), 1u);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_at({0, 0, NAN, 0}, "quasi-elastic", code), 2u);
  EXPECT_EQ(code, ErrorCode::kNonFinite);
  EXPECT_EQ(code_at({0, 0, INFINITY, 0}, "cond-g2", code), 2u);
  EXPECT_EQ(code, ErrorCode::kNonFinite);
  code_at({0, 0.1}, "quasi-elastic", code);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  // Neighbouring balls that overlap: points 1 and 2 are √2 apart.
  EXPECT_EQ(code_at({0, 0.8, 0.7, 0}, "quasi-elastic", code), 1u);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  // Methods that interpolate refuse a ball instead of ignoring it.
  EXPECT_EQ(code_at({0, 0.1, 0, 0}, "li-strain", code), 1u);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(code_at({0, 0.1, 0, 0}, "jaklic-zagar", code), 1u);
  EXPECT_EQ(code, ErrorCode::kInvalidArgument);
  // Zero radii are plain interpolation for every method.
  EXPECT_EQ(code_at({0, 0, 0, 0}, "li-strain", code), 12345u);
}

TEST(DataBalls, CollinearCapableDataGiveAStraightLine) {
  FitInput in;
  in.points = {{0, 0}, {1, 0.1}, {2, -0.1}, {3, 0.12}, {4, -0.05}, {5, 0}};
  in.radii = {0, 0.15, 0.15, 0.15, 0.15, 0};
  const FitResult r = fit_balls("quasi-elastic", in);
  for (const Point& p : r.points) EXPECT_NEAR(p.y, 0.0, 1e-9);
  EXPECT_NEAR(r.method_report.at("energy").get<double>(), 0.0, 1e-12);
  EXPECT_EQ(r.method_report.at("balls").at("status"), "converged");
}

struct Case {
  std::string method;
  nlohmann::json options;
};

std::vector<Case> every_basis() {
  return {
      {"quasi-elastic", nlohmann::json::object()},      {"cond-g2", {{"lambda", 1.6}}},
      {"min-energy", {{"basis", "jaklic-zagar"}}},      {"min-energy", {{"basis", "yong-cheng"}}},
      {"restricted-elastic", nlohmann::json::object()}, {"elastic", nlohmann::json::object()}};
}

TEST(DataBalls, KktConditionsHoldForEveryBasis) {
  for (const Case& c : every_basis()) {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      FitInput in;
      const bool closed = seed % 2 == 0;
      in.points = noisy(circle(24, 3.0), 0.25, seed);
      if (!closed) in.points.resize(18);
      in.closed = closed;
      in.radii.assign(in.points.size(), 0.2);
      if (!closed) in.radii.front() = in.radii.back() = 0.0;
      const FitResult r = fit_balls(c.method, in, c.options);
      const Kkt k = kkt_of(r, in, basis_of(c.method, c.options));
      SCOPED_TRACE(c.method + " " + c.options.dump() + " seed " + std::to_string(seed));
      EXPECT_LE(k.outside, 1e-12);
      EXPECT_LE(k.inactive, 1e-8);
      EXPECT_LE(k.tangential, 1e-8);
      EXPECT_LE(k.inward, 1e-8);
      EXPECT_GT(k.active, 0u);
      EXPECT_EQ(k.active, r.method_report.at("balls").at("active").size());
    }
  }
}

// A near-repeated pair (6.6e-8 apart, a ball of 1.4e-8 on one) among spans of 1 to 100: its
// weight, 1e7 times the others', set the scale of the stopping test, so that the other balls
// stopped with forces of a tenth of their own spans' (energy 0.0126, the optimum's 0.0097).
// Measured against each node's own spans, every ball's KKT conditions hold.
TEST(DataBalls, ANearRepeatedPairDoesNotSetTheOthersTolerance) {
  FitInput in;
  in.points = {{0.0, 0.0},
               {-6.1494429007044955, 7.939199715391322},
               {-34.00808019462335, 25.98556217161567},
               {-58.265578199676334, 25.81065487664222},
               {-158.4533618411341, -23.74580741902277},
               {-162.50679434322396, -26.82293461930923},
               {-165.58528208633652, -28.025172028888317},
               {-165.58528215155297, -28.025172041118783},
               {-166.56838669012987, -28.722601944306362}};
  in.radii = {0.7054881629831273,
              0.264358350530813,
              5.44390633299274,
              6.8784258206915965,
              1.4101736232611597,
              1.1654265334212008,
              0.0,
              1.3737760631373945e-08,
              0.3444589276426099};
  const FitResult r = fit_balls("quasi-elastic", in, nlohmann::json::object());
  EXPECT_EQ(r.method_report.at("balls").at("status"), "converged");
  // The stress suite's certificate: it allows the tiny ball's position the rounding of its
  // coordinates (166 ± 3e-14 is 2e-6 of its radius).
  const stress::KktResult k = stress::check_optimum(in, r);
  EXPECT_TRUE(k.checked);
  EXPECT_TRUE(k.pass) << k.what;
}

// A derivative-free search over the positions (polar coordinates in each disc, compass steps
// shrinking to 1e-7 of the radius) with the interpolation's optimum at each: no lower energy.
// With `from` (positions inside the discs) the search starts there with steps of 1/64: a check
// that no nearby positions are better, which holds at a local minimum too.
double reference_energy(const std::string& method, const FitInput& in, const nlohmann::json& opt,
                        const std::vector<Point>* from = nullptr) {
  std::vector<std::size_t> balls;
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    if (in.radii[i] > 0) balls.push_back(i);
  }
  std::vector<double> rho(balls.size(), 0.0), ang(balls.size(), 0.0);
  if (from) {
    for (std::size_t k = 0; k < balls.size(); ++k) {
      const Vec2 off = (*from)[balls[k]] - in.points[balls[k]];
      rho[k] = norm(off) / in.radii[balls[k]];
      ang[k] = std::atan2(off.y, off.x);
    }
  }
  auto energy = [&](const std::vector<double>& rh, const std::vector<double>& an) {
    FitInput at = in;
    at.radii.clear();
    for (std::size_t k = 0; k < balls.size(); ++k) {
      const double rr = in.radii[balls[k]] * std::clamp(rh[k], 0.0, 1.0);
      at.points[balls[k]] = in.points[balls[k]] + Vec2{rr * std::cos(an[k]), rr * std::sin(an[k])};
    }
    try {
      return fit(method, at, opt, FitOptions{.level = ReportLevel::kNone})
          .method_report.at("energy")
          .get<double>();
    } catch (const Error&) {
      return HUGE_VAL;
    }
  };
  double best = energy(rho, ang);
  // Start from the eight compass directions at half the radius, the best of each ball alone.
  for (std::size_t k = 0; k < balls.size() && !from; ++k) {
    for (int q = 0; q < 8; ++q) {
      std::vector<double> r2 = rho, a2 = ang;
      r2[k] = 0.5;
      a2[k] = q * kPi / 4;
      const double e = energy(r2, a2);
      if (e < best) {
        best = e;
        rho = r2;
        ang = a2;
      }
    }
  }
  for (double h = from ? 1.0 / 64 : 0.25; h > 1e-7; h *= 0.5) {
    for (bool moved = true; moved;) {
      moved = false;
      for (std::size_t k = 0; k < balls.size(); ++k) {
        for (int which = 0; which < 2; ++which) {
          for (double sgn : {-1.0, 1.0}) {
            std::vector<double> r2 = rho, a2 = ang;
            (which ? a2[k] : r2[k]) += sgn * h * (which ? 2 * kPi : 1.0);
            r2[k] = std::clamp(r2[k], 0.0, 1.0);
            const double e = energy(r2, a2);
            if (e < best - 1e-15 * std::abs(best)) {
              best = e;
              rho = r2;
              ang = a2;
              moved = true;
            }
          }
        }
      }
    }
  }
  return best;
}

// A zigzag whose restricted-elastic optimum has directions on its 90° box: the elastic spline
// goes on beyond it (the second stage), to a lower energy, KKT-certified with the elastic
// energy, and the elastic interpolation through its positions is the same curve.
TEST(DataBalls, ElasticGoesBeyondTheRestrictedBox) {
  FitInput in;
  in.points = {{0, 0}, {3, 1}, {0, 2}, {3, 3}, {0, 4}, {3, 5}};
  in.radii = {0, 0.2, 0.2, 0.2, 0.2, 0};
  const FitResult restricted = fit_balls("restricted-elastic", in);
  // Read at a finer Bézier accuracy than the default 1e-6: the certificate takes the directions
  // off the Béziers' ends.
  const FitResult elastic = fit("elastic", in, nlohmann::json::object(),
                                FitOptions{.level = ReportLevel::kBasic, .accuracy = 1e-10});
  const double er = restricted.method_report.at("energy").get<double>();
  const double ee = elastic.method_report.at("energy").get<double>();
  EXPECT_FALSE(restricted.method_report.at("active").empty());  // on the 90° box
  EXPECT_EQ(elastic.method_report.at("balls").at("status"), "converged");
  EXPECT_LT(ee, 0.9 * er);
  std::vector<std::size_t> skip;
  for (std::size_t sp : elastic.method_report.at("active_spans").get<std::vector<std::size_t>>()) {
    skip.push_back(sp);
    skip.push_back(sp + 1);
  }
  const Kkt k = kkt_of(elastic, in, basis_of("elastic", nlohmann::json::object()), skip);
  EXPECT_LE(k.skipped, 2u);  // balls 2 and 3 are judged
  // The solver's own residual is below its 2.5e-9 stop. Read back from the returned curve (the
  // elastic interpolation through the positions, which stops at its own tolerance) the forces
  // measure 2.2e-8 here.
  EXPECT_LE(elastic.method_report.at("balls").at("kkt_residual").get<double>(), 2.5e-9);
  EXPECT_LE(k.outside, 1e-12);
  EXPECT_LE(k.inactive, 5e-8);
  EXPECT_LE(k.tangential, 5e-8);
  EXPECT_LE(k.inward, 5e-8);
  FitInput through = in;
  through.points = elastic.points;
  through.radii.clear();
  const FitResult again = fit_balls("elastic", through);
  EXPECT_NEAR(again.method_report.at("energy").get<double>(), ee, 1e-9 * ee);
  // No nearby positions do better (a local check around the returned ones).
  EXPECT_GE(reference_energy("elastic", in, nlohmann::json::object(), &elastic.points),
            ee * (1 - 1e-9));
}

TEST(DataBalls, NoLowerEnergyFoundByABruteForceSearch) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int cases = 0;
  for (const Case& c : every_basis()) {
    for (int rep = 0; rep < 3; ++rep) {
      FitInput in;
      const std::size_t n = 4 + static_cast<std::size_t>(rep % 2);
      in.closed = rep == 2;
      for (std::size_t i = 0; i < n; ++i) {
        const double t = 2 * kPi * static_cast<double>(i) / static_cast<double>(n + 1);
        in.points.push_back({3 * std::cos(t) + 0.5 * u(rng), 2 * std::sin(t) + 0.5 * u(rng)});
      }
      in.radii.assign(n, 0.0);
      for (std::size_t i = 0; i < n; ++i) in.radii[i] = (i % 2 == 1 || in.closed) ? 0.3 : 0.0;
      FitResult r;
      try {
        r = fit_balls(c.method, in, c.options, ReportLevel::kNone);
      } catch (const Error& e) {
        ASSERT_EQ(e.code(), ErrorCode::kInfeasible)
            << c.method << " " << c.options.dump() << " case " << rep << ": " << e.what();
        continue;
      }
      const double e = r.method_report.at("energy").get<double>();
      const double ref = reference_energy(c.method, in, c.options);
      EXPECT_LE(e, ref * (1 + 1e-9) + 1e-12) << c.method << " " << c.options.dump() << " " << rep;
      ++cases;
    }
  }
  EXPECT_GE(cases, 12);
}

// Noisy samples of a curve (noise up to a fifth of the spacing) with the noise amplitude as
// radius: the bending energy of the fit is near the curve's, where interpolation takes up the
// noise (9× to 45× the true energy), and the KKT conditions hold. Circle of radius 1:
// ∫κ² ds = 2π; ellipse 2×1 by quadrature; a clothoid κ = s, s ∈ [0, 2]: s³/3. The open
// clothoid may straighten within its discs (its sagitta per span is far below the radius), so
// its energy comes out lower.
TEST(DataBalls, NoisyCirclesEllipsesAndClothoidsGiveTheTrueBendingEnergy) {
  struct Shape {
    std::string name;
    std::vector<Point> points;
    bool closed;
    double energy;
  };
  std::vector<Shape> shapes;
  shapes.push_back({"circle", circle(60, 1.0), true, 2 * kPi});
  {
    std::vector<Point> e(80);
    double bend = 0.0;
    const int q = 200000;
    for (int k = 0; k < q; ++k) {  // ∫κ² ds of x = 2cos t, y = sin t
      const double t = 2 * kPi * (k + 0.5) / q, sp = std::hypot(2 * std::sin(t), std::cos(t));
      bend += std::pow(2.0 / (sp * sp * sp), 2) * sp * (2 * kPi / q);
    }
    for (std::size_t i = 0; i < e.size(); ++i) {
      const double t = 2 * kPi * static_cast<double>(i) / static_cast<double>(e.size());
      e[i] = {2 * std::cos(t), std::sin(t)};
    }
    shapes.push_back({"ellipse", e, true, bend});
  }
  {
    std::vector<Point> c;
    const double smax = 2.0;
    const int q = 400000;
    double x = 0, y = 0;
    for (int k = 0; k <= q; ++k) {  // x' = cos(s²/2), y' = sin(s²/2), κ = s
      const double s = smax * k / q;
      if (k % (q / 40) == 0) c.push_back({x, y});
      const double sm = s + 0.5 * smax / q;
      x += std::cos(0.5 * sm * sm) * smax / q;
      y += std::sin(0.5 * sm * sm) * smax / q;
    }
    shapes.push_back({"clothoid", c, false, smax * smax * smax / 3});
  }
  const std::vector<double> within = {0.01, 0.04, 0.25};  // measured: docs/methods/min-energy.md
  for (std::size_t which = 0; which < shapes.size(); ++which) {
    const Shape& sh = shapes[which];
    double spacing = HUGE_VAL;
    for (std::size_t i = 0; i + 1 < sh.points.size(); ++i) {
      spacing = std::min(spacing, distance(sh.points[i], sh.points[i + 1]));
    }
    const double amp = 0.2 * spacing;
    FitInput in;
    in.points = noisy(sh.points, amp, 3);
    in.closed = sh.closed;
    const double plain =
        fit_balls("quasi-elastic", in, {}, ReportLevel::kFull).report->bending_energy.value();
    in.radii.assign(in.points.size(), amp);
    if (!sh.closed) in.radii.front() = in.radii.back() = 0.0;
    const FitResult r = fit_balls("quasi-elastic", in, {}, ReportLevel::kFull);
    const double bend = r.report->bending_energy.value();
    SCOPED_TRACE(sh.name);
    EXPECT_NEAR(bend / sh.energy, 1.0, within[which]) << "interpolation: " << plain / sh.energy;
    if (std::getenv("FAIRSPLINE_PRINT_BALLS")) {
      std::printf("%s: balls %.4f, interpolation %.3f of the true bending energy %.6f\n",
                  sh.name.c_str(), bend / sh.energy, plain / sh.energy, sh.energy);
    }
    EXPECT_GT(plain / sh.energy, 1.2);
    const Kkt k = kkt_of(r, in, BasicCurveMethod{});
    EXPECT_LE(k.inactive, 1e-8);
    EXPECT_LE(k.tangential, 1e-8);
    EXPECT_LE(k.outside, 1e-12);
  }
}

TEST(DataBalls, NodeStatesWithBalls) {
  FitInput in;
  in.points = noisy(circle(16, 2.0), 0.2, 9);
  in.points.resize(12);
  in.radii.assign(12, 0.15);
  in.states.assign(12, NodeState{});
  in.states[5] = {SideState::kFree, SideState::kFree};     // a corner, its position shared
  in.states[0] = {SideState::kFree, SideState::kClamped};  // a clamped start
  in.out_tangents.assign(12, std::nullopt);
  in.out_tangents[0] = Vec2{-0.2, 1.0};
  in.corners_deg.assign(12, 0.0);
  in.corners_deg[8] = 10.0;
  const FitResult r = fit_balls("quasi-elastic", in);
  const Kkt k = kkt_of(r, in, BasicCurveMethod{});
  EXPECT_LE(k.inactive, 1e-8);
  EXPECT_LE(k.tangential, 1e-8);
  EXPECT_LE(k.inward, 1e-8);
  EXPECT_LE(k.outside, 1e-12);
  // The clamped start keeps its direction; the corner keeps its angle.
  const auto [d0, unused] = span_directions(r, 0);
  EXPECT_NEAR(cross(d0, Vec2{-0.2, 1.0} / norm(Vec2{-0.2, 1.0})), 0.0, 1e-12);
  const auto [out8, u8] = span_directions(r, 8);
  const auto [u7, in8] = span_directions(r, 7);
  EXPECT_NEAR(std::atan2(cross(in8, out8), dot(in8, out8)) * 180 / kPi, 10.0, 1e-9);
}

// Every combination of side states (regular, clamped, free on each side), corners on regular
// nodes and balls on any node, for every basis: the fit keeps the clamped directions and the
// corners, its positions stay in their discs, and the derivative-free search over the positions
// finds no lower energy.
// cond-G2 with λ = 1.6 is concave around a straight span (E_1's Hessian there has eigenvalues
// 6λ − 4λ² < 0 and 6λ): span 0, between free ends, starts as a saddle. The Newton matrix of the
// whole problem was shifted for it until every unknown crept (279 iterations, not converged, on
// these five points); each span's E_1 is now made convex in the matrix instead.
TEST(DataBalls, AConcaveSpanBetweenFreeEndsDoesNotSlowTheRest) {
  FitInput in;
  in.points = {{0, 0},
               {1.0045039080724523, 0.17712114122026895},
               {2.3691066883727077, 1.7469170680836348},
               {3.1108717575744151, 3.1419742648007394},
               {5.2099590547089649, 4.3055173533919477}};
  in.radii = {0, 0.102, 0.2528, 0, 0.168};
  const SideState R = SideState::kRegular, C = SideState::kClamped, F = SideState::kFree;
  in.states = {{F, F}, {F, R}, {R, R}, {R, F}, {C, F}};
  in.corners_deg = {0, 0, 2, 0, 0};
  in.in_tangents.assign(5, std::nullopt);
  in.in_tangents[4] = Vec2{std::cos(0.12217304763960307), std::sin(0.12217304763960307)};
  const nlohmann::json opt = {{"lambda", 1.6}};
  const FitResult r = fit_balls("cond-g2", in, opt);
  ASSERT_TRUE(r.solver);
  EXPECT_EQ(r.solver->status, SolverStatus::kConverged);
  EXPECT_LE(r.solver->iterations, 60);
  const double e = r.method_report.at("energy").get<double>();
  EXPECT_LE(e, reference_energy("cond-g2", in, opt, &r.points) * (1 + 1e-9));
  // The free-ended span leaves the saddle: its end angles are ±acos(3/(2λ)) from its chord.
  const auto [d0, d1] = span_directions(r, 0);
  const Vec2 c = r.points[1] - r.points[0];
  const double a = std::atan2(cross(c, d0), dot(c, d0)), b = std::atan2(cross(c, d1), dot(c, d1));
  EXPECT_NEAR(std::abs(a), std::acos(3.0 / (2 * 1.6)), 1e-6);
  EXPECT_NEAR(a, -b, 1e-6);
}

// The optimizer may say that it did not converge (an error, never a silent wrong curve), on a few
// of these harsh inputs: on at most 1 in 20 of the cases for the bases of the energy's smooth
// part, and 2 in 5 for the elastic spline, whose box corners it does not handle (rates measured by
// the stress suite: docs/hardening.md, "Data balls"). What it returns is a local optimum, except,
// open, in a few cases in a hundred runs (counted, bounded at 1 in 20).
void every_state_combination(int& cases, int& elastic_cases, int& not_converged,
                             int& elastic_not_converged, int& not_minimal);

TEST(DataBallsProps, EveryStateCombinationReachesTheBruteForceReference) {
  int cases = 0, elastic_cases = 0, not_converged = 0, elastic_not_converged = 0;
  int not_minimal = 0;
  EXPECT_TRUE(rc::check([&] {
    every_state_combination(cases, elastic_cases, not_converged, elastic_not_converged,
                            not_minimal);
  }));
  RecordProperty("cases", cases);
  RecordProperty("not_converged", not_converged);
  RecordProperty("elastic_not_converged", elastic_not_converged);
  RecordProperty("not_minimal", not_minimal);
  EXPECT_LE(not_converged, cases / 20 + 1);
  EXPECT_LE(elastic_not_converged, 2 * elastic_cases / 5 + 1);
  EXPECT_LE(not_minimal, (cases + elastic_cases) / 20 + 1);
}

void every_state_combination(int& cases, int& elastic_cases, int& not_converged,
                             int& elastic_not_converged, int& not_minimal) {
  // One seed per case, every draw uniform from it (rapidcheck's own generators favour small
  // values at small sizes: 40% of the cases were the first basis).
  std::mt19937_64 rng(static_cast<std::uint64_t>(*rc::gen::inRange(0, 1 << 30)));
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi - 1)(rng); };
  const std::vector<Case> bases = every_basis();
  const Case c = bases[static_cast<std::size_t>(pick(0, static_cast<int>(bases.size())))];
  const bool closed = pick(0, 2) == 1;
  const auto n = static_cast<std::size_t>(pick(closed ? 3 : 4, 7));
  FitInput in;
  in.closed = closed;
  double heading = 0.0;
  Point p{0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    in.points.push_back(p);
    heading += pick(-50, 51) * kPi / 180.0;
    p = p + (0.5 + pick(0, 100) / 50.0) * Vec2{std::cos(heading), std::sin(heading)};
  }
  auto gap = [&](std::size_t a, std::size_t b) { return distance(in.points[a], in.points[b]); };
  auto unit_chord = [&](std::size_t a) {
    const Vec2 d = in.points[(a + 1) % n] - in.points[a];
    return d / norm(d);
  };
  auto turned = [](Vec2 v, double deg) {
    const double a = deg * kPi / 180.0;
    return Vec2{v.x * std::cos(a) - v.y * std::sin(a), v.x * std::sin(a) + v.y * std::cos(a)};
  };
  const SideState kStates[] = {SideState::kRegular, SideState::kClamped, SideState::kFree};
  in.states.resize(n);
  in.in_tangents.assign(n, std::nullopt);
  in.out_tangents.assign(n, std::nullopt);
  in.corners_deg.assign(n, 0.0);
  in.radii.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    NodeState& s = in.states[i];
    s.in = kStates[pick(0, 3)];
    s.out = kStates[pick(0, 3)];
    const bool has_prev = closed || i > 0, has_next = closed || i + 1 < n;
    if (!has_prev) s.in = s.out == SideState::kClamped ? SideState::kFree : s.out;
    if (!has_next) s.out = s.in == SideState::kClamped ? SideState::kFree : s.in;
    // Clamped directions within 25° of the adjacent chord: feasible for every basis's Ω once
    // the positions move by the radii below (at most 0.2 of a chord: 11.5° each way).
    if (s.in == SideState::kClamped) {
      in.in_tangents[i] = turned(unit_chord(i == 0 ? n - 1 : i - 1), pick(-25, 26));
    }
    if (s.out == SideState::kClamped) in.out_tangents[i] = turned(unit_chord(i), pick(-25, 26));
    if (s.in == SideState::kRegular && s.out == SideState::kRegular && has_prev && has_next &&
        pick(0, 3) == 0) {
      in.corners_deg[i] = pick(-30, 31);
    }
    if (pick(0, 2) == 0) {
      const double room = std::min(has_prev ? gap(i, (i + n - 1) % n) : HUGE_VAL,
                                   has_next ? gap(i, (i + 1) % n) : HUGE_VAL);
      in.radii[i] = room * pick(5, 21) / 100.0;
    }
  }
  if (std::all_of(in.radii.begin(), in.radii.end(), [](double r) { return r == 0.0; })) {
    in.radii[n / 2] = 0.1 * gap(n / 2, (n / 2 + 1) % n);
  }
  RC_TAG(c.method + " " + c.options.dump());
  ++(c.method == "elastic" ? elastic_cases : cases);
  RC_LOG() << "basis " << c.method << " " << c.options.dump() << "\n";
  for (std::size_t i = 0; i < n; ++i) {
    RC_LOG() << std::setprecision(17) << "point " << i << " (" << in.points[i].x << ", "
             << in.points[i].y << ") r " << in.radii[i] << " states "
             << static_cast<int>(in.states[i].in) << "/" << static_cast<int>(in.states[i].out)
             << " corner " << in.corners_deg[i]
             << (in.in_tangents[i]
                     ? " in-tangent " +
                           std::to_string(std::atan2(in.in_tangents[i]->y, in.in_tangents[i]->x))
                     : "")
             << (in.out_tangents[i]
                     ? " out-tangent " +
                           std::to_string(std::atan2(in.out_tangents[i]->y, in.out_tangents[i]->x))
                     : "")
             << (closed ? " closed" : "") << "\n";
  }
  FitResult r;
  try {
    r = fit_balls(c.method, in, c.options, ReportLevel::kNone);
  } catch (const Error& e) {
    // Only a stencil or clamped direction beyond the basis's feasible range may refuse it, or
    // the optimizer say that it did not converge (counted above).
    RC_LOG() << c.method << " " << c.options.dump() << ": " << e.what() << "\n";
    if (e.code() == ErrorCode::kNotConverged)
      ++(c.method == "elastic" ? elastic_not_converged : not_converged);
    RC_SUCCEED(e.code() == ErrorCode::kInfeasible ? "infeasible" : "not_converged");
  }
  // Directions to 1e-9°; the elastic spline's with balls to 1e-6° (deviations up to 6.5e-8° seen
  // in this property, not in its interpolation; open in docs/hardening.md).
  const double angle_tol = c.method == "elastic" ? 1e-6 : 1e-9;
  for (std::size_t i = 0; i < n; ++i) {
    RC_ASSERT(distance(r.points[i], in.points[i]) <= in.radii[i] * (1 + 1e-12));
  }
  auto turn_deg = [](Vec2 a, Vec2 b) { return std::atan2(cross(a, b), dot(a, b)) * 180.0 / kPi; };
  for (std::size_t i = 0; i < n; ++i) {
    const bool has_prev = closed || i > 0, has_next = closed || i + 1 < n;
    const std::size_t before = i == 0 ? n - 1 : i - 1;
    if (has_prev && in.in_tangents[i]) {
      const Vec2 t = *in.in_tangents[i] / norm(*in.in_tangents[i]);
      RC_ASSERT(std::abs(turn_deg(t, span_directions(r, before).second)) < angle_tol);
    }
    if (has_next && in.out_tangents[i]) {
      const Vec2 t = *in.out_tangents[i] / norm(*in.out_tangents[i]);
      RC_ASSERT(std::abs(turn_deg(t, span_directions(r, i).first)) < angle_tol);
    }
    if (has_prev && has_next && in.states[i] == NodeState{}) {
      const double turn = turn_deg(span_directions(r, before).second, span_directions(r, i).first);
      RC_ASSERT(std::abs(turn - in.corners_deg[i]) < angle_tol);
    }
  }
  // A local minimum: the search from the returned positions finds nothing lower. (From the
  // centres it finds a lower minimum on a few percent of these inputs, the energy not being
  // convex in the positions: docs/methods/min-energy.md, "Data balls".)
  // To 1e-7: a clamped direction's box that bounds the positions (|θ − φ| <= Ω as the chord
  // turns) is held by a log barrier of weight 1e-8 of the typical torque, which stops that much
  // inside it (a log barrier's duality gap is its weight per constraint): 2 runs in 100 found
  // the search 1e-9 lower there, none more than 1e-7. The local minima it misses are 1e-5 and
  // more (docs/hardening.md, "Data balls").
  const double e = r.method_report.at("energy").get<double>();
  const double near = reference_energy(c.method, in, c.options, &r.points);
  if (!(e <= near * (1 + 1e-7) + 1e-12)) {
    // Open (docs/hardening.md, "Data balls"): about 4 runs in 100 have one such case (elastic,
    // restricted-elastic, cond-g2), 1e-5 to 40% above the search, where the interpolation's
    // own start jumps between minima of the directions; counted and bounded above.
    ++not_minimal;
    RC_LOG() << "a lower minimum nearby: " << e << " > " << near << "\n";
    RC_SUCCEED("a lower minimum nearby");
  }
}

TEST(DataBalls, TheLowerOfTwoMinimaOfTheDirectionsIsTaken) {
  // Found by the property above: at the positions the optimizer first settled at, the
  // directions have two local minima (S-curves through point 3 at -74° and -36°), and it was in
  // the higher one (4.05154) while the interpolation's own start finds 4.05143 there. It goes on
  // from the lower one; the result is what a refit gives, and no position nearby is lower.
  FitInput in;
  in.points = {{0.0, 0.0},
               {1.7835541375750326, -0.9483325568274994},
               {3.5989498027257207, -1.5734234133852403},
               {4.8324177691834027, -3.0966294978409032},
               {6.3176138920610194, -4.930693966879355}};
  in.radii = {0.0, 0.0, 0.3072, 0.098, 0.0};
  using S = SideState;
  in.states = {{S::kFree, S::kClamped},
               {S::kFree, S::kRegular},
               {S::kClamped, S::kFree},
               {S::kRegular, S::kRegular},
               {S::kFree, S::kFree}};
  in.out_tangents.assign(5, std::nullopt);
  in.in_tangents.assign(5, std::nullopt);
  in.out_tangents[0] = Vec2{std::cos(-0.488692), std::sin(-0.488692)};
  in.in_tangents[2] = Vec2{std::cos(-0.314159), std::sin(-0.314159)};
  const nlohmann::json opt = {{"lambda", 1.6}};
  const FitResult r = fit_balls("cond-g2", in, opt);
  const double e = r.method_report.at("energy").get<double>();
  FitInput at = in;
  at.points = r.points;
  at.radii.clear();
  EXPECT_NEAR(fit_balls("cond-g2", at, opt).method_report.at("energy").get<double>(), e, 1e-12 * e);
  EXPECT_LT(e, 4.05143);
  EXPECT_LE(e, reference_energy("cond-g2", in, opt, &r.points) * (1 + 1e-9));
}

TEST(DataBalls, ElasticBesideAHalfTurnReachesAStationaryPoint) {
  // Found by the property above: the closing span ends on its half-turn bound. The optimizer
  // once stopped at 3.0924, where moving point 5 along its circle lowers the energy (3.0923 by
  // 1e-3 rad), and said so (not_converged at point 5). Since the output refit honours a warm
  // direction in a U-turn node's second interval and a piece on its pair bound, the optimizer
  // goes on to a lower optimum, the closing span still on that bound.
  FitInput in;
  in.closed = true;
  in.points = {{0.0, 0.0},
               {1.002249690135276, 0.34510224372458603},
               {1.502249690135276, 0.34510224372458603},
               {3.908583091299747, 0.94506854481176195},
               {4.7473272052228888, 2.2366212194477146},
               {6.2233874048068349, 3.1951859210741622}};
  in.radii = {0.0, 0.0, 0.085, 0.0, 0.2926, 0.2992};
  using S = SideState;
  in.states = {{S::kRegular, S::kRegular}, {S::kClamped, S::kRegular}, {S::kClamped, S::kRegular},
               {S::kRegular, S::kFree},    {S::kClamped, S::kFree},    {S::kRegular, S::kFree}};
  in.in_tangents.assign(6, std::nullopt);
  for (auto [i, a] : {std::pair{1, 0.244346}, {2, 0.383972}, {4, 0.575959}}) {
    in.in_tangents[static_cast<std::size_t>(i)] = Vec2{std::cos(a), std::sin(a)};
  }
  const FitResult r = fit_balls("elastic", in);
  EXPECT_EQ(r.method_report.at("balls").at("status"), "converged");
  const double e = r.method_report.at("energy").get<double>();
  EXPECT_LT(e, 3.0923);
  const auto [out, inn] = span_directions(r, 5);
  EXPECT_NEAR(std::abs(std::atan2(cross(out, inn), dot(out, inn))), kPi, 1e-9);
  const Kkt k = kkt_of(r, in, basis_of("elastic", nlohmann::json::object()));
  EXPECT_LE(k.inactive, 1e-8);
  EXPECT_LE(k.tangential, 1e-8);
  EXPECT_LE(k.inward, 1e-8);
  EXPECT_LE(e, reference_energy("elastic", in, nlohmann::json::object(), &r.points) * (1 + 1e-9));
}

TEST(DataBalls, TheElasticSplineLocksAUTurnPieceOnItsRidge) {
  // Stress walk s19-c150: the closing span is a U-turn piece at α = β ≈ −133°, where E_1 has a
  // convex kink across the diagonal. Newton steps crossed it back and forth under a growing
  // shift (not_converged, residual 3.7; best effort 21.4915) until such a span is locked on it.
  FitInput in;
  in.closed = true;
  in.points = {{0.0, 0.0},
               {0.03911053592017336, -0.31837573595331475},
               {0.1127821723216459, -0.9180929453026636},
               {0.15308765787875916, -1.2461960593431618},
               {0.22087697733107728, -1.7980288062647862}};
  in.radii = {0.03395257061922154, 0.0778157626710227, 0.015182502733134495, 0.0,
              0.13914706061104268};
  const FitResult r = fit_balls("elastic", in);
  EXPECT_EQ(r.method_report.at("balls").at("status"), "converged");
  const auto& last = r.method_report.at("spans").back();
  EXPECT_EQ(last.at("kind"), "u-turn");
  const double a = last.at("alpha_deg").get<double>(), b = last.at("beta_deg").get<double>();
  EXPECT_GT(std::abs(a), 98.5);
  EXPECT_NEAR(a, b, 1e-9);
  const double e = r.method_report.at("energy").get<double>();
  EXPECT_LT(e, 21.4915 - 0.05);
  EXPECT_LT(e, fit_balls("restricted-elastic", in).method_report.at("energy").get<double>());
}

TEST(DataBalls, RefitReproducesTheCurve) {
  FitInput in;
  in.points = noisy(circle(20, 2.0), 0.2, 4);
  in.closed = true;
  in.radii.assign(20, 0.15);
  const FitResult a = fit_balls("cond-g2", in, {{"lambda", 1.3}});
  const FitResult b =
      fit(a.method, refit_input(a), a.options, FitOptions{.level = ReportLevel::kBasic});
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].x, b.points[i].x);
    EXPECT_EQ(a.points[i].y, b.points[i].y);
  }
  EXPECT_EQ(refit_input(a).radii, in.radii);
}

// A closed curve is numbered from a cut, two consecutive nodes that form the border of the
// banded Newton matrix. A cut whose outer chords both hold its nodes' directions on a bound would
// couple the band's two ends (a dense factorization: a 783-point zig-zag took 456 s); this
// wobbly 21-point outline has such nodes at 0 and 1 on several steps, so it is cut elsewhere
// there. The optimum does not depend on where: the same input started at another point gives
// the same curve.
TEST(DataBalls, AClosedCurveIsCutWhereNoBoundCouplesTheBandsEnds) {
  FitInput in;
  in.closed = true;
  in.points = {
      {1.2788795993005206, 0.06839578318570308},  {0.5448793558472522, 0.18287066678506622},
      {1.1380250499066138, 0.6254898305633046},   {0.6069528971270025, 0.8396873187062238},
      {0.523185937421948, 1.477516369695116},     {0.1437773260849346, 1.0786687479545018},
      {-0.0902264395640597, 0.4916341280351173},  {-0.7806654540076322, 1.257146924310488},
      {-1.0852857144964414, 1.053259492160925},   {-1.3769432343843897, 0.6962493074137273},
      {-1.5026157056378144, 0.40309946661571827}, {-1.0746547583101094, -0.17184576098896073},
      {-0.890723675545972, -0.5188939923682695},  {-0.46233952904575387, -0.4654857856273059},
      {-0.4945843234399994, -1.1374504207044296}, {-0.10430418070155954, -0.8879674350486447},
      {0.16266832303118514, -0.992135024045267},  {0.2324816678767899, -0.5980459955101557},
      {0.9815762577595576, -1.112297882337157},   {0.9655857187861024, -0.5434570209144995},
      {0.5100917079476324, -0.20550838387009643}};
  in.radii = {0.02746283494383826,   0.06172749394697439, 0.06845120728139703,  0.14492658426391053,
              0.1002885308023078,    0.04758515501826602, 0.04014082990509073,  0.12719710063155304,
              0.12891902523430226,   0.12415562489029419, 0.013728383163056806, 0.15911258386490162,
              0.0062096259305519695, 0.1586027897421475,  0.026396336577165773, 0.04546128797414833,
              0.09818226380705598,   0.12890135860923377, 0.12817871519105986,  0.03441487010768658,
              0.1666295700884982};
  const FitResult a = fit_balls("quasi-elastic", in);
  ASSERT_TRUE(a.solver);
  EXPECT_EQ(a.solver->status, SolverStatus::kConverged);
  const stress::KktResult k = stress::check_optimum(in, a);
  EXPECT_TRUE(k.checked && k.pass) << k.what;
  const std::size_t n = in.points.size(), shift = 7;
  FitInput turned = in;
  std::rotate(turned.points.begin(), turned.points.begin() + shift, turned.points.end());
  std::rotate(turned.radii.begin(), turned.radii.begin() + shift, turned.radii.end());
  const FitResult b = fit_balls("quasi-elastic", turned);
  const double ea = a.method_report.at("energy").get<double>();
  EXPECT_NEAR(b.method_report.at("energy").get<double>(), ea, 1e-9 * ea);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_LE(norm(b.points[i] - a.points[(i + shift) % n]), 1e-6) << "point " << i;
  }
}

TEST(DataBalls, ScaleInvariant) {
  FitInput in;
  in.points = noisy(circle(20, 2.0), 0.2, 5);
  in.closed = true;
  in.radii.assign(20, 0.15);
  const FitResult a = fit_balls("quasi-elastic", in);
  FitInput big = in;
  for (Point& p : big.points) p = p * 0x1p40;
  for (double& r : big.radii) r *= 0x1p40;
  const FitResult b = fit_balls("quasi-elastic", big);
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].x * 0x1p40, b.points[i].x);
    EXPECT_EQ(a.points[i].y * 0x1p40, b.points[i].y);
  }
}

}  // namespace
}  // namespace fairspline
