#include "fairspline/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "detail/bernstein.hpp"
#include "detail/format.hpp"
#include "detail/normalize.hpp"
#include "detail/scale.hpp"
#include "fairspline/energy.hpp"
#include "fairspline/error.hpp"

namespace fairspline {

namespace {

using detail::format_number;

// Lengths and distances square the coordinates, which leaves the double range near 1e±154:
// such curves are measured on a copy scaled by a power of two (exact: the same bits wherever
// the original computation neither overflows nor underflows) and the results scaled back.
class UnitSpline {
 public:
  /// `also`: a point the computation meets too (a query), counted in the scale.
  explicit UnitSpline(const Spline& s, std::optional<Point> also = std::nullopt) : original_(s) {
    std::vector<Vec2> points;
    points.reserve(4 * s.segments.size() + 1);
    if (also) points.push_back(*also);
    for (const Segment& g : s.segments)
      points.insert(points.end(), g.bezier.p.begin(), g.bezier.p.end());
    const int ex = detail::scale_exponent(points);
    if (std::abs(ex) <= detail::kNormalRange) return;
    ex_ = ex;
    copy_ = s;
    for (Segment& g : copy_->segments) {
      for (Point& p : g.bezier.p) p = detail::scaled(p, -ex);
    }
  }
  const Spline& get() const { return copy_ ? *copy_ : original_; }
  double down(double v) const { return std::scalbn(v, -ex_); }
  Point down(Point p) const { return detail::scaled(p, -ex_); }
  /// A length or distance back in the curve's units; Error when it overflows there.
  double up(double v) const {
    const double out = std::scalbn(v, ex_);
    if (!std::isfinite(out)) {
      throw Error(ErrorCode::kNonFinite,
                  "the curve's length or distance exceeds the range of floating-point numbers");
    }
    return out;
  }
  Point up(Point p) const { return detail::scaled(p, ex_); }

