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
};

/// Stable lower-case name of a code, e.g. "repeated_point".
std::string_view error_code_name(ErrorCode code);

/// The exception thrown for every bad input or failed computation.
/// `index()` is the offending point (or span / line) when there is one.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, std::string message, std::optional<std::size_t> index = std::nullopt)
      : std::runtime_error(std::move(message)), code_(code), index_(index) {}

  ErrorCode code() const noexcept { return code_; }
  std::optional<std::size_t> index() const noexcept { return index_; }

 private:
  ErrorCode code_;
  std::optional<std::size_t> index_;
};

}  // namespace fairspline
