// Registry options shared by the methods built on fit_min_energy (min-energy.cpp, elastic.cpp).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "fairspline/methods/min_energy.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::detail {

/// The option "search" (MinEnergySearch), its parser and its name for method_report.
OptionSpec min_energy_search_option();
MinEnergySearch parse_min_energy_search(const nlohmann::json& options);
std::string min_energy_search_name(MinEnergySearch search);

/// The option "max_iterations": unset (null), the limit depends on the input.
inline constexpr const char* kMaxIterationsDoc =
    "Newton iteration limit (an error if reached); default 200 up to 1000 points, "
    "200 (log10 n - 2) beyond; for the elastic spline 400 (log10 n - 2) from 316 points; with "
    "data balls at least 4000000 / n, within 1000 to 4000";

/// MinEnergyOptions::max_iterations when it is unset, for n points of a fit with this basis.
int default_iteration_limit(std::size_t n, bool data_balls, MinEnergyBasis basis);

/// The iteration limit of a fit with these options (MinEnergyOptions::max_iterations).
inline int iteration_limit(const MinEnergyOptions& options) {
  return options.max_iterations.value_or(MinEnergyOptions::kDefaultIterations);
}

/// The scale-dependent numbers of the framework's method_report (E_L = E_1/L).
std::vector<ReportUnit> min_energy_report_units();

}  // namespace fairspline::detail
