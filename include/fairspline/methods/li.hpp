// Li: C1 cubic Hermite interpolation by approximate energy minimization.
// Paper: J. Li, "Constructing planar C1 cubic Hermite interpolation curves via approximate
// energy minimization", Section 2 (systems 2.13, 2.16, 2.17, 2.20, 2.21), generalized here to
// non-uniform knots (see docs/methods/li.md).
//
// The tangent vectors m_i = s'(t_i) minimize
//   E(m) = w1 · Σ ∫|s''(t)|² dt  +  w2 · H² · Σ ∫|s'''(t)|² dt,
// H = mean knot interval, so that E is invariant under rescaling the knots and, for uniform
// knots with Δt = 1 and (w1, w2) = (1, 0) or (1, 1), the normal equations are exactly the
// paper's (2.13) or (2.17). The stationarity conditions form a tridiagonal (cyclic when closed)
// symmetric positive definite system solved in O(n).
#pragma once

#include "fairspline/fit.hpp"

namespace fairspline {

/// Options of the Li methods.
struct LiOptions {
  double strain_weight = 1.0;               ///< w1 >= 0
  double curvature_variation_weight = 0.0;  ///< w2 >= 0; w1 + w2 > 0
};

/// Fits a C1 cubic Hermite spline whose tangent vectors minimize the weighted approximate
/// energy. Clamped tangents (FitInput::start_tangent, end_tangent, and points of kind
/// kClamped with their FitInput::tangents entry) are derivatives with respect to the knot
/// parameter and are kept exactly.
/// With w1 = 0 the energy is singular (Li 2.16): a clamped tangent is then required, except
/// for closed curves with an odd number of points, where the solution is unique.
/// Throws Error on bad input (see detail::prepare_input) and kSingularSystem as above.
FitResult fit_li(const FitInput& input, const LiOptions& options,
                 ReportLevel level = ReportLevel::kBasic);
/// The same, written into `out` reusing its capacity (see fairspline::fit_into). The report is
/// not computed here (the registry's fit() does that); `level` only sizes the method_report.
void fit_li(const FitInput& input, const LiOptions& options, ReportLevel level, FitResult& out);

}  // namespace fairspline
