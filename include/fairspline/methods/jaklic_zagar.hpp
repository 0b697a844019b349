// Jaklič–Žagar: planar cubic G1 interpolatory spline with small (approximate) strain energy.
// Paper: G. Jaklič, E. Žagar, "Planar cubic G1 interpolatory splines with small strain energy",
// J. Comput. Appl. Math. 235 (2011) 2758–2765 (Theorems 2, 4, 6, Lemma 5, Corollary 7).
//
// Local construction, O(n) time and memory:
//  * knots t_i from the α-parameterization (or given);
//  * interior tangent directions d_i = w_i/|w_i| from (10), w_i = λ_i u_i + (1 − λ_i) v_i,
//    with λ_i the stationary point of Theorem 6 / (11) (`optimal`), the bisector of Corollary 7,
//    or a user value in (0, 1); end directions along the end chords unless given;
//  * tangent magnitudes α* = d·ΔT/Δt of Theorem 2, Bézier form of the proof of Theorem 4:
//      T_{i-1},  T_{i-1} + (d_{i-1}·ΔT_{i-1}) d_{i-1}/3,  T_i − (d_i·ΔT_{i-1}) d_i/3,  T_i.
// Every segment is regular, loop-, cusp- and fold-free (Theorem 4) whenever all λ_i ∈ (0, 1).
//
// Finding (docs/methods/jaklic-zagar.md): for a turn ∠(ΔT_{i-1}, ΔT_i) above 90° the stationary
// point of Theorem 6 is the MAXIMUM of the approximate energy (7)+(8) over the admissible
// directions. The method implements the paper's formula and classifies every node
// (StationaryKind) instead of silently changing it.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline {

/// How the shape parameters λ_i of (10) are chosen.
enum class JaklicZagarLambda {
  kOptimal,  ///< Theorem 6, (11): stationary point of the approximate energy (default)
  kBisector,  ///< λ_i = |ΔT_i| / (|ΔT_{i-1}| + |ΔT_i|): d_i on the angle bisector (Lemma 5 remark)
  kFixed,     ///< one user value λ ∈ (0, 1) at every interior point
};

/// What to do at a 180° reversal (ΔT_{i-1} and ΔT_i collinear and opposite).
enum class JaklicZagarReversal {
  kError,   ///< raise Error(kReversal) naming the point (default)
  kInsert,  ///< insert one point next to the reversal (see docs/methods/jaklic-zagar.md)
};

/// Options of fit_jaklic_zagar.
struct JaklicZagarOptions {
  JaklicZagarLambda lambda = JaklicZagarLambda::kOptimal;
  double fixed_lambda = 0.5;  ///< used when lambda == kFixed; must be in the open interval (0, 1)
  /// Per-point λ_i (one per input point, open interval (0, 1)); when non-empty it replaces
  /// `lambda`. Entries at the two ends of an open curve are ignored (any value in [0, 1]).
  std::vector<double> lambdas;
  JaklicZagarReversal reversal = JaklicZagarReversal::kError;
};

/// What the chosen direction d_i is for the approximate energy of the two segments meeting at
/// point i, as a function of the direction along the admissible arc {d : d·ΔT_{i-1} > 0,
/// d·ΔT_i > 0} (for an end of an open curve: the half-plane d·ΔT > 0 of its one segment).
enum class StationaryKind {
  kMinimum,   ///< an interior (strict or, for a straight point, global) minimum
  kMaximum,   ///< an interior maximum: turns above 90° with λ = λ* (the paper's formula)
  kBoundary,  ///< an exact right angle (u·v = 0): no λ ∈ (0, 1) is stationary, bisector taken
  kNone,      ///< not stationary (bisector or fixed λ away from λ*, a user tangent)
};

/// Stable lower-case name: "minimum", "maximum", "boundary", "none".
std::string_view stationary_kind_name(StationaryKind kind);

/// The construction at one interior point between the chords a = ΔT_{i-1} and b = ΔT_i.
struct JaklicZagarNode {
  Vec2 direction;                ///< unit tangent direction d_i
  std::optional<double> lambda;  ///< λ_i of (10); nullopt for a straight point (z_i = 0, w = ΔT_i)
  StationaryKind kind = StationaryKind::kNone;
};

