// Throughput of jaklic-zagar (points per second, ReportLevel::kNone, Bézier output written),
// next to a memcpy of the same bytes measured in the same run.
//   fit/jaklic-zagar/open/{1e3..1e6}     fresh FitResult per fit (what `fairspline bench` does)
//   fit_into/jaklic-zagar/open/...       result reused (a pipeline's steady state)
//   fit*/jaklic-zagar/closed/1e6, fit*/jaklic-zagar/open/alpha:0.666667/1e6 (bisector = optimal)
//   memcpy/jaklic-zagar/1e6              memcpy of the input points (16 B each) plus the output
//                                        control points (64 B per piece); items = points
//   ratio/jaklic-zagar/open/1e6          fit_into and that memcpy alternated in one benchmark;
//                                        counters fit_pps, memcpy_pps and ratio_to_memcpy
//                                        (best of the iterations; target >= 0.25)
// bench/compare_scipy.py runs fit/<method>/<open|closed>/<n> and compares with SciPy.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "bench_data.hpp"

namespace {

using fairspline::bench::register_fit;
using fairspline::bench::walk_input;

constexpr const char* kMethod = "jaklic-zagar";

// Bytes of the input points and of the output Bézier control points for n points, open curve.
std::size_t io_bytes(std::size_t n) {
  return n * sizeof(fairspline::Point) + (n - 1) * 4 * sizeof(fairspline::Point);
}

struct CopyBuffers {
  std::vector<unsigned char> src, dst;
  explicit CopyBuffers(std::size_t bytes) : src(bytes, 1), dst(bytes, 0) {}  // pre-faulted
  void copy() {
    std::memcpy(dst.data(), src.data(), src.size());
    benchmark::DoNotOptimize(dst.data());
    benchmark::ClobberMemory();
  }
};

void bm_memcpy(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  CopyBuffers buf(io_bytes(n));
  for (auto _ : state) buf.copy();
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(io_bytes(n)));
}

// fit_into and memcpy alternated, so that both see the same machine state (other processes,
// frequency); the iteration time is the fit's, the ratio uses the best time of each.
void bm_ratio(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const fairspline::FitInput& input = walk_input(n);
  CopyBuffers buf(io_bytes(n));
  fairspline::FitResult r;
  fairspline::fit_into(kMethod, input, {}, fairspline::ReportLevel::kNone, r);
  double best_fit = std::numeric_limits<double>::infinity(), best_copy = best_fit;
  using clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const auto t0 = clock::now();
    fairspline::fit_into(kMethod, input, {}, fairspline::ReportLevel::kNone, r);
    benchmark::DoNotOptimize(r.spline.segments.data());
    benchmark::ClobberMemory();
    const auto t1 = clock::now();
    buf.copy();
    const auto t2 = clock::now();
    const double fit_s = std::chrono::duration<double>(t1 - t0).count();
    best_fit = std::min(best_fit, fit_s);
    best_copy = std::min(best_copy, std::chrono::duration<double>(t2 - t1).count());
    state.SetIterationTime(fit_s);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
  state.counters["fit_pps"] = static_cast<double>(n) / best_fit;
  state.counters["memcpy_pps"] = static_cast<double>(n) / best_copy;
  state.counters["ratio_to_memcpy"] = best_copy / best_fit;
}

[[maybe_unused]] const bool kRegistered = [] {
  register_fit(kMethod, false, {1'000, 10'000, 100'000, 1'000'000});
  register_fit(kMethod, true, {1'000'000});
  register_fit(kMethod, false, {1'000'000}, 2.0 / 3.0);
  benchmark::RegisterBenchmark("memcpy/jaklic-zagar", bm_memcpy)
      ->Arg(1'000'000)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("ratio/jaklic-zagar/open", bm_ratio)
      ->Arg(1'000'000)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
