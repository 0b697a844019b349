// CubicBezier: one planar cubic in Bernstein-Bézier form on the local parameter u in [0, 1].
#pragma once

#include <algorithm>
#include <array>
#include <utility>

#include "fairspline/vec2.hpp"

namespace fairspline {

/// Axis-aligned bounding box.
struct BBox {
  Point min;
  Point max;
};

/// Quadratic Bézier (used for the hodograph of a cubic).
struct QuadBezier {
  std::array<Vec2, 3> p;
  Vec2 eval(double u) const {
    const double v = 1.0 - u;
    return v * v * p[0] + 2.0 * u * v * p[1] + u * u * p[2];
  }
};

/// Planar cubic Bézier curve with control points p[0..3].
struct CubicBezier {
  std::array<Point, 4> p;

  /// Point at local parameter u (de Casteljau-free Bernstein evaluation).
  Point eval(double u) const {
    const double v = 1.0 - u;
    const double b0 = v * v * v, b1 = 3.0 * u * v * v, b2 = 3.0 * u * u * v, b3 = u * u * u;
    return b0 * p[0] + b1 * p[1] + b2 * p[2] + b3 * p[3];
  }
  /// First derivative d/du.
  Vec2 d1(double u) const {
    const double v = 1.0 - u;
    return 3.0 * (v * v * (p[1] - p[0]) + 2.0 * u * v * (p[2] - p[1]) + u * u * (p[3] - p[2]));
  }
  /// Second derivative d²/du².
  Vec2 d2(double u) const {
    return 6.0 * ((1.0 - u) * (p[2] - 2.0 * p[1] + p[0]) + u * (p[3] - 2.0 * p[2] + p[1]));
  }
  /// Third derivative d³/du³ (constant).
  Vec2 d3() const { return 6.0 * (p[3] - 3.0 * p[2] + 3.0 * p[1] - p[0]); }

  /// Signed curvature at u: cross(c', c'') / |c'|³ (positive = turning left).
  /// Returns +-infinity-free 0 when the speed is exactly 0 — use diagnostics to detect cusps.
  double curvature(double u) const;

  /// Hodograph: the derivative as a quadratic Bézier with control points 3(p[k+1]-p[k]).
  QuadBezier hodograph() const {
    return {{3.0 * (p[1] - p[0]), 3.0 * (p[2] - p[1]), 3.0 * (p[3] - p[2])}};
  }

  /// Split at u into [0,u] and [u,1] (de Casteljau). Inline: subdivision searches call it
  /// millions of times.
  std::pair<CubicBezier, CubicBezier> split(double u) const {
    const Point a = lerp(p[0], p[1], u), b = lerp(p[1], p[2], u), c = lerp(p[2], p[3], u);
    const Point ab = lerp(a, b, u), bc = lerp(b, c, u);
    const Point m = lerp(ab, bc, u);
    return {CubicBezier{{p[0], a, ab, m}}, CubicBezier{{m, bc, c, p[3]}}};
  }
  /// The piece on [u0, u1] reparameterized to [0, 1]; u0 > u1 gives the reversed piece.
  CubicBezier subsegment(double u0, double u1) const;
  /// The same curve traversed backwards.
  CubicBezier reversed() const { return {{p[3], p[2], p[1], p[0]}}; }

  /// Tight bounding box (extrema of the coordinate polynomials).
  BBox bbox() const;
  /// Bounding box of the control polygon (contains the curve; cheap, inline).
  BBox control_bbox() const {
    BBox box{p[0], p[0]};
    for (const Point& q : p) {
      box.min = {std::min(box.min.x, q.x), std::min(box.min.y, q.y)};
      box.max = {std::max(box.max.x, q.x), std::max(box.max.y, q.y)};
    }
    return box;
  }

  /// Arc length to an absolute error of about accuracy·(control polygon length)
  /// by adaptive Gauss–Kronrod (15/31) quadrature of |c'(u)|.
  double arc_length(double accuracy = 1e-10) const;
};

}  // namespace fairspline
