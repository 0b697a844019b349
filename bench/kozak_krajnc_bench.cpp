// Throughput of the Kozak–Krajnc single-piece solver on one core:
//   BM_KozakKrajncSolvePiece/<n>   n calls of kozak_krajnc_solve, cycling through a fixed pool of
//                                  4096 random admissible pieces; items = pieces
// A piece is sampled like four consecutive points of a smooth curve: a base turning angle κ
// uniform in ±0.9 rad, the two turns κ + noise (noise uniform in ±0.5 rad), chord lengths
// uniform in [0.5, 2], and end directions = the first / last chord rotated by an angle uniform
// in ±1.2 rad. Only admissible samples are kept (Theorem 2.4 or 2.5 holds; degenerate ones,
// where kozak_krajnc_constants throws, are skipped). With the default seed the pool is 76%
// convex (3108 pieces: λ1, λ2 > 0, Theorem 2.4) and 24% inflection (988 pieces: λ1λ2 < 0,
// Theorem 2.5) data, each with exactly one admissible solution; the counters convex_fraction and
// solutions_per_piece report the mix and the mean number of admissible solutions.
// bench/compare_scipy.py --benchmark BM_KozakKrajncSolvePiece/1000000 --target 0.25 compares
// the pieces per second with SciPy's natural-spline points per second measured in the same run.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "bench_data.hpp"
#include "fairspline/methods/kozak_krajnc.hpp"
#include "fairspline/registry.hpp"

namespace {

using fairspline::Point;
using fairspline::Vec2;

struct Piece {
  Point t0, t1, t2, t3;
  Vec2 d0, d3;
  bool convex;
};

constexpr std::size_t kPoolSize = 4096;

/// kPoolSize admissible pieces (generated once, seeded).
const std::vector<Piece>& piece_pool() {
  static const std::vector<Piece> pool = [] {
    std::mt19937_64 rng(fairspline::bench::kDefaultSeed);
    std::uniform_real_distribution<double> heading(0.0, 2.0 * std::numbers::pi),
        curvature(-0.9, 0.9), noise(-0.5, 0.5), step(0.5, 2.0), end_turn(-1.2, 1.2);
    std::vector<Piece> out;
    out.reserve(kPoolSize);
    while (out.size() < kPoolSize) {
      const double kappa = curvature(rng);
      double h = heading(rng);
      Piece p{};
      p.t0 = {0.0, 0.0};
      const Vec2 c0 = step(rng) * fairspline::from_angle(h);
      p.t1 = p.t0 + c0;
      h += kappa + noise(rng);
      p.t2 = p.t1 + step(rng) * fairspline::from_angle(h);
      h += kappa + noise(rng);
      const Vec2 c2 = step(rng) * fairspline::from_angle(h);
      p.t3 = p.t2 + c2;
      p.d0 = fairspline::rotate(fairspline::normalized(c0), end_turn(rng));
      p.d3 = fairspline::rotate(fairspline::normalized(c2), end_turn(rng));
      try {
        const fairspline::KozakKrajncConstants c =
            fairspline::kozak_krajnc_constants(p.t0, p.t1, p.t2, p.t3, p.d0, p.d3);
        if (!(fairspline::kozak_krajnc_theorem_2_4(c) || fairspline::kozak_krajnc_theorem_2_5(c))) {
          continue;
        }
        p.convex = c.lambda1 > 0.0 && c.lambda2 > 0.0;
      } catch (const fairspline::Error&) {
        continue;  // degenerate sample (collinear chords, end direction along its chord)
      }
      out.push_back(p);
    }
    return out;
  }();
  return pool;
}

void BM_KozakKrajncSolvePiece(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const std::vector<Piece>& pool = piece_pool();
  // Untimed pass: reports solver errors as a skipped benchmark and gathers the counters.
  std::size_t convex = 0, solutions = 0;
  try {
    for (const Piece& p : pool) {
      const auto r = fairspline::kozak_krajnc_solve(p.t0, p.t1, p.t2, p.t3, p.d0, p.d3);
      solutions += static_cast<std::size_t>(r.count);
      convex += p.convex ? 1 : 0;
    }
  } catch (const fairspline::Error& e) {
    state.SkipWithError(e.what());
    return;
  }
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const Piece& p = pool[i % kPoolSize];
      auto r = fairspline::kozak_krajnc_solve(p.t0, p.t1, p.t2, p.t3, p.d0, p.d3);
      benchmark::DoNotOptimize(r);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
  state.counters["convex_fraction"] =
      static_cast<double>(convex) / static_cast<double>(pool.size());
  state.counters["solutions_per_piece"] =
      static_cast<double>(solutions) / static_cast<double>(pool.size());
}

BENCHMARK(BM_KozakKrajncSolvePiece)->Arg(kPoolSize)->Arg(1000000)->Unit(benchmark::kMillisecond);

// The whole spline (constants, forward and backward sweeps, selection, one solve per piece,
// output) on n = 3m+1 points of a wavy curve with inflections, y = sin x + 0.3 sin 0.37x
// sampled every 0.05: the timings at 10^4, 10^5 and 3·10^5 + 1 points show the O(n) cost
// (items/s stays flat). A random walk is not used here: one infeasible piece anywhere in 10^5
// fails the whole fit.
void BM_KozakKrajncSpline(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  fairspline::FitInput in;
  in.points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = 0.05 * static_cast<double>(i);
    in.points.push_back({x, std::sin(x) + 0.3 * std::sin(0.37 * x)});
  }
  fairspline::FitResult out;
  try {
    fairspline::fit_into("kozak-krajnc", in, nlohmann::json::object(),
                         fairspline::ReportLevel::kNone, out);
  } catch (const fairspline::Error& e) {
    state.SkipWithError(e.what());
    return;
  }
  for (auto _ : state) {
    fairspline::fit_into("kozak-krajnc", in, nlohmann::json::object(),
                         fairspline::ReportLevel::kNone, out);
    benchmark::DoNotOptimize(out.spline.segments.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
}

BENCHMARK(BM_KozakKrajncSpline)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(300001)
    ->Unit(benchmark::kMillisecond);

}  // namespace
