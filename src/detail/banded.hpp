// Cholesky factorization of a symmetric positive definite band matrix with a dense border
// (the last rows and columns): the Newton systems of the data-ball optimizer, whose unknowns
// couple only nearby nodes, except for a closed curve's wrap-around (the border).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace fairspline::detail {

class BorderedBand {
 public:
  /// `band` unknowns coupled within `width` of each other, then `border` unknowns coupled with
  /// all. Every entry starts at 0.
  void reset(std::size_t band, std::size_t width, std::size_t border);
  std::size_t size() const { return nb_ + nk_; }
  /// Adds v to entry (i, j) and (j, i) (once when i == j). |i − j| must be within the width
  /// unless one of them is a border unknown.
  void add(std::size_t i, std::size_t j, double v);
  double diagonal(std::size_t i) const;
  /// Entry (i, j) of the matrix (0 outside the band).
  double entry(std::size_t i, std::size_t j) const;
  /// Fixes unknown i of the system A x = rhs at `value`: its column moves to rhs, its row
  /// and column become those of the identity (call before factor).
  void pin(std::size_t i, double value, std::span<double> rhs);
  /// Factors the matrix plus shift·I in place of the factor (the matrix itself is kept).
  /// False when a pivot is not above `min_pivot` (not positive definite enough).
  bool factor(double shift, double min_pivot);
  /// Solves (A + shift·I) x = b with the last factor; b is overwritten by x.
  void solve(std::span<double> b) const;

 private:
  double& lo(std::size_t i, std::size_t j) { return a_[i * (w_ + 1) + (i - j)]; }
  std::size_t nb_ = 0, w_ = 0, nk_ = 0;
  std::vector<double> a_, l_;  // band, lower part: row i, entries i − w .. i
  std::vector<double> c_, x_;  // border rows C (nk × nb), and X = L⁻¹Cᵀ (nb × nk)
  std::vector<double> d_, s_;  // border block D (nk × nk) and the Schur complement's factor
};

}  // namespace fairspline::detail
