// Energies of cubic pieces and splines.
//   linearized strain energy  ∫|s''(t)|² dt  (closed form, in the global parameter)
//   bending energy            ∫κ² ds         (adaptive Gauss–Legendre)
//   curvature variation       ∫(dκ/ds)² ds   (adaptive Gauss–Legendre)
//   arc length                ∫|s'| dt
#pragma once

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/spline.hpp"

namespace fairspline {

/// Accuracy of the quadratures: relative error target of each integral.
struct EnergyOptions {
  double accuracy = 1e-9;
  /// A piece whose speed drops below speed_floor·(control polygon length) somewhere is treated
  /// as singular: κ is unbounded there and ∫κ² ds may diverge.
  double speed_floor = 1e-9;
  int max_depth = 30;  ///< maximum bisection depth of the adaptive rule
};

/// Result of a quadrature: value, an error estimate, and whether the integrand was singular
/// (vanishing speed). When singular, value is the finite partial integral and must not be
/// trusted as the energy.
struct Quadrature {
  double value = 0.0;
  double error_estimate = 0.0;
  bool singular = false;
};

/// ∫_0^1 |b''(u)|² du for the local parameter (closed form).
double linearized_energy_local(const CubicBezier& b);
/// ∫|s''(t)|² dt of a piece spanning a global parameter interval of length dt: local / dt³.
double linearized_energy(const CubicBezier& b, double dt);
/// Sum of the pieces' linearized energies in the global parameter.
double linearized_energy(const Spline& s);

/// ∫κ² ds over the piece (parameterization-invariant).
Quadrature bending_energy(const CubicBezier& b, const EnergyOptions& options = {});
/// ∫(dκ/ds)² ds over the piece.
Quadrature curvature_variation_energy(const CubicBezier& b, const EnergyOptions& options = {});
/// Arc length of the piece.
Quadrature arc_length(const CubicBezier& b, const EnergyOptions& options = {});

/// Totals over a spline; `singular` is set when any piece is.
Quadrature bending_energy(const Spline& s, const EnergyOptions& options = {});
Quadrature curvature_variation_energy(const Spline& s, const EnergyOptions& options = {});
Quadrature arc_length(const Spline& s, const EnergyOptions& options = {});

}  // namespace fairspline
