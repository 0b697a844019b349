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

ChainDerivatives chain_derivatives(const BasicCurveMethod& m, std::span<const Point> p,
                                   std::span<const double> theta, std::span<const double> corner,
                                   bool closed) {
  const std::size_t n = p.size(), spans = closed ? n : (n > 0 ? n - 1 : 0);
  ChainDerivatives d;
  d.g.assign(n, {});
  d.diag.assign(n, {});
  d.off.assign(spans, {});
  for (std::size_t s = 0; s < spans; ++s) {
    const std::size_t i = s, j = s + 1 == n ? 0 : s + 1;
    const Vec2 c = p[j] - p[i];
    const double phi = std::atan2(c.y, c.x);
    const double out = theta[i] + (corner.empty() ? 0.0 : corner[i]);
    const SpanDerivatives sd = span_derivatives(basic_energy(m, out - phi, theta[j] - phi), c);
    d.e += sd.e;
    // c = p_j − p_i: node i sees −∂/∂c, node j +∂/∂c. Local order (θ_i, θ_j, c_x, c_y).
    d.g[i][0] += sd.g[0];
    d.g[j][0] += sd.g[1];
    for (int a = 0; a < 2; ++a) {
      d.g[i][1 + a] -= sd.g[2 + a];
      d.g[j][1 + a] += sd.g[2 + a];
    }
    const auto& h = sd.h;
    Block3& di = d.diag[i];
    Block3& dj = d.diag[j];
    Block3& o = d.off[s];
    di[0][0] += h[0][0];
    dj[0][0] += h[1][1];
    o[0][0] += h[0][1];
    for (int a = 0; a < 2; ++a) {
      di[0][1 + a] -= h[0][2 + a];
      di[1 + a][0] -= h[2 + a][0];
      dj[0][1 + a] += h[1][2 + a];
      dj[1 + a][0] += h[2 + a][1];
      o[0][1 + a] += h[0][2 + a];  // (θ_i, p_j)
      o[1 + a][0] -= h[2 + a][1];  // (p_i, θ_j)
      for (int b = 0; b < 2; ++b) {
        di[1 + a][1 + b] += h[2 + a][2 + b];
        dj[1 + a][1 + b] += h[2 + a][2 + b];
        o[1 + a][1 + b] -= h[2 + a][2 + b];  // (p_i, p_j)
      }
    }
  }
  return d;
}

}  // namespace fairspline::detail
