// Knot parameterization: the global parameter values t_i at the input points.
#pragma once

#include <span>
#include <vector>

#include "fairspline/vec2.hpp"

namespace fairspline {

/// Common exponents of the alpha-parameterization Δt_i = |ΔP_i|^alpha.
inline constexpr double kUniform = 0.0;
inline constexpr double kCentripetal = 0.5;
inline constexpr double kChordal = 1.0;

/// Knots t_0 = 0, t_{i+1} = t_i + |P_{i+1} - P_i|^alpha for alpha in [0, 1].
/// Open curves: n points give n knots. Closed curves: n points give n+1 knots, the last one
/// for the closing span P_{n-1} -> P_0. Throws Error for alpha outside [0,1] or zero spans.
std::vector<double> alpha_knots(std::span<const Point> points, double alpha, bool closed);
/// The same, written into `knots` (its capacity is reused).
void alpha_knots(std::span<const Point> points, double alpha, bool closed,
                 std::vector<double>& knots);

/// Checks user-given knots: strictly increasing, finite, and the right count
/// (n for open, n+1 for closed). Throws Error naming the first offending knot.
void validate_knots(std::span<const double> knots, std::size_t point_count, bool closed);

}  // namespace fairspline
