// The list of built-in methods (private). Each method file contributes a function returning
// its MethodInfo entries; registry.cpp calls builtin_methods() once. An explicit list (rather
// than static self-registration) survives static linking, where unreferenced objects drop out.
#pragma once

#include <vector>

#include "fairspline/registry.hpp"

namespace fairspline::detail {

std::vector<MethodInfo> li_methods();
std::vector<MethodInfo> jaklic_zagar_methods();
std::vector<MethodInfo> yong_cheng_methods();
std::vector<MethodInfo> kozak_krajnc_methods();
std::vector<MethodInfo> min_energy_methods();
std::vector<MethodInfo> elastic_methods();

std::vector<MethodInfo> builtin_methods();

}  // namespace fairspline::detail