 private:
  const Spline& original_;
  std::optional<Spline> copy_;
  int ex_ = 0;
};

void check_not_empty(const Spline& s) {
  if (s.segments.empty()) throw Error(ErrorCode::kInvalidArgument, "the curve has no pieces");
}

void check_accuracy(double accuracy) {
  if (!(accuracy > 0.0 && accuracy < 1.0)) {
    throw Error(
        ErrorCode::kInvalidArgument,
        "the arc-length accuracy must be a number in (0, 1), got " + format_number(accuracy));
  }
}

double piece_length(const CubicBezier& b, double accuracy) {
  EnergyOptions o;
  o.accuracy = accuracy;
  return arc_length(b, o).value;
}

// Length of piece k from its start to local parameter u.
double partial_length(const Spline& s, std::size_t k, double u, double accuracy) {
  if (u <= 0.0) return 0.0;
  const CubicBezier& b = s.segments[k].bezier;
  return piece_length(u >= 1.0 ? b : b.subsegment(0.0, u), accuracy);
}

// Cumulative lengths at the pieces' starts, and the total last (size m + 1).
std::vector<double> cumulative_lengths(const Spline& s, double accuracy) {
  std::vector<double> cum(s.segments.size() + 1, 0.0);
  for (std::size_t k = 0; k < s.segments.size(); ++k) {
    cum[k + 1] = cum[k] + piece_length(s.segments[k].bezier, accuracy);
  }
  return cum;
}

// The local parameter u of piece k where the length from its start is r (0 <= r <= len):
// Newton on ℓ(u) − r with ℓ' = |b'(u)|, kept inside a bisection bracket.
double local_at_length(const Spline& s, std::size_t k, double r, double len, double tol,
                       double accuracy) {
  if (r <= 0.0) return 0.0;
  if (r >= len) return 1.0;
  const CubicBezier& b = s.segments[k].bezier;
  double lo = 0.0, hi = 1.0, u = r / len;
  for (int it = 0; it < 100; ++it) {
    const double g = partial_length(s, k, u, accuracy) - r;
    if (std::abs(g) <= tol) return u;
    (g < 0.0 ? lo : hi) = u;
    if (hi - lo <= 4 * std::numeric_limits<double>::epsilon()) return u;
    const double speed = norm(b.d1(u));
    double next = speed > 0.0 ? u - g / speed : -1.0;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    u = next;
  }
  return u;
}

// Distance from q to the segment [a, b].
double distance_to_segment(Point q, Point a, Point b) {
  const Vec2 ab = b - a;
  const double l2 = norm2(ab);
  if (l2 == 0.0) return distance(q, a);
  const double u = std::clamp(dot(q - a, ab) / l2, 0.0, 1.0);
  return distance(q, a + u * ab);
}

double box_distance(Point q, const BBox& box) {
  const double dx = std::max({box.min.x - q.x, 0.0, q.x - box.max.x});
  const double dy = std::max({box.min.y - q.y, 0.0, q.y - box.max.y});
  return std::hypot(dx, dy);
}

Point checked(Point p) {
  if (!is_finite(p)) {
    throw Error(ErrorCode::kNonFinite,
                "the transformed curve has a control point beyond the "
                "range of floating-point numbers");
  }
  return p;
}

}  // namespace

std::vector<double> segment_lengths(const Spline& s, double accuracy) {
  check_not_empty(s);
  check_accuracy(accuracy);
  const UnitSpline unit(s);
  std::vector<double> out;
  out.reserve(s.segments.size());
  for (const Segment& g : unit.get().segments)
    out.push_back(unit.up(piece_length(g.bezier, accuracy)));
  return out;
}

double length(const Spline& s, double accuracy) {
  check_not_empty(s);
  check_accuracy(accuracy);
  const UnitSpline unit(s);
  return unit.up(cumulative_lengths(unit.get(), accuracy).back());
}

std::vector<double> lengths_at(const Spline& s, const std::vector<double>& t, double accuracy) {
  check_not_empty(s);
  check_accuracy(accuracy);
  for (std::size_t i = 0; i < t.size(); ++i) s.check_parameter(t[i], i);
  const UnitSpline unit(s);
  const Spline& us = unit.get();
  const std::vector<double> cum = cumulative_lengths(us, accuracy);
  std::vector<double> out;
  out.reserve(t.size());
  for (double ti : t) {
    const std::size_t k = us.segment_index(ti);
    out.push_back(unit.up(cum[k] + partial_length(us, k, us.local_parameter(k, ti), accuracy)));
  }
  return out;
}

std::vector<double> parameters_at_lengths(const Spline& s, const std::vector<double>& lengths,
                                          double accuracy) {
  check_not_empty(s);
  check_accuracy(accuracy);
  const UnitSpline unit(s);
  const Spline& us = unit.get();
  const std::vector<double> cum = cumulative_lengths(us, accuracy);
  const double total = cum.back();
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    const double l = unit.down(lengths[i]);
    // Rounding of the total: a length a few ulps past it is the end.
    if (!(l >= 0.0 && l <= total * (1 + 8 * std::numeric_limits<double>::epsilon()))) {
      throw Error(ErrorCode::kInvalidArgument,
                  "arc length " + format_number(lengths[i]) + " is outside the curve's [0, " +
                      format_number(unit.up(total)) + "]",
                  i);
    }
  }
  const double tol = accuracy * total;
  std::vector<double> out;
  out.reserve(lengths.size());
  for (double given : lengths) {
    const double l = unit.down(given);
    // The piece holding l: the last whose start is at most l (a joint goes to the later piece).
    auto it = std::upper_bound(cum.begin() + 1, cum.end() - 1, l);
    const auto k = static_cast<std::size_t>(it - cum.begin()) - 1;
    const Segment& g = us.segments[k];
    const double u = local_at_length(us, k, l - cum[k], cum[k + 1] - cum[k], tol, accuracy);
    out.push_back(u >= 1.0 ? g.t1 : g.t0 + u * (g.t1 - g.t0));
  }
  return out;
}

std::vector<double> equal_length_parameters(const Spline& s, std::size_t count, double accuracy) {
  if (count < 2) {
    throw Error(ErrorCode::kInvalidArgument,
                "the number of samples must be at least 2, got " + std::to_string(count));
  }
  const double total = length(s, accuracy);
  std::vector<double> at(count);
  for (std::size_t i = 0; i < count; ++i) {
    at[i] = total * static_cast<double>(i) / static_cast<double>(count - 1);
  }
  at.back() = total;
  std::vector<double> t = parameters_at_lengths(s, at, accuracy);
  t.front() = s.t_begin();
  t.back() = s.t_end();
  return t;
}

