// Requests a method accepts, derived from its declared capabilities (tests and benchmarks that
// run every registered method on the same data; no method names here).
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "fairspline/fit.hpp"
#include "fairspline/registry.hpp"

namespace fairspline::testing {

/// The method that supplies missing directions to Hermite methods in these requests.
inline constexpr const char* kDirectionSupplier = "jaklic-zagar";

/// Options that let the method take any point set: a Hermite method's missing directions from
/// kDirectionSupplier (the registry's tangents_from); a point-count rule relaxed by its option.
inline nlohmann::json options_for_any_points(const MethodInfo& m) {
  const Capabilities& k = m.capabilities;
  nlohmann::json o = nlohmann::json::object();
  if (k.tangents == TangentUse::kRequired) o[std::string(kTangentsFromOption)] = kDirectionSupplier;
  if (k.points.step > 1 && !k.points.relaxed_by.empty()) {
    o[std::string(k.points.relaxed_by)] = k.points.relaxed_value;
  }
  return o;
}

/// The largest count <= n that the method's point-count rule accepts without relaxing it.
inline std::size_t accepted_count(const MethodInfo& m, std::size_t n) {
  const std::size_t step = m.capabilities.points.step;
  return step > 1 && n > 0 ? n - (n - 1) % step : n;
}

/// A method unique only with a clamped tangent gets point 0 clamped along its chord, as a C1
/// derivative (|ΔP|^(1-α) long).
inline void clamp_if_needed(const MethodInfo& m, FitInput& in) {
  if (!m.capabilities.needs_clamped_tangent || in.points.size() < 2) return;
  const Vec2 d = in.points[1] - in.points[0];
  const double len = norm(d);
  in.kinds.assign(in.points.size(), PointKind::kSmooth);
  in.tangents.assign(in.points.size(), std::nullopt);
  in.kinds[0] = PointKind::kClamped;
  in.tangents[0] = (d / len) * std::pow(len, 1.0 - in.alpha);
}

}  // namespace fairspline::testing
