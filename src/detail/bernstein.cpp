#include "detail/bernstein.hpp"

#include <algorithm>
#include <cmath>

namespace fairspline::detail {

namespace {

// The kernels take the degree as a template argument N (N = 0: the runtime degree n), so that
// the degrees in use (3 and 9 in the Kozak–Krajnc solver) get fully unrolled loops.
template <int N>
constexpr int degree_of(int n) {
  static_assert(N == 0 || N >= 2, "fixed degrees start at 2 (eval_with_derivatives)");
  return N > 0 ? N : n;
}

/// Sign variations of b[0..n], zero coefficients skipped.
template <int N>
int sign_variations(const double* b, int rn) {
  const int n = degree_of<N>(rn);
  // Without zero coefficients (the usual case): sign-bit changes between neighbours, branch-free.
  bool zero = false;
  for (int i = 0; i <= n; ++i) zero |= b[i] == 0.0;
  if (!zero) {
    int variations = 0;
    for (int i = 0; i < n; ++i) variations += std::signbit(b[i]) != std::signbit(b[i + 1]);
    return variations;
  }
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

// The fixed-degree kernels below recurse over the de Casteljau levels: every loop has a fixed
// trip count, so the levels unroll and w stays in registers (a runtime-degree loop over a stack
// array stalls on store-to-load forwarding).

/// De Casteljau levels M, M − 1, ..., Stop + 1 on w[0..M] at u (v = 1 − u): level m replaces
/// w[0..m−1] by v·w[i] + u·w[i+1].
template <int M, int Stop>
inline void casteljau_levels(double* w, double u, double v) {
  if constexpr (M > Stop) {
    for (int i = 0; i < M; ++i) w[i] = v * w[i] + u * w[i + 1];
    casteljau_levels<M - 1, Stop>(w, u, v);
  }
}

/// De Casteljau levels M, ..., 1 at the midpoint for a subdivision of degree N: level m gives
/// left[N + 1 − m] and right[m − 1].
template <int M, int N>
inline void midpoint_levels(double* w, double* left, double* right) {
  if constexpr (M > 0) {
    for (int i = 0; i < M; ++i) w[i] = 0.5 * (w[i] + w[i + 1]);
    left[N + 1 - M] = w[0];
    right[M - 1] = w[M - 1];
    midpoint_levels<M - 1, N>(w, left, right);
  }
}

/// Splits coefficients b (on [lo, hi]) at the midpoint into left and right halves. `right` may
/// be `b`.
template <int N>
void subdivide(const double* b, int rn, double* left, double* right) {
  const int n = degree_of<N>(rn);
  double w[kBernsteinMaxDegree + 1];
  for (int i = 0; i <= n; ++i) w[i] = b[i];
  left[0] = b[0];
  right[n] = b[n];
  if constexpr (N > 0) {
    midpoint_levels<N, N>(w, left, right);
  } else {
    for (int r = 1; r <= n; ++r) {
      for (int i = 0; i <= n - r; ++i) w[i] = 0.5 * (w[i] + w[i + 1]);
      left[r] = w[0];
      right[n - r] = w[n - r];
    }
  }
}

/// Splits coefficients b (degree n, on [lo, hi]) at the local parameter t into left and right
/// halves by de Casteljau; `left` or `right` may be `b`.
void split_at(const double* b, int n, double t, double* left, double* right) {
  double w[kBernsteinMaxDegree + 1];
  for (int i = 0; i <= n; ++i) w[i] = b[i];
  const double s = 1.0 - t;
  double l[kBernsteinMaxDegree + 1];
  l[0] = b[0];
  right[n] = b[n];
  for (int r = 1; r <= n; ++r) {
    for (int i = 0; i <= n - r; ++i) w[i] = s * w[i] + t * w[i + 1];
    l[r] = w[0];
    right[n - r] = w[n - r];
  }
  for (int i = 0; i <= n; ++i) left[i] = l[i];
}

/// Value and first two derivatives of the Bernstein polynomial b (degree n ≥ 1) at local u in
/// [0, 1], by de Casteljau down to the last three coefficients.
template <int N>
void eval_with_derivatives(const double* b, int rn, double u, double& value, double& d1,
                           double& d2) {
  const int n = degree_of<N>(rn);
  double w[kBernsteinMaxDegree + 1];
  for (int i = 0; i <= n; ++i) w[i] = b[i];
  const double v = 1.0 - u;
  if constexpr (N > 0) {
    casteljau_levels<N, 2>(w, u, v);
  } else {
    if (n < 2) {  // linear
      value = v * w[0] + u * w[1];
      d1 = w[1] - w[0];
      d2 = 0.0;
      return;
    }
    for (int r = 1; r < n - 1; ++r) {
      for (int i = 0; i <= n - r; ++i) w[i] = v * w[i] + u * w[i + 1];
    }
  }
  d2 = n * (n - 1) * (w[2] - 2.0 * w[1] + w[0]);
  const double a = v * w[0] + u * w[1], c = v * w[1] + u * w[2];
  d1 = n * (c - a);
  value = v * a + u * c;
}

/// The root of b (degree n) in local [0, 1] where b[0] and b[n] have opposite signs and exactly
/// one sign variation: Halley steps (cubic convergence; Newton's where Halley's denominator is
/// not positive) kept inside a shrinking bracket, bisection fallback, from where the control
/// polygon crosses zero.
template <int N>
double refine(const double* b, int rn) {
  const int n = degree_of<N>(rn);
  double lo = 0.0, hi = 1.0;
  const bool increasing = b[n] > 0.0;
  double u = 0.5;
  for (int i = 0; i < n; ++i) {
    if (std::signbit(b[i]) != std::signbit(b[i + 1]) && b[i] != 0.0) {
      u = (i + b[i] / (b[i] - b[i + 1])) / n;
      break;
    }
  }
  double last_step = HUGE_VAL;  // no step taken yet
  for (int it = 0; it < 100; ++it) {
    double value = 0.0, derivative = 0.0, second = 0.0;
    eval_with_derivatives<N>(b, n, u, value, derivative, second);
    if (value == 0.0) return u;
    const bool above = (value > 0.0) == increasing;
    hi = above ? u : hi;
    lo = above ? lo : u;
    if (derivative == 0.0) {
      u = 0.5 * (lo + hi);
      last_step = HUGE_VAL;
      continue;
    }
    const double den = 2.0 * derivative * derivative - value * second;
    const double step = den > 0.0 ? 2.0 * value * derivative / den : value / derivative;
    const double tol = 4e-16 * std::max(1.0, std::abs(u));
    const double next = u - step;
    // Converged once the step is at rounding level. (Tested before the bracket: a step below the
    // spacing of the doubles lands on a bracket end, which is no reason to bisect.)
    if (std::abs(step) <= tol) return next;
    if (next > lo && next < hi) {
      // In the cubic regime the following step would be about step⁴ / last_step³: when that is
      // at rounding level too, `next` is the root and its evaluation can be saved.
      const double s = std::abs(step);
      if (last_step < HUGE_VAL && s <= 1e-4 &&
          s * s * s * s <= tol * last_step * last_step * last_step) {
        return next;
      }
      last_step = s;
      u = next;
    } else {
      u = 0.5 * (lo + hi);
      last_step = HUGE_VAL;
    }
    if (hi - lo <= 1e-16) return u;
  }
  return u;
}

/// Whether the differences b[i+1] − b[i] (the derivative's coefficients) keep one sign.
template <int N>
bool monotone(const double* b, int rn) {
  const int n = degree_of<N>(rn);
  bool up = false, down = false;
  for (int i = 0; i < n; ++i) {
    up |= b[i + 1] > b[i];
    down |= b[i + 1] < b[i];
  }
  return !(up && down);
}

/// Smallest |b[i]|, i = 0..n.
template <int N>
double min_abs(const double* b, int rn) {
  const int n = degree_of<N>(rn);
  double m = std::abs(b[0]);
  for (int i = 1; i <= n; ++i) m = std::min(m, std::abs(b[i]));
  return m;
}

template <int N>
BernsteinRoots isolate(const BernsteinPoly& p, double resolution, double touch) {
  BernsteinRoots out;
  const int n = degree_of<N>(p.degree);
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
  // Intervals without sign variation where p comes within `touch` of zero.
  struct Interval {
    double lo, hi;
  };
  constexpr int kSuspects = 8;
  Interval suspect[kSuspects];
  int nsuspect = 0;
  auto push_root = [&out](double u, int count) {
    if (out.count == BernsteinRoots::kCapacity) {
      out.overflow = true;
      return;
    }
    out.items[out.count++] = {u, count};
  };
  while (top > 0) {
    Item& item = stack[--top];
    const int v = sign_variations<N>(item.b, n);
    const double lo = item.lo, hi = item.hi, width = hi - lo;
    if (v == 0) {
      // No root here. p ≥ min |b| in absolute value (convex hull), so p can touch zero within
      // `touch` only if that is small: remembered for the pass below.
      if (touch > 0.0 && min_abs<N>(item.b, n) <= touch) {
        // Intervals come in increasing order: one that continues the last suspect (or finds no
        // room) extends it.
        if (nsuspect > 0 && (lo <= suspect[nsuspect - 1].hi || nsuspect == kSuspects)) {
          suspect[nsuspect - 1].hi = std::max(suspect[nsuspect - 1].hi, hi);
        } else {
          suspect[nsuspect++] = {lo, hi};
        }
      }
      continue;
    }
    // One root, unless (with `touch`) p may also touch zero beside it: at an end of the
    // interval (a split point) it is that small and p is not monotone (its derivative's
    // coefficients, the differences, change sign).
    if (v == 1 && item.b[0] != 0.0 && item.b[n] != 0.0 &&
        (!(touch > 0.0) || width <= resolution ||
         (std::abs(item.b[0]) > touch && std::abs(item.b[n]) > touch) || monotone<N>(item.b, n))) {
      push_root(lo + width * refine<N>(item.b, n), 1);
      continue;
    }
    if (width <= resolution || top + 2 > kStack) {
      push_root(0.5 * (lo + hi), v);
      continue;
    }
    // Split in place: the right half overwrites the item, the left half goes above it (popped
    // first, so roots come out in increasing order). subdivide reads b before writing.
    const double mid = 0.5 * (lo + hi);
    Item& left = stack[top + 1];
    subdivide<N>(item.b, n, left.b, item.b);
    item.lo = mid;
    left.lo = lo;
    left.hi = mid;
    if (left.b[n] == 0.0) push_root(mid, 1);  // a root exactly at the split point
    top += 2;
  }
  if (nsuspect > 0) {
    // Near tangencies: roots of p' in a suspect interval (widened by a quarter on each side, so
    // that a minimum on its end is inside) where |p| has a local minimum (p·p'' ≥ 0) of at most
    // `touch`. The derivative is isolated only there, on p's coefficients over that interval.
    for (int k = 0; k < nsuspect; ++k) {
      const double w = suspect[k].hi - suspect[k].lo;
      const double a = std::max(0.0, suspect[k].lo - 0.25 * w);
      const double b = std::min(1.0, suspect[k].hi + 0.25 * w);
      double local[kBernsteinMaxDegree + 1], scratch[kBernsteinMaxDegree + 1];
      for (int i = 0; i <= n; ++i) local[i] = p.b[i];
      if (b < 1.0) split_at(local, n, b, local, scratch);      // [0, b]
      if (a > 0.0) split_at(local, n, a / b, scratch, local);  // [a, b]
      BernsteinPoly d;
      d.degree = n - 1;
      for (int i = 0; i < n; ++i) d.b[i] = n * (local[i + 1] - local[i]);
      if (d.degree < 1) continue;
      const BernsteinRoots extrema = isolate<0>(d, resolution / (b - a), 0.0);
      for (int i = 0; i < extrema.count; ++i) {
        const double t = extrema.items[i].u, u = a + t * (b - a);
        if (u < suspect[k].lo - resolution || u > suspect[k].hi + resolution) continue;
        double value = 0.0, d1 = 0.0, d2 = 0.0;
        eval_with_derivatives<0>(local, n, t, value, d1, d2);
        if (std::abs(value) <= touch && !(value * d2 < 0.0)) push_root(u, 0);
      }
    }
    std::sort(out.items.begin(), out.items.begin() + out.count,
              [](const BernsteinRoot& x, const BernsteinRoot& y) { return x.u < y.u; });
  }
  return out;
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

BernsteinRoots bernstein_roots(const BernsteinPoly& p, double resolution, double touch) {
  switch (p.degree) {
    case 3:
      return isolate<3>(p, resolution, touch);
    case 9:
      return isolate<9>(p, resolution, touch);
    default:
      return isolate<0>(p, resolution, touch);
  }
}

}  // namespace fairspline::detail
