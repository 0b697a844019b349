#include "fairspline/io/json.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "detail/choices.hpp"
#include "detail/huge_pages.hpp"
#include "detail/json_input.hpp"
#include "fairspline/io/csv.hpp"

namespace fairspline::io {

using nlohmann::json;

namespace {

constexpr detail::ChoiceTable<ReportLevel, 3> kReportLevels{
    {{"none", ReportLevel::kNone}, {"basic", ReportLevel::kBasic}, {"full", ReportLevel::kFull}}};
constexpr detail::ChoiceTable<PointKind, 3> kPointKinds{{{"smooth", PointKind::kSmooth},
                                                         {"clamped", PointKind::kClamped},
                                                         {"corner", PointKind::kCorner}}};
constexpr detail::ChoiceTable<SideState, 3> kSideStates{{{"regular", SideState::kRegular},
                                                         {"clamped", SideState::kClamped},
                                                         {"free", SideState::kFree}}};
constexpr detail::ChoiceTable<SolverStatus, 4> kSolverStatuses{
    {{"converged", SolverStatus::kConverged},
     {"conditioning_limit", SolverStatus::kConditioningLimit},
     {"iteration_limit", SolverStatus::kIterationLimit},
     {"stalled", SolverStatus::kStalled}}};

/// The value `table` names `text`, else Error(kInvalidArgument) "<what> must be a, b or c".
template <class E, std::size_t N>
E parse_choice(const detail::ChoiceTable<E, N>& table, std::string_view text, const char* what) {
  if (const std::optional<E> v = table.find(text)) return *v;
  throw Error(ErrorCode::kInvalidArgument, std::string(what) + " must be " + table.or_list() +
                                               ", got '" + std::string(text) + "'");
}

}  // namespace

namespace {

constexpr const char* kInputFields[] = {"points",   "closed",        "tangents",     "kinds",
                                        "states",   "in_tangents",   "out_tangents", "corners_deg",
                                        "radii",    "method",        "options",      "alpha",
                                        "knots",    "start_tangent", "end_tangent",  "lambdas",
                                        "accuracy", "best_effort",   "diagnostics",  "time_limit"};

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

/// Whether brackets outside strings nest deeper than `limit` anywhere in `text` (read as the
/// parser lexes it up to any error: strings end at an unescaped quote).
bool nests_deeper_than(std::string_view text, int limit) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

/// Parses a JSON document with messages for people: line and column of a syntax error (index =
/// line), the field of a number that overflows double (kNonFinite), a nesting limit.
json parse_document(std::string_view text) {
  json doc;
  try {
    // Reject absurd nesting early (messages and dumps of such values recurse). The parser with
    // a callback does that, but it scans an array for discarded values at the end of each
    // object in it: quadratic in a fit result's segments (40 000 points: 1.2 s against 0.23 s
    // without). So it parses only texts that nest deeper than the limit, where it stops first.
    const json::parser_callback_t limit_depth = [](int depth, json::parse_event_t, json&) {
      if (depth > kMaxDepth) {
        throw Error(ErrorCode::kParseError,
                    "JSON nested deeper than " + std::to_string(kMaxDepth) + " levels");
      }
      return true;
    };
    // (A value at nesting k is reported at depth k: within the limit the callback never fires.)
    doc = nests_deeper_than(text, kMaxDepth) ? json::parse(text.begin(), text.end(), limit_depth)
                                             : json::parse(text.begin(), text.end());
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
  return doc;
}

}  // namespace

namespace {

ParsedInput input_from_fields(const json& document, std::vector<Vec2>* points);

/// The scanning steps of the readers below that skip nlohmann's DOM for a text's long arrays:
/// each gives up (returns false) on anything it does not expect, and its reader then leaves
/// the text to the DOM reader, whose errors and positions are the ones users see.
class JsonScanner {
 protected:
  explicit JsonScanner(std::string_view text) : t_(text) {}

