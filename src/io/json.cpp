#include "fairspline/io/json.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fairspline/io/csv.hpp"

namespace fairspline::io {

using nlohmann::json;

namespace {

constexpr const char* kInputFields[] = {"points",        "closed",      "tangents", "kinds",
                                        "method",        "options",     "alpha",    "knots",
                                        "start_tangent", "end_tangent", "lambdas"};

std::string field_list() {
  std::string s;
  for (const char* f : kInputFields) s += (s.empty() ? "" : ", ") + std::string(f);
  return s;
}

std::string indexed(std::string_view field, std::size_t i) {
  return std::string(field) + "[" + std::to_string(i) + "]";
}

/// Short text of a JSON value for messages.
std::string preview(const json& v) {
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 60) {
    // Cut at a character boundary: a multi-byte UTF-8 character split at byte 57 made the
    // message invalid UTF-8, which the server could not write as JSON (found by fuzz_json).
    std::size_t cut = 57;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
    s = s.substr(0, cut) + "...";
  }
  return s;
}

[[noreturn]] void parse_fail(const std::string& message,
                             std::optional<std::size_t> index = std::nullopt) {
  throw Error(ErrorCode::kParseError, message, index);
}

double finite_number(const json& v, const std::string& where, std::optional<std::size_t> index) {
  const double x = v.get<double>();
  if (!std::isfinite(x)) {
    throw Error(ErrorCode::kNonFinite,
                where + ": number is not finite (too large for double precision)", index);
  }
  return x;
}

/// [x, y] with two finite numbers.
Vec2 parse_pair(const json& v, const std::string& where, std::optional<std::size_t> index) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
    parse_fail(where + ": expected [x, y] with two numbers, got " + preview(v), index);
  }
  const Vec2 p{finite_number(v[0], where, index), finite_number(v[1], where, index)};
  return p;
}

const json& require_array(const json& v, const char* field) {
  if (!v.is_array()) parse_fail(std::string(field) + ": expected an array, got " + preview(v));
  return v;
}

bool is_comment_key(const std::string& key) {
  return !key.empty() && (key[0] == '_' || key[0] == '$');
}

/// `s` with every byte outside ASCII written as \xNN: nlohmann's syntax errors quote the bytes
/// last read, which may be invalid UTF-8, and the message must stay writable as JSON.
std::string ascii_only(std::string_view s) {
  std::string out;
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x80) {
      out += c;
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    }
  }
  return out;
}

/// "line L, column C" of a byte offset.
std::pair<std::size_t, std::size_t> line_column(std::string_view text, std::size_t byte) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

json opt_number(const std::optional<double>& v) {
  return v ? json(*v) : json(nullptr);
}

json point_json(Point p) {
  return json::array({p.x, p.y});
}

std::string fmt_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

/// SAX handler that only tracks where the parser is, to name the field of a number that
/// overflows double (nlohmann reports those without a location).
class PathTracker : public nlohmann::json_sax<json> {
 public:
  std::string error_path;
  std::optional<std::size_t> error_index;

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    stack_.push_back({false, 0, {}});
    return true;
  }
  bool key(string_t& k) override {
    stack_.back().key = k;
    return true;
  }
  bool end_object() override {
    stack_.pop_back();
    return value();
  }
  bool start_array(std::size_t) override {
    stack_.push_back({true, 0, {}});
    return true;
  }
  bool end_array() override {
    stack_.pop_back();
    return value();
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    for (std::size_t d = 0; d < stack_.size(); ++d) {
      const Frame& f = stack_[d];
      if (f.array) {
        error_path += '[';
        error_path += std::to_string(f.index);
        error_path += ']';
        if (!error_index) error_index = f.index;
      } else {
        if (!error_path.empty()) error_path += '.';
        error_path += f.key;
      }
    }
    return false;
  }

 private:
  struct Frame {
    bool array = false;
    std::size_t index = 0;
    std::string key;
  };
  bool value() {
    if (!stack_.empty() && stack_.back().array) ++stack_.back().index;
    return true;
  }
  std::vector<Frame> stack_;
};

