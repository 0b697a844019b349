#include "fairspline/error.hpp"

namespace fairspline {

std::string_view error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidArgument:
      return "invalid_argument";
    case ErrorCode::kTooFewPoints:
      return "too_few_points";
    case ErrorCode::kNonFinite:
      return "non_finite";
    case ErrorCode::kRepeatedPoint:
      return "repeated_point";
    case ErrorCode::kReversal:
      return "reversal";
    case ErrorCode::kWrongPointCount:
      return "wrong_point_count";
    case ErrorCode::kSingularSystem:
      return "singular_system";
    case ErrorCode::kInfeasible:
      return "infeasible";
    case ErrorCode::kNotConverged:
      return "not_converged";
    case ErrorCode::kParseError:
      return "parse_error";
    case ErrorCode::kUnknownMethod:
      return "unknown_method";
    case ErrorCode::kUnknownOption:
      return "unknown_option";
    case ErrorCode::kBadOption:
      return "bad_option";
    case ErrorCode::kIoError:
      return "io_error";
    case ErrorCode::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

}  // namespace fairspline
