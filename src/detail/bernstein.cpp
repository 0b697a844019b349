#include "detail/bernstein.hpp"

#include <cmath>

namespace fairspline::detail {

namespace {

int sign_variations(const double* b, int n) {
  int variations = 0;
  int last = 0;
  for (int i = 0; i <= n; ++i) {
    const int s = (b[i] > 0.0) - (b[i] < 0.0);
    if (s == 0) continue;
    if (last != 0 && s != last) ++variations;
    last = s;
  }
  return variations;
}

/// Splits coefficients b (on [lo, hi]) at the midpoint into left and right halves.
void subdivide(const double* b, int n, double* left, double* right) {
  double w[kBernsteinMaxDegree + 1];
  for (int i = 0; i <= n; ++i) w[i] = b[i];
  left[0] = w[0];
  right[n] = w[n];
  for (int r = 1; r <= n; ++r) {
    for (int i = 0; i <= n - r; ++i) w[i] = 0.5 * (w[i] + w[i + 1]);
    left[r] = w[0];
    right[n - r] = w[n - r];
  }
}

/// Value and derivative of the Bernstein polynomial b (degree n) at local u in [0, 1].
void eval_with_derivative(const double* b, int n, double u, double& value, double& derivative) {
  double w[kBernsteinMaxDegree + 1];
  for (int i = 0; i <= n; ++i) w[i] = b[i];
  const double v = 1.0 - u;
  for (int r = 1; r < n; ++r) {
    for (int i = 0; i <= n - r; ++i) w[i] = v * w[i] + u * w[i + 1];
  }
  derivative = n * (w[1] - w[0]);
  value = v * w[0] + u * w[1];
}

/// The root of b (degree n) in local [0, 1] where b[0] and b[n] have opposite signs and exactly
/// one sign variation: Newton steps kept inside a shrinking bracket (bisection fallback).
double refine(const double* b, int n) {
  double lo = 0.0, hi = 1.0;
  const bool increasing = b[n] > 0.0;
  double u = b[0] / (b[0] - b[n]);  // secant start
  for (int it = 0; it < 100; ++it) {
    double value = 0.0, derivative = 0.0;
    eval_with_derivative(b, n, u, value, derivative);
    if (value == 0.0) return u;
    if ((value > 0.0) == increasing) {
      hi = u;
    } else {
      lo = u;
    }
    double next = derivative != 0.0 ? u - value / derivative : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - u) <= 4e-16 * std::max(1.0, std::abs(u)) || hi - lo <= 1e-16) {
      return next;
    }
    u = next;
  }
  return u;
}

}  // namespace

double BernsteinPoly::eval(double u) const {
  double w[kBernsteinMaxDegree + 1];
  for (int i = 0; i <= degree; ++i) w[i] = b[i];
  const double v = 1.0 - u;
  for (int r = 1; r <= degree; ++r) {
    for (int i = 0; i <= degree - r; ++i) w[i] = v * w[i] + u * w[i + 1];
  }
  return w[0];
}

BernsteinRoots bernstein_roots(const BernsteinPoly& p, double resolution) {
  BernsteinRoots out;
  const int n = p.degree;
  struct Item {
    double lo, hi;
    double b[kBernsteinMaxDegree + 1];
  };
  // Depth-first with an explicit stack; each halving pushes at most one extra item, so the depth
  // bound log2(1/resolution) times one bounds the stack.
  constexpr int kStack = 128;
  Item stack[kStack];
  int top = 0;
  stack[top].lo = 0.0;
  stack[top].hi = 1.0;
  for (int i = 0; i <= n; ++i) stack[top].b[i] = p.b[i];
  ++top;
  auto push_root = [&out](double u, int count) {
    if (out.count == BernsteinRoots::kCapacity) {
      out.overflow = true;
      return;
    }
    out.items[out.count++] = {u, count};
  };
  while (top > 0) {
    const Item item = stack[--top];
    const int v = sign_variations(item.b, n);
    if (v == 0) continue;
    const double width = item.hi - item.lo;
    if (v == 1 && item.b[0] != 0.0 && item.b[n] != 0.0) {
      push_root(item.lo + width * refine(item.b, n), 1);
      continue;
    }
    if (width <= resolution || top + 2 > kStack) {
      push_root(0.5 * (item.lo + item.hi), v);
      continue;
    }
    Item left, right;
    const double mid = 0.5 * (item.lo + item.hi);
    left.lo = item.lo;
    left.hi = mid;
    right.lo = mid;
    right.hi = item.hi;
    subdivide(item.b, n, left.b, right.b);
    if (left.b[n] == 0.0) push_root(mid, 1);  // a root exactly at the split point
    stack[top++] = right;  // left is popped first: roots come out in increasing order
    stack[top++] = left;
  }
  return out;
}

}  // namespace fairspline::detail
