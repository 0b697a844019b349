// Umbrella header: everything public in fairspline.
#pragma once

#include "fairspline/cubic_bezier.hpp"
#include "fairspline/diagnostics.hpp"
#include "fairspline/energy.hpp"
#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/io/csv.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/io/svg.hpp"
#include "fairspline/methods/jaklic_zagar.hpp"
#include "fairspline/methods/li.hpp"
#include "fairspline/methods/yong_cheng.hpp"
#include "fairspline/parameterization.hpp"
#include "fairspline/registry.hpp"
#include "fairspline/spline.hpp"
#include "fairspline/vec2.hpp"
