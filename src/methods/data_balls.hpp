// Data balls for the min-energy family (private): points that may move inside discs, their
// positions optimized with the directions. docs/methods/min-energy.md, "Data balls".
#pragma once

#include <array>
#include <vector>

#include "fairspline/methods/min_energy.hpp"

namespace fairspline::detail {

/// Per span: the unit outgoing direction at its start and the unit incoming one at its end.
using SpanDirections = std::vector<std::array<Vec2, 2>>;

/// How far fit_min_energy_at looks for a lower minimum than its descent's: kFull, the
/// interpolation's, also in the elastic stencils' second intervals and, with
/// search=coordinate, at search=newton's minimum too (docs/methods/elastic.md, "Which
/// minimum"); kDescentOnly, a data-ball fit's interpolations: its own optimizer reaches those
/// intervals, and going on from such minima found at its refits stalled beside half-turn bounds
/// (docs/hardening.md).
enum class MinimumSearch { kFull, kDescentOnly };

/// fit_min_energy through the points as they are (radii ignored): started from `warm` where
/// given (the directions of a nearby optimum), and with the directions it chose written to
/// `dirs` where given.
void fit_min_energy_at(const FitInput& input, const MinEnergyOptions& options, ReportLevel level,
                       FitResult& out, MinEnergyReport* report, const SpanDirections* warm,
                       SpanDirections* dirs, MinimumSearch search = MinimumSearch::kDescentOnly);

/// True when some point has a positive radius.
bool has_data_balls(const FitInput& input);

/// The minimal-energy curve through the data balls: directions and positions inside the discs
/// minimize the energy (a projected Newton method over both, O(n) per iteration). The result's
/// `points` are the chosen positions; method_report gains "balls".
void fit_data_balls(const FitInput& input, const MinEnergyOptions& options, ReportLevel level,
                    FitResult& out, MinEnergyReport* report);

}  // namespace fairspline::detail
