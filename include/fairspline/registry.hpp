// The method registry: name -> description, option schema, fit function.
// The CLI, the Python module and the web editor list and call methods only through it.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "fairspline/fit.hpp"

namespace fairspline {

/// Type of an option value in the schema.
enum class OptionType {
  kNumber,          ///< JSON number (double)
  kInteger,         ///< JSON integer
  kBoolean,         ///< true / false
  kChoice,          ///< one string out of `choices`
  kString,          ///< free string (e.g. another method's name)
  kNumberList,      ///< array of numbers
  kChoiceOrNumber,  ///< one string out of `choices`, or a number within [min, max]
};

/// Stable lower-case name of a type ("number", "integer", ...).
std::string_view option_type_name(OptionType type);

/// One documented option of a method.
struct OptionSpec {
  std::string name;
  OptionType type = OptionType::kNumber;
  nlohmann::json default_value;  ///< null = no default (option absent unless given)
  std::optional<double> min;     ///< inclusive lower bound for numbers
  std::optional<double> max;     ///< inclusive upper bound for numbers
  std::vector<std::string> choices;
  std::string doc;
};

/// The fit function every method exposes to the registry: options are a JSON object already
/// validated against the schema and completed with defaults. `level` tells how much of the
/// method_report to build (kNone: only what is O(1) in size, so that timing stays honest).
/// The method overwrites every field of `out` it produces (points, knots, tangents, spline,
/// closed, method_report), reusing the vectors' capacity: fitting many curves into one
/// FitResult then costs no fresh memory per fit.
using MethodFunction = std::function<void(const FitInput&, const nlohmann::json& options,
                                          ReportLevel level, FitResult& out)>;

/// A registered method.
struct MethodInfo {
  std::string name;
  std::string description;  ///< one sentence
  std::string paper;        ///< source paper and section
  std::vector<OptionSpec> options;
  MethodFunction fit;
  /// True when the method itself verifies, while writing its output, that every number is
  /// finite (throwing Error(kNonFinite) otherwise); fit() then skips its own O(n) pass over
  /// the output. Methods that do not set it are checked by fit().
  bool checks_own_output = false;
};

/// All registered methods, in registration order.
const std::vector<MethodInfo>& methods();
/// The method called `name` (or an alias); throws Error(kUnknownMethod) listing valid names.
const MethodInfo& find_method(std::string_view name);
/// Name of the method used when none is given.
std::string_view default_method_name();

/// Validates `given` (a JSON object or null) against the schema and fills in defaults.
/// Throws Error(kUnknownOption) or Error(kBadOption) with a sentence naming the option.
nlohmann::json resolve_options(const MethodInfo& method, const nlohmann::json& given);

/// Schema of one method as JSON ({"name","description","paper","options":[...]}).
nlohmann::json method_schema(const MethodInfo& method);

/// Fits `input` with the named method: validates options, runs the method, checks that no
/// NaN/Inf leaves the library, and computes the report at `level`.
FitResult fit(std::string_view method, const FitInput& input,
              const nlohmann::json& options = nlohmann::json::object(),
              ReportLevel level = ReportLevel::kFull);

/// As fit(), but writes into `out`, reusing the capacity of its vectors. For pipelines that fit
/// many curves one after another (and for benchmarks): at 10^6 points a fresh result costs
/// ~150 MB of new pages, which the kernel must zero — often more time than the fit itself.
/// On error `out` is left in a valid but unspecified state.
void fit_into(std::string_view method, const FitInput& input, const nlohmann::json& options,
              ReportLevel level, FitResult& out);

}  // namespace fairspline