constexpr int kMaxDepth = 64;

}  // namespace

ParsedInput parse_json_input(std::string_view text) {
  json doc;
  try {
    // Reject absurd nesting early (messages and dumps of such values recurse).
    const json::parser_callback_t limit_depth = [](int depth, json::parse_event_t, json&) {
      if (depth > kMaxDepth) {
        throw Error(ErrorCode::kParseError,
                    "JSON nested deeper than " + std::to_string(kMaxDepth) + " levels");
      }
      return true;
    };
    doc = json::parse(text.begin(), text.end(), limit_depth);
  } catch (const json::out_of_range&) {
    // 406: a number too large for double ("1e999").
    PathTracker tracker;
    json::sax_parse(text.begin(), text.end(), &tracker);
    const std::string where = tracker.error_path.empty() ? "JSON" : tracker.error_path;
    throw Error(ErrorCode::kNonFinite,
                where + ": number is not finite (too large for double precision)",
                tracker.error_index);
  } catch (const json::parse_error& e) {
    // nlohmann's byte is 1-based position of the last character read.
    const std::size_t byte = e.byte > 0 ? e.byte - 1 : 0;
    const auto [line, col] = line_column(text, byte);
    std::string what = e.what();
    // Keep the reason after nlohmann's "[json.exception.parse_error.101] parse error at ...: ".
    const auto colon = what.find(": ");
    const std::string reason =
        ascii_only(colon == std::string::npos ? what : what.substr(colon + 2));
    parse_fail("invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(col) +
                   " (byte " + std::to_string(e.byte) + "): " + reason,
               line);
  }
  return input_from_json(doc);
}

ParsedInput input_from_json(const json& document) {
  ParsedInput out;
  if (document.is_array()) {
    return input_from_json(json{{"points", document}});
  }
  if (!document.is_object()) {
    parse_fail("expected a JSON object with a \"points\" field, got " + preview(document));
  }
  for (const auto& [key, value] : document.items()) {
    if (is_comment_key(key)) continue;
    bool known = false;
    for (const char* f : kInputFields) known = known || key == f;
    if (!known) {
      parse_fail("unknown field '" + key + "'; expected " + field_list() +
                 " (keys starting with '_' or '$' are ignored)");
    }
  }
  FitInput& in = out.input;

  if (!document.contains("points")) parse_fail("missing field 'points'");
  const json& pts = require_array(document["points"], "points");
  in.points.reserve(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    in.points.push_back(parse_pair(pts[i], indexed("points", i), i));
  }

  if (auto it = document.find("closed"); it != document.end()) {
    if (!it->is_boolean()) parse_fail("closed: expected true or false, got " + preview(*it));
    in.closed = it->get<bool>();
  }

  if (auto it = document.find("tangents"); it != document.end()) {
    const json& arr = require_array(*it, "tangents");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      if (arr[i].is_null()) {
        in.tangents.emplace_back(std::nullopt);
      } else if (arr[i].is_array() && arr[i].size() == 2 && arr[i][0].is_number() &&
                 arr[i][1].is_number()) {
        in.tangents.emplace_back(parse_pair(arr[i], indexed("tangents", i), i));
      } else {
        parse_fail(indexed("tangents", i) + ": expected [x, y] with two numbers or null, got " +
                       preview(arr[i]),
                   i);
      }
    }
  }

  if (auto it = document.find("kinds"); it != document.end()) {
    const json& arr = require_array(*it, "kinds");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      const json& k = arr[i];
      if (k.is_string() && (k == "smooth" || k == "clamped" || k == "corner")) {
        in.kinds.push_back(parse_point_kind(k.get<std::string>()));
      } else {
        parse_fail(indexed("kinds", i) + ": expected \"smooth\", \"clamped\" or \"corner\", got " +
                       preview(k),
                   i);
      }
    }
  }

  if (auto it = document.find("method"); it != document.end()) {
    if (!it->is_string()) parse_fail("method: expected a method name string, got " + preview(*it));
    out.method = it->get<std::string>();
  }

  if (auto it = document.find("options"); it != document.end()) {
    if (!it->is_object()) parse_fail("options: expected an object, got " + preview(*it));
    out.options = *it;
  }

  if (auto it = document.find("lambdas"); it != document.end()) {
    const json& arr = require_array(*it, "lambdas");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      if (!arr[i].is_number()) {
        parse_fail(indexed("lambdas", i) + ": expected a number, got " + preview(arr[i]), i);
      }
      finite_number(arr[i], indexed("lambdas", i), i);
    }
    if (out.options.contains("lambdas")) {
      parse_fail("lambdas: given both at top level and in options");
    }
    out.options["lambdas"] = arr;
  }

  if (auto it = document.find("alpha"); it != document.end()) {
    if (!it->is_number()) parse_fail("alpha: expected a number, got " + preview(*it));
    in.alpha = finite_number(*it, "alpha", std::nullopt);
  }

  if (auto it = document.find("knots"); it != document.end()) {
    const json& arr = require_array(*it, "knots");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      if (!arr[i].is_number()) {
        parse_fail(indexed("knots", i) + ": expected a number, got " + preview(arr[i]), i);
      }
      in.knots.push_back(finite_number(arr[i], indexed("knots", i), i));
    }
  }

  for (const char* field : {"start_tangent", "end_tangent"}) {
    auto it = document.find(field);
    if (it == document.end() || it->is_null()) continue;
    const Vec2 v = parse_pair(*it, field, std::nullopt);
    (std::string_view(field) == "start_tangent" ? in.start_tangent : in.end_tangent) = v;
  }
  return out;
}

