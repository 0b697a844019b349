// Kozak–Krajnc, Section 4: the G1 cubic spline through T0..T3m, one cubic per three spans, with
// the admissible tangent directions found by forward and backward sweeps.
//
// Tangent directions are parameterized by ξ ∈ (0, 1) as in (4.1); the constants μ of (2.6) are
// then Möbius functions of ξ ((4.2), (4.3)). A piece ℓ (points T3ℓ−3..T3ℓ) is admissible when its
// (μ2ℓ−1, μ2ℓ) satisfy Theorem 2.4 (convex: λ2ℓ−1, λ2ℓ > 0) or Theorem 2.5 (inflection:
// λ2ℓ−1·λ2ℓ < 0). The sweeps carry the sets Ξℓ of reachable ξℓ; a concrete admissible ξ vector is
// then chosen (Corollary 4.3) and every piece solved with kozak_krajnc_solve.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fairspline/fit.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline {

/// An open interval (lo, hi), or the single point {lo} when `point` is set (a fixed ξ).
struct XiInterval {
  double lo = 0.0;
  double hi = 0.0;
  bool point = false;

  bool contains(double x) const { return point ? x == lo : (lo < x && x < hi); }
  /// γ·lo + (1−γ)·hi, the paper's placement of ξ inside Ξ (γ = 1/2: the midpoint).
  double at(double gamma) const { return point ? lo : gamma * lo + (1.0 - gamma) * hi; }
};

/// A union of disjoint intervals, sorted.
using XiSet = std::vector<XiInterval>;

/// R1,ℓ and R2,ℓ of Section 4 for a piece with λ1 := λ2ℓ−1, λ2 := λ2ℓ of opposite signs, applied
/// to an interval of μ values (hi = +∞ allowed). R1 maps a set of μ2ℓ−1 to the μ2ℓ that have an
/// admissible partner in it (Theorem 2.5 / Remark 2.2); R2 maps a set of μ2ℓ to the μ2ℓ−1 with a
/// partner. nullopt = empty. (The paper's BackwardSplit writes R2⁻¹; the map it needs is R2.)
std::optional<XiInterval> kozak_krajnc_r1(XiInterval mu, double lambda1, double lambda2);
std::optional<XiInterval> kozak_krajnc_r2(XiInterval mu, double lambda1, double lambda2);

/// The tangent direction d3ℓ(ξ) of (4.1) at breakpoint ℓ of the points T0..T3m (not normalized).
/// Needs ΔT3ℓ−1, ΔT3ℓ not collinear at interior breakpoints.
Vec2 kozak_krajnc_direction(std::span<const Point> points, std::size_t breakpoint, double xi);

/// The ξ ∈ (0, 1) with d3ℓ(ξ) pointing along `direction` (nullopt if the direction lies outside
/// the cone of (4.1) at that breakpoint).
std::optional<double> kozak_krajnc_xi_of(std::span<const Point> points, std::size_t breakpoint,
                                         Vec2 direction);

/// Whether piece ℓ (1-based) with breakpoint parameters ξℓ−1, ξℓ satisfies Theorem 2.4 or 2.5.
bool kozak_krajnc_piece_admissible(std::span<const Point> points, std::size_t piece, double xi_left,
                                   double xi_right);

/// The sweeps' result for T0..T3m.
struct KozakKrajncSweep {
  std::size_t pieces = 0;      ///< m
  std::vector<XiInterval> I;   ///< Iℓ: ξℓ ∈ (0, 1) with both μ of breakpoint ℓ positive
  std::vector<XiSet> forward;  ///< Ξℓ after ForwardSweep (reachable from the left)
  std::vector<XiSet> xi;  ///< Ξℓ after BackwardSweep: every ξℓ ∈ Ξℓ extends to a full
                          ///< admissible choice (Corollary 4.3)
};

/// Forward and backward sweeps over T0..T3m. `fixed[ℓ]` (optional, size m+1 when given) pins ξℓ
/// (clamped or prescribed directions). Throws Error(kInfeasible) naming the first piece or
/// breakpoint where the admissible set became empty, Error(kInvalidArgument) naming the index
/// when the data violate Theorem 4.1's assumptions (collinear triples, λ2ℓ−1, λ2ℓ both < 0).
KozakKrajncSweep kozak_krajnc_sweep(std::span<const Point> points,
                                    std::span<const std::optional<double>> fixed = {});

/// Corollary 4.3's divide et impera with r = the first free index: ξ0 is placed in Ξ0, then each
/// ξℓ in the set of Ξℓ values admissible with the chosen ξℓ−1 (non-empty by the backward sweep).
/// O(m). Where such a set has several components, the one containing (else nearest to) the
/// tangent of the chord-length parabola through T3ℓ−1, T3ℓ, T3ℓ+1 is used; inside it ξℓ is the
/// γ-point, or with gamma = NaN ("auto") that parabola's ξ kept 10% of the width from the ends.
std::vector<double> kozak_krajnc_select(std::span<const Point> points,
                                        const KozakKrajncSweep& sweep, double gamma);

/// Where the tangent directions come from.
enum class KozakKrajncTangents {
  kSweep,                  ///< ξℓ placed by γ inside the swept Ξℓ (default)
  kLocalQuadraticUniform,  ///< the parabola through T3ℓ−1, T3ℓ, T3ℓ+1 at uniform parameters
  kLocalQuadraticChordal,  ///< ... at chord-length parameters (checked against Ξ)
};

/// Options of the `kozak-krajnc` method.
struct KozakKrajncOptions {
  /// ξℓ = γ·inf Ξℓ + (1−γ)·sup Ξℓ; NaN = "auto" (the chord-length parabola's direction, kept
  /// inside Ξℓ: see kozak_krajnc_select).
  double gamma = 0.5;
  KozakKrajncTangents tangents = KozakKrajncTangents::kSweep;
  bool remainder_hermite = false;  ///< finish 3m+2 / 3m+3 points with G1 Hermite cubics
  bool g2 = false;                 ///< Newton on (1.4) for the interior directions
  int g2_max_iterations = 30;
  /// A G2 iteration that does not converge returns the G1 spline with its SolverStatus
  /// (FitResult::solver) instead of throwing Error(kNotConverged).
  bool best_effort = false;
};

/// The method: see docs/methods/kozak-krajnc.md.
void fit_kozak_krajnc(const FitInput& input, const KozakKrajncOptions& options, ReportLevel level,
                      FitResult& out);
FitResult fit_kozak_krajnc(const FitInput& input, const KozakKrajncOptions& options = {},
                           ReportLevel level = ReportLevel::kBasic);

}  // namespace fairspline
