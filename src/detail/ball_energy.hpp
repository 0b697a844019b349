// One span's energy E_1(α, β)/L with the chord as an unknown too: the derivatives that data
// balls (issue 19: points that may move inside a disc) need, for every basis.
// Derivation and checks: docs/methods/min-energy.md, "Data balls: the span's derivatives".
#pragma once

#include <array>

#include "fairspline/methods/min_energy.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline::detail {

/// E = E_1(θ_i − φ, θ_j − φ) / L for the chord c = p_j − p_i (φ its angle, L its length) and
/// absolute directions θ_i, θ_j. Unknowns in the order (θ_i, θ_j, c_x, c_y); the end points
/// enter through c only (∂/∂p_j = ∂/∂c, ∂/∂p_i = −∂/∂c).
struct SpanDerivatives {
  double e = 0.0;
  std::array<double, 4> g{};                 ///< gradient
  std::array<std::array<double, 4>, 4> h{};  ///< Hessian (symmetric)
};

/// From E_1 and its derivatives at (α, β) = (θ_i − φ, θ_j − φ) and the chord c (non-zero).
SpanDerivatives span_derivatives(const BasicEnergy& e1, Vec2 c);

}  // namespace fairspline::detail
