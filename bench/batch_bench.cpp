// Batch throughput (issue 8): 10^6 curves of 20 points each fitted with jaklic-zagar at
// ReportLevel::kNone through fairspline::fit_many, in curves per second; the goal is a scaling
// of at least 1.8x from 1 to 2 threads. Run with
//   build/bench/fairspline_bench --benchmark_filter=batch/
//   batch/fit_many/jaklic-zagar/20pt/1e6/threads:T
//       one fit_many call per iteration; the time is the call's wall time (manual time, so
//       destroying the 10^6 results afterwards is not in it: counter free_s shows that part;
//       cold_s is the first call of the process, untimed, see warm_up)
//   batch/reuse/jaklic-zagar/20pt/1e6/threads:T
//       the same fits through parallel_for with one FitResult per thread reused by fit_into
//       (what `fairspline batch` does): no result memory to allocate, fill and keep, so this
//       is the scaling of the fitting itself
//   batch/scaling/jaklic-zagar/20pt/1e6
//       1 and 2 threads alternated in every iteration (so both see the same machine: other
//       processes, frequency); counters curves_per_s_1, curves_per_s_2 (fit_many, best of the
//       iterations) and scaling = their ratio; reuse_scaling the same for batch/reuse. On a
//       shared machine the second core may be busy: machine_scaling is the ratio for a
//       compute-only loop (no memory, no allocation) timed alongside, i.e. the parallelism
//       the machine offered meanwhile.
// The curves are 20-point pieces of one random walk (bench_data.hpp's distribution), each
// starting at the origin; they are made once, outside every timing.
// Reading the numbers: fit_many returns 10^6 FitResults (~3 GB, ~20 allocations each), so it
// is bound by allocating and first touching memory, and its times depend on what the heap
// holds from the previous call (a 1-thread run after a 2-thread one finds half the freed
// memory in the other thread's arena). Compare thread counts in separate processes, e.g.
// --benchmark_filter='batch/fit_many/.*threads:1/' --benchmark_repetitions=3, and take the
// best; batch/reuse shows what the fitting itself scales to.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bench_data.hpp"
#include "fairspline/batch.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using fairspline::BatchJob;
using fairspline::BatchOptions;
using fairspline::BatchOutcome;

constexpr std::size_t kCurves = 1'000'000;
constexpr std::size_t kPoints = 20;
constexpr const char* kMethod = "jaklic-zagar";

const std::vector<BatchJob>& jobs() {
  static const std::vector<BatchJob> all = [] {
    namespace b = fairspline::bench;
    std::mt19937_64 rng(b::kDefaultSeed);
    const double max_turn = b::kMaxTurnDeg * std::numbers::pi / 180.0;
    std::uniform_real_distribution<double> turn(-max_turn, max_turn);
    std::uniform_real_distribution<double> step(b::kMinStep, b::kMaxStep);
    std::vector<BatchJob> v(kCurves);
    double heading = 0.0;
    for (BatchJob& job : v) {
      job.method = kMethod;
      job.input.points.reserve(kPoints);
      fairspline::Point p{0.0, 0.0};
      for (std::size_t i = 0; i < kPoints; ++i) {
        job.input.points.push_back(p);
        heading += turn(rng);
        p += step(rng) * fairspline::from_angle(heading);
      }
    }
    return v;
  }();
  return all;
}

/// How the 10^6 curves are fitted.
enum class Way {
  kFitMany,  ///< fit_many: a fresh FitResult per curve, all returned
  kReuse,    ///< parallel_for + fit_into into one FitResult per thread
};

/// Fits every curve once; returns the wall time in seconds and sets `free_seconds` to the time
/// taken to destroy fit_many's outcomes afterwards. Returns a negative number if a fit failed.
double time_fits(Way way, unsigned threads, double& free_seconds) {
  free_seconds = 0.0;
  if (way == Way::kReuse) {
    std::atomic<std::size_t> bad{0};
    const auto t0 = Clock::now();
    fairspline::parallel_for(jobs().size(), threads, [&](std::size_t i) {
      thread_local fairspline::FitResult result;
      fairspline::fit_into(kMethod, jobs()[i].input, jobs()[i].options,
                           fairspline::ReportLevel::kNone, result);
      if (result.spline.segments.size() != kPoints - 1) bad.fetch_add(1);
    });
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return bad.load() == 0 ? seconds : -1.0;
  }
  BatchOptions options;
  options.threads = threads;
  options.fit.level = fairspline::ReportLevel::kNone;
  const auto t0 = Clock::now();
  std::vector<BatchOutcome> out = fairspline::fit_many(jobs(), options);
  const auto t1 = Clock::now();
  benchmark::DoNotOptimize(out.data());
  const bool ok = std::all_of(out.begin(), out.end(), [](const BatchOutcome& o) {
    return o.result.has_value() && o.result->spline.segments.size() == kPoints - 1;
  });
  const auto t2 = Clock::now();
  out = {};
  free_seconds = std::chrono::duration<double>(Clock::now() - t2).count();
  return ok ? std::chrono::duration<double>(t1 - t0).count() : -1.0;
}

