#include "fairspline/cubic_bezier.hpp"

#include <algorithm>
#include <cmath>

#include "fairspline/energy.hpp"

namespace fairspline {

double CubicBezier::curvature(double u) const {
  const Vec2 v = d1(u);
  const double s2 = norm2(v);
  if (s2 == 0.0) return 0.0;
  return cross(v, d2(u)) / (s2 * std::sqrt(s2));
}

CubicBezier CubicBezier::subsegment(double u0, double u1) const {
  // Blossom evaluation: control points are f(u0,u0,u0), f(u0,u0,u1), f(u0,u1,u1), f(u1,u1,u1).
  auto blossom = [this](double a, double b, double c) {
    const Point q0 = lerp(p[0], p[1], a), q1 = lerp(p[1], p[2], a), q2 = lerp(p[2], p[3], a);
    const Point r0 = lerp(q0, q1, b), r1 = lerp(q1, q2, b);
    return lerp(r0, r1, c);
  };
  // The curve's own end points where u0 or u1 is an end: lerp(a, b, 1) = a + (b − a) is not b
  // after rounding, by up to eps·|control points|, which is far from the end point when the inner
  // control points are much larger than the curve (kozak-krajnc pieces through nearly coincident
  // points missed their last point by 2e-6 of the chord; found by fuzz_fit).
  const auto end = [&](double u) { return u == 0.0 ? p[0] : u == 1.0 ? p[3] : blossom(u, u, u); };
  return {{end(u0), blossom(u0, u0, u1), blossom(u0, u1, u1), end(u1)}};
}

namespace {
// Roots in (0,1) of the derivative of one coordinate: a quadratic in Bernstein form
// with coefficients d0, d1, d2 (the hodograph's coordinate).
template <typename F>
void for_each_extremum(double d0, double d1, double d2, F&& f) {
  const double a = d0 - 2.0 * d1 + d2, b = 2.0 * (d1 - d0), c = d0;
  if (a == 0.0) {
    if (b != 0.0) f(-c / b);
    return;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return;
  const double sq = std::sqrt(disc);
  const double q = -0.5 * (b + std::copysign(sq, b));
  if (q != 0.0) {
    f(q / a);
    f(c / q);
  } else {
    f(0.0);
  }
}
}  // namespace

BBox CubicBezier::bbox() const {
  BBox box{{std::min(p[0].x, p[3].x), std::min(p[0].y, p[3].y)},
           {std::max(p[0].x, p[3].x), std::max(p[0].y, p[3].y)}};
  const QuadBezier h = hodograph();
  auto include = [&](double u) {
    if (!(u > 0.0 && u < 1.0)) return;
    const Point q = eval(u);
    box.min.x = std::min(box.min.x, q.x);
    box.min.y = std::min(box.min.y, q.y);
    box.max.x = std::max(box.max.x, q.x);
    box.max.y = std::max(box.max.y, q.y);
  };
  for_each_extremum(h.p[0].x, h.p[1].x, h.p[2].x, include);
  for_each_extremum(h.p[0].y, h.p[1].y, h.p[2].y, include);
  return box;
}

double CubicBezier::arc_length(double accuracy) const {
  EnergyOptions options;
  options.accuracy = accuracy;
  return fairspline::arc_length(*this, options).value;
}

}  // namespace fairspline
