// `--fields` of `fairspline fit` and `batch`: which members of a fit's JSON text to keep.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "fairspline/fit.hpp"
#include "fairspline/io/json.hpp"

namespace fairspline::cli {

/// A record's text (a batch's, or the scratch of a cut one) keeps its memory for the next
/// record unless it grew past this.
inline constexpr std::size_t kKeepTextCapacity = std::size_t{1} << 20;

/// What a fit record keeps (--fields): the members named, each whole or, for an object, with
/// only some of its members ("report.length"). Empty: the whole record.
struct FieldSelection {
  struct Member {
    bool whole = false;
    std::set<std::string, std::less<>> keys;  ///< when not whole: the object's members kept
  };
  std::map<std::string, Member, std::less<>> members;
  bool empty() const { return members.empty(); }
  /// Every member kept whole: the writer's filter alone writes the selection, no cut needed.
  bool whole_members() const {
    for (const auto& [key, m] : members) {
      if (!m.whole) return false;
    }
    return true;
  }
};

/// Parses a --fields list (comma-separated; "report.NAME" and the like for one member of an
/// object). Throws Error(kInvalidArgument) naming an unknown field, or the report with
/// ReportLevel::kNone. "method" is always kept, and "line" for a batch's records (`line`).
FieldSelection parse_fields(const std::optional<std::string>& fields, ReportLevel level,
                            bool line = true);

/// The writer's filter for a selection: the top-level members kept whole or in part (none, so
/// every member, for an empty selection). It refers to `selection`, which must outlive it.
io::MemberFilter member_filter(const FieldSelection& selection);

/// Appends the members of `record` (one compact object) that `selection` keeps, in the
/// record's order.
void append_selected(std::string& out, std::string_view record, const FieldSelection& selection);

/// The compact text of `r` cut down to `selection` (whole when it is empty), appended to `out`;
/// `extra` as io::write_json's. The members not kept are not written at all.
void append_fit_text(std::string& out, const FitResult& r, const FieldSelection& selection,
                     const nlohmann::json& extra = nullptr);

}  // namespace fairspline::cli
