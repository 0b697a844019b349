// Yong–Cheng: optimized geometric Hermite (OGH) curves and composite (COH) curves.
// Paper: J.-H. Yong, F. Cheng, "Geometric Hermite curves with minimum strain energy",
// Computer Aided Geometric Design 21 (2004) 281–301 (Theorems 2–7, methods M1–M7, Section 4).
//
// An OGH curve is the cubic Hermite curve through P0, P1 with end derivatives a0·V0, a1·V1
// whose strain energy ∫|Q''(t)|² dt over [t0, t1] is least over all real a0, a1 (Theorem 2).
// It keeps the given directions iff (5) holds (Theorem 3) and is regular, loop-, cusp- and
// fold-free when cos θ > 1/3 and cos φ > 1/3 (Theorem 4, (6)); θ, φ are the counter-clockwise
// angles from P0P1 to V0 and V1. For every other angle pair a composite curve (COH) of two or
// three OGH pieces, each satisfying (6), is built by one of M1–M7 or their mirror images
// T (about the base line), R (about the perpendicular bisector, reversed) and RT.
// The paper's M2 and M3 are garbled; the reconstructed versions, the dispatcher and the
// evidence that every (θ, φ) is covered are in docs/methods/yong-cheng.md.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline {

// ---- OGH segment (Section 2) ----

/// The optimized coefficients a0*, a1* of Theorem 2, (4): Q'(t0) = a0*·V0, Q'(t1) = a1*·V1.
struct OghCoefficients {
  double a0 = 0.0;
  double a1 = 0.0;
};

namespace detail {
/// Out-of-line path of ogh_coefficients: rescales tangents whose squared lengths under- or
/// overflow, and throws for zero or non-finite tangents, a bad interval or an overflowing result.
OghCoefficients ogh_coefficients_slow(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0, double t1);
}  // namespace detail

/// Theorem 2, (4) for general (non-unit, non-zero) V0, V1 and parameter interval [t0, t1].
/// The 2x2 system is always solvable (its determinant 4|V0|²|V1|² − (V0·V1)² ≥ 3|V0|²|V1|²).
/// Throws Error(kInvalidArgument) for a zero tangent or t1 <= t0, kNonFinite on overflow.
/// Inline: it is the inner loop of every OGH-based construction.
inline OghCoefficients ogh_coefficients(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0 = 0.0,
                                        double t1 = 1.0) {
  const Vec2 d = p1 - p0;
  const double vv = dot(v0, v1), v00 = norm2(v0), v11 = norm2(v1);
  const double den = (4.0 * v00 * v11 - vv * vv) * (t1 - t0);
  const double dv0 = dot(d, v0), dv1 = dot(d, v1);
  const double a0 = (6.0 * dv0 * v11 - 3.0 * dv1 * vv) / den;
  const double a1 = (6.0 * dv1 * v00 - 3.0 * dv0 * vv) / den;
  // den is normal and positive and both results finite: the common case.
  if (den >= 0x1p-1000 && den <= 0x1p1000 && std::abs(a0) <= 0x1p1020 && std::abs(a1) <= 0x1p1020) {
    return {a0, a1};
  }
  return detail::ogh_coefficients_slow(p0, p1, v0, v1, t0, t1);
}

/// The equal-ratio variant a0 = a1 = a* (Section 2): the least strain energy when the ratio of
/// the tangent magnitudes is kept. a* > 0 iff |V0| cos θ + |V1| cos φ > 0. Throws like above.
double ogh_equal_ratio_coefficient(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0 = 0.0,
                                   double t1 = 1.0);

/// The cubic Hermite curve (1) with end derivatives w0, w1 on [t0, t1], in Bézier form:
/// p0, p0 + (t1 − t0)·w0/3, p1 − (t1 − t0)·w1/3, p1.
inline CubicBezier hermite_bezier(Point p0, Point p1, Vec2 w0, Vec2 w1, double t0 = 0.0,
                                  double t1 = 1.0) {
  const double h = (t1 - t0) / 3.0;
  return {{p0, p0 + h * w0, p1 - h * w1, p1}};
}

