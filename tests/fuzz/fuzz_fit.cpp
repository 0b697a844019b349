// Fuzz target: fit() over every registered method with fuzzed points, tangents, kinds, knots,
// end tangents and options built from the method's schema. The promise: a valid curve whose
// every number is finite, or a fairspline::Error; anything else aborts.
// An input names its method (docs/fuzzing.md): the bytes up to the first NUL are the method's
// name, so that registering a method never changes what a committed input does. A name that is
// not registered must give Error(kUnknownMethod), and nothing else is decoded.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"
#include "fuzz_util.hpp"

namespace {

using fairspline::FitInput;
using fairspline::OptionSpec;
using fairspline::OptionType;
using fairspline::Point;
using fairspline::PointKind;
using fairspline::Vec2;
using fairspline::fuzz::ByteReader;
using nlohmann::json;

constexpr std::size_t kMaxPoints = 64;
/// Iteration options (max_iterations, g2_max_iterations) are capped when drawn valid, so that
/// one input stays far below a second even under the sanitizers.
constexpr double kMaxIterations = 1000.0;

/// The next point: a fresh value or one of the patterns that trouble fitting methods.
Point next_point(ByteReader& in, const std::vector<Point>& pts) {
  const std::size_t n = pts.size();
  const Point prev = n ? pts[n - 1] : Point{0.0, 0.0};
  const Point prev2 = n > 1 ? pts[n - 2] : prev;
  const std::uint8_t mode = in.byte();
  switch (mode % 12) {
    case 0:  // repeat of the previous point
      return prev;
    case 1:  // collinear continuation
      return prev + (prev - prev2);
    case 2:  // reversal: back to the point before
      return prev2;
    case 3: {  // a tiny step from the previous point
      const double s = std::ldexp(1.0, -static_cast<int>(in.byte() % 60));
      return prev + Vec2{in.ordinary() * s, in.ordinary() * s};
    }
    case 4:  // collinear but not continuing (back over the chord)
      return prev + (prev - prev2) * in.ordinary();
    case 5:  // the first point again (closing)
      return n ? pts[0] : Point{0.0, 0.0};
    case 6:
    case 7:  // extremes and raw doubles
      return {in.number(), in.number()};
    default:  // ordinary values
      return {in.ordinary(), in.ordinary()};
  }
}

Vec2 direction(ByteReader& in) {
  if (in.byte() < 200) {
    const double a = static_cast<double>(in.bits(2)) * (6.283185307179586 / 65536.0);
    const double len = in.byte() < 128 ? 1.0 : in.ordinary();
    return {len * std::cos(a), len * std::sin(a)};
  }
  return {in.number(), in.number()};
}

/// A count near `n` (usually exactly n, sometimes off by one or arbitrary).
std::size_t count_near(ByteReader& in, std::size_t n) {
  const std::uint8_t b = in.byte();
  if (b < 224) return n;
  if (b < 236) return n + 1;
  if (b < 248) return n ? n - 1 : 0;
  return in.range(0, kMaxPoints + 2);
}

json number_in(ByteReader& in, const OptionSpec& s) {
  if (s.min && s.max) {
    const double u = static_cast<double>(in.bits(2)) / 65535.0;
    return *s.min + (*s.max - *s.min) * u;
  }
  if (s.min) return *s.min + std::abs(in.ordinary());
  if (s.max) return *s.max - std::abs(in.ordinary());
  return in.ordinary();
}

/// A random JSON value of any type, often invalid for the option.
json any_value(ByteReader& in) {
  switch (in.byte() % 9) {
    case 0:
      return nullptr;
    case 1:
      return in.boolean();
    case 2:
      return in.number();
    case 3:
      return static_cast<std::int64_t>(in.bits(8));
    case 4:
      return in.bits(8);
    case 5:
      return in.string(12);
    case 6: {
      json a = json::array();
      const std::size_t k = in.range(0, 4);
      for (std::size_t i = 0; i < k; ++i) a.push_back(in.number());
      return a;
    }
    case 7:
      return json::object({{in.string(4), in.number()}});
    default:
      return static_cast<std::int64_t>(in.range(0, 3)) - 1;
  }
}

json valid_value(ByteReader& in, const OptionSpec& s, std::size_t n) {
  switch (s.type) {
    case OptionType::kNumber:
      return number_in(in, s);
    case OptionType::kInteger: {
      const double lo = s.min ? *s.min : 0.0;
      const double hi = std::min(s.max ? *s.max : kMaxIterations, kMaxIterations);
      return static_cast<std::int64_t>(lo) +
             static_cast<std::int64_t>(in.range(0, static_cast<std::size_t>(hi - lo)));
    }
    case OptionType::kBoolean:
      switch (in.byte() % 3) {
        case 0:
          return in.boolean();
        case 1:
          return in.byte() & 1;
        default:
          return in.boolean() ? "true" : "false";
      }
    case OptionType::kChoice:
      return s.choices.empty() ? json("") : json(s.choices[in.range(0, s.choices.size() - 1)]);
    case OptionType::kString:  // usually a name like the input's method (e.g. tangents_from)
      if (in.byte() < 200) return in.name(fairspline::fuzz::kMaxNameLength);
      return in.string(16);
    case OptionType::kNumberList: {
      json a = json::array();
      const std::size_t k = count_near(in, in.boolean() ? n : 2);
      for (std::size_t i = 0; i < k; ++i) a.push_back(number_in(in, s));
      return a;
    }
    case OptionType::kChoiceOrNumber:
      if (!s.choices.empty() && in.boolean()) {
        return s.choices[in.range(0, s.choices.size() - 1)];
      }
      return number_in(in, s);
  }
  return nullptr;
}

json make_options(ByteReader& in, const fairspline::MethodInfo& m, std::size_t n) {
  json o = json::object();
  for (const OptionSpec& s : m.options) {
    switch (in.byte() % 6) {
      case 0:
      case 1:  // absent
        break;
      case 2:  // the default
        if (!s.default_value.is_null()) o[s.name] = s.default_value;
        break;
      case 3:
      case 4:  // a valid value of the option's type
        o[s.name] = valid_value(in, s, n);
        break;
      default:  // anything, often out of range or of the wrong type
        o[s.name] = any_value(in);
        break;
    }
  }
  if (in.byte() == 0xff) o[in.string(8)] = any_value(in);  // maybe an unknown option
  return o;
}

FitInput make_input(ByteReader& in) {
  FitInput fi;
  const std::uint8_t flags = in.byte();
  fi.closed = flags & 1;
  const std::uint8_t nb = in.byte();
  const std::size_t n = nb < 200 ? nb % 12 : nb % (kMaxPoints + 1);
  for (std::size_t i = 0; i < n; ++i) fi.points.push_back(next_point(in, fi.points));
  switch (in.byte() % 6) {
    case 0:
      fi.alpha = 0.0;
      break;
    case 1:
      fi.alpha = 1.0;
      break;
    case 2:
      fi.alpha = static_cast<double>(in.byte()) / 255.0;
      break;
    case 3:
      fi.alpha = in.number();
      break;
    default:
      break;  // the default 0.5
  }
  if (flags & 2) {
    const std::size_t k = count_near(in, n);
    for (std::size_t i = 0; i < k; ++i) {
      if (in.byte() < 96) {
        fi.tangents.emplace_back(std::nullopt);
      } else {
        fi.tangents.emplace_back(direction(in));
      }
    }
  }
  if (flags & 4) {
    const std::size_t k = count_near(in, n);
    for (std::size_t i = 0; i < k; ++i) {
      const std::uint8_t b = in.byte();
      fi.kinds.push_back(b < 160   ? PointKind::kSmooth
                         : b < 224 ? PointKind::kClamped
                                   : PointKind::kCorner);
    }
  }
  if (flags & 8) fi.start_tangent = direction(in);
  if (flags & 16) fi.end_tangent = direction(in);
  if (flags & 32) {  // explicit knots: increasing steps, or anything
    const std::size_t k = count_near(in, n + (fi.closed ? 1 : 0));
    double t = in.byte() < 200 ? 0.0 : in.number();
    for (std::size_t i = 0; i < k; ++i) {
      fi.knots.push_back(t);
      const std::uint8_t b = in.byte();
      t = b < 200 ? t + std::abs(in.ordinary()) + 1.0 / 64.0 : b < 240 ? t : in.number();
    }
  }
  return fi;
}

/// A result written over an earlier one (fit_into reusing capacity) must equal a fresh one.
void check_reuse(const std::string& method, const FitInput& in, const json& options,
                 const fairspline::FitResult& fresh) {
  fairspline::FitResult reused;
  FitInput other;
  other.points = {{0, 0}, {1, 2}, {3, 1}, {4, 3}, {6, 0}, {7, 1}, {8, 4}};
  other.tangents.assign(other.points.size(), Vec2{1, 0});
  other.start_tangent = Vec2{1, 1};
  try {
    fairspline::fit_into(method, other, json::object(), fairspline::ReportLevel::kFull, reused);
  } catch (const fairspline::Error&) {
  }
  try {
    fairspline::fit_into(method, in, options, fairspline::ReportLevel::kFull, reused);
  } catch (const fairspline::Error& e) {
    fairspline::fuzz::fail(std::string("fit_into over an earlier result failed where a fresh fit "
                                       "succeeded: ") +
                           e.what());
  }
  if (fairspline::io::to_json(reused) != fairspline::io::to_json(fresh)) {
    fairspline::fuzz::fail("fit_into over an earlier result differs from a fresh fit");
  }
}

/// A number for the printed request: finite ones as JSON numbers (which print to the last bit),
/// NaN and ±Inf, which JSON lacks, as the strings "NaN", "Infinity", "-Infinity".
json exact(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "Infinity" : "-Infinity";
  return x;
}

/// `j` with every non-finite number replaced by its string (see exact()).
json exact_json(const json& j) {
  if (j.is_number_float()) return exact(j.get<double>());
  if (!j.is_structured()) return j;
  json out = j;
  for (auto& v : out) v = exact_json(v);
  return out;
}

/// With FUZZ_FIT_PRINT set, the decoded request is printed as one line of JSON (to reproduce a
/// finding by hand, and to check that an input decodes to the same request after a format
/// change). Strings that are not UTF-8 are printed with U+FFFD in place of the bad bytes.
void print_request(const std::string& method, bool reuse, const FitInput& in, const json& options) {
  const auto vec = [](Vec2 v) { return json::array({exact(v.x), exact(v.y)}); };
  json j = {{"method", method},
            {"reuse", reuse},
            {"closed", in.closed},
            {"alpha", exact(in.alpha)},
            {"options", exact_json(options)}};
  json pts = json::array();
  for (const Point& p : in.points) pts.push_back(vec(p));
  j["points"] = pts;
  if (!in.tangents.empty()) {
    json ts = json::array();
    for (const auto& t : in.tangents) ts.push_back(t ? vec(*t) : json(nullptr));
    j["tangents"] = ts;
  }
  if (!in.kinds.empty()) {
    json ks = json::array();
    for (PointKind k : in.kinds) ks.push_back(fairspline::io::point_kind_name(k));
    j["kinds"] = ks;
  }
  if (!in.knots.empty()) {
    json ks = json::array();
    for (double t : in.knots) ks.push_back(exact(t));
    j["knots"] = ks;
  }
  if (in.start_tangent) j["start_tangent"] = vec(*in.start_tangent);
  if (in.end_tangent) j["end_tangent"] = vec(*in.end_tangent);
  const std::string text = j.dump(-1, ' ', false, json::error_handler_t::replace);
  std::fprintf(stderr, "fuzz_fit request: %s\n", text.c_str());
}

/// The registered method called `name`, or null.
const fairspline::MethodInfo* registered(const std::string& name) {
  for (const fairspline::MethodInfo& m : fairspline::methods()) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

/// An input whose name is not a registered method: fit() must refuse the name with
/// Error(kUnknownMethod) whose JSON form can be written (a name that is not UTF-8 made
/// error_to_json(e).dump() throw; reproducer: unknown-method-not-utf8). Nothing depends on which
/// or how many methods are registered.
void check_unknown(const std::string& name) {
  if (std::getenv("FUZZ_FIT_PRINT")) {
    const json j = {{"method", name}, {"registered", false}};
    const std::string text = j.dump(-1, ' ', false, json::error_handler_t::replace);
    std::fprintf(stderr, "fuzz_fit request: %s\n", text.c_str());
  }
  FitInput fi;
  fi.points = {{0, 0}, {1, 2}, {3, 1}};
  std::optional<fairspline::Error> error;
  try {
    (void)fairspline::fit(name, fi, json::object(), fairspline::ReportLevel::kFull);
  } catch (const fairspline::Error& e) {
    error = e;
  } catch (const std::exception& e) {
    fairspline::fuzz::fail(std::string("exception other than fairspline::Error for an unknown "
                                       "method: ") +
                           e.what());
  }
  if (!error) fairspline::fuzz::fail("fit() accepted a method name that is not registered");
  if (error->code() != fairspline::ErrorCode::kUnknownMethod) {
    fairspline::fuzz::fail("an unknown method name gave error " +
                           std::string(fairspline::error_code_name(error->code())) + ": " +
                           error->what());
  }
  try {
    (void)fairspline::io::error_to_json(*error).dump();
  } catch (const std::exception& e) {
    fairspline::fuzz::fail(std::string("the unknown-method error cannot be written as JSON: ") +
                           e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  const std::string name = in.name(fairspline::fuzz::kMaxNameLength);
  const fairspline::MethodInfo* found = registered(name);
  if (!found) {
    check_unknown(name);
    return 0;
  }
  const fairspline::MethodInfo& method = *found;
  const bool reuse = (in.byte() & 3) == 0;
  const FitInput fi = make_input(in);
  const json options = make_options(in, method, fi.points.size());
  if (std::getenv("FUZZ_FIT_PRINT")) print_request(method.name, reuse, fi, options);
  try {
    const fairspline::FitResult r =
        fairspline::fit(method.name, fi, options, fairspline::ReportLevel::kFull);
    fairspline::fuzz::check_result(r);
    if (r.method != method.name) fairspline::fuzz::fail("result names another method");
    if (reuse) check_reuse(method.name, fi, options, r);
  } catch (const fairspline::Error&) {
    // A clear error is a valid answer.
  } catch (const std::exception& e) {
    fairspline::fuzz::fail(std::string("exception other than fairspline::Error: ") + e.what());
  }
  return 0;
}
