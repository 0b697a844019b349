// Throughput of the Li methods (points per second, ReportLevel::kNone).
//   fit/li-strain/open/{1e3..1e6}   natural C2 spline on centripetal knots
//   fit/li-combined/open/1e6        default weights [1, 1]
//   fit/li-strain/closed/1e6        periodic spline (cyclic system)
// bench/compare_scipy.py runs fit/<method>/<open|closed>/<n> and compares with SciPy.
#include <cstdint>

#include "bench_data.hpp"

namespace {

using fairspline::bench::register_fit;

[[maybe_unused]] const bool kRegistered = [] {
  register_fit("li-strain", false, {1'000, 10'000, 100'000, 1'000'000});
  register_fit("li-combined", false, {1'000'000});
  register_fit("li-strain", true, {1'000'000});
  return true;
}();

}  // namespace