/// The OGH curve: hermite_bezier with w0 = a0*·V0, w1 = a1*·V1. Its geometry depends only on
/// the points and the directions of V0, V1 (not on their lengths or on [t0, t1]).
inline CubicBezier ogh_segment(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0 = 0.0,
                               double t1 = 1.0) {
  const OghCoefficients a = ogh_coefficients(p0, p1, v0, v1, t0, t1);
  return hermite_bezier(p0, p1, a.a0 * v0, a.a1 * v1, t0, t1);
}

/// Strain energy ∫_{t0}^{t1} |Q''(t)|² dt of the Hermite curve with derivatives w0, w1: the
/// paper's f(a0, a1) = (t1 − t0)(A²/3 + A·B + B²) in closed form.
double hermite_strain_energy(Point p0, Point p1, Vec2 w0, Vec2 w1, double t0 = 0.0,
                             double t1 = 1.0);

/// Strain energy of the OGH curve, i.e. min over (a0, a1) of f. With P0 = (0, 0), P1 = (1, 0),
/// [0, 1] and unit V0, V1 this is the functional E(θ, φ) of Johnson & Johnson's Example 4.1
/// (scaling: E ∝ |P1 − P0|² / (t1 − t0)³).
double ogh_strain_energy(Point p0, Point p1, Vec2 v0, Vec2 v1, double t0 = 0.0, double t1 = 1.0);

/// The same energy as a function of the end angles for a unit chord on [0, 1]:
/// E(θ, φ) = 12 − 36(cos²θ + cos²φ − cos θ cos φ cos(θ−φ)) / (4 − cos²(θ−φ)), evaluated as
/// 12(3 sin²θ + 3 sin²φ − 3 sin θ sin φ cos(θ−φ) − 2 sin²(θ−φ)) / (4 − cos²(θ−φ)), which keeps
/// its relative accuracy for nearly straight data (docs/methods/yong-cheng.md).
double ogh_unit_energy(double theta, double phi);

/// Theorem 3, (5): 3 cos θ > cos(θ − 2φ) and 3 cos φ > cos(φ − 2θ), i.e. a0* > 0 and a1* > 0.
bool ogh_preserves_directions(double theta, double phi);

/// Theorem 4, (6): cos θ > 1/3 and cos φ > 1/3 (x'(t) > 0: regular, loop-, cusp-, fold-free).
bool ogh_geometrically_smooth(double theta, double phi);

/// θ and φ of Theorem 3 for the end conditions (counter-clockwise from P0P1, in (−π, π]).
struct TangentAngles {
  double theta = 0.0;
  double phi = 0.0;
};
TangentAngles tangent_angles(Point p0, Point p1, Vec2 v0, Vec2 v1);

// ---- COH curves (Sections 3, 4) ----

/// The base constructions: M0 = one OGH, M1–M2 two pieces, M3–M7 three pieces.
enum class CohMethod { kM0, kM1, kM2, kM3, kM4, kM5, kM6, kM7 };

/// Symmetry-based extension (Section 4): T mirrors about the base line P0P1, R mirrors about its
/// perpendicular bisector and reverses the curve, RT does both. On the angles:
/// T: (θ, φ) → (−θ, −φ), R: (θ, φ) → (−φ, −θ), RT: (θ, φ) → (φ, θ).
enum class CohSymmetry { kNone = 0, kT = 1, kR = 2, kRT = 3 };  ///< bit 0: T, bit 1: R

/// Number of OGH pieces of a base method (1, 2 or 3).
int coh_piece_count(CohMethod method);

/// "M4", "M4^RT", "M0", ...
std::string coh_name(CohMethod method, CohSymmetry symmetry);

/// Whether (θ, φ) lies in the applicable region of M_i^s as the paper states it (Section 3 and
/// Theorem 7), closed intervals, angles taken modulo 2π. M0's region is (6) (open).
bool coh_applicable(CohMethod method, CohSymmetry symmetry, double theta, double phi);

/// A COH curve between two points: 1–3 OGH pieces joined with G1 continuity.
struct CohCurve {
  CohMethod method = CohMethod::kM0;
  CohSymmetry symmetry = CohSymmetry::kNone;
  int count = 1;                        ///< number of pieces
  std::array<CubicBezier, 3> pieces{};  ///< pieces[0..count)
  /// Optimized coefficients of each piece relative to unit end directions on the local
  /// parameter [0, 1] (so pieces[k].p[1] = p[0] + a0·u0/3 with |u0| = 1).
  std::array<OghCoefficients, 3> coefficients{};
  /// Every piece keeps its end directions (all coefficients > 0, Theorem 3).
  bool preserved = true;
};

