#include "detail/ball_energy.hpp"

#include <cmath>
#include <cstddef>

namespace fairspline::detail {

SpanDerivatives span_derivatives(const BasicEnergy& e1, Vec2 c) {
  // With t = c/L, n = t turned by +90°: ∂φ/∂c = n/L, ∂L/∂c = t, ∂t/∂c = n nᵀ/L,
  // ∂n/∂c = −t nᵀ/L; α and β both move by −n/L.
  const double len = std::hypot(c.x, c.y);
  const Vec2 t = c / len, n{-t.y, t.x};
  const double l1 = 1.0 / len, l2 = l1 * l1, l3 = l2 * l1;
  const double s = e1.ea + e1.eb;                   // ∂e/∂α + ∂e/∂β
  const double q = e1.eaa + 2.0 * e1.eab + e1.ebb;  // the same, second order
  SpanDerivatives d;
  d.e = e1.e * l1;
  d.g[0] = e1.ea * l1;
  d.g[1] = e1.eb * l1;
  // ∂E/∂c = −(s n + e t)/L².
  d.g[2] = -(s * n.x + e1.e * t.x) * l2;
  d.g[3] = -(s * n.y + e1.e * t.y) * l2;
  d.h[0][0] = e1.eaa * l1;
  d.h[0][1] = e1.eab * l1;
  d.h[1][1] = e1.ebb * l1;
  // ∂²E/∂θ_i∂c = −((e_aa + e_ab) n + e_a t)/L², likewise for θ_j.
  const double ai = e1.eaa + e1.eab, aj = e1.eab + e1.ebb;
  d.h[0][2] = -(ai * n.x + e1.ea * t.x) * l2;
  d.h[0][3] = -(ai * n.y + e1.ea * t.y) * l2;
  d.h[1][2] = -(aj * n.x + e1.eb * t.x) * l2;
  d.h[1][3] = -(aj * n.y + e1.eb * t.y) * l2;
  // ∂²E/∂c² = ((q − e) n nᵀ + 2s (t nᵀ + n tᵀ) + 2e t tᵀ)/L³.
  const double nn = q - e1.e, tn = 2.0 * s, tt = 2.0 * e1.e;
  d.h[2][2] = (nn * n.x * n.x + tn * 2.0 * t.x * n.x + tt * t.x * t.x) * l3;
  d.h[2][3] = (nn * n.x * n.y + tn * (t.x * n.y + n.x * t.y) + tt * t.x * t.y) * l3;
  d.h[3][3] = (nn * n.y * n.y + tn * 2.0 * t.y * n.y + tt * t.y * t.y) * l3;
  for (int r = 0; r < 4; ++r) {
    for (int col = 0; col < r; ++col) d.h[r][col] = d.h[col][r];
  }
  return d;
}

}  // namespace fairspline::detail
