#include "detail/two_threads.hpp"

namespace fairspline::detail {

bool split_in_two(std::size_t n) {
  // hardware_concurrency reads /sys on every call.
  static const bool two_cores = std::thread::hardware_concurrency() > 1;
  return two_cores && n >= kTwoThreadPoints;
}

}  // namespace fairspline::detail