  void skip_space() {
    while (i_ < t_.size() &&
           (t_[i_] == ' ' || t_[i_] == '\n' || t_[i_] == '\r' || t_[i_] == '\t')) {
      ++i_;
    }
  }
  bool eat(char c) {
    if (i_ < t_.size() && t_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  bool at_end() {
    skip_space();
    return i_ == t_.size();
  }

  /// A string of printable ASCII without escapes (any other gives up), its text without quotes.
  bool string_token(std::string_view& s) {
    if (!eat('"')) return false;
    const std::size_t begin = i_;
    for (; i_ < t_.size(); ++i_) {
      const auto c = static_cast<unsigned char>(t_[i_]);
      if (c == '"') {
        s = t_.substr(begin, i_ - begin);
        ++i_;
        return true;
      }
      if (c < 0x20 || c >= 0x7f || c == '\\') return false;
    }
    return false;
  }

  /// A member's "key": (white space around), its key's text in `key`.
  bool member_name(std::string_view& key) {
    skip_space();
    if (!string_token(key)) return false;
    skip_space();
    if (!eat(':')) return false;
    skip_space();
    return true;
  }

  /// Any value, parsed by nlohmann from its own text, as member `key` of `into` (a key it
  /// already has gives up: the DOM reader says what a repeated key means).
  bool other_member(std::string_view key, json& into) {
    if (into.contains(key)) return false;
    const std::size_t begin = i_;
    if (!skip_value()) return false;
    json value = json::parse(t_.begin() + static_cast<std::ptrdiff_t>(begin),
                             t_.begin() + static_cast<std::ptrdiff_t>(i_), nullptr, false);
    if (value.is_discarded()) return false;
    into[std::string(key)] = std::move(value);
    return true;
  }

  /// Past one value of any kind, matching brackets outside strings; nlohmann checks the text.
  /// Gives up beyond a depth that could reach the nesting limit.
  bool skip_value() {
    int depth = 0;
    for (; i_ < t_.size(); ++i_) {
      const char c = t_[i_];
      if (c == '"') {
        for (++i_; i_ < t_.size() && t_[i_] != '"'; ++i_) {
          if (t_[i_] == '\\') ++i_;
        }
        if (i_ >= t_.size()) return false;
        if (depth == 0) {
          ++i_;
          return true;
        }
      } else if (c == '[' || c == '{') {
        if (++depth > kMaxDepth / 2) return false;
      } else if (c == ']' || c == '}') {
        if (depth == 0) return true;  // a scalar's end
        if (--depth == 0) {
          ++i_;
          return true;
        }
      } else if (c == ',' && depth == 0) {
        return true;
      }
    }
    return depth == 0;
  }

  /// A JSON number, as nlohmann reads it to a double. (Scanned with local pointers: through
  /// the members, every step reloaded and stored i_.)
  bool number(double& v) {
    const char* const first = t_.data() + i_;
    const char* const last = t_.data() + t_.size();
    const char* p = first;
    const auto digit = [&] { return p != last && static_cast<unsigned char>(*p - '0') < 10; };
    const bool negative = p != last && *p == '-';
    if (negative) ++p;
    if (!digit()) return false;
    if (*p == '0') {
      ++p;
    } else {
      while (digit()) ++p;
    }
    bool integer = true;
    if (p != last && *p == '.') {
      integer = false;
      ++p;
      if (!digit()) return false;
      while (digit()) ++p;
    }
    if (p != last && (*p == 'e' || *p == 'E')) {
      integer = false;
      ++p;
      if (p != last && (*p == '+' || *p == '-')) ++p;
      if (!digit()) return false;
      while (digit()) ++p;
    }
    i_ = static_cast<std::size_t>(p - t_.data());
    if (negative && integer && p - first == 2 && first[1] == '0') {
      v = 0.0;  // nlohmann's integer -0 is 0
      return true;
    }
    const auto [end, ec] = std::from_chars(first, p, v);
    // Out of range (overflow, or underflow to zero) gives up: the old way names the field.
    return ec == std::errc() && end == p && std::isfinite(v);
  }

  /// [x, y] into `p`.
  bool pair(Vec2& p) {
    if (!eat('[')) return false;
    skip_space();
    if (!number(p.x)) return false;
    skip_space();
    if (!eat(',')) return false;
    skip_space();
    if (!number(p.y)) return false;
    skip_space();
    return eat(']');
  }

  /// The arrays opened directly inside the array at i_ (its own, not the rest of the text's):
  /// the size to reserve for its pairs. Stops at a string or an object, where reading gives up.
  std::size_t pairs_ahead() const {
    std::size_t n = 0;
    int depth = 0;
    for (std::size_t j = i_; j < t_.size(); ++j) {
      const char c = t_[j];
      if (c == '[') {
        n += ++depth == 2;
      } else if (c == ']') {
        if (--depth <= 0) break;
      } else if (c == '"' || c == '{') {
        break;
      }
    }
    return n;
  }

  /// [[x, y], ...] into `points`.
  bool points_array(std::vector<Vec2>& points) {
    // One allocation, advised for huge pages: growing by doubling, then shrinking, touched
    // ~3 arrays of fresh pages for 1 of points (at 2·10^5 points, 2400 page faults of ~14 µs
    // on the measuring VM).
    const std::size_t expected = pairs_ahead();
    if (!eat('[')) return false;
    skip_space();
    if (eat(']')) return true;
    detail::reserve_to_fill(points, points.size() + expected);
    for (;;) {
      skip_space();
      Vec2 p;
      if (!pair(p)) return false;
      points.push_back(p);
      skip_space();
      if (eat(']')) break;
      if (!eat(',')) return false;
    }
    return true;
  }

  std::string_view t_;
  std::size_t i_ = 0;
};

/// Reads the common request straight from its text: an object (or a bare array of points)
/// whose "points" are pairs of numbers, read into Vec2 as they are scanned, and whose other
/// members are each parsed by nlohmann from their own text. For 2·10^5 points the DOM of
/// "points" took 20% of the CPU time of `fairspline fit`, and of a 20-point batch
/// line 30%, most of it building and freeing nodes and strtod.
///
/// It gives up (nullopt) on anything else: invalid JSON, a point that is not [x, y] with two
/// numbers of plain range, escapes in keys, repeated or unknown keys, a fit result, nesting
/// near the limit, or any field the checks refuse. parse_json_input then reads the text the
/// old way, so every error keeps its message, position and code, and a request is read the
/// same either way (from_chars and strtod both round correctly; "-0" is nlohmann's integer 0).
class FastRequestReader : JsonScanner {
 public:
  explicit FastRequestReader(std::string_view text) : JsonScanner(text) {}

  std::optional<ParsedInput> read() {
    skip_space();
    if (i_ < t_.size() && t_[i_] == '[') {
      std::vector<Vec2> points;
      if (!points_array(points) || !at_end()) return std::nullopt;
      ParsedInput out;
      out.input.points = std::move(points);
      return out;
    }
    if (!eat('{')) return std::nullopt;
    json rest = json::object();
    std::vector<Vec2> points;
    bool has_points = false;
    skip_space();
    if (!eat('}')) {
      for (;;) {
        std::string_view key;
        if (!member_name(key)) return std::nullopt;
        if (key == "points") {
          if (has_points || !points_array(points)) return std::nullopt;
          has_points = true;
        } else if (!allowed_key(key) || !other_member(key, rest)) {
          return std::nullopt;
        }
        skip_space();
        if (eat('}')) break;
        if (!eat(',')) return std::nullopt;
      }
    }
    if (!has_points || !at_end()) return std::nullopt;
    try {
      return input_from_fields(rest, &points);
    } catch (const Error&) {
      return std::nullopt;  // the old way says what is wrong, and where
    }
  }

 private:
  /// The request's fields and comments; nothing that makes the text a fit result.
  static bool allowed_key(std::string_view key) {
    if (!key.empty() && (key[0] == '_' || key[0] == '$')) return true;
    for (const char* f : kInputFields) {
      if (key == f) return true;
    }
    return false;
  }
};

}  // namespace

ParsedInput parse_json_input(std::string_view text) {
  if (std::optional<ParsedInput> fast = FastRequestReader(text).read()) return std::move(*fast);
  return detail::parse_json_input_dom(text);
}

ParsedInput input_from_json(const json& document) {
  return input_from_fields(document, nullptr);
}

}  // namespace fairspline::io

namespace fairspline::detail {

io::ParsedInput parse_json_input_dom(std::string_view text) {
  return io::input_from_json(io::parse_document(text));
}

FitResult read_fit_result_dom(std::string_view text) {
  return io::fit_result_from_json(io::parse_document(text));
}

}  // namespace fairspline::detail

namespace fairspline::io {

namespace {

/// input_from_json, with the points already read when `points` is given (the document then has
/// no "points").
ParsedInput input_from_fields(const json& document, std::vector<Vec2>* points) {
  ParsedInput out;
  if (document.is_array()) {
    return input_from_json(json{{"points", document}});
  }
  if (!document.is_object()) {
    parse_fail("expected a JSON object with a \"points\" field, got " + preview(document));
  }
  if (document.contains("request") && document.contains("segments")) {
    // A fit result (write_json): its request fits the same curve again.
    const FitResult r = fit_result_from_json(document);
    out.input = refit_input(r);
    out.method = r.method;
    out.options = r.options;
    out.accuracy = r.accuracy;
    return out;
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

  if (points != nullptr) {
    in.points = std::move(*points);
  } else {
    if (!document.contains("points")) parse_fail("missing field 'points'");
    const json& pts = require_array(document["points"], "points");
    in.points.reserve(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      in.points.push_back(parse_pair(pts[i], indexed("points", i), i));
    }
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

  // Per-side directions: [x, y] or null per point.
  auto side_tangents = [&](const char* field, std::vector<std::optional<Vec2>>& dst) {
    const auto it = document.find(field);
    if (it == document.end()) return;
    const json& arr = require_array(*it, field);
    for (std::size_t i = 0; i < arr.size(); ++i) {
      if (arr[i].is_null()) {
        dst.emplace_back(std::nullopt);
      } else if (arr[i].is_array() && arr[i].size() == 2 && arr[i][0].is_number() &&
                 arr[i][1].is_number()) {
        dst.emplace_back(parse_pair(arr[i], indexed(field, i), i));
      } else {
        parse_fail(indexed(field, i) + ": expected [x, y] with two numbers or null, got " +
                       preview(arr[i]),
                   i);
      }
    }
  };
  side_tangents("in_tangents", in.in_tangents);
  side_tangents("out_tangents", in.out_tangents);

  // Node states: one state for both sides, or [in, out].
  if (auto it = document.find("states"); it != document.end()) {
    const json& arr = require_array(*it, "states");
    auto side = [&](const json& v, std::size_t i) {
      if (v.is_string()) {
        if (const std::optional<SideState> s = kSideStates.find(v.get<std::string>())) return *s;
      }
      parse_fail(indexed("states", i) + ": expected " + kSideStates.or_list() +
                     ", or a pair [in, out] of them, got " + preview(v),
                 i);
    };
    for (std::size_t i = 0; i < arr.size(); ++i) {
      const json& v = arr[i];
      if (v.is_array() && v.size() == 2) {
        in.states.push_back({side(v[0], i), side(v[1], i)});
      } else {
        const SideState s = side(v, i);
        in.states.push_back({s, s});
      }
    }
  }

  if (auto it = document.find("corners_deg"); it != document.end()) {
    const json& arr = require_array(*it, "corners_deg");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      if (!arr[i].is_number()) {
        parse_fail(
            indexed("corners_deg", i) + ": expected a number of degrees, got " + preview(arr[i]),
            i);
      }
      in.corners_deg.push_back(finite_number(arr[i], indexed("corners_deg", i), i));
    }
  }

  if (auto it = document.find("radii"); it != document.end()) {
    const json& arr = require_array(*it, "radii");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      if (!arr[i].is_number()) {
        parse_fail(indexed("radii", i) + ": expected a radius (a number), got " + preview(arr[i]),
                   i);
      }
      in.radii.push_back(finite_number(arr[i], indexed("radii", i), i));
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

  if (auto it = document.find("accuracy"); it != document.end()) {
    if (!it->is_number()) parse_fail("accuracy: expected a number, got " + preview(*it));
    out.accuracy = finite_number(*it, "accuracy", std::nullopt);
  }

  if (auto it = document.find("best_effort"); it != document.end()) {
    if (!it->is_boolean()) parse_fail("best_effort: expected true or false, got " + preview(*it));
    out.best_effort = it->get<bool>();
  }

  if (auto it = document.find("diagnostics"); it != document.end()) {
    if (!it->is_boolean()) parse_fail("diagnostics: expected true or false, got " + preview(*it));
    out.diagnostics = it->get<bool>();
  }

  if (auto it = document.find("time_limit"); it != document.end() && !it->is_null()) {
    if (!it->is_number())
      parse_fail("time_limit: expected a number of seconds, got " + preview(*it));
    out.time_limit = finite_number(*it, "time_limit", std::nullopt);
  }

  for (const char* field : {"start_tangent", "end_tangent"}) {
    auto it = document.find(field);
    if (it == document.end() || it->is_null()) continue;
    const Vec2 v = parse_pair(*it, field, std::nullopt);
    (std::string_view(field) == "start_tangent" ? in.start_tangent : in.end_tangent) = v;
  }
  return out;
}

}  // namespace

namespace {

json input_members(const FitInput& in, std::optional<double> accuracy, bool with_points) {
  const auto pair = [](Vec2 v) { return json::array({v.x, v.y}); };
  const auto optional_pairs = [&](const std::vector<std::optional<Vec2>>& vs) {
    json a = json::array();
    for (const auto& v : vs) a.push_back(v ? pair(*v) : json(nullptr));
    return a;
  };
  json j = json::object();
  if (accuracy) j["accuracy"] = *accuracy;
  if (in.alpha != FitInput::kDefaultAlpha) j["alpha"] = in.alpha;
  if (in.closed) j["closed"] = true;
  if (!in.corners_deg.empty()) j["corners_deg"] = in.corners_deg;
  if (in.end_tangent) j["end_tangent"] = pair(*in.end_tangent);
  if (!in.radii.empty()) j["radii"] = in.radii;
  if (!in.in_tangents.empty()) j["in_tangents"] = optional_pairs(in.in_tangents);
  if (!in.kinds.empty()) {
    json k = json::array();
    for (PointKind kind : in.kinds) k.push_back(std::string(point_kind_name(kind)));
    j["kinds"] = std::move(k);
  }
  if (!in.knots.empty()) j["knots"] = in.knots;
  if (!in.out_tangents.empty()) j["out_tangents"] = optional_pairs(in.out_tangents);
  if (with_points && !in.points.empty()) {
    json p = json::array();
    for (const Point& q : in.points) p.push_back(pair(q));
    j["points"] = std::move(p);
  }
  if (in.start_tangent) j["start_tangent"] = pair(*in.start_tangent);
  if (!in.states.empty()) {
    json st = json::array();
    for (const NodeState& s : in.states) {
      if (s.in == s.out) {
        st.push_back(std::string(side_state_name(s.in)));
      } else {
        st.push_back({std::string(side_state_name(s.in)), std::string(side_state_name(s.out))});
      }
    }
    j["states"] = std::move(st);
  }
  if (!in.tangents.empty()) j["tangents"] = optional_pairs(in.tangents);
  return j;
}

}  // namespace

json input_to_json(const FitInput& in, std::optional<double> accuracy) {
  return input_members(in, accuracy, true);
}

// ---------------------------------------------------------------- reading a result back

namespace {

/// "path.key" ("key" at the top).
std::string member_path(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

[[noreturn]] void bad_field(const std::string& path, std::string_view expected, const json& got,
                            std::optional<std::size_t> index) {
  parse_fail(path + ": expected " + std::string(expected) + ", got " + preview(got), index);
}

double read_number(const json& v, const std::string& path, std::optional<std::size_t> index) {
  if (!v.is_number()) bad_field(path, "a number", v, index);
  return v.get<double>();
}

std::size_t read_size(const json& v, const std::string& path, std::optional<std::size_t> index) {
  if (!v.is_number_integer() || v < 0) bad_field(path, "a non-negative integer", v, index);
  return v.get<std::size_t>();
}

bool read_bool(const json& v, const std::string& path, std::optional<std::size_t> index) {
  if (!v.is_boolean()) bad_field(path, "true or false", v, index);
  return v.get<bool>();
}

Vec2 read_pair(const json& v, const std::string& path, std::optional<std::size_t> index) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
    bad_field(path, "[x, y] with two numbers", v, index);
  }
  return {v[0].get<double>(), v[1].get<double>()};
}

/// Calls read(element, path "name[i]", index) for every element of an array; `index` is the
/// position in the first array of the path, i unless an outer array already set it.
template <class Read>
void read_array(const json& v, const std::string& path, std::optional<std::size_t> index,
                Read read) {
  if (!v.is_array()) bad_field(path, "an array", v, index);
  for (std::size_t i = 0; i < v.size(); ++i) read(v[i], indexed(path, i), index ? index : i);
}

/// The members of one object of a result: each is read once by name, and what is left at the
/// end is an unknown field (a typo, or not a result).
class ObjectReader {
 public:
  ObjectReader(const json& v, std::string path, std::optional<std::size_t> index)
      : v_(v), path_(std::move(path)), index_(index) {
    if (!v.is_object()) bad_field(path_.empty() ? "result" : path_, "an object", v, index_);
  }

  const std::optional<std::size_t>& index() const { return index_; }
  std::string path(std::string_view key) const { return member_path(path_, key); }

  /// The member `key`, or nullptr when absent.
  const json* find(std::string_view key) {
    const auto it = v_.find(key);
    if (it == v_.end()) return nullptr;
    read_.push_back(key);
    return &*it;
  }
  const json& at(std::string_view key) {
    const json* v = find(key);
    if (v == nullptr) parse_fail("missing field '" + path(key) + "'", index_);
    return *v;
  }

  double number(std::string_view key) { return read_number(at(key), path(key), index_); }
  std::optional<double> optional_number(std::string_view key) {
    const json& v = at(key);
    return v.is_null() ? std::nullopt : std::optional<double>(read_number(v, path(key), index_));
  }
  bool boolean(std::string_view key) { return read_bool(at(key), path(key), index_); }
  std::size_t size(std::string_view key) { return read_size(at(key), path(key), index_); }
  Vec2 pair(std::string_view key) { return read_pair(at(key), path(key), index_); }

  /// Every member has been read.
  void done() const {
    if (read_.size() == v_.size()) return;
    for (auto it = v_.begin(); it != v_.end(); ++it) {
      if (std::find(read_.begin(), read_.end(), it.key()) == read_.end()) {
        parse_fail("unknown field '" + path(it.key()) + "'", index_);
      }
    }
  }

 private:
  const json& v_;
  std::string path_;
  std::optional<std::size_t> index_;
  std::vector<std::string_view> read_;
};

Report read_report(const json& v) {
  ObjectReader o(v, "report", std::nullopt);
  Report r;
  r.bending_energy = o.optional_number("bending_energy");
  r.curvature_variation_energy = o.optional_number("curvature_variation_energy");
  r.energy_singular = o.boolean("energy_singular");
  if (const json* xs = o.find("intersections")) {
    read_array(*xs, o.path("intersections"), std::nullopt,
               [&](const json& x, const std::string& path, std::optional<std::size_t> index) {
                 ObjectReader e(x, path, index);
                 Intersection& out = r.intersections.emplace_back();
                 out.point = e.pair("point");
                 out.segment_a = e.size("segment_a");
                 out.segment_b = e.size("segment_b");
                 out.u_a = e.number("u_a");
                 out.u_b = e.number("u_b");
                 e.done();
               });
  }
  r.length = o.optional_number("length");
  r.linearized_energy = o.number("linearized_energy");
  r.max_curvature_jump = o.number("max_curvature_jump");
  r.max_interpolation_residual = o.number("max_interpolation_residual");
  r.max_tangent_angle_jump_deg = o.number("max_tangent_angle_jump_deg");
  r.min_relative_speed = o.number("min_relative_speed");
  r.regular = o.boolean("regular");
  if (const json* segments = o.find("segment_reports")) {
    read_array(*segments, o.path("segment_reports"), std::nullopt,
               [&](const json& x, const std::string& path, std::optional<std::size_t> index) {
                 ObjectReader e(x, path, index);
                 SegmentReport& out = r.segments.emplace_back();
                 out.bending_energy = e.number("bending_energy");
                 out.curvature_variation_energy = e.number("curvature_variation_energy");
                 out.has_cusp = e.boolean("has_cusp");
                 out.has_fold = e.boolean("has_fold");
                 out.has_loop = e.boolean("has_loop");
                 out.length = e.number("length");
                 out.linearized_energy = e.number("linearized_energy");
                 out.min_relative_speed = e.number("min_relative_speed");
                 out.regular = e.boolean("regular");
                 e.done();
               });
  }
  o.done();
  return r;
}

SolverReport read_solver(const json& v, const std::string& path) {
  ObjectReader o(v, path, std::nullopt);
  SolverReport r;
  read_array(o.at("active"), o.path("active"), std::nullopt,
             [&](const json& x, const std::string& p, std::optional<std::size_t> index) {
               r.active.push_back(read_size(x, p, index));
             });
  const json& iterations = o.at("iterations");
  if (!iterations.is_number_integer() || iterations < 0 ||
      iterations > std::numeric_limits<int>::max()) {
    bad_field(o.path("iterations"), "a non-negative integer", iterations, std::nullopt);
  }
  r.iterations = iterations.get<int>();
  r.residual = o.number("residual");
  const json& status = o.at("status");
  const auto expected_status =
      "\"converged\", \"conditioning_limit\", \"iteration_limit\" or \"stalled\"";
  if (!status.is_string()) bad_field(o.path("status"), expected_status, status, std::nullopt);
  try {
    r.status = parse_solver_status(status.get_ref<const std::string&>());
  } catch (const Error&) {
    bad_field(o.path("status"), expected_status, status, std::nullopt);
  }
  r.tolerance = o.number("tolerance");
  o.done();
  return r;
}

}  // namespace

namespace {

/// Reads a fit result as write_json writes it: its long arrays (knots, points, segments,
/// tangents) scanned straight into the result, every other member parsed by nlohmann from its
/// own text and read as from the DOM. Gives up (nullopt) on anything else, the segments' keys
/// in another order included, and on any error of the field readers: read_fit_result then
/// reads the text the old way, so every error keeps its message. A 4·10^4-point result: 0.21 s
/// by the DOM, most of it building and freeing its nodes.
class FastResultReader : JsonScanner {
 public:
  explicit FastResultReader(std::string_view text) : JsonScanner(text) {}

