// fit_into's one normalization (private): data far from unit size are scaled by a power of two
// before the method runs and its result is mapped back, so that no method needs range guards
// of its own for the points' scale.
#pragma once

#include <optional>
#include <span>

#include "fairspline/fit.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::detail {

/// Coordinates whose largest magnitude lies within 2^±kNormalRange are left alone (so normal
/// data give bit-identical results); make_report uses the same rule.
inline constexpr int kNormalRange = 24;

/// How a normalized fit relates to the input: points were multiplied by 2^-length_exponent and
/// so knots by 2^-knot_exponent (alpha-knots scale as the points to the power alpha; explicit
/// knots do not scale).
struct Normalization {
  int length_exponent = 0;
  double knot_exponent = 0.0;
};

/// The normalization `input` needs, or nullopt when its points are within the normal range
/// (or not all finite: the method's own checks then report them). The exponent is even, so
/// that centripetal knots (alpha = 0.5) scale by an exact power of two too.
std::optional<Normalization> normalization_for(const FitInput& input);

/// The input the method sees: points scaled; tangents too where their length is a derivative
/// with respect to the knots (C1 methods), directions are left alone. Point errors are raised
/// here first, on the original points, so that messages quote the user's coordinates.
void normalize_input(const FitInput& input, const Normalization& nz, const Capabilities& caps,
                     FitInput& out);

/// Maps a result of the normalized input back to the input's units: points, knots, pieces,
/// and the method_report numbers listed in `units` (an entry that leaves the double range
/// becomes null, as an overflowing energy does in the methods' own reports).
void denormalize_result(const FitInput& original, const Normalization& nz,
                        std::span<const ReportUnit> units, FitResult& out);

}  // namespace fairspline::detail
