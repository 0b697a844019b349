// Diagnostics: regularity certificate, loops, cusps, folds, joint continuity, residuals,
// and the Report assembled from them.
//
// Scales. Every tolerance is relative to the piece it is applied to: speeds are divided by the
// chord |p3 − p0| of the piece (by its control polygon length when the chord is 0), geometric
// tolerances of the intersection search are multiplied by the control polygon length.
#pragma once

#include <span>
#include <vector>

#include "fairspline/energy.hpp"
#include "fairspline/fit.hpp"

namespace fairspline {

/// Options of the diagnostics.
struct DiagnosticsOptions {
  EnergyOptions energy;
  /// Regularity certificate: a piece is certified regular when a lower bound of |c'(u)| on
  /// [0,1] exceeds min_relative_speed·chord; subdivision of the hodograph stops at max_depth.
  /// The same threshold defines a cusp (see has_cusp).
  double min_relative_speed = 1e-9;
  int max_depth = 24;
  /// The certificate keeps subdividing until its lower bound is at least this fraction of the
  /// minimum speed (so RegularityCertificate::speed_lower is informative, not just positive).
  double certificate_tightness = 0.5;
  /// Intersection search: sub-pieces are subdivided until flat to
  /// tol = intersection_accuracy·(larger control polygon length of the two pieces); where their
  /// chords cross, Newton refines the crossing on the pieces and it is accepted when they are
  /// within 4·tol there. Transversal crossings come out to rounding; an exact tangential contact
  /// is found (located to about sqrt(tol)), a near miss whose chords do not cross is not.
  double intersection_accuracy = 1e-9;
  /// Subdivision depth limit of the intersection search (reached only near tangential contacts
  /// and at joints where consecutive pieces leave in the same direction).
  int intersection_max_depth = 40;
};

/// Result of certifying one piece.
struct RegularityCertificate {
  bool regular = false;      ///< proved: speed > min_relative_speed·chord on [0,1]
  double speed_lower = 0.0;  ///< proven lower bound of |c'(u)| / chord
  double speed_min = 0.0;    ///< smallest |c'(u)| / chord found (an upper bound of the min)
  double u_at_min = 0.0;     ///< where speed_min is attained
  int subdivisions = 0;      ///< hodograph subdivisions used
};

/// Proves regularity from the Bernstein coefficients of the hodograph: on a sub-interval the
/// hodograph lies in the convex hull of its 3 control vectors, so the distance from the origin
/// to that triangle bounds the speed from below; sub-intervals whose bound is too small (or
/// less than certificate_tightness × the minimum speed) are split by de Casteljau.
/// speed_min/u_at_min come from the exact critical points of |c'|² (roots of the cubic c'·c'').
/// A degenerate piece (all control points equal) is not regular and has speed 0.
RegularityCertificate certify_regularity(const CubicBezier& b,
                                         const DiagnosticsOptions& options = {});

/// Cusp: the minimum speed over [0,1] (exact critical points of |c'|²) is at most
/// min_relative_speed·chord — the speed vanishes to the certificate's resolution, at an interior
/// parameter (a cusp proper) or at an end (a zero-length tangent handle, where the curvature is
/// unbounded). A degenerate piece (a point) has no cusp.
bool has_cusp(const CubicBezier& b, const DiagnosticsOptions& options = {});
/// Fold: the tangent directions of the piece do not fit in an open half-plane, i.e. there is no
/// direction e with T(u)·e > 0 for all u, where T(u) = c'(u)/|c'(u)| (extended by continuity at
/// an end where the speed vanishes). Equivalently the tangent turns through 180° or more (the
/// piece doubles back). Exact test: for a regular piece, the origin lies in the convex hull of
/// the hodograph arc (the parabolic segment between the arc and its chord). An interior point of
/// vanishing speed (a cusp) is a fold: the direction reverses there.
bool has_fold(const CubicBezier& b, const DiagnosticsOptions& options = {});

/// All self-intersections of a spline: within a piece (loops, segment_a == segment_b,
/// u_a < u_b) and between pieces (segment_a < segment_b). The joint shared by consecutive
/// pieces (and, for closed splines, by the last and first) is not an intersection, nor is any
/// contact connected to it: where the two pieces leave the joint into the same half-plane (a
/// cusp joint), the stretch next to the joint along which they stay within 4·tol of each other
/// (see DiagnosticsOptions::intersection_accuracy) belongs to the joint. Pieces of zero extent
/// are skipped (their neighbours count as consecutive). Each intersection is reported once; one
/// exactly at a joint is named by the later piece at u = 0. Degenerate overlaps of
/// non-consecutive pieces (one retracing the other along a common arc) are not enumerated: they
/// yield one or a few hits on the common arc; a straight piece retracing itself has a fold, not
/// a loop. Bounding-box sweep along the longer axis of the curve: O(n log n) for curves whose
/// pieces do not all overlap.
std::vector<Intersection> find_self_intersections(const Spline& s,
                                                  const DiagnosticsOptions& options = {});

/// Tangent angle jump at the joint between pieces a (end) and b (start), degrees in [0,180].
/// Directions: the end derivative, or where it vanishes the next non-vanishing one
/// (p3−p2, else p3−p1, else p3−p0 for a; p1−p0, else p2−p0, else p3−p0 for b).
double tangent_angle_jump_deg(const CubicBezier& a, const CubicBezier& b);
/// |κ_a(1) − κ_b(0)| at the joint. When a curved piece has zero speed at the joint its
/// curvature is unbounded there and the result is std::numeric_limits<double>::max().
double curvature_jump(const CubicBezier& a, const CubicBezier& b);

/// Builds the report of a spline interpolating `points` (pieces' starts at their span points;
/// the end of an open curve at the last point).
///   basic: linearized energy (closed form), regular (every piece certified), min_relative_speed
///          (smallest certified speed_lower), joint jumps, max_interpolation_residual — O(n);
///   full:  + bending / curvature-variation energy and length (quadrature; energy_singular when
///          a piece's speed falls below energy.speed_floor, the energies then being finite
///          partial values), per-segment reports, and self-intersections.
/// Throws Error(kNonFinite) for non-finite control points, Error(kInvalidArgument) for a piece
/// with t1 <= t0 or a span outside `points`.
Report make_report(const Spline& s, std::span<const Point> points, ReportLevel level,
                   const DiagnosticsOptions& options = {});

}  // namespace fairspline
