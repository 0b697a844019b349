// JSON input (points + fit request) and output (the FitResult contract used by the web editor,
// Python and external checks), plus small text helpers shared by the tools.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"

namespace fairspline::io {

/// A fit request read from JSON.
struct ParsedInput {
  FitInput input;
  std::optional<std::string> method;                  ///< "method" field, if given
  nlohmann::json options = nlohmann::json::object();  ///< "options" field (+ "lambdas")
};

/// Parses a fit request:
///   {"points": [[x,y],...], "closed": bool, "tangents": [[x,y] or null,...],
///    "kinds": ["smooth"|"clamped"|"corner",...], "method": str, "options": {...},
///    "alpha": num, "knots": [...], "start_tangent": [x,y], "end_tangent": [x,y],
///    "lambdas": [...]}
/// Only "points" is required; a bare array of points is accepted as {"points": [...]}.
/// "lambdas" is a method option given at top level for convenience: it is moved into
/// `options` (giving it in both places is an error). Keys starting with '_' or '$' are
/// comments; any other unknown key is an error (typos). Errors:
///   kParseError  invalid JSON (message with line and column; index = line), or a malformed
///                field ("points[3]: expected [x, y] with two numbers"; index = 3)
///   kNonFinite   a number too large for double (1e999), naming the field
ParsedInput parse_json_input(std::string_view text);
/// Same, from an already parsed document (e.g. the body of a web request).
ParsedInput input_from_json(const nlohmann::json& document);

/// The result as JSON:
///   {"method","closed","options","points","knots","tangents",
///    "segments": [{"bezier": [[x,y]x4], "t0", "t1", "span"}...],
///    "report": {...} (only when the result has one), "method_report": {...}}
/// Report fields not computed are null. Doubles round-trip exactly through dump()/parse().
nlohmann::json to_json(const FitResult& result);
/// to_json(result).dump(indent) (indent < 0: compact, one line).
std::string write_json(const FitResult& result, int indent = -1);
/// The report part of to_json.
nlohmann::json to_json(const Report& report);
/// {"error": {"code": "repeated_point", "message": "...", "index": 3 or null}}
nlohmann::json error_to_json(const Error& error);

/// "none" | "basic" | "full" -> ReportLevel; anything else throws kInvalidArgument.
ReportLevel parse_report_level(std::string_view text);
/// Inverse of parse_report_level.
std::string_view report_level_name(ReportLevel level);

/// "corner" -> PointKind::kCorner etc.; anything else throws kInvalidArgument.
PointKind parse_point_kind(std::string_view text);
std::string_view point_kind_name(PointKind kind);

/// A small aligned two-column table for humans: method, segments, bending, linearized and
/// curvature-variation energies, length, regular yes/no, max tangent jump, max curvature jump
/// ("-" for quantities not computed at the report's level). Ends with a newline.
std::string summary_table(const FitResult& result);

}  // namespace fairspline::io