/// Theorem 6: the direction of (10) with λ_i from (11) for chords a, b with knot intervals
/// ha = Δt_{i-1}, hb = Δt_i (the root of ρ in (0, 1), chosen without cancellation; the
/// direction is evaluated in the bisector frame, see the docs). Special cases: at an exact right
/// angle (u·v = 0, decided on the unit chords to 8 ulps) no λ ∈ (0, 1) is stationary and the
/// direction is Corollary 7's bisector, λ = 1/(1 + |a|/|b|) (kind kBoundary), not the paper's
/// λ = 1 (z_i = 1) or 0 (z_i = −1), which would stop the curve there
/// (docs/methods/jaklic-zagar.md); z_i = 0 with equal directions gives w = ΔT_i, as in the paper.
/// Throws Error(kReversal) for z_i = 0 with opposite directions, kInvalidArgument for zero or
/// non-finite chords / intervals, kNonFinite if the result overflows. Only the ratios |a|/|b| and
/// ha/hb matter (scale invariant).
JaklicZagarNode jaklic_zagar_optimal_node(Vec2 a, Vec2 b, double ha, double hb);

/// (11) alone: λ* ∈ [0, 1] for the chords a, b and knot intervals ha, hb (same special cases
/// as jaklic_zagar_optimal_node); nullopt for collinear chords. Throws like it.
std::optional<double> jaklic_zagar_optimal_lambda(Vec2 a, Vec2 b, double ha, double hb);

/// The direction of (10) for a given λ ∈ [0, 1] (the bisector value gives the exact bisector).
/// Collinear equal directions give b/|b|; throws Error(kReversal) for opposite directions.
Vec2 jaklic_zagar_direction(Vec2 a, Vec2 b, double lambda);

/// Theorem 2 + proof of Theorem 4: the cubic from p0 to p1 with unit end directions d0, d1 and
/// the energy-minimizing magnitudes α* (control points p0 + (d0·Δ)d0/3, p1 − (d1·Δ)d1/3).
/// Throws Error(kNonFinite) if a control point overflows (also the energy below).
CubicBezier jaklic_zagar_segment(Point p0, Point p1, Vec2 d0, Vec2 d1);

/// The approximate strain energy (7) of that segment on a knot interval dt:
/// (2/dt)·ψ(α*) = 2|Δ|²(sin²β0 + sin²β1)/dt³, βk = ∠(dk, Δ), (8) at Theorem 2's minimum.
/// With Δ = (1, 0) and dt = 1, ψ(α*) = sin²β0 + sin²β1 is the functional of Johnson & Johnson's
/// Example 4.2 at its minimum.
double jaklic_zagar_segment_energy(Vec2 chord, double dt, Vec2 d0, Vec2 d1);

/// Fits the Jaklič–Žagar G1 spline.
/// Tangent overrides (FitInput::start_tangent, end_tangent, points of kind kClamped) fix the
/// direction only and must be admissible (positive dot product with the adjacent chords),
/// otherwise Error(kInfeasible) names the point. Corner points are rejected (one G1 curve).
/// Throws Error on bad input (see detail::prepare_input), kBadOption for λ outside (0, 1) or a
/// `lambdas` list of the wrong length, kReversal at a 180° reversal unless reversal = kInsert.
/// method_report (level != kNone): per point `lambda` (null at open ends and straight points),
/// `stationary_kind`; per segment `approx_energy` ((7) at α*); totals and counts. Always:
/// `lambda_mode`, `reversal`, `inserted` (output indices of inserted points), `inserted_at`.
/// The diagnostics Report is added by fairspline::fit(), not here.
FitResult fit_jaklic_zagar(const FitInput& input, const JaklicZagarOptions& options = {},
                           ReportLevel level = ReportLevel::kBasic);
/// The same, written into `out` reusing its capacity (see fairspline::fit_into): no allocation
/// per fit once `out` has seen a curve of the same size (kNone). Only the method_report is
/// built here; the registry's fit() adds the Report.
void fit_jaklic_zagar(const FitInput& input, const JaklicZagarOptions& options, ReportLevel level,
                      FitResult& out);

}  // namespace fairspline
