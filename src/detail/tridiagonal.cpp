#include "detail/tridiagonal.hpp"

#include <cmath>

namespace fairspline::detail {

bool solve_tridiagonal(std::span<const double> sub, std::span<const double> diag,
                       std::span<const double> super, std::span<Vec2> rhs,
                       std::vector<double>& scratch) {
  const std::size_t n = diag.size();
  if (n == 0) return true;
  scratch.resize(n);
  double pivot = diag[0];
  if (!(std::abs(pivot) > 0.0) || !std::isfinite(pivot)) return false;
  scratch[0] = (n > 1 ? super[0] : 0.0) / pivot;
  rhs[0] = rhs[0] / pivot;
  for (std::size_t i = 1; i < n; ++i) {
    pivot = diag[i] - sub[i] * scratch[i - 1];
    if (!(std::abs(pivot) > 0.0) || !std::isfinite(pivot)) return false;
    const double inv = 1.0 / pivot;
    scratch[i] = (i + 1 < n ? super[i] : 0.0) * inv;
    rhs[i] = (rhs[i] - sub[i] * rhs[i - 1]) * inv;
  }
  for (std::size_t i = n - 1; i-- > 0;) rhs[i] -= scratch[i] * rhs[i + 1];
  return true;
}

bool solve_cyclic_symmetric(std::span<const double> off, std::span<const double> diag,
                            std::span<Vec2> rhs) {
  const std::size_t n = diag.size();
  // A = T + u v^T with u = (gamma, 0, ..., 0, corner), v = (1, 0, ..., 0, corner / gamma),
  // where corner = off[n-1] couples x[n-1] and x[0].
  const double corner = off[n - 1];
  const double gamma = -diag[0];
  std::vector<double> sub(n), sup(n), d(diag.begin(), diag.end());
  for (std::size_t i = 0; i < n; ++i) {
    sub[i] = i > 0 ? off[i - 1] : 0.0;
    sup[i] = i + 1 < n ? off[i] : 0.0;
  }
  d[0] -= gamma;
  d[n - 1] -= corner * corner / gamma;
  std::vector<double> scratch;
  if (!solve_tridiagonal(sub, d, sup, rhs, scratch)) return false;
  // z solves T z = u (scalar right-hand side, solved as Vec2 with y = 0).
  std::vector<Vec2> z(n, Vec2{0.0, 0.0});
  z[0].x = gamma;
  z[n - 1].x = corner;
  if (!solve_tridiagonal(sub, d, sup, z, scratch)) return false;
  const double denom = 1.0 + z[0].x + corner * z[n - 1].x / gamma;
  if (!(std::abs(denom) > 0.0) || !std::isfinite(denom)) return false;
  const Vec2 num = rhs[0] + (corner / gamma) * rhs[n - 1];
  const Vec2 factor = num / denom;
  for (std::size_t i = 0; i < n; ++i) {
    rhs[i].x -= factor.x * z[i].x;
    rhs[i].y -= factor.y * z[i].x;
  }
  return true;
}

}  // namespace fairspline::detail
