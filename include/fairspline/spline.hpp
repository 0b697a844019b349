// Spline: a sequence of cubic Bézier pieces on a global parameter.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "fairspline/cubic_bezier.hpp"

namespace fairspline {

/// One piece of a spline: a cubic on the global parameter interval [t0, t1].
/// `span` is the index of the input point the piece starts from (several pieces may share
/// a span when a method splits it, e.g. composite Hermite curves).
struct Segment {
  CubicBezier bezier;
  double t0 = 0.0;
  double t1 = 1.0;
  std::size_t span = 0;
};

/// A piecewise cubic curve. Pieces are ordered by parameter and join end to start.
struct Spline {
  std::vector<Segment> segments;
  bool closed = false;

  bool empty() const { return segments.empty(); }
  /// Parameter range; both throw Error on an empty spline.
  double t_begin() const;
  double t_end() const;

  /// Throws Error(kInvalidArgument) naming t and the range unless t_begin <= t <= t_end (NaN
  /// is outside); `index` is the position of t in the caller's list, if any. The policy of
  /// every evaluation (eval, derivative, curvature, the geometry functions, Python): a
  /// parameter outside the range is an error, never clamped; a closed curve's caller wraps t.
  void check_parameter(double t, std::optional<std::size_t> index = std::nullopt) const;

  /// Index of the piece containing global parameter t (clamped to the ends;
  /// at an interior joint the later piece is chosen). A lookup: it does not check t.
  std::size_t segment_index(double t) const;
  /// Local parameter u in [0,1] of t inside piece k.
  double local_parameter(std::size_t k, double t) const;

  /// Point at global parameter t in [t_begin, t_end] (else Error, see check_parameter).
  Point eval(double t) const;
  /// Derivatives with respect to the global parameter t (order 1..3; higher orders are 0);
  /// t as for eval.
  Vec2 derivative(double t, int order = 1) const;
  /// Signed curvature at global parameter t (parameterization-independent); t as for eval.
  double curvature(double t) const;
  /// `count` points at parameters equally spaced in [t_begin, t_end] (count >= 2).
  std::vector<Point> sample(std::size_t count) const;
};

}  // namespace fairspline
