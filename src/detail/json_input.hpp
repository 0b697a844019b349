// The request reader that builds the whole document first (private; for tests): what
// io::parse_json_input gives for every text, by its fast reader or by this one; and the
// request's members without its points, for the writer.
#pragma once

#include <optional>
#include <string_view>

#include "fairspline/io/json.hpp"

namespace fairspline::detail {

/// parse_json_input through nlohmann's DOM only (no fast reader).
io::ParsedInput parse_json_input_dom(std::string_view text);

/// io::input_to_json without "points" (the writer streams them: a document of 2·10^5 pairs
/// cost ~20 MB and a third of writing a fit).
nlohmann::json input_to_json_without_points(const FitInput& input, std::optional<double> accuracy);

}  // namespace fairspline::detail
