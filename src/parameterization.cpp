#include "fairspline/parameterization.hpp"

#include <cmath>
#include <string>

#include "detail/format.hpp"
#include "detail/knots.hpp"
#include "fairspline/error.hpp"

namespace fairspline {

namespace {

template <detail::AlphaKind Kind>
void fill_knots(std::span<const Point> points, double alpha, bool closed, std::vector<double>& t) {
  const std::size_t n = points.size();
  const std::size_t spans = closed ? n : n - 1;
  t.resize(spans + 1);
  t[0] = 0.0;
  for (std::size_t i = 0; i < spans; ++i) {
    const Vec2 d = points[i + 1 == n ? 0 : i + 1] - points[i];
    const double h = detail::span_length<Kind>(d, alpha);
    if (!std::isfinite(h) || !std::isfinite(t[i] + h)) {
      throw Error(ErrorCode::kNonFinite,
                  "the knot interval after point " + std::to_string(i) +
                      " overflows double precision; scale the data down",
                  i + 1 == n ? 0 : i + 1);
    }
    if (!(h > 0.0)) {
      throw Error(ErrorCode::kRepeatedPoint,
                  "points " + std::to_string(i) + " and " + std::to_string(i + 1 == n ? 0 : i + 1) +
                      " give a zero-length knot interval",
                  i + 1 == n ? 0 : i + 1);
    }
    t[i + 1] = t[i] + h;
  }
}
}  // namespace

std::vector<double> alpha_knots(std::span<const Point> points, double alpha, bool closed) {
  std::vector<double> t;
  alpha_knots(points, alpha, closed, t);
  return t;
}

void alpha_knots(std::span<const Point> points, double alpha, bool closed, std::vector<double>& t) {
  if (!(alpha >= 0.0 && alpha <= 1.0)) {
    throw Error(ErrorCode::kBadOption,
                "alpha must be in [0, 1] (0 uniform, 0.5 centripetal, 1 chordal), got " +
                    detail::format_number(alpha));
  }
  if (points.size() < (closed ? 3u : 2u)) {
    throw Error(ErrorCode::kTooFewPoints, closed ? "a closed curve needs at least 3 points"
                                                 : "a curve needs at least 2 points");
  }
  detail::with_alpha_kind(alpha,
                          [&](auto kind) { fill_knots<kind.value>(points, alpha, closed, t); });
}

void validate_knots(std::span<const double> knots, std::size_t point_count, bool closed) {
  const std::size_t expected = closed ? point_count + 1 : point_count;
  if (knots.size() != expected) {
    throw Error(ErrorCode::kInvalidArgument, "expected " + std::to_string(expected) +
                                                 " knots for " + std::to_string(point_count) +
                                                 (closed ? " points of a closed curve (one more "
                                                           "for the closing span), got "
                                                         : " points, got ") +
                                                 std::to_string(knots.size()));
  }
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) {
      throw Error(ErrorCode::kNonFinite, "knot " + std::to_string(i) + " is not finite", i);
    }
    if (i > 0 && !(knots[i] > knots[i - 1])) {
      throw Error(ErrorCode::kInvalidArgument,
                  "knots must increase strictly: knot " + std::to_string(i) +
                      " is not greater "
                      "than knot " +
                      std::to_string(i - 1),
                  i);
    }
  }
}

}  // namespace fairspline
