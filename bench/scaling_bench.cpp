// Work proportional to n for every registered method (issue 9: "no fit runs longer than a bound
// proportional to n"). Each method fits a gentle wave, adapted to what its capabilities declare
// (tests/capability_inputs.hpp) at n = 1e3 .. 1e6 points without a report; Google Benchmark fits
// time = c·n and prints the coefficient and the RMS of the relative residuals
// (scaling/<method>_BigO, _RMS): an RMS of a few percent means linear time.
//   scaling/<method>/<n>          fit, ReportLevel::kNone
//   scaling-report/<method>/<n>   fit + full report (self-intersection search included)
//   retrace-report/<n>            full report of a curve that retraces itself n times (points
//                                 alternating between two places: O(n²) coinciding pairs, each
//                                 searched with a shrinking cell budget)
//   report-cost/<level>           the default method on a 10^5-point random walk with each
//                                 report level; counter x_fit: its time over the fit's alone,
//                                 measured in the same run (goal: the default level ≤ 3)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "bench_data.hpp"
#include "capability_inputs.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/registry.hpp"

namespace {

using fairspline::FitInput;
using fairspline::FitResult;
using fairspline::ReportLevel;

FitInput wave(std::size_t n) {
  FitInput in;
  in.points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = static_cast<double>(i);
    in.points.push_back({0.5 * x, std::sin(0.05 * x)});
  }
  return in;
}

nlohmann::json options_for(const std::string& method) {
  return fairspline::testing::options_for_any_points(fairspline::find_method(method));
}

FitInput input_for(const std::string& method, std::size_t n) {
  FitInput in = wave(n);
  fairspline::testing::clamp_if_needed(fairspline::find_method(method), in);
  return in;
}

void bm_fit(benchmark::State& state, const std::string& method, ReportLevel level) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const FitInput in = input_for(method, n);
  const nlohmann::json options = options_for(method);
  FitResult out;
  for (auto _ : state) {
    fairspline::fit_into(method, in, options, level, out);
    benchmark::DoNotOptimize(out.spline.segments.data());
  }
  state.SetComplexityN(state.range(0));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
}

void bm_retrace(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  FitInput in;
  in.closed = true;
  in.points = {{0, 0}, {129, 0}, {131.625, 64.5}, {154.75, 28532}, {14769.5, 13896.5}};
  for (std::size_t i = 0; i < n; ++i) {
    in.points.push_back(i % 2 == 0 ? fairspline::Point{29384.25, -739}
                                   : fairspline::Point{43999, -15374.5});
  }
  FitResult out;
  for (auto _ : state) {
    fairspline::fit_into("min-energy", in, nlohmann::json::object(), ReportLevel::kFull, out);
    benchmark::DoNotOptimize(out.report->intersections.data());
  }
  state.SetComplexityN(state.range(0));
}

void bm_report_cost(benchmark::State& state, ReportLevel level) {
  const FitInput& in = fairspline::bench::walk_input(100'000);
  const nlohmann::json options = nlohmann::json::object();
  FitResult out;
  using Clock = std::chrono::steady_clock;
  auto best_of = [&](ReportLevel l, int runs) {
    double best = HUGE_VAL;
    for (int r = 0; r < runs; ++r) {
      const Clock::time_point t0 = Clock::now();
      fairspline::fit_into("quasi-elastic", in, options, l, out);
      best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    return best;
  };
  const double fit_alone = best_of(ReportLevel::kNone, 5);
  double with_report = HUGE_VAL;
  for (auto _ : state) {
    const Clock::time_point t0 = Clock::now();
    fairspline::fit_into("quasi-elastic", in, options, level, out);
    with_report = std::min(with_report, std::chrono::duration<double>(Clock::now() - t0).count());
    benchmark::DoNotOptimize(out.spline.segments.data());
  }
  state.counters["x_fit"] = with_report / fit_alone;
}

void register_scaling(const std::string& prefix, const std::string& method, ReportLevel level,
                      std::int64_t max_n) {
  auto* b = benchmark::RegisterBenchmark(
      (prefix + method).c_str(),
      [method, level](benchmark::State& s) { bm_fit(s, method, level); });
  for (std::int64_t n = 1'000; n <= max_n; n *= 10) b->Arg(n);
  b->Complexity(benchmark::oN)->Unit(benchmark::kMillisecond);
}

[[maybe_unused]] const bool kRegistered = [] {
  for (const fairspline::MethodInfo& m : fairspline::methods()) {
    register_scaling("scaling/", m.name, ReportLevel::kNone, 1'000'000);
    register_scaling("scaling-report/", m.name, ReportLevel::kFull, 100'000);
  }
  for (const auto& [name, level] : {std::pair{"none", ReportLevel::kNone},
                                    {"basic", ReportLevel::kBasic},
                                    {"full", ReportLevel::kFull}}) {
    benchmark::RegisterBenchmark((std::string("report-cost/") + name).c_str(),
                                 [level](benchmark::State& s) { bm_report_cost(s, level); })
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("retrace-report", bm_retrace)
      ->Arg(40)
      ->Arg(80)
      ->Arg(160)
      ->Complexity()
      ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