Polyline flatten(const Spline& s, double tolerance, std::size_t max_points) {
  check_not_empty(s);
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) {
    throw Error(
        ErrorCode::kInvalidArgument,
        "the flattening tolerance must be a positive number, got " + format_number(tolerance));
  }
  const UnitSpline unit(s);
  const double tol = unit.down(tolerance);
  Polyline out;
  out.points.push_back(s.segments.front().bezier.p[0]);
  out.parameters.push_back(s.segments.front().t0);
  struct Part {
    CubicBezier b;
    double u0, u1;
  };
  std::vector<Part> stack;
  for (const Segment& g : unit.get().segments) {
    stack.push_back({g.bezier, 0.0, 1.0});
    while (!stack.empty()) {
      const Part part = stack.back();
      stack.pop_back();
      const CubicBezier& b = part.b;
      const bool flat = distance_to_segment(b.p[1], b.p[0], b.p[3]) <= tol &&
                        distance_to_segment(b.p[2], b.p[0], b.p[3]) <= tol;
      const double um = 0.5 * (part.u0 + part.u1);
      // A part that halving no longer shrinks (rounding) is as flat as doubles can make it.
      if (flat || !(um > part.u0 && um < part.u1)) {
        if (out.points.size() >= max_points) {
          throw Error(ErrorCode::kInvalidArgument,
                      "flattening to a tolerance of " + format_number(tolerance) +
                          " needs more than " + std::to_string(max_points) +
                          " points; give a larger tolerance");
        }
        out.points.push_back(unit.up(b.p[3]));
        out.parameters.push_back(part.u1 >= 1.0 ? g.t1 : g.t0 + part.u1 * (g.t1 - g.t0));
        continue;
      }
      const auto [left, right] = b.split(0.5);
      stack.push_back({right, um, part.u1});  // popped after left: vertices stay in order
      stack.push_back({left, part.u0, um});
    }
  }
  return out;
}

BBox bounds(const Spline& s) {
  check_not_empty(s);
  const UnitSpline unit(s);
  BBox box = unit.get().segments.front().bezier.bbox();
  for (const Segment& g : unit.get().segments) {
    const BBox b = g.bezier.bbox();
    box.min.x = std::min(box.min.x, b.min.x);
    box.min.y = std::min(box.min.y, b.min.y);
    box.max.x = std::max(box.max.x, b.max.x);
    box.max.y = std::max(box.max.y, b.max.y);
  }
  return {unit.up(box.min), unit.up(box.max)};
}

Projection project(const Spline& s, Point q) {
  check_not_empty(s);
  if (!is_finite(q)) {
    throw Error(ErrorCode::kNonFinite,
                "the query point " + detail::format_point(q) + " is not finite");
  }
  const UnitSpline unit(s, q);
  const Spline& us = unit.get();
  q = unit.down(q);
  Projection best;
  best.distance = std::numeric_limits<double>::infinity();
  auto consider = [&](std::size_t k, double u) {
    const Segment& g = us.segments[k];
    const Point p = g.bezier.eval(u);
    const double d = distance(p, q);
    if (d < best.distance) {
      best = {u >= 1.0 ? g.t1 : g.t0 + u * (g.t1 - g.t0), p, d, k};
    }
  };
  // Binomial weights of the Bernstein product (degree 3 times degree 2).
  static constexpr double kC3[4] = {1, 3, 3, 1}, kC2[3] = {1, 2, 1}, kC5[6] = {1, 5, 10, 10, 5, 1};
  for (std::size_t k = 0; k < us.segments.size(); ++k) {
    const CubicBezier& b = us.segments[k].bezier;
    if (box_distance(q, b.control_bbox()) >= best.distance) continue;
    consider(k, 0.0);
    consider(k, 1.0);
    // (b(u) − q)·b'(u) in Bernstein form of degree 5; its roots are the stationary points.
    const QuadBezier h = b.hodograph();
    detail::BernsteinPoly f;
    f.degree = 5;
    for (int i = 0; i <= 3; ++i) {
      for (int j = 0; j <= 2; ++j) {
        f.b[static_cast<std::size_t>(i + j)] +=
            kC3[i] * kC2[j] / kC5[i + j] *
            dot(b.p[static_cast<std::size_t>(i)] - q, h.p[static_cast<std::size_t>(j)]);
      }
    }
    const detail::BernsteinRoots roots = detail::bernstein_roots(f, 1e-14);
    for (int r = 0; r < roots.count; ++r) {
      double u = roots.items[static_cast<std::size_t>(r)].u;
      // Two Newton steps on the squared distance's derivative polish a cluster's midpoint.
      for (int it = 0; it < 2; ++it) {
        const Vec2 d1 = b.d1(u);
        const double g = dot(b.eval(u) - q, d1);
        const double gp = norm2(d1) + dot(b.eval(u) - q, b.d2(u));
        if (!(gp > 0.0)) break;
        const double next = u - g / gp;
        if (!(next >= 0.0 && next <= 1.0)) break;
        u = next;
      }
      consider(k, u);
    }
  }
  best.point = unit.up(best.point);
  best.distance = unit.up(best.distance);
  return best;
}

