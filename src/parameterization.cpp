#include "fairspline/parameterization.hpp"

#include <cmath>
#include <string>

#include "fairspline/error.hpp"

namespace fairspline {

namespace {
// |d|^alpha with fast paths for the common exponents (pow is ~10x slower than sqrt). The
// squared norm under/overflows for |d| outside ~[1e-150, 1e150]: fall back to hypot there.
inline double safe_norm(Vec2 d) {
  const double d2 = d.x * d.x + d.y * d.y;
  if (d2 > 1e-290 && d2 < 1e290) return std::sqrt(d2);
  return std::hypot(d.x, d.y);
}

template <int Kind>
double span_length(Vec2 d, double alpha) {
  if constexpr (Kind == 0) {
    (void)d;
    (void)alpha;
    return 1.0;
  } else if constexpr (Kind == 1) {
    (void)alpha;
    return std::sqrt(safe_norm(d));
  } else if constexpr (Kind == 2) {
    (void)alpha;
    return safe_norm(d);
  } else {
    return std::pow(norm(d), alpha);
  }
}

template <int Kind>
void fill_knots(std::span<const Point> points, double alpha, bool closed, std::vector<double>& t) {
  const std::size_t n = points.size();
  const std::size_t spans = closed ? n : n - 1;
  t.resize(spans + 1);
  t[0] = 0.0;
  for (std::size_t i = 0; i < spans; ++i) {
    const Vec2 d = points[i + 1 == n ? 0 : i + 1] - points[i];
    const double h = span_length<Kind>(d, alpha);
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

void alpha_knots(std::span<const Point> points, double alpha, bool closed,
                 std::vector<double>& t) {
  if (!(alpha >= 0.0 && alpha <= 1.0)) {
    throw Error(ErrorCode::kBadOption,
                "alpha must be in [0, 1] (0 uniform, 0.5 centripetal, 1 chordal), got " +
                    std::to_string(alpha));
  }
  if (points.size() < (closed ? 3u : 2u)) {
    throw Error(ErrorCode::kTooFewPoints, closed ? "a closed curve needs at least 3 points"
                                                 : "a curve needs at least 2 points");
  }
  if (alpha == 0.0) {
    fill_knots<0>(points, alpha, closed, t);
  } else if (alpha == 0.5) {
    fill_knots<1>(points, alpha, closed, t);
  } else if (alpha == 1.0) {
    fill_knots<2>(points, alpha, closed, t);
  } else {
    fill_knots<3>(points, alpha, closed, t);
  }
}

void validate_knots(std::span<const double> knots, std::size_t point_count, bool closed) {
  const std::size_t expected = closed ? point_count + 1 : point_count;
  if (knots.size() != expected) {
    throw Error(ErrorCode::kInvalidArgument,
                "expected " + std::to_string(expected) + " knots for " +
                    std::to_string(point_count) + (closed ? " points of a closed curve (one more "
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
                  "knots must increase strictly: knot " + std::to_string(i) + " is not greater "
                  "than knot " + std::to_string(i - 1), i);
    }
  }
}

}  // namespace fairspline
