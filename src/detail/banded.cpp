#include "detail/banded.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace fairspline::detail {

void BorderedBand::reset(std::size_t band, std::size_t width, std::size_t border) {
  nb_ = band;
  w_ = std::min(width, band == 0 ? 0 : band - 1);
  nk_ = border;
  a_.assign(nb_ * (w_ + 1), 0.0);
  c_.assign(nk_ * nb_, 0.0);
  d_.assign(nk_ * nk_, 0.0);
}

void BorderedBand::add(std::size_t i, std::size_t j, double v) {
  if (i < j) std::swap(i, j);
  if (i >= nb_) {
    const std::size_t r = i - nb_;
    if (j >= nb_) {
      d_[r * nk_ + (j - nb_)] += v;
      if (i != j) d_[(j - nb_) * nk_ + r] += v;
    } else {
      c_[r * nb_ + j] += v;
    }
    return;
  }
  lo(i, j) += v;
}

double BorderedBand::diagonal(std::size_t i) const {
  return i < nb_ ? a_[i * (w_ + 1)] : d_[(i - nb_) * (nk_ + 1)];
}

double BorderedBand::entry(std::size_t i, std::size_t j) const {
  if (i < j) std::swap(i, j);
  if (i >= nb_) return j >= nb_ ? d_[(i - nb_) * nk_ + (j - nb_)] : c_[(i - nb_) * nb_ + j];
  return i - j <= w_ ? a_[i * (w_ + 1) + (i - j)] : 0.0;
}

void BorderedBand::pin(std::size_t i, double value, std::span<double> rhs) {
  const std::size_t n = nb_ + nk_;
  const std::size_t lo = i < nb_ && i > w_ ? i - w_ : 0;
  for (std::size_t k = lo; k < n; ++k) {
    if (k == i) continue;
    if (i < nb_ && k < nb_ && k > i + w_) {
      k = nb_ - 1;  // on to the border
      continue;
    }
    const double a = entry(k, i);
    if (a == 0.0) continue;
    rhs[k] -= a * value;
    add(k, i, -a);
  }
  add(i, i, 1.0 - entry(i, i));
  rhs[i] = value;
}

bool BorderedBand::factor(double shift, double min_pivot) {
  const std::size_t w1 = w_ + 1;
  l_ = a_;
  for (std::size_t i = 0; i < nb_; ++i) l_[i * w1] += shift;
  // Row-oriented band Cholesky: L(i, j) for j = i − w .. i.
  for (std::size_t i = 0; i < nb_; ++i) {
    const std::size_t j0 = i > w_ ? i - w_ : 0;
    for (std::size_t j = j0; j <= i; ++j) {
      double sum = l_[i * w1 + (i - j)];
      const std::size_t k0 = std::max(j0, j > w_ ? j - w_ : 0);
      for (std::size_t k = k0; k < j; ++k) sum -= l_[i * w1 + (i - k)] * l_[j * w1 + (j - k)];
      if (j == i) {
        if (!(sum > min_pivot)) return false;
        l_[i * w1] = std::sqrt(sum);
      } else {
        l_[i * w1 + (i - j)] = sum / l_[j * w1];
      }
    }
  }
  // X = L⁻¹Cᵀ column by column, then the Schur complement S = D + shift·I − XᵀX.
  x_.assign(nb_ * nk_, 0.0);
  for (std::size_t c = 0; c < nk_; ++c) {
    for (std::size_t i = 0; i < nb_; ++i) {
      double sum = c_[c * nb_ + i];
      for (std::size_t k = i > w_ ? i - w_ : 0; k < i; ++k) {
        sum -= l_[i * w1 + (i - k)] * x_[k * nk_ + c];
      }
      x_[i * nk_ + c] = sum / l_[i * w1];
    }
  }
  s_ = d_;
  for (std::size_t r = 0; r < nk_; ++r) {
    s_[r * nk_ + r] += shift;
    for (std::size_t c = 0; c <= r; ++c) {
      double sum = 0.0;
      for (std::size_t i = 0; i < nb_; ++i) sum += x_[i * nk_ + r] * x_[i * nk_ + c];
      s_[r * nk_ + c] -= sum;
    }
  }
  // Dense Cholesky of S (lower part).
  for (std::size_t i = 0; i < nk_; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      double sum = s_[i * nk_ + j];
      for (std::size_t k = 0; k < j; ++k) sum -= s_[i * nk_ + k] * s_[j * nk_ + k];
      if (j == i) {
        if (!(sum > min_pivot)) return false;
        s_[i * nk_ + i] = std::sqrt(sum);
      } else {
        s_[i * nk_ + j] = sum / s_[j * nk_ + j];
      }
    }
  }
  return true;
}

void BorderedBand::solve(std::span<double> b) const {
  const std::size_t w1 = w_ + 1;
  // y1 = L⁻¹ b1
  for (std::size_t i = 0; i < nb_; ++i) {
    double sum = b[i];
    for (std::size_t k = i > w_ ? i - w_ : 0; k < i; ++k) sum -= l_[i * w1 + (i - k)] * b[k];
    b[i] = sum / l_[i * w1];
  }
  // x2 = S⁻¹ (b2 − Xᵀ y1)
  double* b2 = b.data() + nb_;
  for (std::size_t r = 0; r < nk_; ++r) {
    double sum = 0.0;
    for (std::size_t i = 0; i < nb_; ++i) sum += x_[i * nk_ + r] * b[i];
    b2[r] -= sum;
  }
  for (std::size_t i = 0; i < nk_; ++i) {
    double sum = b2[i];
    for (std::size_t k = 0; k < i; ++k) sum -= s_[i * nk_ + k] * b2[k];
    b2[i] = sum / s_[i * nk_ + i];
  }
  for (std::size_t i = nk_; i-- > 0;) {
    double sum = b2[i];
    for (std::size_t k = i + 1; k < nk_; ++k) sum -= s_[k * nk_ + i] * b2[k];
    b2[i] = sum / s_[i * nk_ + i];
  }
  // x1 = L⁻ᵀ (y1 − X x2)
  for (std::size_t i = 0; i < nb_; ++i) {
    double sum = 0.0;
    for (std::size_t c = 0; c < nk_; ++c) sum += x_[i * nk_ + c] * b2[c];
    b[i] -= sum;
  }
  for (std::size_t i = nb_; i-- > 0;) {
    double sum = b[i];
    for (std::size_t k = i + 1; k <= std::min(nb_ - 1, i + w_); ++k) {
      sum -= l_[k * w1 + (k - i)] * b[k];
    }
    b[i] = sum / l_[i * w1];
  }
}

}  // namespace fairspline::detail