/// Wall time of `threads` threads each running the same fixed arithmetic loop (registers only):
/// the reference for how many cores the machine gives us right now.
double time_spin(unsigned threads) {
  const auto spin = [] {
    double x = 0.0;
    for (int i = 0; i < 100'000'000; ++i) {
      x = x * 0.999999 + 1e-9;
      benchmark::DoNotOptimize(x);
    }
  };
  const auto t0 = Clock::now();
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(spin);
  spin();
  for (std::thread& t : pool) t.join();
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The first fit_many of a process also pays for the first touch of its ~3 GB of results
/// (page faults, very slow on some virtual machines): done untimed, its time is counter cold_s.
bool warm_up(benchmark::State& state, Way way, unsigned threads) {
  double free_seconds = 0.0;
  const double cold = time_fits(way, threads, free_seconds);
  if (cold < 0) {
    state.SkipWithError("a curve failed to fit");
    return false;
  }
  state.counters["cold_s"] = cold;
  return true;
}

void bm_fits(benchmark::State& state, Way way) {
  const auto threads = static_cast<unsigned>(state.range(0));
  if (!warm_up(state, way, threads)) return;
  double free_total = 0.0;
  for (auto _ : state) {
    double free_seconds = 0.0;
    const double seconds = time_fits(way, threads, free_seconds);
    if (seconds < 0) {
      state.SkipWithError("a curve failed to fit");
      return;
    }
    state.SetIterationTime(seconds);
    free_total += free_seconds;
  }
  const auto curves = static_cast<std::int64_t>(state.iterations() * kCurves);
  state.SetItemsProcessed(curves);
  state.counters["curves_per_s"] =
      benchmark::Counter(static_cast<double>(curves), benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
  if (way == Way::kFitMany) {
    state.counters["free_s"] = free_total / static_cast<double>(state.iterations());
  }
}

void bm_scaling(benchmark::State& state) {
  if (!warm_up(state, Way::kFitMany, 2)) return;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // best[way][threads]; way 2 is the spin loop.
  double best[3][3] = {{0, kInf, kInf}, {0, kInf, kInf}, {0, kInf, kInf}};
  bool two_first = false;
  for (auto _ : state) {
    double fit_many_two = 0.0;
    for (const unsigned threads : {two_first ? 2u : 1u, two_first ? 1u : 2u}) {
      for (const Way way : {Way::kFitMany, Way::kReuse}) {
        double free_seconds = 0.0;
        const double seconds = time_fits(way, threads, free_seconds);
        if (seconds < 0) {
          state.SkipWithError("a curve failed to fit");
          return;
        }
        double& b = best[static_cast<int>(way)][threads];
        b = std::min(b, seconds);
        if (way == Way::kFitMany && threads == 2) fit_many_two = seconds;
      }
      best[2][threads] = std::min(best[2][threads], time_spin(threads));
    }
    two_first = !two_first;
    state.SetIterationTime(fit_many_two);
  }
  const auto n = static_cast<double>(kCurves);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kCurves));
  state.counters["curves_per_s_1"] = n / best[0][1];
  state.counters["curves_per_s_2"] = n / best[0][2];
  state.counters["scaling"] = best[0][1] / best[0][2];
  state.counters["reuse_curves_per_s_1"] = n / best[1][1];
  state.counters["reuse_curves_per_s_2"] = n / best[1][2];
  state.counters["reuse_scaling"] = best[1][1] / best[1][2];
  // Two threads do twice the work of one in the spin loop.
  state.counters["machine_scaling"] = 2.0 * best[2][1] / best[2][2];
}

[[maybe_unused]] const bool kRegistered = [] {
  for (const auto& [name, way] :
       {std::pair{"batch/fit_many/", Way::kFitMany}, std::pair{"batch/reuse/", Way::kReuse}}) {
    benchmark::RegisterBenchmark((std::string(name) + kMethod + "/20pt/1e6").c_str(), bm_fits, way)
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("batch/scaling/jaklic-zagar/20pt/1e6", bm_scaling)
      ->UseManualTime()
      ->Iterations(5)
      ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