  std::optional<FitResult> read() {
    json rest = json::object();
    std::vector<double> knots;
    std::vector<Vec2> points, tangents;
    std::vector<Segment> segments;
    unsigned seen = 0;  // one bit per long array: each once
    const auto first_time = [&](unsigned bit) { return !(seen & bit) && (seen |= bit); };
    skip_space();
    if (!eat('{')) return std::nullopt;
    for (;;) {
      std::string_view key;
      if (!member_name(key)) return std::nullopt;
      bool ok = true;
      if (key == "knots") {
        ok = first_time(1) && numbers_array(knots);
      } else if (key == "points") {
        ok = first_time(2) && points_array(points);
      } else if (key == "segments") {
        ok = first_time(4) && segments_array(segments);
      } else if (key == "tangents") {
        ok = first_time(8) && points_array(tangents);
      } else {
        ok = other_member(key, rest);
      }
      if (!ok) return std::nullopt;
      skip_space();
      if (eat('}')) break;
      if (!eat(',')) return std::nullopt;
    }
    // Every long array (once: a repeated key is the DOM reader's to judge), nothing after.
    if (seen != 15 || !at_end()) return std::nullopt;
    for (const char* k : {"knots", "points", "segments", "tangents"}) rest[k] = json::array();
    try {
      FitResult r = fit_result_from_json(rest);
      r.knots = std::move(knots);
      r.points = std::move(points);
      r.tangents = std::move(tangents);
      r.spline.segments = std::move(segments);
      return r;
    } catch (const Error&) {
      return std::nullopt;
    }
  }

