// Shared input checks of all methods (private).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string_view>
#include <vector>

#include "fairspline/fit.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::detail {

/// Checks the input against what the method accepts (`caps`, declared once per method and
/// shown in its registry entry; `method` names it in messages) and writes the points to
/// interpolate and their knots into `out.points`, `out.knots` (points.size(), +1 when closed)
/// and sets `out.closed`, reusing capacity. Throws Error with the offending index for too few
/// points, NaN/Inf, consecutive repeated points, bad tangents/kinds arrays, bad knots, a closed
/// curve or a point kind the method does not honour, a point count off the method's rule
/// (unless `count_rule_relaxed`, the option PointCountRule::relaxed_by being set) and missing
/// tangents of a Hermite method. The closing point of a closed curve equal to the first one is
/// dropped silently. Returns the number of spans.
std::size_t prepare_input(const FitInput& input, const Capabilities& caps, std::string_view method,
                          FitResult& out, bool count_rule_relaxed = false);

/// FitInput::radii: empty or one entry per point (n: without a closed curve's repeated end
/// point), each finite (kNonFinite) and non-negative (kInvalidArgument), naming the point.
void check_radii(const FitInput& input, std::size_t n);

/// The point checks of prepare_input alone (NaN/Inf, consecutive repeated points, a closed
/// curve's last point on its first), with the same messages and indices.
void check_points(const FitInput& input);

/// True when a and b are equal to within rounding of their coordinates' magnitude (inline: a
/// per-span check of yong-cheng's COH dispatch, 1% of it as a call).
inline bool coincident(Point a, Point b) {
  // Distinguishable only if the difference exceeds a few ulps of the coordinates.
  const double scale = std::max({std::abs(a.x), std::abs(a.y), std::abs(b.x), std::abs(b.y)});
  const double tol = 4.0 * std::numeric_limits<double>::epsilon() * scale;
  return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol;
}

/// Checks a user tangent (start/end/per-point): finite and non-zero. `what` names it.
void check_tangent(Vec2 v, const char* what, std::size_t index);

}  // namespace fairspline::detail
