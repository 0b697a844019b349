// Energies of cubic pieces and splines.
//   linearized strain energy  ∫|s''(t)|² dt  (closed form, in the global parameter)
//   bending energy            ∫κ² ds         (adaptive Gauss–Kronrod 15/31)
//   curvature variation       ∫(dκ/ds)² ds   (adaptive Gauss–Kronrod 15/31)
//   arc length                ∫|s'| dt       (adaptive Gauss–Kronrod 15/31)
#pragma once

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/spline.hpp"

namespace fairspline {

/// Options of the quadratures. Every tolerance is relative: no absolute epsilon is involved.
struct EnergyOptions {
  /// Relative error target of each integral: the adaptive Gauss–Kronrod (15/31) rule bisects
  /// until its error estimate is at most accuracy·|value| (or max_depth / its 256-interval
  /// budget is reached; the estimate then stays larger and is reported).
  double accuracy = 1e-9;
  /// A piece whose speed |b'(u)| drops to speed_floor·(control polygon length) or below
  /// somewhere is singular: κ is unbounded there and ∫κ² ds may diverge.
  double speed_floor = 1e-9;
  int max_depth = 30;  ///< maximum bisection depth of the adaptive rule
};

/// Result of a quadrature: value, an error estimate, and whether the integrand was singular
/// (vanishing speed). When singular, value is finite — the integral over the parameters where
/// the speed is above the floor — and must not be trusted as the energy. Never NaN or Inf.
struct Quadrature {
  double value = 0.0;
  double error_estimate = 0.0;
  bool singular = false;
};

/// ∫_0^1 |b''(u)|² du for the local parameter. Closed form: b'' = (1−u)A + uB is linear, with
/// A = 6(p2 − 2p1 + p0), B = 6(p3 − 2p2 + p1), so the integral is (|A|² + A·B + |B|²)/3.
double linearized_energy_local(const CubicBezier& b);
/// ∫|s''(t)|² dt of a piece spanning a global parameter interval of length dt: local / dt³.
/// Throws Error(kInvalidArgument) unless dt > 0 is finite, Error(kNonFinite) on overflow.
double linearized_energy(const CubicBezier& b, double dt);
/// Sum of the pieces' linearized energies in the global parameter (each piece's t1 − t0);
/// errors carry the index of the offending piece.
double linearized_energy(const Spline& s);

/// ∫κ² ds = ∫ cross(b',b'')² / |b'|⁵ du over the piece (parameterization-invariant; scales as
/// 1/size). Exactly 0 for a straight piece (control points collinear to rounding), which is
/// still flagged singular if it stops (collinear reversal).
Quadrature bending_energy(const CubicBezier& b, const EnergyOptions& options = {});
/// ∫(dκ/ds)² ds = ∫ (dκ/du)² / |b'| du over the piece (scales as 1/size³); 0 when straight.
Quadrature curvature_variation_energy(const CubicBezier& b, const EnergyOptions& options = {});
/// Arc length ∫|b'| du of the piece. Never singular (a cusp is a kink of |b'|, handled by a
/// breakpoint of the rule at the speed minimum).
Quadrature arc_length(const CubicBezier& b, const EnergyOptions& options = {});

/// Totals over a spline; `singular` is set when any piece is.
Quadrature bending_energy(const Spline& s, const EnergyOptions& options = {});
Quadrature curvature_variation_energy(const Spline& s, const EnergyOptions& options = {});
Quadrature arc_length(const Spline& s, const EnergyOptions& options = {});

}  // namespace fairspline