json to_json(const Report& r) {
  json j = {{"bending_energy", opt_number(r.bending_energy)},
            {"linearized_energy", r.linearized_energy},
            {"curvature_variation_energy", opt_number(r.curvature_variation_energy)},
            {"length", opt_number(r.length)},
            {"regular", r.regular},
            {"max_tangent_angle_jump_deg", r.max_tangent_angle_jump_deg},
            {"max_curvature_jump", r.max_curvature_jump},
            {"min_relative_speed", r.min_relative_speed},
            {"max_interpolation_residual", r.max_interpolation_residual},
            {"energy_singular", r.energy_singular}};
  // Per-segment reports and intersections exist only at the full level (which is also the
  // level that computes the bending energy).
  if (r.bending_energy.has_value() || !r.segments.empty()) {
    json segs = json::array();
    for (const SegmentReport& s : r.segments) {
      segs.push_back({{"linearized_energy", s.linearized_energy},
                      {"bending_energy", s.bending_energy},
                      {"curvature_variation_energy", s.curvature_variation_energy},
                      {"length", s.length},
                      {"regular", s.regular},
                      {"min_relative_speed", s.min_relative_speed},
                      {"has_loop", s.has_loop},
                      {"has_cusp", s.has_cusp},
                      {"has_fold", s.has_fold}});
    }
    j["segment_reports"] = std::move(segs);
    json xs = json::array();
    for (const Intersection& x : r.intersections) {
      xs.push_back({{"segment_a", x.segment_a},
                    {"segment_b", x.segment_b},
                    {"u_a", x.u_a},
                    {"u_b", x.u_b},
                    {"point", point_json(x.point)}});
    }
    j["intersections"] = std::move(xs);
  }
  return j;
}

