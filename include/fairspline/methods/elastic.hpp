// Elastic splines: the interpolating curves of least bending energy ∫κ² ds whose every piece is
// an s-curve (Borbély & Johnson, "Elastic Splines I: Existence", Constr. Approx. 40 (2014)), as
// basic curve methods of Johnson & Johnson's minimal-energy framework (min_energy.hpp). The
// restricted elastic spline (|α|, |β| <= 90° at every chord) is Curve Ensemble's default.
// See docs/methods/elastic.md.
#pragma once

#include <limits>
#include <optional>

#include "fairspline/fit.hpp"
#include "fairspline/methods/min_energy.hpp"

namespace fairspline {

struct ElasticOptions {
  /// true: restricted-elastic (boxes |α|, |β| <= Ω <= 90°); false: elastic (|α|, |β| <= Ω <=
  /// 180° and |α − β| <= 180° on every chord).
  bool restricted = true;
  /// Ω in degrees; NaN: 90 (restricted) or 180.
  double omega_deg = std::numeric_limits<double>::quiet_NaN();
  /// Newton iteration limit; unset: as MinEnergyOptions::max_iterations.
  std::optional<int> max_iterations;
  MinEnergySearch search = MinEnergySearch::kNewton;
  /// The output Béziers are within accuracy·(diagonal of the points' bounding box) of the exact
  /// pieces (Hausdorff distance).
  double accuracy = FitOptions::kDefaultCurveAccuracy;
  bool best_effort = false;
};

/// The elastic spline through input.points (every input of fit_min_energy: open or closed,
/// clamped ends, node kinds). method_report: the exact energy ("energy"), the solver's outcome,
/// and per span the exact piece ("spans": kind, end angles, canonical parameters, energy,
/// length, number of Béziers). Throws as fit_min_energy.
void fit_elastic(const FitInput& input, const ElasticOptions& options, ReportLevel level,
                 FitResult& out, MinEnergyReport* report = nullptr);

}  // namespace fairspline
