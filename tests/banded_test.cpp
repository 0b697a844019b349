// The bordered band Cholesky of the data-ball optimizer (src/detail/banded.cpp) against dense
// Gaussian elimination on the same matrices.
#include "detail/banded.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "test_util.hpp"

namespace fairspline::detail {
namespace {

using testing::dense_solve;

struct Problem {
  std::vector<std::vector<double>> a;
  BorderedBand band;
};

// A random symmetric positive definite matrix: `nb` band unknowns within `w`, `nk` border.
Problem random_problem(std::size_t nb, std::size_t w, std::size_t nk, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::size_t n = nb + nk;
  Problem p;
  p.a.assign(n, std::vector<double>(n, 0.0));
  p.band.reset(nb, w, nk);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      const bool in_band = i >= nb || j >= nb || i - j <= w;
      if (!in_band) continue;
      const double v = i == j ? 4.0 * static_cast<double>(w + nk + 1) : u(rng);
      p.a[i][j] = p.a[j][i] = v;
      p.band.add(i, j, v);
    }
  }
  return p;
}

TEST(BorderedBand, SolvesLikeDenseElimination) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto [nb, w, nk] : {std::tuple{1u, 0u, 0u},
                           {12u, 0u, 0u},
                           {30u, 3u, 0u},
                           {30u, 5u, 4u},
                           {7u, 9u, 2u},
                           {40u, 2u, 8u}}) {
    Problem p = random_problem(nb, w, nk, rng);
    const std::size_t n = nb + nk;
    std::vector<double> b(n);
    for (double& x : b) x = u(rng);
    ASSERT_TRUE(p.band.factor(0.0, 0.0));
    std::vector<double> x = b;
    p.band.solve(x);
    const std::vector<double> ref = dense_solve(p.a, b);
    for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(x[i], ref[i], 1e-12) << nb << " " << w;
    // A shift adds to the diagonal.
    ASSERT_TRUE(p.band.factor(0.5, 0.0));
    x = b;
    p.band.solve(x);
    for (std::size_t i = 0; i < n; ++i) p.a[i][i] += 0.5;
    const std::vector<double> shifted = dense_solve(p.a, b);
    for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(x[i], shifted[i], 1e-12);
  }
}

TEST(BorderedBand, RefusesAMatrixThatIsNotPositiveDefinite) {
  BorderedBand b;
  b.reset(3, 1, 1);
  b.add(0, 0, 1.0);
  b.add(1, 1, 1.0);
  b.add(1, 0, 2.0);  // [[1, 2], [2, 1]] is indefinite
  b.add(2, 2, 1.0);
  b.add(3, 3, 1.0);
  EXPECT_FALSE(b.factor(0.0, 0.0));
  EXPECT_TRUE(b.factor(2.0, 0.0));
}

TEST(BorderedBand, PinnedUnknownsTakeTheirValueAndTheRestSolveTheReducedSystem) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Problem p = random_problem(20, 3, 3, rng);
  const std::size_t n = 23;
  std::vector<double> b(n);
  for (double& x : b) x = u(rng);
  const std::vector<std::pair<std::size_t, double>> pins = {{4, 0.3}, {5, -0.2}, {21, 0.7}};
  std::vector<double> x = b;
  for (auto [i, v] : pins) p.band.pin(i, v, x);
  ASSERT_TRUE(p.band.factor(0.0, 0.0));
  p.band.solve(x);
  // Reference: the rows of the free unknowns with the pinned values moved to the right.
  std::vector<std::size_t> free;
  for (std::size_t i = 0; i < n; ++i) {
    bool pinned = false;
    for (auto [k, v] : pins) pinned = pinned || k == i;
    if (!pinned) free.push_back(i);
  }
  std::vector<std::vector<double>> a(free.size(), std::vector<double>(free.size()));
  std::vector<double> rhs(free.size());
  for (std::size_t r = 0; r < free.size(); ++r) {
    rhs[r] = b[free[r]];
    for (auto [k, v] : pins) rhs[r] -= p.a[free[r]][k] * v;
    for (std::size_t c = 0; c < free.size(); ++c) a[r][c] = p.a[free[r]][free[c]];
  }
  const std::vector<double> ref = dense_solve(a, rhs);
  for (auto [k, v] : pins) EXPECT_DOUBLE_EQ(x[k], v);
  for (std::size_t r = 0; r < free.size(); ++r) EXPECT_NEAR(x[free[r]], ref[r], 1e-12);
}

}  // namespace
}  // namespace fairspline::detail