json to_json(const FitResult& r) {
  json points = json::array();
  for (const Point& p : r.points) points.push_back(point_json(p));
  json tangents = json::array();
  for (const Vec2& t : r.tangents) tangents.push_back(point_json(t));
  json segments = json::array();
  for (const Segment& s : r.spline.segments) {
    json bez = json::array();
    for (const Point& p : s.bezier.p) bez.push_back(point_json(p));
    segments.push_back({{"bezier", std::move(bez)}, {"t0", s.t0}, {"t1", s.t1}, {"span", s.span}});
  }
  json j = {{"method", r.method},
            {"closed", r.closed},
            {"options", r.options.is_null() ? json::object() : r.options},
            {"points", std::move(points)},
            {"knots", r.knots},
            {"tangents", std::move(tangents)},
            {"segments", std::move(segments)}};
  if (r.report) j["report"] = to_json(*r.report);
  j["method_report"] = r.method_report.is_null() ? json::object() : r.method_report;
  return j;
}

std::string write_json(const FitResult& result, int indent) {
  // Replace invalid UTF-8 rather than throwing (method names and reports are library-made).
  return to_json(result).dump(indent, ' ', false, json::error_handler_t::replace);
}

json error_to_json(const Error& error) {
  return {{"error",
           {{"code", std::string(error_code_name(error.code()))},
            {"message", error.what()},
            {"index", error.index() ? json(*error.index()) : json(nullptr)}}}};
}

ReportLevel parse_report_level(std::string_view text) {
  if (text == "none") return ReportLevel::kNone;
  if (text == "basic") return ReportLevel::kBasic;
  if (text == "full") return ReportLevel::kFull;
  throw Error(ErrorCode::kInvalidArgument,
              "report level must be none, basic or full, got '" + std::string(text) + "'");
}

std::string_view report_level_name(ReportLevel level) {
  switch (level) {
    case ReportLevel::kNone:
      return "none";
    case ReportLevel::kBasic:
      return "basic";
    case ReportLevel::kFull:
      return "full";
  }
  return "none";
}

PointKind parse_point_kind(std::string_view text) {
  if (text == "smooth") return PointKind::kSmooth;
  if (text == "clamped") return PointKind::kClamped;
  if (text == "corner") return PointKind::kCorner;
  throw Error(ErrorCode::kInvalidArgument,
              "point kind must be smooth, clamped or corner, got '" + std::string(text) + "'");
}

std::string_view point_kind_name(PointKind kind) {
  switch (kind) {
    case PointKind::kSmooth:
      return "smooth";
    case PointKind::kClamped:
      return "clamped";
    case PointKind::kCorner:
      return "corner";
  }
  return "smooth";
}

std::string summary_table(const FitResult& result) {
  std::vector<std::pair<std::string, std::string>> rows;
  const auto opt = [](const std::optional<double>& v) { return v ? fmt_number(*v) : "-"; };
  rows.emplace_back("method", result.method);
  rows.emplace_back(
      "points", std::to_string(result.points.size()) + (result.closed ? " (closed)" : " (open)"));
  rows.emplace_back("segments", std::to_string(result.spline.segments.size()));
  if (result.report) {
    const Report& r = *result.report;
    const std::string singular = r.energy_singular ? " (singular)" : "";
    rows.emplace_back("bending energy", opt(r.bending_energy) + singular);
    rows.emplace_back("linearized energy", fmt_number(r.linearized_energy));
    rows.emplace_back("curvature-variation energy", opt(r.curvature_variation_energy) + singular);
    rows.emplace_back("length", opt(r.length));
    rows.emplace_back("regular", r.regular ? "yes" : "NO");
    rows.emplace_back("max tangent jump (deg)", fmt_number(r.max_tangent_angle_jump_deg));
    rows.emplace_back("max curvature jump", fmt_number(r.max_curvature_jump));
    if (!r.segments.empty()) {
      rows.emplace_back("self-intersections", std::to_string(r.intersections.size()));
    }
  } else {
    rows.emplace_back("report", "not computed");
  }
  std::size_t width = 0;
  for (const auto& [k, v] : rows) width = std::max(width, k.size());
  std::string out;
  for (const auto& [k, v] : rows) {
    out += k;
    out.append(width + 2 - k.size(), ' ');
    out += v;
    out += '\n';
  }
  return out;
}

}  // namespace fairspline::io
