// Throughput of the Yong–Cheng constructions on one core, random angle pairs:
//   ogh/segments/<n>     n OGH segments (Theorem 2 + Bézier form) from random end data, written
//                        to an output array; items = segments
//   coh/dispatch/<n>     n COH curves (dispatcher + 1–3 OGH pieces) from random end data by
//                        the batch API coh_curves, 256 spans at a time into a reused buffer;
//                        items = dispatches
//   coh/dispatch_single/<n>  the same, one coh_curve call per span
//   fit*/yong-cheng/<open|closed>/<n>   the spline method on the random walk of bench_data.hpp
//                        with a random tangent at every point
// bench/compare_scipy.py --benchmark ogh/segments/1000000 (or coh/dispatch/...) compares the
// items per second with SciPy's natural-spline points per second measured in the same run
// (targets: OGH >= 12x, COH >= 2.5x).
#include <algorithm>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "bench_data.hpp"
#include "fairspline/methods/yong_cheng.hpp"

namespace {

using fairspline::Point;
using fairspline::Vec2;

using EndData = fairspline::HermiteEnds;

/// n random end conditions: points in a unit box, directions uniform on the circle (so every
/// tangent-angle pair occurs), tangent lengths in [0.5, 2].
const std::vector<EndData>& end_data(std::size_t n) {
  static std::vector<EndData> data;
  if (data.size() != n) {
    std::mt19937_64 rng(20240601);
    std::uniform_real_distribution<double> u(-1.0, 1.0), angle(0.0, 2.0 * std::numbers::pi),
        len(0.5, 2.0);
    data.resize(n);
    for (EndData& d : data) {
      d.p0 = {u(rng), u(rng)};
      d.p1 = d.p0 + len(rng) * fairspline::from_angle(angle(rng));
      d.v0 = len(rng) * fairspline::from_angle(angle(rng));
      d.v1 = len(rng) * fairspline::from_angle(angle(rng));
    }
  }
  return data;
}

void bm_ogh(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const std::vector<EndData>& data = end_data(n);
  std::vector<fairspline::CubicBezier> out(n);
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const EndData& d = data[i];
      out[i] = fairspline::ogh_segment(d.p0, d.p1, d.v0, d.v1);
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
}

// The batch API (coh_curves), in chunks of 256 spans into a reused buffer as a spline fit
// would consume them.
void bm_coh(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const std::vector<EndData>& data = end_data(n);
  constexpr std::size_t kChunk = 256;
  std::vector<fairspline::CohCurve> buf(kChunk);
  std::int64_t pieces = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; i += kChunk) {
      const std::size_t m = std::min(kChunk, n - i);
      fairspline::coh_curves({data.data() + i, m}, buf);
      benchmark::DoNotOptimize(buf.data());
      benchmark::ClobberMemory();
      for (std::size_t k = 0; k < m; ++k) pieces += buf[k].count;
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
  state.counters["pieces_per_dispatch"] =
      static_cast<double>(pieces) / static_cast<double>(state.iterations() * n);
}

// One coh_curve call per span (no batching).
void bm_coh_single(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const std::vector<EndData>& data = end_data(n);
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const EndData& d = data[i];
      fairspline::CohCurve c = fairspline::coh_curve(d.p0, d.p1, d.v0, d.v1);
      benchmark::DoNotOptimize(c);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
}

[[maybe_unused]] const bool kRegistered = [] {
  benchmark::RegisterBenchmark("ogh/segments", bm_ogh)
      ->Arg(1000)
      ->Arg(1000000)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("coh/dispatch", bm_coh)
      ->Arg(1000)
      ->Arg(1000000)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("coh/dispatch_single", bm_coh_single)
      ->Arg(1000000)
      ->Unit(benchmark::kMillisecond);
  for (bool closed : {false, true}) {
    fairspline::bench::register_fit("yong-cheng", closed, {1000, 1000000},
                                    fairspline::FitInput::kDefaultAlpha, nlohmann::json::object(),
                                    /*tangents=*/true);
  }
  return true;
}();

}  // namespace
