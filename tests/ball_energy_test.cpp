// A span's energy with its chord as an unknown (src/detail/ball_energy.cpp): derivatives
// against finite differences of E_1(θ_i − φ, θ_j − φ)/L for every basis, and the exact
// identities of rotation and scaling.
#include "detail/ball_energy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace fairspline {
namespace {

constexpr double kPi = std::numbers::pi;

/// E at unknowns z = (θ_i, θ_j, c_x, c_y), from scratch.
double energy_at(const BasicCurveMethod& m, const std::array<double, 4>& z) {
  const double phi = std::atan2(z[3], z[2]), len = std::hypot(z[2], z[3]);
  return basic_energy(m, z[0] - phi, z[1] - phi).e / len;
}

detail::SpanDerivatives derivatives_at(const BasicCurveMethod& m, const std::array<double, 4>& z) {
  const double phi = std::atan2(z[3], z[2]);
  return detail::span_derivatives(basic_energy(m, z[0] - phi, z[1] - phi), {z[2], z[3]});
}

std::vector<BasicCurveMethod> every_basis() {
  return {{MinEnergyBasis::kCondG2, 1.0, kPi / 2},
          {MinEnergyBasis::kCondG2, 1.8, kPi / 2},
          {MinEnergyBasis::kJaklicZagar, 1.0, 0.45 * kPi},
          {MinEnergyBasis::kYongCheng, 1.0, 0.35 * kPi},
          {MinEnergyBasis::kRestrictedElastic, 1.0, kPi / 2},
          {MinEnergyBasis::kElastic, 1.0, kPi}};
}

TEST(SpanDerivatives, MatchFiniteDifferencesForEveryBasis) {
  std::mt19937_64 rng(19);
  for (const BasicCurveMethod& m : every_basis()) {
    SCOPED_TRACE(static_cast<int>(m.basis));
    // Angles well inside the basis' box (and |α − β| < 180° for elastic).
    std::uniform_real_distribution<double> angle(-0.6 * m.omega, 0.6 * m.omega);
    std::uniform_real_distribution<double> coord(-3.0, 3.0), turn(-kPi, kPi);
    for (int trial = 0; trial < 40; ++trial) {
      const Vec2 c{coord(rng), coord(rng)};
      if (std::hypot(c.x, c.y) < 0.3) continue;
      const double phi = std::atan2(c.y, c.x);
      const std::array<double, 4> z = {phi + angle(rng), phi + angle(rng), c.x, c.y};
      if (std::abs(z[0] - z[1]) > 0.9 * kPi) continue;  // elastic: |α − β| < 180°
      SCOPED_TRACE(testing::Message() << "alpha " << z[0] - phi << " beta " << z[1] - phi << " c "
                                      << c.x << ", " << c.y);
      const detail::SpanDerivatives d = derivatives_at(m, z);
      EXPECT_NEAR(d.e, energy_at(m, z), 1e-13 * std::abs(d.e) + 1e-15);
      const double h = 1e-5;
      for (int k = 0; k < 4; ++k) {
        std::array<double, 4> zp = z, zm = z;
        zp[k] += h;
        zm[k] -= h;
        // Gradient: central differences of the energy; Hessian: of the analytic gradient.
        const double fd = (energy_at(m, zp) - energy_at(m, zm)) / (2 * h);
        EXPECT_NEAR(d.g[k], fd, 1e-7 * (1.0 + std::abs(fd))) << "k " << k;
        const detail::SpanDerivatives dp = derivatives_at(m, zp), dm = derivatives_at(m, zm);
        for (int l = 0; l < 4; ++l) {
          const double hd = (dp.g[l] - dm.g[l]) / (2 * h);
          EXPECT_NEAR(d.h[l][k], hd, 1e-6 * (1.0 + std::abs(hd))) << "l " << l << " k " << k;
          EXPECT_EQ(d.h[l][k], d.h[k][l]);
        }
      }
    }
  }
}

TEST(SpanDerivatives, RotationAndScalingIdentities) {
  // E(θ_i + ω, θ_j + ω, R(ω) c) = E: g_θi + g_θj + g_c · (J c) = 0. E(θ, s c) = E / s:
  // g_c · c = −E, and differentiating both once more, H_cc c = −2 g_c and H_θc c = −g_θ.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const BasicCurveMethod& m : every_basis()) {
    for (int trial = 0; trial < 20; ++trial) {
      const Vec2 c{2.0 + u(rng), u(rng)};
      const double phi = std::atan2(c.y, c.x);
      const std::array<double, 4> z = {phi + 0.5 * m.omega * u(rng), phi + 0.5 * m.omega * u(rng),
                                       c.x, c.y};
      const detail::SpanDerivatives d = derivatives_at(m, z);
      const double scale = std::abs(d.g[0]) + std::abs(d.g[1]) + std::abs(d.e) + 1.0;
      EXPECT_NEAR(d.g[0] + d.g[1] + d.g[2] * -c.y + d.g[3] * c.x, 0.0, 1e-13 * scale);
      EXPECT_NEAR(d.g[2] * c.x + d.g[3] * c.y, -d.e, 1e-13 * scale);
      for (int r = 0; r < 4; ++r) {
        const double hc = d.h[r][2] * c.x + d.h[r][3] * c.y;
        const double want = r < 2 ? -d.g[r] : -2.0 * d.g[r];
        EXPECT_NEAR(hc, want, 1e-12 * (scale + std::abs(d.h[r][r]))) << "row " << r;
      }
    }
  }
}

TEST(SpanDerivatives, ConstantEnergyIsOneOverLength) {
  // E_1 = 1 with no slope: E = 1/L, whose Hessian is (3 t tᵀ − I)/L³.
  const BasicEnergy flat{.e = 1.0};
  const Vec2 c{3.0, -4.0};
  const detail::SpanDerivatives d = detail::span_derivatives(flat, c);
  const double len = 5.0, t[2] = {0.6, -0.8};
  EXPECT_DOUBLE_EQ(d.e, 0.2);
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(d.g[2 + a], -t[a] / (len * len), 1e-16);
    for (int b = 0; b < 2; ++b) {
      EXPECT_NEAR(d.h[2 + a][2 + b], (3.0 * t[a] * t[b] - (a == b ? 1.0 : 0.0)) / 125.0, 1e-16);
    }
  }
}

}  // namespace
}  // namespace fairspline
