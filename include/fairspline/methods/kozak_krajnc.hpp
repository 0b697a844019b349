// Kozak–Krajnc: geometric interpolation by planar cubic G1 splines (building blocks).
// Paper: J. Kozak, M. Krajnc, "Geometric interpolation by planar cubic G1 splines",
// BIT Numerical Mathematics 47 (2007) 547–563 (Section 2: (2.3)–(2.7), Lemmas 2.1–2.3,
// Theorems 2.4, 2.5).
//
// Each cubic piece P passes through four points T0..T3 at parameters 0 < t1 < t2 < 1 with end
// derivatives α0·d0, α3·d3 (α > 0). This header has the data constants, the existence
// conditions of Section 2 and Table 3.3, and the single-piece solver that finds *all* admissible
// solutions; kozak_krajnc_spline.hpp has the spline sweeps of Section 4.
#pragma once

#include <array>
#include <optional>

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline {

/// The constants (2.6) of one piece (ℓ = 1): λ1, λ2 from the points only; μ1, μ2, δ1, δ2 also
/// from the end directions. D_ij = det(ΔT_i, ΔT_j).
struct KozakKrajncConstants {
  double lambda1 = 0.0;  ///< D_02 / D_01
  double lambda2 = 0.0;  ///< D_02 / D_12
  double mu1 = 0.0;      ///< det(d0, ΔT1) / det(d0, ΔT0)
  double mu2 = 0.0;      ///< det(ΔT1, d3) / det(ΔT2, d3)
  double delta1 = 0.0;   ///< D_01 / det(d0, ΔT0)
  double delta2 = 0.0;   ///< D_12 / det(ΔT2, d3)
};

/// (2.6) for the points t0..t3 and end directions d0, d3. Throws Error(kInvalidArgument) when a
/// denominator vanishes (collinear consecutive chords, or an end direction along its chord),
/// naming which, kNonFinite for non-finite input.
KozakKrajncConstants kozak_krajnc_constants(Point t0, Point t1, Point t2, Point t3, Vec2 d0,
                                            Vec2 d3);

/// The unique solution (t̃1, t̃2) of (2.7) for λ1, λ2 > 0 (Lemma 2.1): t1 = t1(t2) explicit and
/// t2 the root of the monotone g on (1/∛(1+λ1), 1), found by bisection to full precision.
/// nullopt unless λ1 > 0 and λ2 > 0.
struct ParameterPair {
  double t1 = 0.0;
  double t2 = 0.0;
};
std::optional<ParameterPair> kozak_krajnc_boundary_alpha0(double lambda1, double lambda2);
/// The unique solution of Lemma 2.2's twin system (α3 = 0); by the symmetry t ↦ 1 − t it is
/// (1 − s2, 1 − s1) with (s1, s2) the solution of (2.7) for (λ2, λ1).
std::optional<ParameterPair> kozak_krajnc_boundary_alpha3(double lambda1, double lambda2);

/// φ2(λ1, λ2) of Lemma 2.1 (μ2 at which a solution with α0 = 0 exists) and φ1 of Lemma 2.2
/// (μ1 at which a solution with α3 = 0 exists); nullopt unless λ1, λ2 > 0.
std::optional<double> kozak_krajnc_phi1(double lambda1, double lambda2);
std::optional<double> kozak_krajnc_phi2(double lambda1, double lambda2);

/// φ3, φ4 of Section 2 (before Lemma 2.3), closed forms.
double kozak_krajnc_phi3(double lambda1, double lambda2, double mu1);
double kozak_krajnc_phi4(double lambda1, double lambda2, double mu1);

/// Theorem 2.4 (convex data): λk, δk, μk > 0 and either μ1 < φ1, μ2 < φ2 or μ1 > φ1, μ2 > φ2.
bool kozak_krajnc_theorem_2_4(const KozakKrajncConstants& c);
/// Theorem 2.5 (inflection): λ1 > 0 > λ2, δ1, δ2 > 0, μ1 > 0 and φ3(λ1, λ2, μ1) < μ2 <
/// φ4(λ1, λ2, μ1); with Remark 2.2, also the same with the roles of (λ1, μ1), (λ2, μ2) swapped.
bool kozak_krajnc_theorem_2_5(const KozakKrajncConstants& c);

/// Table 3.3: further sufficient conditions for the existence of P. Returns the row (1–8, top
/// to bottom as read in docs/methods/kozak-krajnc.md) whose conditions hold, or 0.
int kozak_krajnc_table_3_3(const KozakKrajncConstants& c);

/// One admissible solution (t1, t2, α0, α3) ∈ D of (2.3)–(2.5): 0 < t1 < t2 < 1, α0, α3 > 0.
/// α are relative to the direction vectors as given (P'(0) = α0·d0, P'(1) = α3·d3).
struct KozakKrajncSolution {
  double t1 = 0.0;
  double t2 = 0.0;
  double alpha0 = 0.0;
  double alpha3 = 0.0;
  /// Intersection multiplicity of the two curves (2.3) at (t1, t2): 1 when they cross
  /// transversally; otherwise their order of contact k (the first Lie derivative of one along
  /// the other that does not vanish within rounding; docs/methods/kozak-krajnc.md).
  int multiplicity = 1;
  /// Linearized strain energy ∫₀¹ |P''(t)|² dt of the piece: the rule that picks one solution.
  double energy = 0.0;
};

/// All admissible solutions of one piece (at most 9: the eliminated polynomial has degree 9).
struct KozakKrajncSolutions {
  static constexpr int kCapacity = 9;
  std::array<KozakKrajncSolution, kCapacity> items{};
  int count = 0;    ///< number of distinct admissible solutions, sorted by t1
  int chosen = -1;  ///< index of the least-energy solution, −1 when there is none

  const KozakKrajncSolution* begin() const { return items.data(); }
  const KozakKrajncSolution* end() const { return items.data() + count; }
  /// Sum of the multiplicities (odd under Theorems 2.4/2.5 by the degree argument of Section 3).
  int total_multiplicity() const;
};

/// Every admissible solution of (2.3)–(2.5) for the points T0..T3 and end directions d0, d3
/// (any length, not both needed unit). The system (2.3) is cleared of denominators, t1 is
/// eliminated by the Bézout resultant (a degree-15 polynomial in t2 that always carries the
/// spurious factor t2³(1−t2)³; the rest has degree ≤ 9), its real roots in (0, 1) are isolated in
/// Bernstein form by Descartes' rule, t1 follows from the null vector of the Bézout matrix, and
/// each pair is polished by Newton's method on (2.3). Where the two curves (2.3) are tangent (a
/// multiple solution, or close ones) the cluster is resolved through the derivative system
/// along one curve: a k-fold solution to full precision with multiplicity k, or its distinct
/// solutions. Throws what kozak_krajnc_constants throws.
KozakKrajncSolutions kozak_krajnc_solve(Point t0, Point t1, Point t2, Point t3, Vec2 d0, Vec2 d3);

/// The cubic of one solution: control points T0, T0 + α0·d0/3, T3 − α3·d3/3, T3.
CubicBezier kozak_krajnc_bezier(Point t0, Point t3, Vec2 d0, Vec2 d3,
                                const KozakKrajncSolution& solution);

}  // namespace fairspline
