// The request reader that builds the whole document first (private; for tests): what
// io::parse_json_input gives for every text, by its fast reader or by this one.
#pragma once

#include <string_view>

#include "fairspline/io/json.hpp"

namespace fairspline::detail {

/// parse_json_input through nlohmann's DOM only (no fast reader).
io::ParsedInput parse_json_input_dom(std::string_view text);

}  // namespace fairspline::detail
