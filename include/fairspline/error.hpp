// fairspline::Error: the single exception type of the library.
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace fairspline {

/// What went wrong; stable names (see error_code_name) are part of the JSON/CLI/Python contract.
enum class ErrorCode {
  kInvalidArgument,  ///< a parameter outside its documented domain
  kTooFewPoints,     ///< fewer points than the method or curve type needs
  kNonFinite,        ///< NaN or Inf in points, tangents, knots or options
  kRepeatedPoint,    ///< two consecutive points coincide
  kReversal,         ///< a 180 degree reversal the method cannot represent
  kWrongPointCount,  ///< the method needs a specific number of points (e.g. 3m+1)
  kSingularSystem,   ///< the method's linear system has no unique solution
  kInfeasible,       ///< no admissible curve exists for this data under the method's constraints
  kNotConverged,     ///< an iterative solver stopped before reaching its tolerance
  kParseError,       ///< malformed input file or request
  kUnknownMethod,    ///< no method registered under that name
  kUnknownOption,    ///< option name not in the method's schema
  kBadOption,        ///< option value of the wrong type or out of range
  kIoError,          ///< a file could not be read or written
  kCancelled,        ///< the fit ran past FitOptions::time_limit, or its progress callback
                     ///< stopped it
};

/// Stable lower-case name of a code, e.g. "repeated_point".
std::string_view error_code_name(ErrorCode code);

/// A method option that would get past an error (e.g. remainder = "hermite"). The message says
/// it in words; each front end shows it in its own syntax (the CLI as --set name=value, Python
/// as a keyword, the editor as the option's control). An empty value: any value the option's
/// documentation allows (e.g. a method name for tangents_from).
struct OptionHint {
  std::string name;
  std::string value;
};

/// The exception thrown for every bad input or failed computation.
/// `index()` is the offending point (or span / line) when there is one.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, std::string message, std::optional<std::size_t> index = std::nullopt,
        std::optional<OptionHint> hint = std::nullopt)
      : std::runtime_error(std::move(message)),
        code_(code),
        index_(index),
        hint_(std::move(hint)) {}

  ErrorCode code() const noexcept { return code_; }
  std::optional<std::size_t> index() const noexcept { return index_; }
  const std::optional<OptionHint>& hint() const noexcept { return hint_; }

 private:
  ErrorCode code_;
  std::optional<std::size_t> index_;
  std::optional<OptionHint> hint_;
};

}  // namespace fairspline