 private:
  /// [x, ...] into `out`.
  bool numbers_array(std::vector<double>& out) {
    if (!eat('[')) return false;
    skip_space();
    if (eat(']')) return true;
    out.reserve(static_cast<std::size_t>(std::count(t_.begin() + i_, t_.end(), ',')) / 8 + 1);
    for (;;) {
      skip_space();
      double v = 0.0;
      if (!number(v)) return false;
      out.push_back(v);
      skip_space();
      if (eat(']')) return true;
      if (!eat(',')) return false;
    }
  }

  /// "key": as write_json writes it, after a ',' where `comma`.
  bool member_key(std::string_view want, bool comma) {
    skip_space();
    if (comma && !eat(',')) return false;
    std::string_view key;
    return member_name(key) && key == want;
  }

  /// [{"bezier": [4 pairs], "span": N, "t0": x, "t1": y}, ...] into `out`, keys in that order.
  bool segments_array(std::vector<Segment>& out) {
    if (!eat('[')) return false;
    skip_space();
    if (eat(']')) return true;
    for (;;) {
      skip_space();
      if (!eat('{') || !member_key("bezier", false)) return false;
      Segment g;
      if (!control_points(g.bezier.p) || !member_key("span", true) || !size(g.span) ||
          !member_key("t0", true) || !number(g.t0) || !member_key("t1", true) || !number(g.t1)) {
        return false;
      }
      skip_space();
      if (!eat('}')) return false;
      out.push_back(g);
      skip_space();
      if (eat(']')) return true;
      if (!eat(',')) return false;
    }
  }

