// Shared input checks of all methods (private).
#pragma once

#include <cstddef>
#include <vector>

#include "fairspline/fit.hpp"

namespace fairspline::detail {

/// Minimum point counts of a method.
struct InputRequirements {
  std::size_t min_points_open = 2;
  std::size_t min_points_closed = 3;
  const char* method = "this method";
};

/// Checks the input and writes the points to interpolate and their knots into `out.points`,
/// `out.knots` (points.size(), +1 when closed) and sets `out.closed`, reusing capacity.
/// Throws Error with the offending index for too few points, NaN/Inf, consecutive repeated
/// points, bad tangents/kinds arrays or bad knots. The closing point of a closed curve equal to
/// the first one is dropped silently. Returns the number of spans.
std::size_t prepare_input(const FitInput& input, const InputRequirements& req, FitResult& out);

/// True when a and b are equal to within rounding of their coordinates' magnitude.
bool coincident(Point a, Point b);

/// Checks a user tangent (start/end/per-point): finite and non-zero. `what` names it.
void check_tangent(Vec2 v, const char* what, std::size_t index);

}  // namespace fairspline::detail
