// Shared input data of the benchmarks: seeded planar random walks.
//
// A walk turns by an angle uniform in [-kMaxTurnDeg, +kMaxTurnDeg] degrees at every point and
// steps a length uniform in [kMinStep, kMaxStep]. bench/compare_scipy.py generates the same
// distribution (not the same numbers) for its peer timings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/registry.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline::bench {

inline constexpr double kMaxTurnDeg = 120.0;
inline constexpr double kMinStep = 0.5;
inline constexpr double kMaxStep = 2.0;
inline constexpr std::uint64_t kDefaultSeed = 20240601;

/// `n` points of a random walk starting at the origin, heading along +x.
inline std::vector<Point> random_walk(std::size_t n, std::uint64_t seed = kDefaultSeed) {
  std::mt19937_64 rng(seed);
  const double max_turn = kMaxTurnDeg * std::numbers::pi / 180.0;
  std::uniform_real_distribution<double> turn(-max_turn, max_turn);
  std::uniform_real_distribution<double> step(kMinStep, kMaxStep);
  std::vector<Point> pts;
  pts.reserve(n);
  Point p{0.0, 0.0};
  double heading = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    pts.push_back(p);
    heading += turn(rng);
    p += step(rng) * from_angle(heading);
  }
  return pts;
}

/// A FitInput around a cached random walk of `n` points (generated once per (n, seed), so
/// that data generation stays outside every timed loop and is shared between benchmarks).
/// With `tangents`, every point also gets a tangent direction uniform on the circle (for the
/// Hermite methods, e.g. yong-cheng).
inline const FitInput& walk_input(std::size_t n, bool closed = false,
                                  double alpha = FitInput::kDefaultAlpha,
                                  std::uint64_t seed = kDefaultSeed, bool tangents = false) {
  struct Key {
    std::size_t n;
    bool closed;
    double alpha;
    std::uint64_t seed;
    bool tangents;
    bool operator<(const Key& o) const {
      return std::tie(n, closed, alpha, seed, tangents) <
             std::tie(o.n, o.closed, o.alpha, o.seed, o.tangents);
    }
  };
  static std::map<Key, FitInput> cache;
  const Key key{n, closed, alpha, seed, tangents};
  auto it = cache.find(key);
  if (it == cache.end()) {
    FitInput in;
    in.points = random_walk(n, seed);
    in.closed = closed;
    in.alpha = alpha;
    if (tangents) {
      std::mt19937_64 rng(seed + 1);
      std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
      in.tangents.reserve(n);
      for (std::size_t i = 0; i < n; ++i) in.tangents.emplace_back(from_angle(angle(rng)));
    }
    it = cache.emplace(key, std::move(in)).first;
  }
  return it->second;
}

/// Times `fairspline::fit(method, walk, options, ReportLevel::kNone)` on a random walk of
/// state.range(0) points and reports items_per_second = points per second.
/// With `reuse`, times `fit_into` writing every fit into the same FitResult instead: the
/// steady state of a pipeline that fits curve after curve, where the output's memory is
/// already mapped (a fresh 10^6-point result costs ~150 MB of new pages to zero).
inline void fit_walk(benchmark::State& state, const std::string& method, bool closed, double alpha,
                     const nlohmann::json& options, bool reuse, bool tangents) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const FitInput& input = walk_input(n, closed, alpha, kDefaultSeed, tangents);
  try {
    // One untimed call: reports bad input as a skipped benchmark and warms up the allocator.
    (void)fit(method, input, options, ReportLevel::kNone);
  } catch (const Error& e) {
    state.SkipWithError(e.what());
    return;
  }
  if (reuse) {
    FitResult r;
    fit_into(method, input, options, ReportLevel::kNone, r);
    for (auto _ : state) {
      fit_into(method, input, options, ReportLevel::kNone, r);
      benchmark::DoNotOptimize(r.spline.segments.data());
      benchmark::ClobberMemory();
    }
  } else {
    for (auto _ : state) {
      FitResult r = fit(method, input, options, ReportLevel::kNone);
      benchmark::DoNotOptimize(r.spline.segments.data());
      benchmark::ClobberMemory();
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
  state.counters["n"] = static_cast<double>(n);
}

/// Registers "fit/<method>/<open|closed>/<n>" (fresh result per fit) and
/// "fit_into/<method>/<open|closed>/<n>" (result reused) for each n in `sizes` (the names
/// bench/compare_scipy.py filters on; keep the scheme when adding methods). A non-default
/// alpha adds "/alpha:<value>" before the size. `tangents` gives every point a random tangent.
inline void register_fit(const std::string& method, bool closed,
                         const std::vector<std::int64_t>& sizes,
                         double alpha = FitInput::kDefaultAlpha,
                         nlohmann::json options = nlohmann::json::object(), bool tangents = false) {
  for (bool reuse : {false, true}) {
    std::string name = (reuse ? "fit_into/" : "fit/") + method + (closed ? "/closed" : "/open");
    if (alpha != FitInput::kDefaultAlpha) name += "/alpha:" + std::to_string(alpha);
    auto* b = benchmark::RegisterBenchmark(
        name.c_str(), [method, closed, alpha, options, reuse, tangents](benchmark::State& state) {
          fit_walk(state, method, closed, alpha, options, reuse, tangents);
        });
    for (std::int64_t n : sizes) b->Arg(n);
    // CPU time of every thread: long inputs run parts of a fit on a second thread, whose time
    // a per-thread clock would leave out of the CPU-time ratios (bench/compare_scipy.py).
    b->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
  }
}

}  // namespace fairspline::bench
