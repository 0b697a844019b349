// Kozak–Krajnc: geometric interpolation by planar cubic G1 splines (building blocks).
// Paper: J. Kozak, M. Krajnc, "Geometric interpolation by planar cubic G1 splines",
// BIT Numerical Mathematics 47 (2007) 547–563 (Section 2: (2.3)–(2.7), Lemmas 2.1–2.3,
// Theorems 2.4, 2.5).
//
// Each cubic piece P passes through four points T0..T3 at parameters 0 < t1 < t2 < 1 with end
// derivatives α0·d0, α3·d3 (α > 0). This header has the data constants and the existence
// conditions of Section 2; the single-piece solver and the spline sweeps of Section 4 build on
// them (issue 5, in progress: no registered method yet).
#pragma once

#include <optional>

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

}  // namespace fairspline