/// End conditions of one Hermite span.
struct HermiteEnds {
  Point p0;
  Point p1;
  Vec2 v0;
  Vec2 v1;
};

/// Builds M_i^s for the end conditions, whatever the angles (no region check: outside its
/// region a construction may violate (6), which `preserved` and coh_check reveal).
/// Throws Error(kInvalidArgument) for coincident points or zero tangents, kInfeasible when the
/// construction's joints do not exist for these angles (lines that do not meet).
CohCurve coh_construct(CohMethod method, CohSymmetry symmetry, Point p0, Point p1, Vec2 v0,
                       Vec2 v1);

/// The dispatcher: for any (θ, φ) ∈ [0, 2π)² picks the construction with the fewest pieces
/// whose (corrected) applicable region contains the angles, and builds it. Equivariant: the
/// choice for the mirrored or reversed data is the mirrored or reversed choice (except on the
/// measure-zero lines where two mirror images meet). Throws like coh_construct.
CohCurve coh_curve(Point p0, Point p1, Vec2 v0, Vec2 v1);

/// coh_curve for many spans: out[i] = coh_curve(ends[i]) (bit-identical), computed stage by
/// stage over blocks of spans so that their dependency chains overlap (several times faster
/// per span). Errors carry the index i of the offending span. out.size() >= ends.size().
void coh_curves(std::span<const HermiteEnds> ends, std::span<CohCurve> out);

/// Which construction coh_curve uses for the angles (no geometry built).
struct CohChoice {
  CohMethod method = CohMethod::kM0;
  CohSymmetry symmetry = CohSymmetry::kNone;
};
CohChoice coh_choose(double theta, double phi);

/// Smallest margin min(cos β) − 1/3 over all piece end angles β relative to their chords:
/// positive iff every piece satisfies Theorem 4's conditions (6).
double coh_min_margin(const CohCurve& curve);

// ---- Spline level ----

/// How the magnitudes of each span are chosen.
enum class YongChengRatio {
  kFree,   ///< a0, a1 independent (Theorem 2), COH pieces when needed (default)
  kEqual,  ///< a0 = a1 (equal-ratio variant), one piece per span; needs a* > 0
};

/// Options of fit_yong_cheng.
struct YongChengOptions {
  /// true (default): spans whose angles violate (6) get a COH curve; false: one OGH per span
  /// even if it reverses a direction (reported as preserved = false).
  bool composite = true;
  YongChengRatio ratio = YongChengRatio::kFree;
  /// The registry option that supplied the missing directions (fit() fills them in before this
  /// method runs; recorded in method_report). A direct call needs a tangent at every point.
  std::string tangents_from;
};

/// Fits a G1 spline through points with a tangent vector at each point: every span is an OGH
/// curve or a COH curve (Segment::span tells which input span a piece belongs to; a span's
/// parameter interval is split among its pieces in proportion to their chords). Tangents come
/// from FitInput::tangents (and start_tangent / end_tangent for an open curve); a point without
/// one is Error(kInvalidArgument) naming it (through fit(), the registry option tangents_from
/// fills them in first).
/// method_report (level != kNone): per span `construction` ("M4^RT"), `pieces`, `theta_deg`,
/// `phi_deg`, `coefficients` ([[a0, a1], ...] relative to the given tangent vectors at the
/// span's ends and unit vectors at joints, on each piece's parameter interval) and `preserved`;
/// totals `constructions` (count per name), `all_preserved`. Always: `composite`, `ratio`,
/// `tangents_from`.
FitResult fit_yong_cheng(const FitInput& input, const YongChengOptions& options = {},
                         ReportLevel level = ReportLevel::kBasic);
/// The same, written into `out` reusing its capacity (see fairspline::fit_into).
void fit_yong_cheng(const FitInput& input, const YongChengOptions& options, ReportLevel level,
                    FitResult& out);

}  // namespace fairspline