  /// Exactly four pairs [x, y] in brackets: a piece's control points.
  bool control_points(std::array<Point, 4>& out) {
    if (!eat('[')) return false;
    for (std::size_t k = 0; k < out.size(); ++k) {
      skip_space();
      if (k > 0 && !eat(',')) return false;
      skip_space();
      if (!pair(out[k])) return false;
    }
    skip_space();
    return eat(']');
  }

  /// A non-negative integer (as read_size takes it: no fraction or exponent).
  bool size(std::size_t& v) {
    const char* const first = t_.data() + i_;
    const char* const last = t_.data() + t_.size();
    const auto [end, ec] = std::from_chars(first, last, v);
    if (ec != std::errc() || end == first) return false;
    if (end != last && (*end == '.' || *end == 'e' || *end == 'E')) return false;
    if (*first == '0' && end - first > 1) return false;  // JSON has no leading zeros
    i_ = static_cast<std::size_t>(end - t_.data());
    return true;
  }
};

}  // namespace

FitResult read_fit_result(std::string_view text) {
  if (std::optional<FitResult> fast = FastResultReader(text).read()) return std::move(*fast);
  return detail::read_fit_result_dom(text);
}

FitResult fit_result_from_json(const json& document) {
  ObjectReader o(document, "", std::nullopt);
  FitResult r;
  r.closed = o.boolean("closed");
  read_array(o.at("knots"), "knots", std::nullopt,
             [&](const json& v, const std::string& path, std::optional<std::size_t> index) {
               r.knots.push_back(read_number(v, path, index));
             });
  const json& method = o.at("method");
  if (!method.is_string()) bad_field("method", "a method name string", method, std::nullopt);
  r.method = method.get<std::string>();
  const json& method_report = o.at("method_report");
  if (!method_report.is_object())
    bad_field("method_report", "an object", method_report, std::nullopt);
  r.method_report = method_report;
  if (const auto solver = method_report.find("solver"); solver != method_report.end()) {
    r.solver = read_solver(*solver, "method_report.solver");
    r.method_report.erase("solver");
  }
  const json& options = o.at("options");
  if (!options.is_object()) bad_field("options", "an object", options, std::nullopt);
  r.options = options;
  read_array(o.at("points"), "points", std::nullopt,
             [&](const json& v, const std::string& path, std::optional<std::size_t> index) {
               r.points.push_back(read_pair(v, path, index));
             });
  if (const json* report = o.find("report")) r.report = read_report(*report);
  if (const json* request = o.find("request")) {
    if (!request->is_object()) bad_field("request", "an object", *request, std::nullopt);
    json req = *request;
    if (!req.contains("points")) req["points"] = json::array();  // the result's own points
    ParsedInput p;
    try {
      p = input_from_json(req);
    } catch (const Error& e) {
      throw Error(e.code(), std::string("request.") + e.what(), e.index());
    }
    if (p.method || !p.options.empty() || p.best_effort || p.diagnostics || p.time_limit) {
      bad_field("request", "the fit input alone (method and options are the result's)", *request,
                std::nullopt);
    }
    r.input = std::move(p.input);
    r.accuracy = p.accuracy;
  }
  read_array(o.at("segments"), "segments", std::nullopt,
             [&](const json& v, const std::string& path, std::optional<std::size_t> index) {
               ObjectReader e(v, path, index);
               Segment& s = r.spline.segments.emplace_back();
               const json& bezier = e.at("bezier");
               if (!bezier.is_array() || bezier.size() != 4) {
                 bad_field(e.path("bezier"), "4 control points [x, y]", bezier, index);
               }
               for (std::size_t k = 0; k < 4; ++k) {
                 s.bezier.p[k] = read_pair(bezier[k], indexed(e.path("bezier"), k), index);
               }
               s.span = e.size("span");
               s.t0 = e.number("t0");
               s.t1 = e.number("t1");
               e.done();
             });
  r.spline.closed = r.closed;
  read_array(o.at("tangents"), "tangents", std::nullopt,
             [&](const json& v, const std::string& path, std::optional<std::size_t> index) {
               r.tangents.push_back(read_pair(v, path, index));
             });
  o.done();
  return r;
}

json error_to_json(const Error& error) {
  json body = {{"code", std::string(error_code_name(error.code()))},
               {"message", error.what()},
               {"index", error.index() ? json(*error.index()) : json(nullptr)}};
  // The option that gets past the error, for the client to offer in its own terms.
  if (const auto& hint = error.hint()) {
    body["hint"] = {{"option", hint->name},
                    {"value", hint->value.empty() ? json(nullptr) : json(hint->value)}};
  }
  return {{"error", std::move(body)}};
}

ReportLevel parse_report_level(std::string_view text) {
  return parse_choice(kReportLevels, text, "report level");
}

std::string_view report_level_name(ReportLevel level) {
  return kReportLevels.name(level);
}

PointKind parse_point_kind(std::string_view text) {
  return parse_choice(kPointKinds, text, "point kind");
}

std::string_view point_kind_name(PointKind kind) {
  return kPointKinds.name(kind);
}

SideState parse_side_state(std::string_view text) {
  return parse_choice(kSideStates, text, "side state");
}

std::string_view side_state_name(SideState state) {
  return kSideStates.name(state);
}

std::string_view solver_status_name(SolverStatus status) {
  return kSolverStatuses.name(status);
}

SolverStatus parse_solver_status(std::string_view text) {
  return parse_choice(kSolverStatuses, text, "solver status");
}

std::string summary_table(const FitResult& result) {
  std::vector<std::pair<std::string, std::string>> rows;
  rows.reserve(16);  // (also keeps GCC 12's -Warray-bounds from a false alarm under LTO)
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
    if (r.curvature_variation_energy) {  // the full report's
      rows.emplace_back("curvature-variation energy", opt(r.curvature_variation_energy) + singular);
    }
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
  if (const auto b = result.method_report.find("balls"); b != result.method_report.end()) {
    rows.emplace_back("data balls", std::to_string(b->at("active").size()) + " of " +
                                        b->at("count").dump() + " on their circle (" +
                                        b->at("status").get<std::string>() + ")");
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

namespace fairspline::detail {

nlohmann::json input_to_json_without_points(const FitInput& input, std::optional<double> accuracy) {
  return io::input_members(input, accuracy, false);
}

}  // namespace fairspline::detail
