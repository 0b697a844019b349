// `--fields`: the members of a fit's JSON text that `fairspline fit` and `batch` keep.
#include "fields.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <iterator>

#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"

namespace fairspline::cli {

namespace {

using nlohmann::json;

/// Objects whose members depend on the method or on the request: any name is taken in them.
constexpr std::string_view kOpenObjects[] = {"method_report", "options", "request"};

std::string joined(const std::set<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

/// One past the end of the JSON value starting at text[i]. The text is the writer's compact
/// JSON (no white space between tokens), so matching the brackets outside strings is all the
/// parsing it needs; the kept members are copied as they were written, byte for byte.
std::size_t value_end(std::string_view t, std::size_t i) {
  // Which characters matter: 1 a bracket or brace, 2 a quote, 3 a comma (a scalar's end).
  static constexpr auto kClass = [] {
    std::array<unsigned char, 256> c{};
    for (const char b : {'{', '[', '}', ']'}) c[static_cast<unsigned char>(b)] = 1;
    c['"'] = 2;
    c[','] = 3;
    return c;
  }();
  std::size_t depth = 0;
  for (; i < t.size(); ++i) {
    const char c = t[i];
    const unsigned char k = kClass[static_cast<unsigned char>(c)];
    if (k == 0) continue;  // the digits that make most of a record
    if (k == 2) {
      for (++i; i < t.size() && t[i] != '"'; ++i) {
        if (t[i] == '\\') ++i;
      }
      if (depth == 0) return i + 1;
    } else if (k == 3) {
      if (depth == 0) return i;
    } else if (c == '{' || c == '[') {
      ++depth;
    } else {
      if (depth == 0) return i;  // a number or literal ending its container
      if (--depth == 0) return i + 1;
    }
  }
  return i;
}

/// Calls f(key, value) for each member of a compact JSON object (its text, braces included);
/// key is the text between the quotes.
template <class F>
void for_each_member(std::string_view object, F f) {
  for (std::size_t i = 1; i < object.size() && object[i] == '"';) {
    const std::size_t key_end = value_end(object, i);  // past the closing quote, at ':'
    const std::size_t end = value_end(object, key_end + 1);
    f(object.substr(i + 1, key_end - i - 2), object.substr(key_end + 1, end - key_end - 1));
    i = end + 1;  // past ',' (or '}')
  }
}

void append_member(std::string& out, bool& first, std::string_view key, std::string_view value) {
  if (!first) out += ',';
  first = false;
  out += '"';
  out += key;
  out += "\":";
  out += value;
}

}  // namespace

/// Parses --fields. The record's keys and the report's are read off the writer (a result with a
/// full report), so that the names accepted are always those written. "line" and "method" are
/// always kept: with several -m they are what tells the records of one line apart.
FieldSelection parse_fields(const std::optional<std::string>& fields, ReportLevel level,
                            bool line) {
  FieldSelection selection;
  if (!fields) return selection;
  const std::string_view list = *fields;
  FitResult sample;
  sample.report.emplace();
  sample.report->curvature_variation_energy = 0.0;  // the full report's members
  const json record = io::to_json(sample);
  std::set<std::string> keys, report_keys;
  if (line) keys.insert("line");
  for (auto it = record.begin(); it != record.end(); ++it) keys.insert(it.key());
  for (auto it = record["report"].begin(); it != record["report"].end(); ++it) {
    report_keys.insert(it.key());
  }
  const auto is_open = [](std::string_view head) {
    return std::find(std::begin(kOpenObjects), std::end(kOpenObjects), head) !=
           std::end(kOpenObjects);
  };
  const auto unknown = [&](std::string_view name) {
    return Error(ErrorCode::kInvalidArgument,
                 "--fields: unknown field '" + std::string(name) + "'; the fields are " +
                     joined(keys) + "; report.NAME for NAME one of " + joined(report_keys) +
                     "; and method_report.NAME, options.NAME, request.NAME for any member");
  };
  for (std::size_t begin = 0; begin <= list.size();) {
    std::size_t end = list.find(',', begin);
    if (end == std::string_view::npos) end = list.size();
    std::string_view name = list.substr(begin, end - begin);
    begin = end + 1;
    while (!name.empty() && name.front() == ' ') name.remove_prefix(1);
    while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
    const std::size_t dot = name.find('.');
    const std::string_view head = name.substr(0, dot);
    if (!keys.contains(std::string(head))) throw unknown(name);
    FieldSelection::Member& member = selection.members[std::string(head)];
    if (dot == std::string_view::npos) {
      member.whole = true;
      continue;
    }
    const std::string_view sub = name.substr(dot + 1);
    // One level into an object; the report's members are known, the others' are not.
    const bool known_sub =
        head == "report" ? report_keys.contains(std::string(sub))
                         : is_open(head) && !sub.empty() && sub.find('.') == std::string_view::npos;
    if (!known_sub) throw unknown(name);
    member.keys.emplace(sub);
  }
  if (level == ReportLevel::kNone && selection.members.contains("report")) {
    throw Error(ErrorCode::kInvalidArgument,
                "--fields names the report, but --report none writes none; give --report basic "
                "or full");
  }
  if (line) selection.members["line"].whole = true;
  selection.members["method"].whole = true;
  return selection;
}

io::MemberFilter member_filter(const FieldSelection& selection) {
  if (selection.empty()) return {};
  return [&selection](std::string_view key) { return selection.members.contains(key); };
}

/// Appends the members of `record` (one compact object) that `selection` keeps, in the
/// record's order.
void append_selected(std::string& out, std::string_view record, const FieldSelection& selection) {
  out += '{';
  bool first = true;
  for_each_member(record, [&](std::string_view key, std::string_view value) {
    const auto it = selection.members.find(key);
    if (it == selection.members.end()) return;
    const FieldSelection::Member& member = it->second;
    if (member.whole || value.empty() || value.front() != '{') {  // a non-object stays whole
      append_member(out, first, key, value);
      return;
    }
    std::string inner = "{";
    bool inner_first = true;
    for_each_member(value, [&](std::string_view k, std::string_view v) {
      if (member.keys.contains(k)) append_member(inner, inner_first, k, v);
    });
    inner += '}';
    append_member(out, first, key, inner);
  });
  out += '}';
}

void append_fit_text(std::string& out, const FitResult& r, const FieldSelection& selection,
                     const json& extra) {
  if (selection.empty()) {
    io::write_json(r, out, -1, extra);
    return;
  }
  if (selection.whole_members()) {
    io::write_json(r, out, -1, extra, member_filter(selection));
    return;
  }
  // The members not kept are not written at all; those kept in part are cut from theirs.
  thread_local std::string whole;
  whole.clear();
  io::write_json(r, whole, -1, extra, member_filter(selection));
  append_selected(out, whole, selection);
  if (whole.capacity() > kKeepTextCapacity) std::string().swap(whole);  // after a huge one
}

}  // namespace fairspline::cli
