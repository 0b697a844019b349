// Throughput of the Johnson–Johnson minimal-energy methods (points per second, kNone).
//   fit/quasi-elastic/open/{1e3, 1e4, 1e5}   the default method on random walks (turns ±120°)
//   fit/quasi-elastic/closed/1e5             periodic (cyclic LDLᵀ)
//   reference/quasi-elastic/1000             the Curve-Ensemble-like coordinate descent
//   newton/quasi-elastic/1000                fit_min_energy on the same 1000 points
// Goals (issue 6): at 1e5 points >= 2M points/s and >= half of SciPy's natural spline, which
// solves a linear system (bench/compare_scipy.py --method quasi-elastic --n 100000 --target 0.5;
// `--peer linear` times SciPy's piecewise-linear interpolant instead); at 1000 points
// >= 50x faster than the reference at equal or lower energy (counter "energy").
#include <cstdint>

#include "bench_data.hpp"
#include "fairspline/methods/min_energy.hpp"

namespace {

using fairspline::bench::register_fit;

void bm_reference(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const fairspline::FitInput& in = fairspline::bench::walk_input(n);
  fairspline::MinEnergyOptions opt;
  double energy = 0.0;
  for (auto _ : state) {
    const fairspline::MinEnergyReference r = fairspline::min_energy_reference(in, opt);
    benchmark::DoNotOptimize(r.angles.data());
    energy = r.energy;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
  state.counters["energy"] = energy;
}

void bm_newton(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const fairspline::FitInput& in = fairspline::bench::walk_input(n);
  fairspline::MinEnergyOptions opt;
  fairspline::FitResult out;
  fairspline::MinEnergyReport rep;
  for (auto _ : state) {
    fairspline::fit_min_energy(in, opt, fairspline::ReportLevel::kNone, out, &rep);
    benchmark::DoNotOptimize(out.spline.segments.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(n));
  state.counters["energy"] = rep.energy;
  state.counters["iterations"] = rep.iterations;
}

[[maybe_unused]] const bool kRegistered = [] {
  register_fit("quasi-elastic", false, {1'000, 10'000, 100'000});
  register_fit("quasi-elastic", true, {100'000});
  benchmark::RegisterBenchmark("reference/quasi-elastic", bm_reference)
      ->Arg(1'000)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("newton/quasi-elastic", bm_newton)
      ->Arg(1'000)
      ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
