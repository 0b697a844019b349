// Curve Ensemble's text files (the program of the Johnson–Johnson paper): one node per line,
// "x y DIR CORNER STATE BE" (docs/curve-ensemble.md has the format as its source defines it).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "fairspline/fit.hpp"

namespace fairspline::io {

/// Curve Ensemble's node state codes.
enum class CurveEnsembleState {
  kRegular = 0,      ///< both sides optimized, the corner kept
  kClamped = 1,      ///< both sides given: incoming DIR − CORNER, outgoing DIR
  kFreeClamped = 3,  ///< incoming free, outgoing given (DIR): a clamped start
  kClampedFree = 5,  ///< incoming given (DIR − CORNER), outgoing free: a clamped end
  kFree = 7,         ///< both sides free (the ends of an open curve, a cusp between pieces)
};

/// Parses a Curve Ensemble text file into a fit input with the node model: per node
/// `states`, `in_tangents` / `out_tangents` for clamped sides, `corners_deg` for regular nodes
/// (DIR and CORNER are degrees; DIR is the outgoing direction, the incoming one is
/// DIR − CORNER), and `radii` for data balls: a row with state < 0 (radius −state) or > 100
/// (Curve Ensemble's "marked" ball, radius state − 100) is a regular node at the ball's centre,
/// and a file with three numbers on every line is Curve Ensemble's data-ball file "x y r". As
/// Curve Ensemble reads it: lines starting with '#' are comments, missing columns are 0 (so a
/// file of "x y" lines is a closed curve of regular nodes), BE (the sixth column, the piece's
/// energy) is informational and ignored, and the curve is open exactly when the first node's
/// state is 7 or 3 and the last one's 7 or 5. Blank lines are skipped. Errors name the line and
/// the node: kParseError for text that is not a number, more than six columns or a state code
/// Curve Ensemble does not use; kNonFinite for a coordinate or angle that is not finite;
/// kInvalidArgument for a negative radius in a three-column file; kTooFewPoints for a file
/// without nodes.
FitInput parse_curve_ensemble(std::string_view text);

/// Reads a file and parses it with parse_curve_ensemble; kIoError when it cannot be read.
FitInput read_curve_ensemble(const std::filesystem::path& path);

/// A fitted curve as Curve Ensemble writes it: the header line "#Curve Ensemble Text File",
/// then per node x, y, DIR (the fitted outgoing direction, degrees), CORNER, STATE and BE, a
/// quarter of the bending energy ∫κ² ds of the piece that starts at the node (what Curve
/// Ensemble calls the energy; 0 for the last node of an open curve), each followed by a space.
/// The states come from the result's request (FitResult::input: kinds or the node model);
/// a side that is optimized on its own next to a free side is written as free (7), which is
/// what it means. A data ball is written as Curve Ensemble writes one: its centre, DIR the
/// fitted direction, in the CORNER column the angle of the chosen position from the centre,
/// STATE −r. Numbers are the shortest text that reads back to the same double.
std::string write_curve_ensemble(const FitResult& result);

}  // namespace fairspline::io