Spline subcurve(const Spline& s, double t0, double t1) {
  check_not_empty(s);
  s.check_parameter(t0);
  s.check_parameter(t1);
  if (!(t0 < t1)) {
    throw Error(ErrorCode::kInvalidArgument, "a sub-curve needs t0 < t1, got t0 = " +
                                                 format_number(t0) + ", t1 = " + format_number(t1));
  }
  Spline out;
  for (const Segment& g : s.segments) {
    if (g.t1 <= t0 || g.t0 >= t1) continue;
    const double a = std::max(g.t0, t0), b = std::min(g.t1, t1);
    const double u0 = a == g.t0 ? 0.0 : (a - g.t0) / (g.t1 - g.t0);
    const double u1 = b == g.t1 ? 1.0 : (b - g.t0) / (g.t1 - g.t0);
    out.segments.push_back({g.bezier.subsegment(u0, u1), a, b, g.span});
  }
  return out;
}

std::pair<Spline, Spline> split(const Spline& s, double t) {
  check_not_empty(s);
  s.check_parameter(t);
  if (!(t > s.t_begin() && t < s.t_end())) {
    throw Error(
        ErrorCode::kInvalidArgument,
        "a split needs a parameter strictly inside the curve's range, got t = " + format_number(t));
  }
  return {subcurve(s, s.t_begin(), t), subcurve(s, t, s.t_end())};
}

Spline reversed(const Spline& s) {
  check_not_empty(s);
  const double a = s.t_begin(), b = s.t_end();
  Spline out;
  out.closed = s.closed;
  out.segments.reserve(s.segments.size());
  for (auto it = s.segments.rbegin(); it != s.segments.rend(); ++it) {
    // a + b − t maps the ends exactly onto each other.
    const double t0 = it->t1 == b ? a : a + b - it->t1;
    const double t1 = it->t0 == a ? b : a + b - it->t0;
    out.segments.push_back({it->bezier.reversed(), t0, t1, it->span});
  }
  return out;
}

Spline transformed(const Spline& s, const Affine& m) {
  for (double v : {m.a, m.b, m.c, m.d, m.e, m.f}) {
    if (!std::isfinite(v)) {
      throw Error(ErrorCode::kInvalidArgument, "the affine map has a non-finite entry");
    }
  }
  Spline out = s;
  for (Segment& g : out.segments) {
    for (Point& p : g.bezier.p) p = checked(m(p));
  }
  return out;
}

Frame frame_at(const Spline& s, double t) {
  check_not_empty(s);
  s.check_parameter(t);
  const std::size_t k = s.segment_index(t);
  const Segment& g = s.segments[k];
  const double u = s.local_parameter(k, t);
  const CubicBezier& b = g.bezier;
  Vec2 d = b.d1(u);
  if (norm(d) == 0.0) {
    // At a stop the direction of motion is that of the first non-zero derivative; leaving the
    // end u = 1 backwards (its limit from the left) flips the sign of an even one.
    d = b.d2(u);
    if (u >= 1.0) d = -1.0 * d;
    if (norm(d) == 0.0) d = b.d3();
  }
  if (norm(d) == 0.0) {
    throw Error(
        ErrorCode::kInvalidArgument,
        "the curve has no direction at t = " + format_number(t) + " (its piece is a single point)",
        g.span);
  }
  const Vec2 tangent = normalized(d);
  return {b.eval(u), tangent, Vec2{-tangent.y, tangent.x}};
}

}  // namespace fairspline
