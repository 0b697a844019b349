// Data balls (issue 19) next to interpolation on the same points: noisy samples of a circle
// (noise up to a fifth of the spacing, radius = the noise amplitude), n = 10³ and 10⁵.
//   fit/balls/{1e3, 1e5}        quasi-elastic through the discs (positions optimized)
//   fit/interpolate/{1e3, 1e5}  quasi-elastic through the noisy points themselves
// Counters: points/s; "iterations" (Newton steps of the ball optimizer, barrier and exact
// phases), "active" (discs the curve touches), "energy" (E of the fit).
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "bench_data.hpp"

namespace {

using fairspline::FitInput;

const FitInput& noisy_circle(std::size_t n, bool balls) {
  static std::map<std::pair<std::size_t, bool>, FitInput> cache;
  auto [it, fresh] = cache.try_emplace({n, balls});
  if (!fresh) return it->second;
  FitInput& in = it->second;
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double spacing = 2 * std::numbers::pi / static_cast<double>(n), noise = 0.2 * spacing;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = spacing * static_cast<double>(i);
    in.points.push_back({std::cos(t) + noise * u(rng) / std::sqrt(2.0),
                         std::sin(t) + noise * u(rng) / std::sqrt(2.0)});
  }
  in.closed = true;
  if (balls) in.radii.assign(n, noise);
  return in;
}

void BM_Fit(benchmark::State& state, bool balls) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const FitInput& in = noisy_circle(n, balls);
  fairspline::FitResult r;
  for (auto _ : state) {
    fairspline::fit_into("quasi-elastic", in, nlohmann::json::object(),
                         fairspline::FitOptions{.level = fairspline::ReportLevel::kNone}, r);
    benchmark::DoNotOptimize(r.spline.segments.data());
  }
  state.counters["points/s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["energy"] = r.method_report.value("energy", 0.0);
  if (balls) {
    const auto& b = r.method_report.at("balls");
    state.counters["iterations"] = b.at("iterations").get<double>();
    state.counters["active"] = static_cast<double>(b.at("active").size());
  }
}

BENCHMARK_CAPTURE(BM_Fit, balls, true)
    ->Name("fit/balls")
    ->Arg(1'000)
    ->Arg(100'000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_Fit, interpolate, false)
    ->Name("fit/interpolate")
    ->Arg(1'000)
    ->Arg(100'000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
