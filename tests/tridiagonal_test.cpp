// Tests of the private O(n) tridiagonal solvers against dense Gaussian elimination.
#include "detail/tridiagonal.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <vector>

#include "test_util.hpp"

namespace fairspline::detail {
namespace {

using testing::dense_solve;

RC_GTEST_PROP(Tridiagonal, MatchesDenseSolve, ()) {
  const auto n = *rc::gen::inRange<std::size_t>(1, 30);
  std::vector<double> sub(n), diag(n), sup(n);
  std::vector<Vec2> rhs(n);
  std::vector<std::vector<double>> A(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i) {
    sub[i] = i > 0 ? *rc::gen::inRange(-100, 100) / 10.0 : 0.0;
    sup[i] = i + 1 < n ? *rc::gen::inRange(-100, 100) / 10.0 : 0.0;
    diag[i] = std::abs(sub[i]) + std::abs(sup[i]) + 0.5 + *rc::gen::inRange(0, 100) / 10.0;
    rhs[i] = {*rc::gen::inRange(-100, 100) / 7.0, *rc::gen::inRange(-100, 100) / 3.0};
    A[i][i] = diag[i];
    if (i > 0) A[i][i - 1] = sub[i];
    if (i + 1 < n) A[i][i + 1] = sup[i];
  }
  const auto expected = dense_solve(A, rhs);
  std::vector<double> scratch;
  RC_ASSERT(solve_tridiagonal(sub, diag, sup, rhs, scratch));
  for (std::size_t i = 0; i < n; ++i) RC_ASSERT(norm(rhs[i] - expected[i]) < 1e-10);
}

RC_GTEST_PROP(CyclicTridiagonal, MatchesDenseSolve, ()) {
  const auto n = *rc::gen::inRange<std::size_t>(3, 30);
  std::vector<double> off(n), diag(n);
  std::vector<Vec2> rhs(n);
  for (std::size_t i = 0; i < n; ++i) off[i] = *rc::gen::inRange(1, 100) / 10.0;
  std::vector<std::vector<double>> A(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t prev = (i + n - 1) % n;
    diag[i] = off[i] + off[prev] + *rc::gen::inRange(1, 100) / 10.0;
    A[i][i] = diag[i];
    A[i][(i + 1) % n] += off[i];
    A[i][prev] += off[prev];
    rhs[i] = {*rc::gen::inRange(-100, 100) / 7.0, *rc::gen::inRange(-100, 100) / 3.0};
  }
  const auto expected = dense_solve(A, rhs);
  RC_ASSERT(solve_cyclic_symmetric(off, diag, rhs));
  for (std::size_t i = 0; i < n; ++i) RC_ASSERT(norm(rhs[i] - expected[i]) < 1e-10);
}

TEST(Tridiagonal, ReportsZeroPivot) {
  std::vector<double> sub{0, 1}, diag{1, 1}, sup{1, 0}, scratch;
  std::vector<Vec2> rhs{{1, 1}, {1, 1}};
  EXPECT_FALSE(solve_tridiagonal(sub, diag, sup, rhs, scratch));
}

}  // namespace
}  // namespace fairspline::detail
