// The method registry: name -> description, option schema, fit function.
// The CLI, the Python module and the web editor list and call methods only through it.
#pragma once

#include <cstddef>
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
  std::string name{};
  OptionType type = OptionType::kNumber;
  nlohmann::json default_value{};  ///< null = no default (option absent unless given)
  std::optional<double> min{};     ///< inclusive lower bound for numbers
  std::optional<double> max{};     ///< inclusive upper bound for numbers
  std::vector<std::string> choices{};
  std::string doc{};
};

/// The continuity a method's curve has at its interior points.
enum class Continuity {
  kG1,  ///< common tangent direction
  kC1,  ///< common derivative with respect to the knot parameter
  kG2,  ///< common tangent direction and curvature
};

/// How a method uses per-point tangent vectors (FitInput::tangents, start/end tangents).
enum class TangentUse {
  kOptional,  ///< the method chooses directions; given ones are used where the method says
  kRequired,  ///< a Hermite method: every point needs one (or the registry option
              ///< `tangents_from` names a method that supplies the missing ones)
};

/// How many points a method needs.
struct PointCountRule {
  std::size_t min_open = 2;    ///< distinct points of an open curve
  std::size_t min_closed = 3;  ///< distinct points of a closed curve
  /// An open curve needs step·m + 1 points (Kozak–Krajnc: 3m+1) ...
  std::size_t step = 1;
  /// ... unless the option `relaxed_by` is `relaxed_value` (empty: no such option).
  std::string_view relaxed_by{};
  std::string_view relaxed_value{};
};

/// What a method accepts and produces. prepare_input enforces it for every method, with the
/// same error codes and sentences, and every front end and test harness reads it instead of
/// method names.
struct Capabilities {
  bool closed = true;  ///< closed curves allowed
  /// Point kinds the method honours; kSmooth is always among them.
  std::vector<PointKind> kinds = {PointKind::kSmooth, PointKind::kClamped};
  TangentUse tangents = TangentUse::kOptional;
  PointCountRule points{};
  Continuity continuity = Continuity::kG1;
  /// The curve is provably regular (no cusps, loops or folds within a piece); C1 methods may
  /// stop at a reversal instead.
  bool regular = true;
  /// Needs no three consecutive collinear points (Kozak–Krajnc's Theorem 4.1): collinear runs
  /// are refused with kInvalidArgument or kInfeasible.
  bool needs_turns = false;
  /// Unique only with a clamped tangent (or a closed curve with an odd number of points).
  bool needs_clamped_tangent = false;
  /// Honours Curve Ensemble's node model (FitInput::states, in_tangents, out_tangents,
  /// corners_deg). Other methods get inputs that `kinds` can express rewritten as kinds, and
  /// an error for the rest.
  bool node_states = false;
  /// Fits data balls (FitInput::radii > 0): the curve passes through discs around the points.
  bool data_balls = false;
  /// Example requests (JSON fit requests with at least "points") that the method fits: the
  /// fuzzer's seeds, the extremes suite's and the benchmarks' inputs, the docs' examples.
  std::vector<std::string> examples{};

  bool honours(PointKind kind) const;
};

std::string_view continuity_name(Continuity c);
std::string_view tangent_use_name(TangentUse t);

/// The fit function every method exposes to the registry: options are a JSON object already
/// validated against the schema and completed with defaults. `fit.level` tells how much of the
/// method_report to build (kNone: only what is O(1) in size, so that timing stays honest);
/// `fit.accuracy` bounds every approximation the method makes.
/// The method overwrites every field of `out` it produces (points, knots, tangents, spline,
/// closed, method_report), reusing the vectors' capacity: fitting many curves into one
/// FitResult then costs no fresh memory per fit.
using MethodFunction = std::function<void(const FitInput&, const nlohmann::json& options,
                                          const FitOptions& fit, FitResult& out)>;

/// The option the registry adds to every method with TangentUse::kRequired: a registered method
/// that supplies the directions missing from the input (empty: every point needs a tangent).
inline constexpr std::string_view kTangentsFromOption = "tangents_from";

/// A number of method_report that depends on the data's scale: with the points multiplied by s
/// and the knots by k (k = s^alpha for alpha-knots, 1 for explicit knots) it becomes
/// s^length · k^knots times itself. fit() rescales data far from unit size before the method
/// runs and maps these numbers back; numbers not listed must not depend on the scale (angles,
/// counts, relative residuals), which the registry's scale test checks for every method.
struct ReportUnit {
  std::string path{};  ///< keys separated by '/'; "*" stands for every element of an array
  int length = 0;
  int knots = 0;
};

/// A registered method.
struct MethodInfo {
  std::string name{};
  std::string description{};  ///< one sentence
  std::string paper{};        ///< source paper and section
  std::vector<OptionSpec> options{};
  MethodFunction fit{};
  Capabilities capabilities{};
  /// True when the method itself verifies, while writing its output, that every number is
  /// finite (throwing Error(kNonFinite) otherwise); fit() then skips its own O(n) pass over
  /// the output. Methods that do not set it are checked by fit().
  bool checks_own_output = false;
  /// The scale-dependent numbers of its method_report.
  std::vector<ReportUnit> report_units{};
};

/// All registered methods, in registration order.
const std::vector<MethodInfo>& methods();
/// Adds a method to the registry (a plug-in, or a test's throw-away method). Throws
/// Error(kInvalidArgument) if the name is taken or empty. Not thread-safe: register before
/// fitting; references returned by methods() and find_method() are invalidated.
void register_method(MethodInfo method);
/// The method called `name` (or an alias); throws Error(kUnknownMethod) listing valid names.
const MethodInfo& find_method(std::string_view name);
/// Name of the method used when none is given.
std::string_view default_method_name();

/// Validates `given` (a JSON object or null) against the schema and fills in defaults.
/// Throws Error(kUnknownOption) or Error(kBadOption) with a sentence naming the option.
nlohmann::json resolve_options(const MethodInfo& method, const nlohmann::json& given);

/// Schema of one method as JSON: {"name", "description", "paper", "default", "options": [...],
/// "capabilities": {"closed", "kinds", "tangents", "points", "continuity", "regular",
/// "needs_turns", "needs_clamped_tangent"}, "examples": [request, ...]}.
nlohmann::json method_schema(const MethodInfo& method);
/// The schemas of every registered method, in registration order: what `fairspline methods
/// --json`, GET /api/methods and Python's fairspline.methods() show.
nlohmann::json registry_schema();

/// Fits `input` with the named method: validates options, runs the method, checks that no
/// NaN/Inf leaves the library, and computes the report at `level`.
FitResult fit(std::string_view method, const FitInput& input,
              const nlohmann::json& options = nlohmann::json::object(),
              ReportLevel level = ReportLevel::kBasic);
/// As above, with every fit option (report level, accuracy, diagnostics, best effort).
auto fit(std::string_view method, const FitInput& input, const nlohmann::json& options,
         const FitOptions& fit_options) -> FitResult;

/// As fit(), but writes into `out`, reusing the capacity of its vectors. For pipelines that fit
/// many curves one after another (and for benchmarks): at 10^6 points a fresh result costs
/// ~150 MB of new pages, which the kernel must zero — often more time than the fit itself.
/// On error `out` is left in a valid but unspecified state.
void fit_into(std::string_view method, const FitInput& input, const nlohmann::json& options,
              ReportLevel level, FitResult& out);
void fit_into(std::string_view method, const FitInput& input, const nlohmann::json& options,
              const FitOptions& fit_options, FitResult& out);

}  // namespace fairspline
