// Johnson & Johnson's minimal-energy framework: every tangent direction is chosen so that the
// total energy of the admissible curve (a basic curve per span) is minimal.
// Paper: M. J. Johnson, H. S. Johnson, "A constructive framework for minimal energy planar curves"
// (Sections 2–6, Examples 1.1, 4.1, 4.2, Theorem 4.4). See docs/methods/min-energy.md.
//
// A basic curve method maps a chord of length L and the end angles (α, β) — the angles of the
// end directions measured from the chord — to a curve c_L(α, β) with energy
// E_L(α, β) = E_1(α, β) / L, defined for |α|, |β| ≤ Ω.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/fit.hpp"

namespace fairspline {

/// The basic curve methods.
enum class MinEnergyBasis {
  kCondG2,  ///< conditionally G2 cubic, speeds s0 = s1 = λ (Theorem 4.4); λ = 1: quasi-elastic
  kJaklicZagar,  ///< s0 = cos α, s1 = cos β, E_1 = sin²α + sin²β (Example 4.2)
  kYongCheng,    ///< optimized geometric Hermite speeds, E_1 = ∫|c''|² (Example 4.1)
  /// The exact s-curve of least ∫κ² ds (a piece of the rectangular elastica; Borbély–Johnson),
  /// restricted to |α|, |β| <= Ω <= 90° (Curve Ensemble's default). Not a cubic: each piece is
  /// output as cubic Béziers within MinEnergyOptions::accuracy. docs/methods/elastic.md.
  kRestrictedElastic,
  /// The same curve on the whole s-curve domain |α|, |β| < 180°, |α − β| <= 180° (coupled
  /// constraints between neighbouring directions).
  kElastic,
};

/// True for the bases whose basic curve is not a cubic (the elastic splines).
constexpr bool is_elastic(MinEnergyBasis basis) {
  return basis == MinEnergyBasis::kRestrictedElastic || basis == MinEnergyBasis::kElastic;
}

/// A basic curve method with its parameters.
struct BasicCurveMethod {
  MinEnergyBasis basis = MinEnergyBasis::kCondG2;
  double lambda = 1.0;                ///< shape parameter of kCondG2, in (0, 3)
  double omega = 1.5707963267948966;  ///< Ω (radians): feasible |α|, |β| ≤ Ω

