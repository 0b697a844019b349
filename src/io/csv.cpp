#include "fairspline/io/csv.hpp"
#include "fairspline/io/file.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>

#include "fairspline/error.hpp"

namespace fairspline::io {

namespace {

constexpr std::string_view kSpace = " \t\r\v\f";

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(kSpace);
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(kSpace);
  return s.substr(b, e - b + 1);
}

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

/// For text that std::from_chars reports out of range: true when its magnitude is huge
/// (overflow), false when tiny (underflow). `s` has no sign and is a valid decimal number.
bool overflows(std::string_view s) {
  long long exp10 = 0;
  const auto e = s.find_first_of("eE");
  if (e != std::string_view::npos) {
    std::string_view ex = s.substr(e + 1);
    bool neg = false;
    if (!ex.empty() && (ex[0] == '+' || ex[0] == '-')) {
      neg = ex[0] == '-';
      ex.remove_prefix(1);
    }
    for (char c : ex) {
      if (!is_digit(c)) break;
      if (exp10 < 1'000'000'000) exp10 = exp10 * 10 + (c - '0');
    }
    if (neg) exp10 = -exp10;
    s = s.substr(0, e);
  }
  // Decimal exponent of the leading significant digit.
  const auto dot = s.find('.');
  const std::string_view int_part = s.substr(0, dot);
  const auto first = int_part.find_first_not_of('0');
  long long lead = 0;
  if (first != std::string_view::npos) {
    lead = static_cast<long long>(int_part.size() - first) - 1;
  } else if (dot != std::string_view::npos) {
    const std::string_view frac = s.substr(dot + 1);
    const auto nz = frac.find_first_not_of('0');
    lead = nz == std::string_view::npos ? 0 : -static_cast<long long>(nz) - 1;
  }
  return lead + exp10 > 0;
}

/// 'text' for messages: at most 60 characters, bytes outside printable ASCII as \xNN.
std::string quoted(std::string_view s) {
  constexpr std::size_t kMax = 60;
  std::string out = "'";
  for (std::size_t i = 0; i < s.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (s.size() > kMax) out += "...";
  out += "'";
  return out;
}

/// A header line: exactly two fields of printable text, neither of them a number.
bool is_header(const std::vector<std::string_view>& fields) {
  if (fields.size() != 2) return false;
  for (std::string_view f : fields) {
    if (f.empty()) return false;
    for (char c : f) {
      const auto u = static_cast<unsigned char>(c);
      if (u < 0x20 || u == 0x7f) return false;
    }
  }
  return true;
}

std::string line_prefix(std::size_t line) {
  return "line " + std::to_string(line) + ": ";
}

/// Splits a content line into fields: by ',' if present, else ';', else whitespace.
std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  char sep = 0;
  if (line.find(',') != std::string_view::npos) {
    sep = ',';
  } else if (line.find(';') != std::string_view::npos) {
    sep = ';';
  }
  if (sep) {
    std::size_t start = 0;
    while (true) {
      const auto pos = line.find(sep, start);
      fields.push_back(trim(line.substr(start, pos - start)));
      if (pos == std::string_view::npos) break;
      start = pos + 1;
    }
  } else {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && kSpace.find(line[i]) != std::string_view::npos) ++i;
      const std::size_t b = i;
      while (i < line.size() && kSpace.find(line[i]) == std::string_view::npos) ++i;
      if (i > b) fields.push_back(line.substr(b, i - b));
    }
  }
  return fields;
}

}  // namespace

bool parse_number(std::string_view text, double& value, std::string_view what,
                  std::optional<std::size_t> index) {
  std::string_view s = trim(text);
  if (s.empty()) return false;
  std::string_view body = s;
  bool negative = false;
  if (body[0] == '+' || body[0] == '-') {
    negative = body[0] == '-';
    body.remove_prefix(1);
  }
  // from_chars would accept a '-' itself but not '+'; it also accepts "0x" only as "0".
  if (body.empty() || body[0] == '+' || body[0] == '-') return false;
  double v = 0.0;
  const auto r = std::from_chars(body.data(), body.data() + body.size(), v);
  if (r.ptr != body.data() + body.size()) return false;
  if (r.ec == std::errc::result_out_of_range) {
    if (overflows(body)) {
      throw Error(ErrorCode::kNonFinite,
                  std::string(what) + " " + quoted(s) + " is too large for double precision",
                  index);
    }
    v = 0.0;  // underflow: the nearest double
  } else if (r.ec != std::errc()) {
    return false;
  }
  if (!std::isfinite(v)) {
    throw Error(ErrorCode::kNonFinite, std::string(what) + " " + quoted(s) + " is not finite",
                index);
  }
  value = negative ? -v : v;
  return true;
}

std::string format_double(double value) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  return std::string(buf.data(), r.ptr);
}

std::vector<Point> parse_csv_points(std::string_view text) {
  std::vector<Point> points;
  bool seen_content = false;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  // Skip a UTF-8 byte order mark.
  if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;
  while (pos <= text.size()) {
    // Lines end with "\n", "\r\n" or a lone "\r".
    const auto nl = text.find_first_of("\r\n", pos);
    std::string_view raw =
        text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    if (nl == std::string_view::npos) {
      pos = text.size() + 1;
    } else {
      pos = nl + 1;
      if (text[nl] == '\r' && pos < text.size() && text[pos] == '\n') ++pos;
    }
    ++line_no;
    std::string_view line = raw;
    const auto hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    const std::string prefix = line_prefix(line_no);
    const std::vector<std::string_view> fields = split_fields(line);
    double xy[2] = {0.0, 0.0};
    bool ok = fields.size() == 2;
    bool any_number = false;
    for (std::size_t k = 0; k < fields.size(); ++k) {
      double v = 0.0;
      // A non-finite coordinate names the point (index = its 0-based number, as everywhere
      // else a point is at fault) and the line.
      const bool is_num = parse_number(fields[k], v,
                                       "line " + std::to_string(line_no) + " (point " +
                                           std::to_string(points.size()) + "): coordinate",
                                       points.size());
      any_number = any_number || is_num;
      if (k < 2) xy[k] = v;
      ok = ok && is_num;
    }
    if (!seen_content) {
      seen_content = true;
      if (!any_number && is_header(fields)) continue;
    }
    if (!ok) {
      throw Error(ErrorCode::kParseError,
                  prefix + "expected two numbers 'x,y', got " + quoted(trim(raw)), line_no);
    }
    points.push_back({xy[0], xy[1]});
  }
  return points;
}

std::vector<Point> read_csv_points(const std::filesystem::path& path) {
  return parse_csv_points(read_file(path).view());
}

std::string write_csv(const FitResult& result) {
  std::string out = "x0,y0,x1,y1,x2,y2,x3,y3\n";
  for (const Segment& s : result.spline.segments) {
    for (std::size_t k = 0; k < 4; ++k) {
      out += format_double(s.bezier.p[k].x);
      out += ',';
      out += format_double(s.bezier.p[k].y);
      out += k == 3 ? '\n' : ',';
    }
  }
  return out;
}

}  // namespace fairspline::io
