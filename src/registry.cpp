#include "fairspline/registry.hpp"

#include <cmath>
#include <string>

#include "detail/finite.hpp"
#include "fairspline/diagnostics.hpp"
#include "fairspline/error.hpp"
#include "methods/builtin.hpp"

namespace fairspline {

std::string_view option_type_name(OptionType type) {
  switch (type) {
    case OptionType::kNumber:
      return "number";
    case OptionType::kInteger:
      return "integer";
    case OptionType::kBoolean:
      return "boolean";
    case OptionType::kChoice:
      return "choice";
    case OptionType::kString:
      return "string";
    case OptionType::kNumberList:
      return "number_list";
    case OptionType::kChoiceOrNumber:
      return "choice_or_number";
  }
  return "unknown";
}

const std::vector<MethodInfo>& methods() {
  static const std::vector<MethodInfo> registry = detail::builtin_methods();
  return registry;
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
  throw Error(ErrorCode::kUnknownMethod,
              "unknown method '" + std::string(name) + "'; available: " + known);
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
  return {{"name", method.name},
          {"description", method.description},
          {"paper", method.paper},
          {"default", method.name == default_method_name()},
          {"options", std::move(opts)}};
}

void fit_into(std::string_view method_name, const FitInput& input, const nlohmann::json& options,
              ReportLevel level, FitResult& out) {
  const MethodInfo& method = find_method(method_name);
  nlohmann::json resolved = resolve_options(method, options);
  out.report.reset();
  out.method_report = nlohmann::json::object();
  method.fit(input, resolved, level, out);
  out.method = method.name;
  out.options = std::move(resolved);
  if (!method.checks_own_output) detail::check_finite_output(out, method.name);
  if (level != ReportLevel::kNone) out.report = make_report(out.spline, out.points, level);
}

FitResult fit(std::string_view method_name, const FitInput& input, const nlohmann::json& options,
              ReportLevel level) {
  FitResult result;
  fit_into(method_name, input, options, level, result);
  return result;
}

}  // namespace fairspline
