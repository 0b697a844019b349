// The exact basic curve of elastic splines (Borbély & Johnson, "Elastic Splines I: Existence",
// Constr. Approx. 40 (2014)): between two points with given end directions, the s-curve (at most
// one inflection, each turn at most 180°) of least bending energy ∫κ² ds, its length free.
// Derivation, conventions and verified numbers: docs/methods/elastic.md.
//
// Angles follow basic_curve / basic_energy of min_energy.hpp: α is the start direction and β the
// end direction, both measured counter-clockwise from the chord p1 − p0. E(α, β) = E(β, α) =
// E(−α, −β). The minimizing curves are pieces of Bernoulli's rectangular elastica, except for
// large turns where the 180° limit of the first turn is reached ("U-turn" pieces, below).
#pragma once

#include <limits>
#include <numbers>
#include <vector>

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline::detail {

/// The canonical rectangular elastica p(u) = (√2 sin u, X(u)) (docs): X(u) =
/// ∫_0^u √2 sin²v / √(1 + sin²v) dv and its arc length from u = 0, for u ∈ [−π, π], accurate
/// to 1e-15 relative (also near u = 0, where X ≈ √2u³/3).
double elastica_x(double u);
double elastica_arc_length(double u);

/// True when a minimizing s-curve exists: |α| < π, |β| < π and |α − β| ≤ π (a rounding of
/// 4 ulp of π above π is accepted and treated as π).
bool elastica_feasible(double alpha, double beta);

/// E_1(α, β) = min ∫κ² ds over s-curves on the unit chord, with gradient and Hessian.
struct ElasticaEnergy {
  double e = 0.0;
  double ea = 0.0, eb = 0.0;  ///< ∂E/∂α = −2κ_a, ∂E/∂β = 2κ_b (elastica pieces)
  double eaa = 0.0, eab = 0.0, ebb = 0.0;  ///< Hessian
};

/// E_1(α, β) with derivatives; a chord of length L has E_L = E_1 / L. Throws
/// Error(kInfeasible) outside elastica_feasible, Error(kNonFinite) on NaN/Inf. Never returns
/// NaN or Inf: where the second derivatives do not exist (the corners (±π/2, ∓π/2) of the box
/// and the edge |α − β| = π) it returns those at distance 1e-16 from the edge (~1.7e8).
/// In the box |α|, |β| ≤ π/2 E_1 is C¹, C² except at those corners, and the piece is always an
/// elastica arc (consistent with end curvatures). Outside it E_1 has kinks where the minimizer
/// switches between candidates; on α = β past 98.56° (a U-turn piece with both turns full) the
/// gradient returned is the mean of the two one-sided ones. About 0.8 µs in the box, 7 µs
/// outside it; for max(|α|, |β|) ≤ 1e-4 the degree-4 Taylor polynomial (docs).
ElasticaEnergy elastica_energy(double alpha, double beta);

/// The s-curves' pair constraint |α − β| <= this, just inside 180°, where E_1 is finite (both
/// the interpolation and the data-ball optimizer hold their pieces to it).
inline constexpr double kElasticaPairLimit = std::numbers::pi * (1.0 - 1e-12);

/// Past this turn a U-turn piece with both turns full exists on α = β, and E_1 has a convex kink
/// across the diagonal there (a V in α − β: a ridge, docs/methods/elastic.md).
bool elastica_ridge_capable(double alpha, double beta);

/// The kink's half-width on the ridge α = β = mid: moving one end's direction alone by ε off the
/// ridge changes E_1 by ε times the mean derivative plus this times |ε|. `on` is
/// elastica_energy(mid, mid). Off the ridge by δ the derivatives differ from their limit like
/// √δ (E_1 has a |α − β|^{3/2} term), so the values at δ and 2δ are extrapolated in √δ.
double elastica_ridge_half_jump(double mid, const ElasticaEnergy& on);

/// A warm start for repeated evaluations of one span at nearby angles (the optimizer's
/// iterations): the canonical root of the last solve, the canonical angles and symmetry it was
/// found under, and the root's derivatives in them (the next root-find starts from the
/// first-order prediction).
struct ElasticaHint {
  double u1 = std::numeric_limits<double>::quiet_NaN();
  double a = 0.0, b = 0.0;            ///< canonical angles of that solve
  double du1_da = 0.0, du1_db = 0.0;  ///< ∂u1/∂a, ∂u1/∂b there (0 when unknown)
  bool reversed = false, mirrored = false;
};

/// elastica_energy, starting the root-find from `hint` when it applies and updating it: the
/// same values up to the root-find's rounding, in 1–2 instead of ~5 evaluations near the last.
ElasticaEnergy elastica_energy(double alpha, double beta, ElasticaHint& hint);

/// The exact minimizing piece from p0 to p1. It is described on the canonical elastica
/// p(u) = (√2 sin u, X(u)), u ∈ [−π, π] (inflection at u = 0, curvature √2 sin u), mapped onto
/// the chord by a similarity.
struct ElasticaArc {
  enum class Kind {
    kStraight,  ///< α = β = 0: the segment p0 p1
    kElastica,  ///< one arc [u0, u1] of the rectangular elastica
    kUTurn,     ///< a full 180° turn [−π, 0], a straight segment, then the arc [0, u1]
  };
  Kind kind = Kind::kStraight;
  Point p0, p1;                    ///< end points (world)
  double alpha = 0.0, beta = 0.0;  ///< end angles from the chord (as given)
  /// Canonical description (a reflection and/or reversal of the piece itself, see below).
  double u0 = 0.0, u1 = 0.0;  ///< canonical parameter range, −π ≤ u0 < u1 ≤ π
  double segment = 0.0;       ///< kUTurn: length of the straight part at u = 0 (canonical)
  Vec2 chord{1.0, 0.0};       ///< canonical chord (end − start, including the segment)
  bool reversed = false;      ///< canonical piece solves (β, α): traverse it backwards
  bool mirrored = false;      ///< canonical piece solves (−α, −β): reflect it in the chord
  double unit_energy = 0.0;   ///< E_1(α, β)

  /// Length of the piece (world units).
  double length() const;
  /// ∫κ² ds of the piece (world units): E_1 / |p1 − p0|.
  double energy() const { return unit_energy / distance(p0, p1); }
  /// Position, unit tangent and signed curvature at the arc-length fraction t ∈ [0, 1].
  Point point(double t) const;
  Vec2 tangent(double t) const;
  double curvature(double t) const;
};

/// The minimizing piece from p0 to p1 (p0 ≠ p1, finite) with end angles (α, β) as above, its
/// root-find started from `hint` when given (the optimizer's last solve of the span).
/// Throws like elastica_energy, and Error(kInvalidArgument) when p0 = p1.
ElasticaArc elastica_arc(Point p0, Point p1, double alpha, double beta,
                         const ElasticaHint* hint = nullptr);

/// Diagnostics (tests, docs): every piece satisfying the first-order conditions for (α, β)
/// that a scan of the canonical path at `samples` points finds (elastica arcs, and the U-turn
/// piece when it exists), in no particular order; elastica_arc returns the one of least
/// energy. Empty for α = β = 0.
std::vector<ElasticaArc> elastica_candidates(Point p0, Point p1, double alpha, double beta,
                                             int samples);

/// Cubic Béziers approximating the piece: G1 (shared joints and tangent directions), end points
/// and end tangent directions exact, Hausdorff distance to the exact piece at most
/// accuracy·|p1 − p0| — certified by a bound that holds everywhere on both curves (up to
/// rounding, for which an allowance is included), not only at samples. Each cubic is the G2
/// Hermite cubic of its sub-arc (end curvatures matched; where that system has no solution the
/// handles closest to it; least squares when that is closer), the sub-arcs placed greedily,
/// each about as long as its bound allows. Regular cubics (no cusp; handles at least 5% of the
/// chord); bending energy within accuracy·(E + 1/|p1 − p0|) (quadrature). About 30-40 µs per
/// span in the box at 1e-6, 100-150 µs at 1e-9 (docs). accuracy ∈ [1e-13, ∞); below that
/// Error(kInvalidArgument).
std::vector<CubicBezier> elastica_to_beziers(const ElasticaArc& arc, double accuracy);

}  // namespace fairspline::detail
