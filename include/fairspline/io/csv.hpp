// CSV input (points) and output (Bézier control points of a fit).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fairspline/fit.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline::io {

/// Parses points from CSV text: one `x,y` per line. Tolerated: an optional header line (a first
/// content line none of whose fields is a number), `#` comments (whole-line or trailing), blank
/// lines, surrounding whitespace, CRLF line ends, and `;` or whitespace as separator instead of
/// `,`. Errors:
///   kParseError  "line 7: expected two numbers 'x,y', got 'abc'"  (index = 1-based line)
///   kNonFinite   "line 3 (point 1): coordinate 'nan' is not finite" (NaN, Inf, or overflowing
///                text; index = the 0-based point)
std::vector<Point> parse_csv_points(std::string_view text);

/// Reads a file and parses it with parse_csv_points; kIoError when it cannot be read.
std::vector<Point> read_csv_points(const std::filesystem::path& path);

/// One row per Bézier piece with its 8 control coordinates, header `x0,y0,x1,y1,x2,y2,x3,y3`.
/// Numbers are written in the shortest form that reads back to the same double.
std::string write_csv(const FitResult& result);

/// Parses one number as written in CSV or on a command line (locale-independent; accepts a
/// leading '+'). Returns false when `text` is not a number; throws kNonFinite (with `what` as
/// the message prefix and `index`) when it is NaN, Inf, or overflows double.
bool parse_number(std::string_view text, double& value, std::string_view what = "number",
                  std::optional<std::size_t> index = std::nullopt);

/// Shortest decimal text of a double that reads back to the same value ("0.1", "1e+300").
std::string format_double(double value);

}  // namespace fairspline::io
