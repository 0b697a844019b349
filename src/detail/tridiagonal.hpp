// O(n) solvers for tridiagonal and cyclic tridiagonal systems with Vec2 right-hand sides.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "fairspline/vec2.hpp"

namespace fairspline::detail {

/// Solves the tridiagonal system sub[i] x[i-1] + diag[i] x[i] + super[i] x[i+1] = rhs[i]
/// (sub[0] and super[n-1] unused) in place: rhs becomes x. `scratch` is resized to n.
/// Thomas algorithm without pivoting: the caller guarantees no zero pivot (e.g. diagonal
/// dominance, or a symmetric positive definite matrix). Returns false on a zero/non-finite pivot.
bool solve_tridiagonal(std::span<const double> sub, std::span<const double> diag,
                       std::span<const double> super, std::span<Vec2> rhs,
                       std::vector<double>& scratch);

/// Solves the symmetric cyclic tridiagonal system
///   off[i-1] x[i-1] + diag[i] x[i] + off[i] x[i+1] = rhs[i]   (indices mod n, n >= 3)
/// where off[i] couples x[i] and x[i+1 mod n], by Sherman–Morrison on top of the Thomas
/// algorithm. In place; returns false when the system is numerically singular.
bool solve_cyclic_symmetric(std::span<const double> off, std::span<const double> diag,
                            std::span<Vec2> rhs);

}  // namespace fairspline::detail
