// Long passes over the points, split in two halves with one on a helper thread. One core does
// not reach the memory's speed on them (a 10^6-point refit: the copy, the knots and the scans
// before the fit are half of the time once the fit itself is split), and the halves do the
// same operations per point, so the results are the same bits on one thread or two.
#pragma once

#include <cstddef>
#include <exception>
#include <thread>

namespace fairspline::detail {

/// Below this many points a thread's start (~50 µs) is not worth it.
inline constexpr std::size_t kTwoThreadPoints = std::size_t{1} << 17;

/// Whether a pass over n points is split (n >= kTwoThreadPoints and a second core).
bool split_in_two(std::size_t n);

/// half(1) on a helper thread and half(0) on this one. An exception of half(0) is rethrown in
/// preference to one of half(1) (the first half's error names the lower index).
template <class F>
void on_two_threads(F&& half) {
  std::exception_ptr second;
  std::thread helper([&] {
    try {
      half(1);
    } catch (...) {
      second = std::current_exception();
    }
  });
  try {
    half(0);
  } catch (...) {
    helper.join();
    throw;
  }
  helper.join();
  if (second) std::rethrow_exception(second);
}

}  // namespace fairspline::detail
