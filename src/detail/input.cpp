#include "detail/input.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "fairspline/error.hpp"
#include "fairspline/parameterization.hpp"

namespace fairspline::detail {

namespace {
std::string point_text(std::size_t i, Point p) {
  return "point " + std::to_string(i) + " (" + std::to_string(p.x) + ", " + std::to_string(p.y) +
         ")";
}
}  // namespace

bool coincident(Point a, Point b) {
  // Distinguishable only if the difference exceeds a few ulps of the coordinates.
  const double scale = std::max({std::abs(a.x), std::abs(a.y), std::abs(b.x), std::abs(b.y)});
  const double tol = 4.0 * std::numeric_limits<double>::epsilon() * scale;
  return std::abs(a.x - b.x) <= tol && std::abs(a.y - b.y) <= tol;
}

namespace {
// Cheap pre-test for the loop over all points: a difference larger than 4 eps times the sum of
// the coordinates' magnitudes (>= their max) can never be coincident.
inline bool maybe_coincident(Point a, Point b) {
  const double dx = std::abs(a.x - b.x), dy = std::abs(a.y - b.y);
  const double sum = std::abs(a.x) + std::abs(a.y) + std::abs(b.x) + std::abs(b.y);
  return std::max(dx, dy) <= 4.0 * std::numeric_limits<double>::epsilon() * sum;
}
}  // namespace

void check_tangent(Vec2 v, const char* what, std::size_t index) {
  if (!is_finite(v)) {
    throw Error(ErrorCode::kNonFinite, std::string(what) + " is not finite", index);
  }
  if (v.x == 0.0 && v.y == 0.0) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + " is the zero vector", index);
  }
}

std::size_t prepare_input(const FitInput& input, const InputRequirements& req, FitResult& out) {
  out.closed = input.closed;
  const auto& pts = input.points;
  std::size_t n = pts.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_finite(pts[i])) {
      throw Error(ErrorCode::kNonFinite, "point " + std::to_string(i) + " has a NaN or infinite "
                                         "coordinate", i);
    }
  }
  // A closed curve given with its first point repeated at the end: drop the duplicate.
  if (input.closed && n >= 2 && coincident(pts[0], pts[n - 1])) --n;
  const std::size_t need = input.closed ? req.min_points_closed : req.min_points_open;
  if (n < need) {
    throw Error(ErrorCode::kTooFewPoints,
                std::string(req.method) + " needs at least " + std::to_string(need) +
                    " distinct points for " + (input.closed ? "a closed" : "an open") +
                    " curve, got " + std::to_string(n));
  }
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (maybe_coincident(pts[i], pts[i + 1]) && coincident(pts[i], pts[i + 1])) {
      throw Error(ErrorCode::kRepeatedPoint,
                  point_text(i + 1, pts[i + 1]) + " repeats point " + std::to_string(i) +
                      "; remove consecutive duplicates",
                  i + 1);
    }
  }
  if (input.closed && coincident(pts[n - 1], pts[0])) {
    throw Error(ErrorCode::kRepeatedPoint,
                point_text(n - 1, pts[n - 1]) + " repeats the first point", n - 1);
  }
  if (!input.tangents.empty() && input.tangents.size() != pts.size() &&
      input.tangents.size() != n) {
    throw Error(ErrorCode::kInvalidArgument,
                "tangents has " + std::to_string(input.tangents.size()) +
                    " entries but there are " + std::to_string(n) + " points");
  }
  for (std::size_t i = 0; i < std::min(input.tangents.size(), n); ++i) {
    if (input.tangents[i]) check_tangent(*input.tangents[i], "tangent", i);
  }
  if (!input.kinds.empty() && input.kinds.size() != pts.size() && input.kinds.size() != n) {
    throw Error(ErrorCode::kInvalidArgument, "kinds has " + std::to_string(input.kinds.size()) +
                                                 " entries but there are " + std::to_string(n) +
                                                 " points");
  }
  for (std::size_t i = 0; i < std::min(input.kinds.size(), n); ++i) {
    if (input.kinds[i] == PointKind::kClamped &&
        (i >= input.tangents.size() || !input.tangents[i])) {
      throw Error(ErrorCode::kInvalidArgument,
                  "point " + std::to_string(i) + " is clamped but has no tangent", i);
    }
  }
  if (input.start_tangent) check_tangent(*input.start_tangent, "start tangent", 0);
  if (input.end_tangent) check_tangent(*input.end_tangent, "end tangent", n - 1);
  if (input.closed && input.end_tangent) {
    throw Error(ErrorCode::kInvalidArgument,
                "a closed curve has no end tangent; clamp a point with kinds/tangents or use the "
                "start tangent");
  }

  out.points.assign(pts.begin(), pts.begin() + static_cast<std::ptrdiff_t>(n));
  if (!input.knots.empty()) {
    validate_knots(input.knots, n, input.closed);
    out.knots.assign(input.knots.begin(), input.knots.end());
  } else {
    alpha_knots(out.points, input.alpha, input.closed, out.knots);
  }
  return out.knots.size() - 1;
}

}  // namespace fairspline::detail
