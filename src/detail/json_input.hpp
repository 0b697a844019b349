// The request and result readers that build the whole document first (private; for tests):
// what io::parse_json_input and io::read_fit_result give for every text, by their fast readers
// or by these; and the request's members without its points, for the writer.
#pragma once

#include <optional>
#include <string_view>

#include "fairspline/io/json.hpp"

namespace fairspline::detail {

/// parse_json_input through nlohmann's DOM only (no fast reader).
io::ParsedInput parse_json_input_dom(std::string_view text);

/// read_fit_result through nlohmann's DOM only (no fast reader).
FitResult read_fit_result_dom(std::string_view text);

/// io::input_to_json without "points" (the writer streams them: a document of 2·10^5 pairs
/// cost ~20 MB and a third of writing a fit).
nlohmann::json input_to_json_without_points(const FitInput& input, std::optional<double> accuracy);

}  // namespace fairspline::detail
