// JSON input (points + fit request) and output (the FitResult contract used by the web editor,
// Python and external checks), plus small text helpers shared by the tools.
#pragma once

#include <functional>
#include <iosfwd>
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
  std::optional<double> accuracy;                     ///< "accuracy" (FitOptions::accuracy)
  std::optional<bool> best_effort;                    ///< "best_effort" (FitOptions::best_effort)
  std::optional<bool> diagnostics;                    ///< "diagnostics" (FitOptions::diagnostics)
  std::optional<double> time_limit;                   ///< "time_limit" (FitOptions::time_limit)
  /// FitOptions at `level` with the request's accuracy, best_effort, diagnostics and time
  /// limit where it gives them.
  FitOptions fit_options(ReportLevel level) const {
    return {.level = level,
            .accuracy = accuracy,
            .diagnostics = diagnostics.value_or(true),
            .best_effort = best_effort.value_or(false),
            .time_limit = time_limit};
  }
};

/// Parses a fit request:
///   {"points": [[x,y],...], "closed": bool, "tangents": [[x,y] or null,...],
///    "kinds": ["smooth"|"clamped"|"corner",...], "method": str, "options": {...},
///    "alpha": num, "knots": [...], "start_tangent": [x,y], "end_tangent": [x,y],
///    "lambdas": [...], "accuracy": num, "best_effort": bool, "diagnostics": bool,
///    "time_limit": seconds}
/// Only "points" is required; a bare array of points is accepted as {"points": [...]}, and a
/// fit result (write_json) as the request that fits its curve again (refit_input, its method,
/// options and accuracy).
/// "lambdas" is a method option given at top level for convenience: it is moved into
/// `options` (giving it in both places is an error). Keys starting with '_' or '$' are
/// comments; any other unknown key is an error (typos). Errors:
///   kParseError  invalid JSON (message with line and column; index = line), or a malformed
///                field ("points[3]: expected [x, y] with two numbers"; index = 3)
///   kNonFinite   a number too large for double (1e999), naming the field
ParsedInput parse_json_input(std::string_view text);
/// Same, from an already parsed document (e.g. the body of a web request).
ParsedInput input_from_json(const nlohmann::json& document);

/// The fit request of `input` (and `accuracy`) as JSON, the inverse of input_from_json: only
/// the fields that differ from their defaults (a FitInput with no points writes none).
nlohmann::json input_to_json(const FitInput& input, std::optional<double> accuracy = {});

/// The result as JSON:
///   {"method","closed","options","points","knots","tangents",
///    "segments": [{"bezier": [[x,y]x4], "t0", "t1", "span"}...],
///    "report": {...} (only when the result has one),
///    "request": input_to_json(result.input, result.accuracy) (what fits the curve again:
///               its points only where they differ from "points"),
///    "method_report": {..., "solver": {"status", "iterations", "residual", "tolerance",
///                                      "active": [...]} (only when the result has one)}}
/// Report fields not computed are null. Doubles round-trip exactly through dump()/parse().
/// (The document write_json writes, parsed.)
nlohmann::json to_json(const FitResult& result);
/// The report part of to_json.
nlohmann::json to_json(const Report& report);

/// Which top-level members of a result's text to write (empty: all of them).
using MemberFilter = std::function<bool(std::string_view key)>;

/// Appends the text of to_json(result).dump(indent) to `out` (indent < 0: compact, one line),
/// written straight from the result, without a JSON tree: keys in order, numbers as dump()
/// writes them. The one serializer of a FitResult: the CLI's fit and batch, the web server,
/// Python's to_json, dicts and pickles all go through it. `extra` (an object, or null for none)
/// adds members among the result's in key order, e.g. the batch record's {"line": N}; a key the
/// result also writes throws Error(kInvalidArgument) (with `out` partly written). With `keep`,
/// only the result's top-level members it accepts are written (`extra`'s always), the others
/// not even formatted: `--fields` of `fairspline fit` and `batch`.
void write_json(const FitResult& result, std::string& out, int indent = -1,
                const nlohmann::json& extra = nullptr, const MemberFilter& keep = {});
/// The same text as a string.
std::string write_json(const FitResult& result, int indent = -1);
/// The same text written to `out` as it is made, a megabyte at a time (a long curve's text is
/// never held whole); a failed write throws Error(kIoError). `keep` as above.
void write_json(const FitResult& result, std::ostream& out, int indent = -1,
                const MemberFilter& keep = {});

/// The SAX interface of nlohmann::json (json::sax_parse drives one).
using JsonSax = nlohmann::json_sax<nlohmann::json>;
/// Gives `handler` the events json::sax_parse would give for the text of write_json, without
/// writing or parsing text (number_float's string argument is empty; return values are
/// ignored): to build another representation of the document, e.g. Python objects, from the
/// one field list.
void write_json(const FitResult& result, JsonSax& handler);
/// The same for the "report" member alone.
void write_json(const Report& report, JsonSax& handler);
/// The same for the "method_report" member alone (the method's report with "solver" merged in).
void write_method_report(const FitResult& result, JsonSax& handler);

/// Reads what write_json wrote back into an equal FitResult: every field, doubles bit for bit
/// ("solver" inside "method_report" goes to FitResult::solver; the spline's `closed` is the
/// result's). Throws Error(kParseError) for invalid JSON (line and column, as
/// parse_json_input) or a missing, unknown or malformed field, naming it
/// ("report.segment_reports[2].length: expected a number, got "x""; index = the position in
/// the first array of that path: the point, the segment, the segment report), or kNonFinite
/// for a number too large for double.
FitResult read_fit_result(std::string_view text);
/// Same, from an already parsed document (a name of its own: a string converts to both).
FitResult fit_result_from_json(const nlohmann::json& document);

/// "converged" | "conditioning_limit" | "iteration_limit" | "stalled" (the JSON name of a
/// SolverStatus).
std::string_view solver_status_name(SolverStatus status);
/// Inverse of solver_status_name; anything else throws kInvalidArgument.
SolverStatus parse_solver_status(std::string_view text);

/// {"error": {"code": "repeated_point", "message": "...", "index": 3 or null}}, plus
/// "hint": {"option": name, "value": value or null} when an option would get past the error
/// (Error::hint).
nlohmann::json error_to_json(const Error& error);

/// "none" | "basic" | "full" -> ReportLevel; anything else throws kInvalidArgument.
ReportLevel parse_report_level(std::string_view text);
/// Inverse of parse_report_level.
std::string_view report_level_name(ReportLevel level);

/// "corner" -> PointKind::kCorner etc.; anything else throws kInvalidArgument.
PointKind parse_point_kind(std::string_view text);
std::string_view point_kind_name(PointKind kind);

/// "regular" | "clamped" | "free" -> SideState; anything else throws kInvalidArgument.
SideState parse_side_state(std::string_view text);
std::string_view side_state_name(SideState state);

/// A small aligned two-column table for humans: method, segments, bending, linearized and
/// curvature-variation energies, length, regular yes/no, max tangent jump, max curvature jump
/// ("-" for quantities not computed at the report's level). Ends with a newline.
std::string summary_table(const FitResult& result);

}  // namespace fairspline::io
