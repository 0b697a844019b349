// Tests of the private Bernstein root isolation (src/detail/bernstein.cpp): simple roots, and the
// near tangencies it reports with `touch` (a double root that rounding lifted off the axis).
#include "detail/bernstein.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fairspline::detail {
namespace {

/// Bernstein form on [0, 1] of the product of the given monomial-coefficient polynomials.
BernsteinPoly product(const std::vector<std::vector<double>>& factors) {
  std::vector<double> a{1.0};
  for (const std::vector<double>& f : factors) {
    std::vector<double> r(a.size() + f.size() - 1, 0.0);
    for (std::size_t i = 0; i < a.size(); ++i) {
      for (std::size_t j = 0; j < f.size(); ++j) r[i + j] += a[i] * f[j];
    }
    a = r;
  }
  BernsteinPoly p;
  p.degree = static_cast<int>(a.size()) - 1;
  const int n = p.degree;
  for (int m = 0; m <= n; ++m) {  // b_m = Σ_{i≤m} C(m, i)/C(n, i) a_i
    double s = 0.0, cm = 1.0, cn = 1.0;
    for (int i = 0; i <= m; ++i) {
      s += cm / cn * a[static_cast<std::size_t>(i)];
      cm = cm * (m - i) / (i + 1);
      cn = cn * (n - i) / (i + 1);
    }
    p.b[static_cast<std::size_t>(m)] = s;
  }
  return p;
}

/// (u − c)² + e: a double root at c lifted off the axis by e > 0.
std::vector<double> lifted(double c, double e) {
  return {c * c + e, -2.0 * c, 1.0};
}

TEST(BernsteinRoots, SimpleRootsOfACubic) {
  const BernsteinPoly p = product({{-0.2, 1}, {-0.5, 1}, {-0.9, 1}});
  const BernsteinRoots r = bernstein_roots(p, 1e-12);
  ASSERT_EQ(r.count, 3);
  const double expected[] = {0.2, 0.5, 0.9};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r.items[i].u, expected[i], 1e-14);
    EXPECT_EQ(r.items[i].count, 1);
  }
}

TEST(BernsteinRoots, NearTangenciesAreReportedWithTouch) {
  // Degree 9: a lifted double root between simple ones (also at the first split point 0.5,
  // inside an interval with one sign variation), at 1e-14 above the axis.
  for (double c : {0.3, 0.5, 0.61}) {
    const BernsteinPoly p = product(
        {lifted(c, 1e-14), {-0.1, 1}, {-0.8, 1}, {-0.95, 1}, {2, 1}, {3, 1}, {-4, 1}, {5, 1}});
    EXPECT_EQ(bernstein_roots(p, 1e-7).count, 3) << c;  // without touch: invisible
    const BernsteinRoots r = bernstein_roots(p, 1e-7, 1e-9);
    ASSERT_EQ(r.count, 4) << c;
    int touching = 0;
    for (int i = 0; i < r.count; ++i) {
      if (i > 0) {
        EXPECT_LT(r.items[i - 1].u, r.items[i].u) << c;  // in increasing order
      }
      if (r.items[i].count != 0) continue;
      ++touching;
      EXPECT_NEAR(r.items[i].u, c, 1e-7) << c;
    }
    EXPECT_EQ(touching, 1) << c;
  }
}

TEST(BernsteinRoots, TouchIgnoresSmallValuesThatAreNoTangency) {
  // A flat simple root: |p| stays below `touch` over a wide stretch, but p is monotone there.
  const BernsteinPoly flat = product({{-0.4e-6, 1e-6}, {1, 1}});
  const BernsteinRoots r = bernstein_roots(flat, 1e-7, 1e-9);
  ASSERT_EQ(r.count, 1);
  EXPECT_NEAR(r.items[0].u, 0.4, 1e-12);
  EXPECT_EQ(r.items[0].count, 1);
  // A minimum of |p| above `touch` is no tangency either.
  const BernsteinPoly above = product({lifted(0.3, 1e-6), {-0.8, 1}});
  EXPECT_EQ(bernstein_roots(above, 1e-7, 1e-9).count, 1);
}

}  // namespace
}  // namespace fairspline::detail
