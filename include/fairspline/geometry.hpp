// Geometry of a spline: arc length and its inverse, flattening to a polyline, exact bounds,
// the nearest point, sub-curves, reversal, affine maps and tangent frames. Parameters are the
// spline's global t. Every function checks its arguments and throws Error (kInvalidArgument
// for a parameter outside [t_begin, t_end] or NaN, an empty spline or a bad tolerance;
// kNonFinite when a result overflows): nothing is clamped silently, no NaN is returned.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/spline.hpp"

namespace fairspline {

/// Relative accuracy of the arc-length functions: each piece's length is integrated (adaptive
/// Gauss–Kronrod 15/31) to this fraction of itself, and an inverse is solved to this fraction of
/// the total length.
inline constexpr double kDefaultLengthAccuracy = 1e-12;

/// Arc length of each piece, in order.
std::vector<double> segment_lengths(const Spline& s, double accuracy = kDefaultLengthAccuracy);
/// Total arc length.
double length(const Spline& s, double accuracy = kDefaultLengthAccuracy);
/// Arc length from t_begin to each of `t` (any order).
std::vector<double> lengths_at(const Spline& s, const std::vector<double>& t,
                               double accuracy = kDefaultLengthAccuracy);
/// The parameters at which the arc length from t_begin equals each of `lengths` (any order,
/// each in [0, length(s)]): Newton on the arc-length integral, bracketed by bisection.
std::vector<double> parameters_at_lengths(const Spline& s, const std::vector<double>& lengths,
                                          double accuracy = kDefaultLengthAccuracy);
/// `count` >= 2 parameters at equal arc-length steps, from t_begin to t_end.
std::vector<double> equal_length_parameters(const Spline& s, std::size_t count,
                                            double accuracy = kDefaultLengthAccuracy);

/// A polyline on the curve: its vertices and their parameters.
struct Polyline {
  std::vector<Point> points;
  std::vector<double> parameters;
};

/// The curve as a polyline within `tolerance` (absolute, > 0) of it in Hausdorff distance:
/// adaptive de Casteljau halving of each piece until its inner control points lie within
/// `tolerance` of its chord (the piece lies in their convex hull, so within `tolerance` of the
/// chord, and the chord within `tolerance` of the piece). Vertices lie on the curve. A closed
/// curve's polyline ends at its first point again. Throws kInvalidArgument when the tolerance
/// would need more than `max_points` vertices.
Polyline flatten(const Spline& s, double tolerance, std::size_t max_points = 10'000'000);

/// Exact axis-aligned bounds of the curve (the coordinates' extrema on every piece).
BBox bounds(const Spline& s);

/// The point of the curve nearest to a query point.
struct Projection {
  double t = 0.0;         ///< its global parameter
  Point point;            ///< the curve's point there
  double distance = 0.0;  ///< |point − query|
  std::size_t segment = 0;
};
/// The nearest point: on every piece whose control box could hold a nearer point, the roots
/// of (b(u) − q)·b'(u), a quintic in Bernstein form, are isolated and refined; the least
/// distance among them and the piece ends wins (the earliest parameter on a tie).
Projection project(const Spline& s, Point q);

/// The part of the curve between t0 < t1 (both in [t_begin, t_end]) as an open spline on the
/// same parameters.
Spline subcurve(const Spline& s, double t0, double t1);
/// The parts before and after t (t_begin < t < t_end), both open.
std::pair<Spline, Spline> split(const Spline& s, double t);
/// The same curve traversed backwards, on the parameters t_begin + t_end − t.
Spline reversed(const Spline& s);

/// An affine map in SVG's matrix(a b c d e f) form: x' = a x + c y + e, y' = b x + d y + f.
struct Affine {
  double a = 1.0, b = 0.0, c = 0.0, d = 1.0, e = 0.0, f = 0.0;
  Point operator()(Point p) const { return {a * p.x + c * p.y + e, b * p.x + d * p.y + f}; }
};
/// The image of the curve under `m` (exact: Béziers map by their control points). Throws
/// kInvalidArgument for a non-finite map, kNonFinite when a control point overflows.
Spline transformed(const Spline& s, const Affine& m);

/// The curve's point, unit tangent and unit normal (the tangent turned +90°) at t. Where the
/// speed vanishes (a cusp) the tangent is the one-sided limit along the curve, from the next
/// non-zero derivative.
struct Frame {
  Point point;
  Vec2 tangent;
  Vec2 normal;
};
Frame frame_at(const Spline& s, double t);

}  // namespace fairspline
