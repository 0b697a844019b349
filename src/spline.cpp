#include "fairspline/spline.hpp"

#include <algorithm>
#include <cmath>

#include "detail/format.hpp"
#include "fairspline/error.hpp"

namespace fairspline {

double Spline::t_begin() const {
  if (segments.empty()) throw Error(ErrorCode::kInvalidArgument, "the spline has no segments");
  return segments.front().t0;
}

double Spline::t_end() const {
  if (segments.empty()) throw Error(ErrorCode::kInvalidArgument, "the spline has no segments");
  return segments.back().t1;
}

void Spline::check_parameter(double t, std::optional<std::size_t> index) const {
  const double a = t_begin(), b = t_end();
  if (!(t >= a && t <= b)) {
    throw Error(ErrorCode::kInvalidArgument,
                "parameter t = " + detail::format_number(t) + " is outside the curve's range [" +
                    detail::format_number(a) + ", " + detail::format_number(b) + "]",
                index);
  }
}

std::size_t Spline::segment_index(double t) const {
  if (segments.empty()) throw Error(ErrorCode::kInvalidArgument, "the spline has no segments");
  // First segment whose end is beyond t; joints go to the later piece.
  auto it = std::upper_bound(segments.begin(), segments.end(), t,
                             [](double value, const Segment& s) { return value < s.t1; });
  if (it == segments.end()) return segments.size() - 1;
  return static_cast<std::size_t>(it - segments.begin());
}

double Spline::local_parameter(std::size_t k, double t) const {
  const Segment& s = segments[k];
  const double u = (t - s.t0) / (s.t1 - s.t0);
  return std::clamp(u, 0.0, 1.0);
}

Point Spline::eval(double t) const {
  check_parameter(t);
  const std::size_t k = segment_index(t);
  return segments[k].bezier.eval(local_parameter(k, t));
}

Vec2 Spline::derivative(double t, int order) const {
  check_parameter(t);
  const std::size_t k = segment_index(t);
  const Segment& s = segments[k];
  const double u = local_parameter(k, t);
  const double inv = 1.0 / (s.t1 - s.t0);
  switch (order) {
    case 1:
      return inv * s.bezier.d1(u);
    case 2:
      return (inv * inv) * s.bezier.d2(u);
    case 3:
      return (inv * inv * inv) * s.bezier.d3();
    default:
      if (order > 3) return {0.0, 0.0};
      throw Error(ErrorCode::kInvalidArgument, "derivative order must be at least 1");
  }
}

double Spline::curvature(double t) const {
  check_parameter(t);
  const std::size_t k = segment_index(t);
  return segments[k].bezier.curvature(local_parameter(k, t));
}

std::vector<Point> Spline::sample(std::size_t count) const {
  if (count < 2) throw Error(ErrorCode::kInvalidArgument, "sample count must be at least 2");
  std::vector<Point> out;
  out.reserve(count);
  const double a = t_begin(), b = t_end();
  for (std::size_t i = 0; i < count; ++i) {
    const double t = (i + 1 == count) ? b : a + (b - a) * static_cast<double>(i) / (count - 1);
    out.push_back(eval(t));
  }
  return out;
}

}  // namespace fairspline
