#include "fairspline/registry.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "detail/choices.hpp"
#include "detail/finite.hpp"
#include "detail/input.hpp"
#include "detail/nodes.hpp"
#include "detail/normalize.hpp"
#include "detail/progress.hpp"
#include "detail/two_threads.hpp"
#include "fairspline/diagnostics.hpp"
#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "methods/builtin.hpp"

namespace fairspline {

namespace {

constexpr detail::ChoiceTable<OptionType, 7> kOptionTypes{
    {{"number", OptionType::kNumber},
     {"integer", OptionType::kInteger},
     {"boolean", OptionType::kBoolean},
     {"choice", OptionType::kChoice},
     {"string", OptionType::kString},
     {"number_list", OptionType::kNumberList},
     {"choice_or_number", OptionType::kChoiceOrNumber}}};
constexpr detail::ChoiceTable<Continuity, 3> kContinuity{
    {{"G1", Continuity::kG1}, {"C1", Continuity::kC1}, {"G2", Continuity::kG2}}};
constexpr detail::ChoiceTable<TangentUse, 2> kTangentUse{
    {{"optional", TangentUse::kOptional}, {"required", TangentUse::kRequired}}};

}  // namespace

std::string_view option_type_name(OptionType type) {
  return kOptionTypes.name(type);
}

std::string_view continuity_name(Continuity c) {
  return kContinuity.name(c);
}

std::string_view tangent_use_name(TangentUse t) {
  return kTangentUse.name(t);
}

bool Capabilities::honours(PointKind kind) const {
  return kind == PointKind::kSmooth || std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}

namespace {

/// Registry options shared by methods of one capability, appended to their schema.
void add_registry_options(MethodInfo& m) {
  if (m.capabilities.tangents != TangentUse::kRequired) return;
  for (const OptionSpec& s : m.options) {
    if (s.name == kTangentsFromOption) return;
  }
  m.options.push_back({.name = std::string(kTangentsFromOption),
                       .type = OptionType::kString,
                       .default_value = "",
                       .doc = "registered method that supplies the tangent directions missing "
                              "from the input (e.g. jaklic-zagar); empty: every point needs a "
                              "tangent"});
}

std::vector<MethodInfo>& registry() {
  static std::vector<MethodInfo> all = [] {
    std::vector<MethodInfo> v = detail::builtin_methods();
    for (MethodInfo& m : v) add_registry_options(m);
    return v;
  }();
  return all;
}

}  // namespace

const std::vector<MethodInfo>& methods() {
  return registry();
}

void register_method(MethodInfo method) {
  if (method.name.empty() || !method.fit) {
    throw Error(ErrorCode::kInvalidArgument, "a method needs a name and a fit function");
  }
  for (const MethodInfo& m : registry()) {
    if (m.name == method.name) {
      throw Error(ErrorCode::kInvalidArgument,
                  "a method called '" + method.name + "' is already registered");
    }
  }
  for (const std::string& e : method.capabilities.examples) {
    if (!nlohmann::json::accept(e)) {
      throw Error(ErrorCode::kInvalidArgument,
                  "an example request of method " + method.name + " is not valid JSON");
    }
  }
  add_registry_options(method);
  registry().push_back(std::move(method));
}

std::string_view default_method_name() {
  return "quasi-elastic";
}

const MethodInfo& find_method(std::string_view name) {
  for (const MethodInfo& m : methods()) {
    if (m.name == name) return m;
  }
  std::string known;
  for (const MethodInfo& m : methods()) known += (known.empty() ? "" : ", ") + m.name;
  // The name may come from a command line or a file: invalid UTF-8 is replaced so that the
  // message can always be written as JSON (found by fuzz_fit).
  const std::string text = nlohmann::json(std::string(name))
                               .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  throw Error(ErrorCode::kUnknownMethod,
              "unknown method '" + text.substr(1, text.size() - 2) + "'; available: " + known);
}

namespace {

std::string bounds_text(const OptionSpec& spec) {
  std::string s;
  if (spec.min && spec.max) {
    s = " in [" + nlohmann::json(*spec.min).dump() + ", " + nlohmann::json(*spec.max).dump() + "]";
  } else if (spec.min) {
    s = " >= " + nlohmann::json(*spec.min).dump();
  } else if (spec.max) {
    s = " <= " + nlohmann::json(*spec.max).dump();
  }
  return s;
}

std::string choices_text(const OptionSpec& spec) {
  std::string s;
  for (const auto& c : spec.choices) s += (s.empty() ? "" : ", ") + c;
  return s;
}

/// A user's value for a message: strings from a command line may be invalid UTF-8, which
/// json::dump refuses (the message would then be an exception of its own).
std::string shown(const nlohmann::json& v) {
  return v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

[[noreturn]] void bad(const std::string& method, const OptionSpec& spec, const nlohmann::json& v,
                      const std::string& expected) {
  throw Error(ErrorCode::kBadOption, "option '" + spec.name + "' of " + method + " must be " +
                                         expected + ", got " + shown(v));
}

bool number_ok(const OptionSpec& spec, double x) {
  return std::isfinite(x) && (!spec.min || x >= *spec.min) && (!spec.max || x <= *spec.max);
}

nlohmann::json check_value(const std::string& method, const OptionSpec& spec,
                           const nlohmann::json& v) {
  switch (spec.type) {
    case OptionType::kNumber:
      if (!v.is_number() || !number_ok(spec, v.get<double>())) {
        bad(method, spec, v, "a finite number" + bounds_text(spec));
      }
      return v.get<double>();
    case OptionType::kInteger:
      if (!v.is_number_integer() &&
          !(v.is_number() && std::floor(v.get<double>()) == v.get<double>())) {
        bad(method, spec, v, "an integer" + bounds_text(spec));
      }
      if (!number_ok(spec, v.get<double>())) bad(method, spec, v, "an integer" + bounds_text(spec));
      return v.get<long long>();
    case OptionType::kBoolean:
      if (v.is_boolean()) return v;
      if (v.is_number_integer() && (v.get<long long>() == 0 || v.get<long long>() == 1)) {
        return v.get<long long>() == 1;
      }
      if (v.is_string() && (v == "true" || v == "false")) return v == "true";
      bad(method, spec, v, "true or false");
    case OptionType::kChoice:
      for (const auto& c : spec.choices) {
        if (v.is_string() && v.get<std::string>() == c) return v;
      }
      bad(method, spec, v, "one of " + choices_text(spec));
    case OptionType::kString:
      if (!v.is_string()) bad(method, spec, v, "a string");
      return v;
    case OptionType::kNumberList:
      if (!v.is_array()) bad(method, spec, v, "a list of numbers" + bounds_text(spec));
      for (const auto& x : v) {
        if (!x.is_number() || !number_ok(spec, x.get<double>())) {
          bad(method, spec, v, "a list of finite numbers" + bounds_text(spec));
        }
      }
      return v;
    case OptionType::kChoiceOrNumber:
      if (v.is_number() && number_ok(spec, v.get<double>())) return v.get<double>();
      for (const auto& c : spec.choices) {
        if (v.is_string() && v.get<std::string>() == c) return v;
      }
      bad(method, spec, v, "one of " + choices_text(spec) + " or a number" + bounds_text(spec));
  }
  bad(method, spec, v, "valid");
}

}  // namespace

nlohmann::json resolve_options(const MethodInfo& method, const nlohmann::json& given) {
  if (!given.is_null() && !given.is_object()) {
    throw Error(ErrorCode::kBadOption, "options must be a JSON object, got " + shown(given));
  }
  nlohmann::json out = nlohmann::json::object();
  if (given.is_object()) {
    for (const auto& [key, value] : given.items()) {
      const OptionSpec* spec = nullptr;
      for (const auto& s : method.options) {
        if (s.name == key) spec = &s;
      }
      if (!spec) {
        std::string known;
        for (const auto& s : method.options) known += (known.empty() ? "" : ", ") + s.name;
        throw Error(ErrorCode::kUnknownOption,
                    "method " + method.name + " has no option '" + key + "'" +
                        (known.empty() ? " (it takes no options)" : "; its options: " + known));
      }
      out[key] = check_value(method.name, *spec, value);
    }
  }
  for (const auto& s : method.options) {
    if (!out.contains(s.name) && !s.default_value.is_null()) out[s.name] = s.default_value;
  }
  return out;
}

nlohmann::json method_schema(const MethodInfo& method) {
  nlohmann::json opts = nlohmann::json::array();
  for (const auto& s : method.options) {
    nlohmann::json o = {{"name", s.name},
                        {"type", option_type_name(s.type)},
                        {"default", s.default_value},
                        {"doc", s.doc}};
    if (s.min) o["min"] = *s.min;
    if (s.max) o["max"] = *s.max;
    if (!s.choices.empty()) o["choices"] = s.choices;
    opts.push_back(std::move(o));
  }
  const Capabilities& c = method.capabilities;
  nlohmann::json kinds = nlohmann::json::array();
  for (PointKind k : {PointKind::kSmooth, PointKind::kClamped, PointKind::kCorner}) {
    if (c.honours(k)) kinds.push_back(io::point_kind_name(k));
  }
  nlohmann::json points = {{"min_open", c.points.min_open}, {"min_closed", c.points.min_closed}};
  if (c.points.step != 1) {
    points["step"] = c.points.step;
    if (!c.points.relaxed_by.empty()) {
      points["relaxed_by"] = {{std::string(c.points.relaxed_by), c.points.relaxed_value}};
    }
  }
  nlohmann::json examples = nlohmann::json::array();
  for (const std::string& e : c.examples) examples.push_back(nlohmann::json::parse(e));
  return {{"name", method.name},
          {"description", method.description},
          {"paper", method.paper},
          {"default", method.name == default_method_name()},
          {"options", std::move(opts)},
          {"capabilities",
           {{"closed", c.closed},
            {"kinds", std::move(kinds)},
            {"tangents", tangent_use_name(c.tangents)},
            {"points", std::move(points)},
            {"continuity", continuity_name(c.continuity)},
            {"regular", c.regular},
            {"needs_turns", c.needs_turns},
            {"needs_clamped_tangent", c.needs_clamped_tangent},
            {"node_states", c.node_states},
            {"data_balls", c.data_balls}}},
          {"examples", std::move(examples)}};
}

nlohmann::json registry_schema() {
  nlohmann::json all = nlohmann::json::array();
  for (const MethodInfo& m : methods()) all.push_back(method_schema(m));
  return all;
}

namespace {

/// The registry's pre-step of Hermite methods: the directions missing from the input are taken
/// from the method named by the option `tangents_from` (the method itself sees a complete
/// input and never calls back into the registry).
const FitInput& with_tangents_from(const MethodInfo& method, const FitInput& input,
                                   const nlohmann::json& options, FitInput& storage) {
  if (method.capabilities.tangents != TangentUse::kRequired) return input;
  const auto it = options.find(kTangentsFromOption);
  if (it == options.end()) return input;
  const std::string other = it->get<std::string>();
  if (other.empty()) return input;
  if (other == method.name) {
    throw Error(ErrorCode::kBadOption,
                "tangents_from cannot be " + method.name +
                    " itself; name a method that chooses directions from points alone (e.g. "
                    "jaklic-zagar)");
  }
  const std::size_t n = input.points.size();
  bool complete = input.tangents.size() >= n;
  for (std::size_t i = 0; complete && i < n; ++i) complete = input.tangents[i].has_value();
  if (complete) return input;
  FitResult supplier;
  FitInput plain = input;
  plain.tangents.clear();
  plain.kinds.clear();
  fit_into(other, plain, nlohmann::json::object(), FitOptions{.level = ReportLevel::kNone},
           supplier);
  // The supplier may drop the closing duplicate of a closed curve; it may not insert points.
  const std::size_t m = supplier.tangents.size();
  if (m != n && !(input.closed && m + 1 == n)) {
    throw Error(ErrorCode::kBadOption, "tangents_from=" + other + " returned " + std::to_string(m) +
                                           " tangents for " + std::to_string(n) +
                                           " points (did it insert points?)");
  }
  storage = input;
  storage.tangents.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const bool start = i == 0 && input.start_tangent;
    const bool end = i + 1 == n && !input.closed && input.end_tangent;
    if (!storage.tangents[i] && !start && !end) storage.tangents[i] = supplier.tangents[i % m];
  }
  return storage;
}

}  // namespace

namespace {

/// A method that does not honour the node model gets an input using it rewritten as kinds, or
/// an error naming the first point that kinds cannot express.
const FitInput& with_kinds_only(const MethodInfo& method, const FitInput& input,
                                FitInput& storage) {
  if (method.capabilities.node_states || !detail::uses_node_model(input)) return input;
  std::size_t n = input.points.size();
  if (input.closed && n >= 2 && detail::coincident(input.points[0], input.points[n - 1])) --n;
  std::size_t bad = 0;
  std::optional<FitInput> plain = detail::as_kinds(input, n, bad);
  if (!plain) {
    throw Error(ErrorCode::kInvalidArgument,
                method.name +
                    " honours only the node kinds smooth, clamped and corner (both sides in the "
                    "same state, one direction, no corner angle), but point " +
                    std::to_string(bad) +
                    " has a half state, a corner angle or two different directions; use a "
                    "method of the min-energy family, or give that point as a kind",
                bad);
  }
  storage = std::move(*plain);
  return storage;
}

}  // namespace

namespace {

/// Keeps what was asked in `out.input` (all but the points, which the result holds unless the
/// method changed them: remember_points after the fit).
void remember_request(const FitInput& in, const FitOptions& fit_options, FitResult& out) {
  out.accuracy = fit_options.accuracy;
  if (&in == &out.input) return;  // refitting a result's own input into it
  FitInput& r = out.input;
  r.points.clear();
  r.closed = in.closed;
  r.alpha = in.alpha;
  r.knots.assign(in.knots.begin(), in.knots.end());
  r.tangents.assign(in.tangents.begin(), in.tangents.end());
  r.kinds.assign(in.kinds.begin(), in.kinds.end());
  r.states.assign(in.states.begin(), in.states.end());
  r.in_tangents.assign(in.in_tangents.begin(), in.in_tangents.end());
  r.out_tangents.assign(in.out_tangents.begin(), in.out_tangents.end());
  r.corners_deg.assign(in.corners_deg.begin(), in.corners_deg.end());
  r.radii.assign(in.radii.begin(), in.radii.end());
  r.start_tangent = in.start_tangent;
  r.end_tangent = in.end_tangent;
}

void remember_points(const FitInput& in, FitResult& out) {
  if (&in == &out.input) return;
  // Bitwise, so that -0.0 and NaN payloads survive a refit; one memcmp of the whole array
  // (Point is two doubles, no padding).
  static_assert(sizeof(Point) == 2 * sizeof(double));
  const std::size_t n = in.points.size();
  bool same = n == out.points.size();
  if (same && detail::split_in_two(n)) {
    const std::size_t mid = n / 2;
    bool equal[2] = {false, false};
    detail::on_two_threads([&](int h) {
      const std::size_t first = h == 0 ? 0 : mid, count = h == 0 ? mid : n - mid;
      equal[h] = std::memcmp(in.points.data() + first, out.points.data() + first,
                             count * sizeof(Point)) == 0;
    });
    same = equal[0] && equal[1];
  } else if (same && n > 0) {
    same = std::memcmp(in.points.data(), out.points.data(), n * sizeof(Point)) == 0;
  }
  if (!same) out.input.points.assign(in.points.begin(), in.points.end());
}

}  // namespace

FitInput refit_input(const FitResult& result) {
  FitInput in = result.input;
  if (in.points.empty()) in.points = result.points;
  return in;
}

namespace {
void fit_watched(const MethodInfo& method, const FitInput& input, const nlohmann::json& options,
                 const FitOptions& fit_options, FitResult& out);
}  // namespace

void fit_into(std::string_view method_name, const FitInput& input, const nlohmann::json& options,
              const FitOptions& fit_options, FitResult& out) {
  const MethodInfo& method = find_method(method_name);
  if (fit_options.accuracy && !(*fit_options.accuracy > 0.0 && *fit_options.accuracy < 1.0)) {
    throw Error(ErrorCode::kBadOption, "the accuracy must be a number between 0 and 1, got " +
                                           nlohmann::json(*fit_options.accuracy).dump());
  }
  if (fit_options.time_limit && !(*fit_options.time_limit > 0.0)) {
    throw Error(ErrorCode::kBadOption, "the time limit must be a positive number of seconds, got " +
                                           nlohmann::json(*fit_options.time_limit).dump());
  }
  if (!(fit_options.progress_interval >= 0.0)) {
    throw Error(ErrorCode::kBadOption,
                "the progress interval must be a number of seconds, 0 or more, got " +
                    nlohmann::json(fit_options.progress_interval).dump());
  }
  detail::FitWatch watch(fit_options);
  try {
    fit_watched(method, input, options, fit_options, out);
  } catch (const Error&) {
    // A solver that caught the stop and failed otherwise still failed because of the stop.
    if (watch.stopped()) throw *watch.stopped();
    throw;
  }
  if (watch.stopped()) throw *watch.stopped();
}

namespace {

void fit_watched(const MethodInfo& method, const FitInput& input, const nlohmann::json& options,
                 const FitOptions& fit_options, FitResult& out) {
  nlohmann::json resolved = resolve_options(method, options);
  FitInput kinds_only, completed;
  const FitInput& in =
      with_tangents_from(method, with_kinds_only(method, input, kinds_only), resolved, completed);
  // Data far from unit size: the method sees them scaled by a power of two (exact) and the
  // result is mapped back, so that no method needs range guards for the points' scale.
  const std::optional<detail::Normalization> nz = detail::normalization_for(in);
  FitInput normalized;
  if (nz) detail::normalize_input(in, *nz, method.capabilities, normalized);
  out.report.reset();
  out.solver.reset();
  out.method_report = nlohmann::json::object();
  method.fit(nz ? normalized : in, resolved, fit_options, out);
  if (nz) detail::denormalize_result(in, *nz, method.report_units, out);
  out.method = method.name;
  out.options = std::move(resolved);
  remember_request(input, fit_options, out);
  remember_points(input, out);
  // (Mapped back, numbers near the double range's ends may overflow after all.)
  if (!method.checks_own_output || nz) detail::check_finite_output(out, method.name);
  if (fit_options.level != ReportLevel::kNone) {
    detail::checkpoint("report", 0);
    DiagnosticsOptions d;
    d.energy.accuracy = fit_options.report_accuracy();
    d.intersection_accuracy = fit_options.report_accuracy();
    out.report = make_report(out.spline, out.points, fit_options.level, d);
  }
}

}  // namespace

void fit_into(std::string_view method_name, const FitInput& input, const nlohmann::json& options,
              ReportLevel level, FitResult& out) {
  fit_into(method_name, input, options, FitOptions{.level = level}, out);
}

FitResult fit(std::string_view method_name, const FitInput& input, const nlohmann::json& options,
              const FitOptions& fit_options) {
  FitResult result;
  fit_into(method_name, input, options, fit_options, result);
  return result;
}

FitResult fit(std::string_view method_name, const FitInput& input, const nlohmann::json& options,
              ReportLevel level) {
  return fit(method_name, input, options, FitOptions{.level = level});
}

}  // namespace fairspline