  /// The default Ω of each basis: 90° (cond-G2, quasi-elastic, restricted elastic), 80°
  /// (Jaklič–Žagar, as in Fig. 7), 60° (Yong–Cheng), 180° (elastic).
  static double default_omega(MinEnergyBasis basis);
};

/// E_1 and its first and second partial derivatives at (α, β) (unit chord).
struct BasicEnergy {
  double e = 0.0;
  double ea = 0.0, eb = 0.0;               ///< ∂E/∂α, ∂E/∂β
  double eaa = 0.0, eab = 0.0, ebb = 0.0;  ///< Hessian
};

/// E_1(α, β) with derivatives. cond-G2: E_1 = ½∫|c''|² = 2λ² cos(α−β) − 6λ(cos α + cos β)
/// + 4λ² + 6 (Section 4; Example 1.1 prints half of the λ = 1 case — same minimizers).
BasicEnergy basic_energy(const BasicCurveMethod& method, double alpha, double beta);

/// Speeds (s0, s1) of the basic curve c_1(α, β) (4.1).
struct BasicSpeeds {
  double s0 = 0.0;
  double s1 = 0.0;
};
BasicSpeeds basic_speeds(const BasicCurveMethod& method, double alpha, double beta);

/// The basic curve c_L(α, β) from p0 to p1 as a Bézier cubic (α, β measured from the chord).
/// The elastic bases have no cubic basic curve: Error(kInvalidArgument), see basic_curve_pieces.
CubicBezier basic_curve(const BasicCurveMethod& method, Point p0, Point p1, double alpha,
                        double beta);

/// The basic curve as cubic Béziers: the cubic itself, or for the elastic bases the exact piece
/// approximated within accuracy·|p1 − p0| (Hausdorff distance), G1, end points and end
/// directions exact.
std::vector<CubicBezier> basic_curve_pieces(const BasicCurveMethod& method, Point p0, Point p1,
                                            double alpha, double beta, double accuracy);

/// Options of the minimal-energy fit.
/// How the directions are searched for. E_1 is not convex on the whole box (beyond Ω_conv,
/// Proposition 6.2), so the energy can have several local minima; each search returns one.
enum class MinEnergySearch {
  /// Projected Newton from the chord bisectors: fast; the local minimum of that start.
  kNewton,
  /// Curve Ensemble's search first (each direction to the best of its one-degree offsets,
  /// sweeps until none moves), then projected Newton from there: never above the coordinate
  /// search's energy; about 100× the time (docs/methods/min-energy.md, "Which minimum").
  kCoordinate,
  /// The least energy over a grid of directions at every node (4° apart, 5° for
  /// restricted-elastic, 10° for elastic), found exactly by dynamic programming along the
  /// chain; projected Newton from there and from the least points of other basins of the grid,
  /// then from finer grids about each minimum; search=newton's minimum where that is lower.
  /// O(n K²) evaluations of E_1 for K grid directions a node; about 50× search=newton's time
  /// (docs/methods/min-energy.md, "Which minimum").
  kGlobal,
};

struct MinEnergyOptions {
  BasicCurveMethod method;
  MinEnergySearch search = MinEnergySearch::kNewton;
  /// Newton iteration limit. Unset: kDefaultIterations up to 10³ points and
  /// kDefaultIterations · (log10 n − 2) beyond (400 at 10⁴, 600 at 10⁵: every late active-set
  /// change in a long chain costs a global iteration); for the elastic spline
  /// 2 kDefaultIterations · (log10 n − 2) from 316 points (800 at 10⁴, 1200 at 10⁵: a 10⁵-point
  /// walk within ±150° needed 623); with data balls at least 4·10⁶ / n within
  /// [kDefaultBallIterations, kMostBallIterations] (their active set may change by one disc per
  /// iteration, and beside near-repeated pairs they converge linearly).
  std::optional<int> max_iterations;
  static constexpr int kDefaultIterations = 200;
  static constexpr int kDefaultBallIterations = 1000;
  static constexpr int kMostBallIterations = 4000;
  /// Stop when the projected gradient's largest entry is below tolerance · max(1/L_i) (the
  /// natural size of the gradient for the data's chord lengths).
  double tolerance = 1e-10;
  /// At the iteration cap, return the curve with SolverStatus::kIterationLimit (FitResult::solver)
  /// instead of throwing Error(kNotConverged).
  bool best_effort = false;
  /// Elastic bases: the output Béziers are within accuracy·(diagonal of the points' bounding
  /// box) of the exact pieces (Hausdorff distance).
  double accuracy = FitOptions::kDefaultCurveAccuracy;
};

/// One span of an elastic spline: the exact piece (method_report "spans").
struct ElasticSpan {
  std::string kind;                ///< "straight" | "elastica" | "u-turn"
  double alpha = 0.0, beta = 0.0;  ///< end angles from the chord (radians)
  double u0 = 0.0, u1 = 0.0;       ///< canonical parameter range (docs/methods/elastic.md)
  double straight = 0.0;           ///< u-turn: canonical length of the straight part
  bool reversed = false, mirrored = false;
  double energy = 0.0;  ///< ∫κ² ds of the exact piece
  double length = 0.0;  ///< its arc length
  int beziers = 0;      ///< cubic pieces in the output
};

/// Outcome of the optimizer (also in FitResult::method_report).
struct MinEnergyReport {
  int iterations = 0;
  /// Long chains (≥ 4096 nodes): how many times the few nodes left above the tolerance were
  /// solved in windows of their own (each counts as an iteration too; docs/methods/min-energy.md).
  int window_passes = 0;
  /// The windows those passes solved, and the Newton iterations they took in all (each window
  /// starts near its optimum: a few iterations apiece).
  int windows = 0, window_iterations = 0;
  double energy = 0.0;
  double projected_gradient = 0.0;  ///< final, relative (see MinEnergyOptions::tolerance)
  std::vector<std::size_t> active;  ///< points whose direction sits on a bound of D_i
  int pieces = 1;                   ///< independent pieces (split at corners)
  std::vector<ElasticSpan> spans;   ///< elastic bases only, one per span
  /// elastic basis: spans whose |α − β| sits at its bound 180° (a coupled constraint)
  std::vector<std::size_t> active_spans;
  /// search=coordinate or global: the minimum returned is that search's on some piece, lower
  /// than search=newton's (which it returns on the others); method_report "minimum" names the
  /// search the returned minimum came from.
  bool below_newton = false;
};

/// The minimal-energy curve through input.points (open or closed; clamped ends via
/// start_tangent / end_tangent; node kinds smooth / clamped / corner). Throws
/// Error(kInfeasible) listing the points with |ψ_i| > 2Ω (Theorem 2.3) or clamped directions
/// outside their feasible range, Error(kNotConverged) if the optimizer stops early.
void fit_min_energy(const FitInput& input, const MinEnergyOptions& options, ReportLevel level,
                    FitResult& out, MinEnergyReport* report = nullptr);

/// Slow reference optimizer in the manner of Curve Ensemble (tests and benchmarks only): cyclic
/// coordinate descent over each free direction, first over 360 one-degree offsets until no
/// move lowers the energy, then 10 refinement levels with steps shrinking 4× per level; a move
/// is accepted only if it lowers the energy. Same input conventions as fit_min_energy; returns
/// the directions' angles (radians, absolute) and the energy.
struct MinEnergyReference {
  std::vector<double> angles;
  double energy = 0.0;
};
MinEnergyReference min_energy_reference(const FitInput& input, const MinEnergyOptions& options);

}  // namespace fairspline
