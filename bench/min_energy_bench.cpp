// Throughput of the Johnson–Johnson minimal-energy methods (points per second, kNone).
//   fit/quasi-elastic/open/{1e3, 1e4, 1e5, 1e6}   the default method on random walks (±120°)
//   fit/quasi-elastic/closed/1e5             periodic (cyclic LDLᵀ)
//   reference/quasi-elastic/1000             the Curve-Ensemble-like coordinate descent
//   newton/quasi-elastic/1000                fit_min_energy on the same 1000 points
// Goals (issue 6): at 1e5 points >= 2M points/s and >= half of SciPy's natural spline, which
// solves a linear system (bench/compare_scipy.py --method quasi-elastic --n 100000 --target 0.5;
// `--peer linear` times SciPy's piecewise-linear interpolant instead); at 1000 points
// >= 50x faster than the reference at equal or lower energy (counter "energy").
#include "bench_data.hpp"
#include "min_energy_runs.hpp"

namespace {

using fairspline::bench::register_fit;

[[maybe_unused]] const bool kRegistered = [] {
  register_fit("quasi-elastic", false, {1'000, 10'000, 100'000, 1'000'000});
  register_fit("quasi-elastic", true, {100'000});
  fairspline::bench::register_min_energy_runs("quasi-elastic", {}, 1'000);
  return true;
}();

}  // namespace
