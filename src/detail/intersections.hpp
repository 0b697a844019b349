// Private helpers of find_self_intersections: intersections of two cubic pieces by recursive
// subdivision (bounding boxes, flatness, Newton refinement) and the closed-form self-intersection
// of one cubic.
#pragma once

#include <cstddef>
#include <vector>

#include "fairspline/cubic_bezier.hpp"

namespace fairspline::detail {

/// One intersection of piece A (parameter u_a) with piece B (u_b).
struct CurveHit {
  double u_a = 0.0;
  double u_b = 0.0;
  Point point;
};

/// Corners of the parameter square where A and B share a joint point (not intersections).
enum SharedJoint : unsigned {
  kNoJoint = 0,
  kEndToStart = 1,  ///< A(1) = B(0): B follows A
  kStartToEnd = 2,  ///< A(0) = B(1): A follows B (closed curves)
};

/// Reusable scratch memory of intersect_pieces (no allocation per call once warm).
struct IntersectionWorkspace {
  struct Cell {
    CubicBezier a, b;
    double a0, a1, b0, b1;
    int depth;
  };
  std::vector<Cell> stack;
  std::vector<CurveHit> hits;
  /// Pairs found to share an arc by exhausting the cell budget. Each one halves the budget of
  /// the pairs searched after it with this workspace (down to 2^10 cells; find_self_intersections
  /// resets it per chunk of pairs): a curve that retraces itself many times
  /// (points alternating between two places) has O(n²) coinciding pairs, and at 2^15 cells each
  /// the full report of 44 such points took 0.5 s (13 s under the sanitizers; found by fuzz_fit).
  std::size_t overlaps = 0;
};

/// Appends to `out` the intersections of A and B (each point once), excluding the shared
/// joints given by `joints`: a sub-pair containing a shared joint J is discarded once the cones
/// from J spanned by the two sub-pieces' control points meet only at J (then their convex hulls
/// meet only at J), and at max_depth otherwise (a cusp joint); where the pieces leave J into the
/// same half-plane, hits in the contact zone next to J (the pieces within 4·tol of each other)
/// are dropped too. `tol` is the absolute geometric tolerance: subdivision stops when both
/// sub-pieces are flat to tol, chord crossings are refined by Newton and accepted within 4·tol.
/// Pieces that share an arc (a curve retracing itself) meet in a continuum: when the search
/// finds more than the 9 crossings two distinct cubics can have, or needs more than 2^15 cells
/// (fewer after earlier overlaps: IntersectionWorkspace::overlaps), one hit (the one of smallest
/// parameter on A) stands for the shared arc.
/// The coordinates must be within 2^±kNormalRange (squares of differences are taken).
void intersect_pieces(const CubicBezier& A, const CubicBezier& B, unsigned joints, double tol,
                      int max_depth, IntersectionWorkspace& ws, std::vector<CurveHit>& out);

/// Self-intersection of one cubic: parameters s < t in [0,1] with b(s) = b(t), from the closed
/// form in σ = s + t, π = s t (the divided difference (b(s) − b(t))/(s − t) is linear in π),
/// polished by Newton. A cubic has at most one. `tol` is the absolute geometric tolerance used
/// to reject a (near-)cusp, where s and t merge. Returns false when there is none.
bool self_intersection(const CubicBezier& b, double tol, double& s, double& t);

}  // namespace fairspline::detail
