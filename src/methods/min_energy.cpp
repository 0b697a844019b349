// Johnson & Johnson minimal-energy curves. See include/fairspline/methods/min_energy.hpp and
// docs/methods/min-energy.md.
#include "fairspline/methods/min_energy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <memory_resource>
#include <numbers>
#include <optional>
#include <queue>
#include <string>
#include <utility>

#include "detail/angles.hpp"
#include "detail/choices.hpp"
#include "detail/elastica.hpp"
#include "detail/huge_pages.hpp"
#include "detail/input.hpp"
#include "detail/nodes.hpp"
#include "detail/numbers.hpp"
#include "detail/progress.hpp"
#include "fairspline/error.hpp"
#include "methods/data_balls.hpp"
#include "methods/min_energy_options.hpp"

namespace fairspline {

namespace {

/// Hyper-dual number a + b ε1 + c ε2 + d ε1ε2 (ε1² = ε2² = 0): exact first and mixed second
/// derivatives of a smooth expression in one pass (used for the Yong–Cheng energy).
struct HD {
  double a = 0, b = 0, c = 0, d = 0;
};
HD operator+(HD x, HD y) {
  return {x.a + y.a, x.b + y.b, x.c + y.c, x.d + y.d};
}
HD operator-(HD x, HD y) {
  return {x.a - y.a, x.b - y.b, x.c - y.c, x.d - y.d};
}
HD operator*(HD x, HD y) {
  return {x.a * y.a, x.a * y.b + x.b * y.a, x.a * y.c + x.c * y.a,
          x.a * y.d + x.b * y.c + x.c * y.b + x.d * y.a};
}
HD operator*(double s, HD x) {
  return {s * x.a, s * x.b, s * x.c, s * x.d};
}
HD operator/(HD x, HD y) {
  const double inv = 1.0 / y.a;
  // 1/y = 1/a − b/a² ε1 − c/a² ε2 + (2bc/a³ − d/a²) ε1ε2
  const HD r{inv, -y.b * inv * inv, -y.c * inv * inv, (2.0 * y.b * y.c * inv - y.d) * inv * inv};
  return x * r;
}
HD hsin(HD x) {
  const double s = std::sin(x.a), c = std::cos(x.a);
  return {s, c * x.b, c * x.c, c * x.d - s * x.b * x.c};
}
HD hcos(HD x) {
  const double s = std::sin(x.a), c = std::cos(x.a);
  return {c, -s * x.b, -s * x.c, -s * x.d - c * x.b * x.c};
}

/// OGH energy in the sine form of ogh_unit_energy (accurate near straight data).
HD ogh_energy(HD t, HD p) {
  const HD st = hsin(t), sp = hsin(p), c = hcos(t - p), sd = hsin(t - p);
  const HD num = 3.0 * (st * st) + 3.0 * (sp * sp) - 3.0 * (st * sp * c) - 2.0 * (sd * sd);
  const HD den = HD{4.0} - c * c;
  return 12.0 * (num / den);
}

/// Conditionally G2 cubic (Theorem 4.4) from the cosines and sines of α and β.
inline BasicEnergy cond_g2_energy(double lambda, double ca, double sa, double cb, double sb) {
  BasicEnergy r;
  const double l = lambda, l2 = 2.0 * l * l, l6 = 6.0 * l;
  const double cd = ca * cb + sa * sb, sd = sa * cb - ca * sb;  // cos, sin of α − β
  // Cancels terms of size ~6λ(λ+2) near straight data: the line search allows for that
  // rounding (rounding_scale).
  r.e = l2 * cd - l6 * (ca + cb) + 2.0 * l2 + 6.0;
  r.ea = -l2 * sd + l6 * sa;
  r.eb = l2 * sd + l6 * sb;
  r.eaa = -l2 * cd + l6 * ca;
  r.ebb = -l2 * cd + l6 * cb;
  r.eab = l2 * cd;
  return r;
}

/// E_1 from the cosines and sines of α and β (the optimizer's inner loop).
BasicEnergy energy_cs(const BasicCurveMethod& m, double ca, double sa, double cb, double sb) {
  BasicEnergy r;
  switch (m.basis) {
    case MinEnergyBasis::kCondG2:
      return cond_g2_energy(m.lambda, ca, sa, cb, sb);
    case MinEnergyBasis::kJaklicZagar:
      r.e = sa * sa + sb * sb;
      r.ea = 2.0 * sa * ca;
      r.eb = 2.0 * sb * cb;
      r.eaa = 2.0 * (ca * ca - sa * sa);
      r.ebb = 2.0 * (cb * cb - sb * sb);
      r.eab = 0.0;
      return r;
    case MinEnergyBasis::kYongCheng: {
      const double a = std::atan2(sa, ca), b = std::atan2(sb, cb);
      const HD ab = ogh_energy({a, 1, 1, 0}, {b, 0, 0, 0});  // ∂α, ∂²α (ε1 = ε2 = α)
      const HD bb = ogh_energy({a, 0, 0, 0}, {b, 1, 1, 0});
      const HD mixed = ogh_energy({a, 1, 0, 0}, {b, 0, 1, 0});
      r.e = ab.a;
      r.ea = ab.b;
      r.eaa = ab.d;
      r.eb = bb.b;
      r.ebb = bb.d;
      r.eab = mixed.d;
      return r;
    }
    case MinEnergyBasis::kRestrictedElastic:
    case MinEnergyBasis::kElastic: {
      const double a = std::atan2(sa, ca), b = std::atan2(sb, cb);
      // Outside the s-curve domain there is no piece: an infinite energy that every line
      // search refuses (the optimizer's constraints keep its iterates inside).
      if (!detail::elastica_feasible(a, b)) {
        r.e = std::numeric_limits<double>::infinity();
        return r;
      }
      const detail::ElasticaEnergy q = detail::elastica_energy(a, b);
      return {q.e, q.ea, q.eb, q.eaa, q.eab, q.ebb};
    }
  }
  return r;
}

BasicSpeeds speeds_cs(const BasicCurveMethod& m, double ca, double sa, double cb, double sb) {
  switch (m.basis) {
    case MinEnergyBasis::kCondG2:
      return {m.lambda, m.lambda};
    case MinEnergyBasis::kJaklicZagar:
      return {ca, cb};
    case MinEnergyBasis::kYongCheng: {
      // Example 4.1: s0 = (6 cos α − 3 cos β cos(α−β)) / (4 − cos²(α−β)), s1 = s0(β, α).
      const double c = ca * cb + sa * sb, den = 4.0 - c * c;
      return {(6.0 * ca - 3.0 * cb * c) / den, (6.0 * cb - 3.0 * ca * c) / den};
    }
    case MinEnergyBasis::kRestrictedElastic:
    case MinEnergyBasis::kElastic:
      break;  // no cubic (basic_curve_pieces)
  }
  return {1.0, 1.0};
}

}  // namespace

double BasicCurveMethod::default_omega(MinEnergyBasis basis) {
  switch (basis) {
    case MinEnergyBasis::kCondG2:
      return kPi / 2.0;
    case MinEnergyBasis::kJaklicZagar:
      return 80.0 * kPi / 180.0;
    case MinEnergyBasis::kYongCheng:
      return kPi / 3.0;
    case MinEnergyBasis::kRestrictedElastic:
      return kPi / 2.0;
    case MinEnergyBasis::kElastic:
      return kPi;
  }
  return kPi / 2.0;
}

BasicEnergy basic_energy(const BasicCurveMethod& method, double alpha, double beta) {
  return energy_cs(method, std::cos(alpha), std::sin(alpha), std::cos(beta), std::sin(beta));
}

BasicSpeeds basic_speeds(const BasicCurveMethod& method, double alpha, double beta) {
  return speeds_cs(method, std::cos(alpha), std::sin(alpha), std::cos(beta), std::sin(beta));
}

CubicBezier basic_curve(const BasicCurveMethod& method, Point p0, Point p1, double alpha,
                        double beta) {
  if (is_elastic(method.basis)) {
    throw Error(ErrorCode::kInvalidArgument,
                "the elastic basic curve is not a cubic; approximate it with basic_curve_pieces");
  }
  const Vec2 chord = p1 - p0;
  const double phi = std::atan2(chord.y, chord.x);
  const BasicSpeeds s = basic_speeds(method, alpha, beta);
  // c_L = L·c_1 rotated onto the chord: P'(0) = L s0 e^{i(φ+α)}, P'(1) = L s1 e^{i(φ+β)}.
  const double L = norm(chord);
  return {{p0, p0 + (L * s.s0 / 3.0) * from_angle(phi + alpha),
           p1 - (L * s.s1 / 3.0) * from_angle(phi + beta), p1}};
}

namespace {

/// A double array whose resize keeps no contents and never zero-fills: every user writes each
/// entry before reading it (the optimizer's work arrays; a memset of them was 5% of a fit).
/// It can also lend storage of its owner's (use), up to the first larger resize. Its memory is
/// a detail::Block, kept by the thread for the next fit when large (like the arenas').
class Scratch {
 public:
  Scratch() = default;
  explicit Scratch(std::size_t n) { resize(n); }
  Scratch(Scratch&&) noexcept = default;
  Scratch& operator=(Scratch&&) noexcept = default;
  ~Scratch() { detail::give_block(std::move(own_)); }
  void resize(std::size_t n) {
    if (n > cap_) {
      detail::give_block(std::exchange(own_, detail::take_block(n * sizeof(double))));
      p_ = reinterpret_cast<double*>(own_.data.get());
      cap_ = own_.size / sizeof(double);
    }
    n_ = n;
  }
  /// Works in the n doubles at p (which must outlive this use), size 0.
  void use(double* p, std::size_t n) {
    detail::give_block(std::exchange(own_, {}));
    p_ = p;
    cap_ = n;
    n_ = 0;
  }
  std::size_t size() const { return n_; }
  double& operator[](std::size_t i) { return p_[i]; }
  double operator[](std::size_t i) const { return p_[i]; }
  double* begin() { return p_; }
  double* end() { return p_ + n_; }
  const double* begin() const { return p_; }
  const double* end() const { return p_ + n_; }
  operator std::span<double>() { return {p_, n_}; }
  operator std::span<const double>() const { return {p_, n_}; }

 private:
  detail::Block own_;
  double* p_ = nullptr;  // own_ or lent storage
  std::size_t n_ = 0, cap_ = 0;
};

/// One independent chain of nodes (the whole curve, or a piece between corners).
struct Chain {
  /// The solver-only arrays (ca … hi, fixed, a, b) from `solver`, those the output reads too
  /// (node, ref, w, corner) from `kept` (a fit's arenas; copies and windows use the default
  /// resource).
  explicit Chain(std::pmr::memory_resource* solver = std::pmr::get_default_resource(),
                 std::pmr::memory_resource* kept = std::pmr::get_default_resource())
      : node(kept),
        ref(kept),
        ca(solver),
        sa(solver),
        cb(solver),
        sb(solver),
        lo(solver),
        hi(solver),
        fixed(solver),
        w(kept),
        a(solver),
        b(solver),
        corner(kept) {}
  bool closed = false;
  std::pmr::vector<std::size_t> node;  // point indices
  // Per node: α of the next segment = x + a, β of the previous = x + b; x ∈ [lo, hi].
  std::pmr::vector<Vec2> ref;  // per node: unit reference direction (x = 0)
  std::pmr::vector<double> ca, sa, cb, sb, lo, hi;
  detail::BlockVector<double> x;  // swapped with the optimizer's trial points
  std::pmr::vector<char> fixed;
  std::pmr::vector<double> w;     // per segment: 1 / L
  std::pmr::vector<double> a, b;  // per node: the offsets as angles, atan2(sa, ca), atan2(sb, cb)
  /// Per node: the corner angle from its incoming to its outgoing direction (node model); the
  /// offsets a above already see the next chord turned back by it.
  std::pmr::vector<double> corner;
  /// Elastic bases: per segment, the warm start of its root-find (a cache, hence mutable).
  mutable std::vector<detail::ElasticaHint> hint;
  std::size_t segments() const { return closed ? node.size() : node.size() - 1; }
};

/// Arrays of one fit carved from one block: it spans transparent huge pages (at 10^5 nodes each
/// chain array alone is under one, and their 4 KiB pages were two thirds of a fit's page
/// faults), and it is freed at once (the solver-only arrays when the optimizer is done, before
/// the result is allocated, so the peak memory does not grow).
class FitArena {
 public:
  explicit FitArena(std::size_t bytes) : block_(detail::take_block(bytes)) {
    pool_.emplace(block_.data.get(), block_.size, std::pmr::new_delete_resource());
  }
  FitArena(const FitArena&) = delete;
  FitArena& operator=(const FitArena&) = delete;
  ~FitArena() { release(); }
  std::pmr::memory_resource* resource() { return &*pool_; }
  /// Gives the memory back (detail::give_block); every array from it must be empty by then
  /// (release_solver_arrays).
  void release() {
    pool_.reset();
    detail::give_block(std::exchange(block_, {}));
  }

 private:
  detail::Block block_;
  std::optional<std::pmr::monotonic_buffer_resource> pool_;  // over block_, then the heap
};

struct Evaluation {
  double energy = 0.0;
  Scratch g, d, e;  // gradient, Hessian diagonal, off-diagonal (i, i+1)
  // Elastic bases: the same from each segment's 2×2 Hessian projected onto the PSD cone, and
  // per node whether a segment at it has an indefinite block.
  Scratch pd, pe;
  std::vector<char> concave;
};

/// The nearest positive semidefinite matrix to [[a, b], [b, c]] (eigenvalues clamped at 0):
/// with λ− < 0 < λ+, λ+ (H − λ− I) / (λ+ − λ−).
inline bool psd_block(double& a, double& b, double& c) {
  const double m = 0.5 * (a + c), h = 0.5 * (a - c), r = std::sqrt(h * h + b * b);
  const double lmin = m - r, lmax = m + r;
  if (lmin >= 0.0) return false;
  if (lmax <= 0.0) {
    a = b = c = 0.0;
    return true;
  }
  const double f = lmax / (2.0 * r);
  a = f * (a - lmin);
  c = f * (c - lmin);
  b = f * b;
  return true;
}

/// Segments per block of an evaluation: the cos and sin of a block's nodes live on the stack
/// (an array of 2k of them was 16 bytes a node and a pass over memory per evaluation).
constexpr std::size_t kEvalBlock = 256;

/// cos and sin of x at the chain nodes first, first + 1, … (count of them, cyclic in k) into
/// cs[2q], cs[2q+1]: the polynomial over all entries in a branch-free loop (the compiler
/// vectorizes it; a per-entry branch to libm kept it scalar, 13% of a fit), then libm for the
/// rare entries outside its range, |x| > 1.6.
void sincos_block(std::span<const double> x, std::size_t first, std::size_t count, double* cs) {
  const std::size_t k = x.size(), direct = std::min(count, k - first);
  const double* xf = x.data() + first;
  for (std::size_t q = 0; q < direct; ++q) detail::sincos_taylor(xf[q], cs[2 * q + 1], cs[2 * q]);
  for (std::size_t q = direct; q < count; ++q) {  // past the end of a closed chain: node 0, …
    detail::sincos_taylor(x[q - direct], cs[2 * q + 1], cs[2 * q]);
  }
  for (std::size_t q = 0; q < count; ++q) {
    const double v = q < direct ? xf[q] : x[q - direct];
    if (!(std::abs(v) <= 1.6)) ::sincos(v, &cs[2 * q + 1], &cs[2 * q]);
  }
}

/// No per-block preparation (the elastic bases read the angles directly).
struct NoBlock {
  void operator()(std::size_t, std::size_t) const {}
};

/// Energy (and, with kDerivatives, gradient and tridiagonal Hessian; with kProjected also
/// its PSD-projected form and the concave flags) of a chain at x, with the basic energy of
/// segment s from node i to j, `energy(s, i, j)`, inlined into the loop; `block(first, last)`
/// runs before the segments first … last − 1 (at most kEvalBlock of them).
template <bool kDerivatives, bool kProjected, typename Energy, typename Block = NoBlock>
double evaluate_with(const Chain& ch, Evaluation& ev, Energy energy, Block block = {}) {
  const std::size_t k = ch.node.size(), segs = ch.segments();
  if constexpr (kDerivatives) {
    // Every entry is written by the segment that ends at its node (node 0 of an open chain has
    // none): no zero-fill pass.
    ev.g.resize(k);
    ev.d.resize(k);
    ev.e.resize(k);
    ev.g[0] = ev.d[0] = 0.0;
    ev.e[k - 1] = 0.0;
    if constexpr (kProjected) {
      ev.pd.resize(k);
      ev.pe.resize(k);
      ev.concave.assign(k, 0);
      ev.pd[0] = 0.0;
      ev.pe[k - 1] = 0.0;
    }
  }
  double total = 0.0;
  for (std::size_t first = 0; first < segs; first += kEvalBlock) {
    const std::size_t last = std::min(first + kEvalBlock, segs);
    block(first, last);
    for (std::size_t s = first; s < last; ++s) {
      const std::size_t i = s, j = s + 1 == k ? 0 : s + 1;
      const BasicEnergy be = energy(s, i, j);
      const double w = ch.w[s];
      total += w * be.e;
      if constexpr (kDerivatives) {
        ev.g[i] += w * be.ea;
        ev.d[i] += w * be.eaa;
        if (j == 0) {  // the closing segment of a closed chain
          ev.g[0] += w * be.eb;
          ev.d[0] += w * be.ebb;
        } else {
          ev.g[j] = w * be.eb;
          ev.d[j] = w * be.ebb;
        }
        ev.e[s] = w * be.eab;  // couples i and j (s = k−1: the corner of a closed chain)
        if constexpr (kProjected) {
          double haa = w * be.eaa, hab = w * be.eab, hbb = w * be.ebb;
          if (psd_block(haa, hab, hbb)) ev.concave[i] = ev.concave[j] = 1;
          ev.pd[i] += haa;
          if (j == 0) {
            ev.pd[0] += hbb;
          } else {
            ev.pd[j] = hbb;
          }
          ev.pe[s] = hab;
        }
      }
    }
  }
  ev.energy = total;
  return total;
}

/// The elastic bases' E_1 at angles α, β from the chord; infinite outside the s-curve domain
/// (no piece there: every line search refuses it, and the constraints keep iterates inside).
BasicEnergy elastic_energy(double a, double b, detail::ElasticaHint& hint) {
  if (!detail::elastica_feasible(a, b)) return {std::numeric_limits<double>::infinity()};
  const detail::ElasticaEnergy q = detail::elastica_energy(a, b, hint);
  return {q.e, q.ea, q.eb, q.eaa, q.eab, q.ebb};
}

double evaluate(const Chain& ch, const BasicCurveMethod& m, std::span<const double> x,
                bool derivatives, Evaluation& ev) {
  if (is_elastic(m.basis)) {
    // Angles added directly (the elastica works with angles: no sin/cos round trip), and each
    // segment's root-find starts from its last solve.
    ch.hint.resize(ch.segments());
    auto energy = [&](std::size_t s, std::size_t i, std::size_t j) {
      return elastic_energy(x[i] + ch.a[i], x[j] + ch.b[j], ch.hint[s]);
    };
    return derivatives ? evaluate_with<true, true>(ch, ev, energy)
                       : evaluate_with<false, true>(ch, ev, energy);
  }
  // cos, sin of x at the nodes first … last of the current block (segment s joins the nodes
  // at s − first and s − first + 1).
  double cs[2 * (kEvalBlock + 1)];
  std::size_t base = 0;
  auto block = [&](std::size_t first, std::size_t last) {
    base = first;
    sincos_block(x, first, last - first + 1, cs);
  };
  // α = x_i + a_i, β = x_j + b_j by the angle-addition formulas.
  auto cos_sin = [&](std::size_t i, std::size_t j, auto basic) {
    const std::size_t q = 2 * (i - base);
    const double cx = cs[q], sx = cs[q + 1], cy = cs[q + 2], sy = cs[q + 3];
    const double ca = cx * ch.ca[i] - sx * ch.sa[i], sa = sx * ch.ca[i] + cx * ch.sa[i];
    const double cb = cy * ch.cb[j] - sy * ch.sb[j], sb = sy * ch.cb[j] + cy * ch.sb[j];
    return basic(ca, sa, cb, sb);
  };
  auto run = [&](auto energy) {
    return derivatives ? evaluate_with<true, false>(ch, ev, energy, block)
                       : evaluate_with<false, false>(ch, ev, energy, block);
  };
  if (m.basis == MinEnergyBasis::kCondG2) {
    const double l = m.lambda;
    return run([&, l](std::size_t, std::size_t i, std::size_t j) {
      return cos_sin(i, j, [l](double ca, double sa, double cb, double sb) {
        return cond_g2_energy(l, ca, sa, cb, sb);
      });
    });
  }
  return run([&](std::size_t, std::size_t i, std::size_t j) {
    return cos_sin(i, j, [&m](double ca, double sa, double cb, double sb) {
      return energy_cs(m, ca, sa, cb, sb);
    });
  });
}

/// The diagonal entry of a held (active or fixed) row of a Newton system: a power of two of the
/// gradient's scale, so that the held rows neither dominate nor vanish beside the Hessian's
/// (with 1.0 the solve's pivot floor, relative to the largest entry, depended on the data's
/// scale), and dividing by it is exact.
double pivot_unit(double gscale) {
  return std::isnormal(gscale) ? std::scalbn(1.0, std::ilogb(gscale)) : 1.0;
}

/// How an LDLᵀ factorization ended: solved, a pivot positive but below the floor (1e-14 · the
/// largest diagonal entry; a larger or a smaller shift may factor), or a pivot not positive
/// (the matrix is not positive definite, and neither is it with any smaller shift).
enum class Factor { kOk, kSmallPivot, kIndefinite };

Factor pivot_failure(double pivot) {
  return pivot > 0.0 ? Factor::kSmallPivot : Factor::kIndefinite;
}

/// Solves the symmetric (cyclic when `corner`) tridiagonal system by LDLᵀ (kOk), or says why not.
/// d, e as in Evaluation; b is overwritten.
Factor ldl_solve(std::span<const double> d, std::span<const double> e, bool corner,
                 std::span<double> b, Scratch& work) {
  const std::size_t n = d.size();
  work.resize(3 * n);  // every entry is written before it is read
  double* D = work.begin();
  double* l = D + n;      // l[i] = L[i+1][i]
  double* mlast = l + n;  // L[n−1][i] (cyclic fill-in)
  const double scale = [&] {
    double s = 0.0;
    for (double v : d) s = std::max(s, std::abs(v));
    return s;
  }();
  const double tiny = 1e-14 * scale;
  if (!corner || n < 3) {
    // D_i = d_i − l_{i−1} e_{i−1} (= d_i − l² D_{i−1}); one division per row.
    // Factorization fused with the forward substitution L y = b; then x = D⁻¹y − Lᵀx.
    double prev = 0.0;  // l_{i−1} e_{i−1}
    for (std::size_t i = 0; i < n; ++i) {
      const double piv = d[i] - prev;
      if (!(piv > tiny)) return pivot_failure(piv);
      D[i] = 1.0 / piv;
      if (i > 0) b[i] -= l[i - 1] * b[i - 1];
      if (i + 1 < n) {
        l[i] = e[i] * D[i];
        prev = l[i] * e[i];
      }
    }
    b[n - 1] *= D[n - 1];
    for (std::size_t i = n - 1; i-- > 0;) b[i] = b[i] * D[i] - l[i] * b[i + 1];
    return Factor::kOk;
  }
  const double c = e[n - 1];  // couples n−1 and 0
  double last = d[n - 1];
  for (std::size_t i = 0; i + 1 < n; ++i) {
    D[i] = d[i] - (i > 0 ? l[i - 1] * l[i - 1] * D[i - 1] : 0.0);
    if (!(D[i] > tiny)) return pivot_failure(D[i]);
    const double a_last = i == 0 ? c : 0.0;
    const double coupling = i + 2 == n ? e[i] : 0.0;  // A[n−1][n−2]
    mlast[i] = (a_last + coupling - (i > 0 ? mlast[i - 1] * l[i - 1] * D[i - 1] : 0.0)) / D[i];
    if (i + 2 < n) l[i] = e[i] / D[i];
    last -= mlast[i] * mlast[i] * D[i];
  }
  D[n - 1] = last;
  if (!(D[n - 1] > tiny)) return pivot_failure(D[n - 1]);
  // Forward (L y = b), the last row uses mlast.
  for (std::size_t i = 1; i + 1 < n; ++i) b[i] -= l[i - 1] * b[i - 1];
  for (std::size_t i = 0; i + 1 < n; ++i) b[n - 1] -= mlast[i] * b[i];
  for (std::size_t i = 0; i < n; ++i) b[i] /= D[i];
  // Backward (Lᵀ x = z).
  b[n - 2] -= mlast[n - 2] * b[n - 1];
  for (std::size_t i = n - 2; i-- > 0;) b[i] -= l[i] * b[i + 1] + mlast[i] * b[n - 1];
  return Factor::kOk;
}

/// Solves an open symmetric tridiagonal system of k rows by LDLᵀ, each row made when the
/// factorization reaches it: row(i, d, e, b) gives the diagonal, the coupling to row i + 1 (not
/// read for the last row) and the right-hand side (one pass over the data instead of three:
/// build, scale, factor). x gets the solution, work holds 2k doubles. The pivots are ratios of
/// continuants, q_i = d_i q_{i−1} − e_{i−1}² q_{i−2}, D_i = q_{i−1}/q_i: the serial dependence is
/// a multiply and a subtract per row, where D_i = 1/(d_i − e_{i−1}² D_{i−1}) waited for a
/// division (the loop's latency, ~40% of a fit at 10^5 points; 12 of the 22 ms of the start at
/// 10^6); the divisions are independent. q is kept within 2^±512 by exact power-of-two
/// rescaling. The floor is ldl_solve's, 1/D_i > 1e-14 · the largest diagonal, known only at the
/// end; a non-positive pivot ends the pass at once (the shift search's indefinite tries: a
/// random 10^6-point walk's first iteration made five, all failing at one concave span).
template <typename Row>
Factor solve_open_tridiagonal(std::size_t k, Row&& row, double* x, double* work) {
  double* D = work;
  double* l = work + k;
  double scale = 0.0, max_inv = 0.0, q1 = 1.0, q2 = 0.0, e2 = 0.0;  // q_{i−1}, q_{i−2}
  for (std::size_t i = 0; i < k; ++i) {
    double di, ei, bi;
    row(i, di, ei, bi);
    scale = std::max(scale, std::abs(di));
    double q = di * q1 - e2 * q2;
    const double inv = q1 / q;
    if (!(inv > 0.0)) return Factor::kIndefinite;
    max_inv = std::max(max_inv, inv);
    D[i] = inv;
    if (!(std::abs(q) <= 0x1p512 && std::abs(q) >= 0x1p-512) && std::isnormal(q)) {
      const int ex = std::ilogb(q);
      q = std::scalbn(q, -ex);
      q1 = std::scalbn(q1, -ex);
    }
    q2 = q1;
    q1 = q;
    if (i > 0) bi -= l[i - 1] * x[i - 1];
    x[i] = bi;
    if (i + 1 < k) {
      l[i] = ei * inv;
      e2 = ei * ei;
    }
  }
  if (!(max_inv * (1e-14 * scale) < 1.0)) return Factor::kSmallPivot;
  x[k - 1] *= D[k - 1];
  for (std::size_t i = k - 1; i-- > 0;) x[i] = x[i] * D[i] - l[i] * x[i + 1];
  return Factor::kOk;
}

struct ChainResult {
  int iterations = 0;
  int window_passes = 0;
  int windows = 0, window_iterations = 0;
  double pg = 0.0;
  bool converged = false;
  /// Stopped at the accuracy of the energy's own derivatives (converged to that limit).
  bool at_precision = false;
  /// elastic: the restricted start breaks a pair constraint (infinite energy): nothing was run.
  bool no_start = false;
  /// elastic: stationary only with a ridge kept locked whose force exceeds its kink's half-jump
  /// (released and locked again twice: docs/methods/elastic.md, "Ridges"), so not certainly
  /// a KKT point.
  bool ridge_kept = false;
  /// search=coordinate or global: the minimum is that search's, not search=newton's.
  bool by_search = false;
  std::size_t worst = 0;  ///< the chain node with the largest residual
};

/// Projected Newton (bound constraints, active set) on one chain, from ch.x.
/// max |x − P(x − g/gscale)| over the nodes (P: projection on the boxes; a fixed node has
/// lo = hi = x, so it contributes 0). The gradient is divided by its scale (the largest chord
/// weight, ∝ 1/length) before the step: x are angles, so with the raw gradient the measure was
/// capped by the box width for small data (every fit "converged" at iteration 0) and rounded to
/// 0 for large data (found by the extremes suite: quasi-elastic gave another curve at 2^-50).
/// `worst`: the node where it is largest (named by the not-converged error).
/// Node i's projected gradient |x − P(x − g/gscale)|.
double node_residual(const Chain& ch, std::span<const double> g, double gscale, std::size_t i) {
  return std::abs(ch.x[i] - std::clamp(ch.x[i] - g[i] / gscale, ch.lo[i], ch.hi[i]));
}

/// Node i held by the active set (Bertsekas): fixed, or within eps of a bound with the gradient
/// pushing outwards. Branch-free: each factorization reads the flags (several when the system
/// needs a shift), and the test's branches were 6% of a fit.
inline char held(const Chain& ch, std::span<const double> g, double eps, std::size_t i) {
  const int low = static_cast<int>(ch.x[i] <= ch.lo[i] + eps) & static_cast<int>(g[i] > 0.0);
  const int high = static_cast<int>(ch.x[i] >= ch.hi[i] - eps) & static_cast<int>(g[i] < 0.0);
  return static_cast<char>(ch.fixed[i] | low | high);
}

/// The active set's band around the bounds: eps = min(kActiveBand, pg).
constexpr double kActiveBand = 1e-8;

/// `above`, if given: how many nodes' residuals exceed `tol` (the windows' test, in the same pass).
/// `active`, if given: held(…, kActiveBand, i) per node, in the same pass (a pass over the
/// nodes' arrays fewer per iteration; right whenever pg >= kActiveBand).
double projected_gradient(const Chain& ch, std::span<const double> g, double gscale,
                          std::size_t& worst, double tol = 0.0, std::size_t* above = nullptr,
                          char* active = nullptr) {
  double pg = 0.0;
  std::size_t count = 0;
  worst = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double v = node_residual(ch, g, gscale, i);
    count += v > tol;
    if (v > pg) pg = v, worst = i;
    if (active) active[i] = held(ch, g, kActiveBand, i);
  }
  if (above) *above = count;
  return pg;
}

/// xn = P(x + step·dir); returns the first-order change g·(xn − x).
double project_step(const Chain& ch, std::span<const double> dir, double step,
                    std::span<const double> g, std::span<double> xn) {
  double decrease = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    xn[i] = std::clamp(ch.x[i] + step * dir[i], ch.lo[i], ch.hi[i]);
    decrease += g[i] * (xn[i] - ch.x[i]);
  }
  return decrease;
}

/// Elastic bases: E_1 is concave towards the box corners (α, β) = ±(90°, −90°) (E ≈ E_c −
/// (8/3) X_h Θ^{3/2}, Θ = 180° − |α − β|), so a segment heading there is reached by Newton
/// steps only geometrically (each step sees the curvature of the neighbours alone). After each
/// step, every segment with a concave Hessian block whose two directions move apart (dir of
/// opposite signs) is tried at its nodes' bounds in the directions of motion; kept when the
/// energy of the three segments touching them goes down (other segments do not change).
/// Returns whether a node moved (the caller re-evaluates).
bool corner_moves(Chain& ch, std::span<const double> dir, const std::vector<char>& concave) {
  const std::size_t k = ch.node.size(), segs = ch.segments();
  auto segment_energy = [&](std::size_t s) {
    const std::size_t j = s + 1 == k ? 0 : s + 1;
    return ch.w[s] * elastic_energy(ch.x[s] + ch.a[s], ch.x[j] + ch.b[j], ch.hint[s]).e;
  };
  bool moved = false;
  for (std::size_t s = 0; s < segs; ++s) {
    const std::size_t i = s, j = s + 1 == k ? 0 : s + 1;
    if (!concave[i] || !concave[j] || ch.fixed[i] || ch.fixed[j]) continue;
    if (!(dir[i] * dir[j] < 0.0)) continue;
    const double ti = dir[i] > 0.0 ? ch.hi[i] : ch.lo[i];
    const double tj = dir[j] > 0.0 ? ch.hi[j] : ch.lo[j];
    if (ti == ch.x[i] && tj == ch.x[j]) continue;
    // The segments touching i or j: s − 1, s, s + 1 where they exist.
    std::array<std::size_t, 3> near{segs, s, segs};
    if (s > 0 || ch.closed) near[0] = s == 0 ? segs - 1 : s - 1;
    if (s + 1 < segs || ch.closed) near[2] = s + 1 == segs ? 0 : s + 1;
    if (near[2] == near[0] || near[2] == s) near[2] = segs;  // short closed chains
    if (near[0] == s) near[0] = segs;
    auto local = [&] {
      double e = 0.0;
      for (std::size_t q : near) {
        if (q < segs) e += segment_energy(q);
      }
      return e;
    };
    const double before = local(), xi = ch.x[i], xj = ch.x[j];
    ch.x[i] = ti;
    ch.x[j] = tj;
    if (local() < before) {
      moved = true;
    } else {
      ch.x[i] = xi;
      ch.x[j] = xj;
    }
  }
  return moved;
}

/// Energy of the (at most two) segments of a chain that touch node t, for direction offset x.
double local_energy(const Chain& ch, const BasicCurveMethod& m, std::size_t t, double x) {
  const std::size_t k = ch.node.size();
  const double cx = std::cos(x), sx = std::sin(x);
  double e = 0.0;
  if (ch.closed || t + 1 < k) {  // segment t: α at t, β at t+1
    const std::size_t j = t + 1 == k ? 0 : t + 1;
    const double ca = cx * ch.ca[t] - sx * ch.sa[t], sa = sx * ch.ca[t] + cx * ch.sa[t];
    const double cy = std::cos(ch.x[j]), sy = std::sin(ch.x[j]);
    const double cb = cy * ch.cb[j] - sy * ch.sb[j], sb = sy * ch.cb[j] + cy * ch.sb[j];
    e += ch.w[t] * energy_cs(m, ca, sa, cb, sb).e;
  }
  if (ch.closed || t > 0) {  // segment t−1: α at t−1, β at t
    const std::size_t i = t == 0 ? k - 1 : t - 1;
    const double cy = std::cos(ch.x[i]), sy = std::sin(ch.x[i]);
    const double ca = cy * ch.ca[i] - sy * ch.sa[i], sa = sy * ch.ca[i] + cy * ch.sa[i];
    const double cb = cx * ch.cb[t] - sx * ch.sb[t], sb = sx * ch.cb[t] + cx * ch.sb[t];
    e += ch.w[i] * energy_cs(m, ca, sa, cb, sb).e;
  }
  return e;
}

ChainResult optimize(Chain& ch, const MinEnergyOptions& opt, double gscale);

/// Long chains whose residual is left at a few nodes: each such node's neighbourhood is solved
/// on its own (windows of kWindowRadius nodes each side, merged where they overlap), its
/// outer nodes held, so that the spans outside keep their energies. A stretch creeping out of
/// a concave region took one global iteration per ~4% of progress (a 10⁵-point walk: 174
/// iterations, 130 of them with 5 nodes above the tolerance); the windows take those
/// iterations on ~30 spans instead of 10⁵.
constexpr std::size_t kWindowMinNodes = 4096;
constexpr std::size_t kWindowRadius = 16;

/// The sub-chain of `ch` on the consecutive nodes first, first + 1, … (mod k), `count` of them;
/// its ends held unless they are ends of `ch` itself.
Chain window_chain(const Chain& ch, std::size_t first, std::size_t count) {
  const std::size_t k = ch.node.size();
  Chain w;
  w.closed = false;
  // Appends entry t of each listed per-node (or per-segment) vector of `ch` to `w`'s.
  auto take = [&](std::size_t t, auto... member) { ((w.*member).push_back((ch.*member)[t]), ...); };
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t t = (first + i) % k;
    take(t, &Chain::node, &Chain::ref, &Chain::ca, &Chain::sa, &Chain::cb, &Chain::sb, &Chain::lo,
         &Chain::hi, &Chain::x, &Chain::fixed, &Chain::a, &Chain::b, &Chain::corner);
    if (i + 1 < count) {
      take(t, &Chain::w);  // segment t joins t and t + 1
      if (t < ch.hint.size()) take(t, &Chain::hint);
    }
  }
  const bool chain_start = !ch.closed && first == 0;
  const bool chain_end = !ch.closed && first + count == k;
  // A held end stays where it is (lo = hi = x, as for every fixed node): its gradient has a
  // term from outside the window, which the window cannot lower (held by `fixed` alone, that
  // residual kept every window iterating to the limit: 68% of a 10^6-point fit).
  auto hold = [&](std::size_t t) {
    w.fixed[t] = 1;
    w.lo[t] = w.hi[t] = w.x[t];
  };
  if (!chain_start) hold(0);
  if (!chain_end) hold(count - 1);
  return w;
}

/// Solves the windows around the nodes whose projected residual exceeds the tolerance, when
/// there are few of them (at most k/128); returns whether any was solved (the caller then
/// re-evaluates). `v`: each node's projected residual.
bool solve_windows(Chain& ch, const MinEnergyOptions& opt, double gscale, std::span<const double> g,
                   std::size_t n_above, ChainResult& res) {
  const std::size_t k = ch.node.size();
  // Counted (by projected_gradient) before they are listed: early on every node is above the
  // tolerance, and listing them all was a vector of k indices per iteration (and its growth,
  // at the fit's peak memory).
  if (n_above == 0 || n_above > k / 128) return false;
  auto above = [&](std::size_t i) { return node_residual(ch, g, gscale, i) > opt.tolerance; };
  std::vector<std::size_t> bad;
  bad.reserve(n_above);
  for (std::size_t i = 0; i < k; ++i) {
    if (above(i)) bad.push_back(i);
  }
  // Windows [lo, hi], merged; a closed chain's in indices shifted by k (no wrap below 0).
  std::vector<std::pair<std::size_t, std::size_t>> windows;
  for (std::size_t i : bad) {
    const std::size_t lo =
        ch.closed ? i + k - kWindowRadius : (i >= kWindowRadius ? i - kWindowRadius : 0);
    const std::size_t hi = ch.closed ? i + k + kWindowRadius : std::min(i + kWindowRadius, k - 1);
    if (!windows.empty() && lo <= windows.back().second + 1) {
      windows.back().second = hi;
    } else {
      windows.emplace_back(lo, hi);
    }
  }
  for (const auto& [lo, hi] : windows) {
    const std::size_t count = std::min(hi - lo + 1, k);
    Chain w = window_chain(ch, lo % k, count);
    const ChainResult r = optimize(w, opt, gscale);
    ++res.windows;
    res.window_iterations += r.iterations;
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t t = (lo + i) % k;
      ch.x[t] = w.x[i];
      if (i + 1 < count && t < ch.hint.size() && i < w.hint.size()) ch.hint[t] = w.hint[i];
    }
  }
  return true;
}

/// The largest residual (relative to the gradient's scale) the elastic basis reports as optimal
/// to double precision when Newton steps no longer change the energy (docs/methods/elastic.md).
constexpr double kElasticPrecision = 1e-6;
/// A Newton step this small (radians) that no longer lowers the energy leaves the directions
/// optimal to double precision whatever the residual (docs/methods/elastic.md, "Precision").
constexpr double kStepPrecision = 1e-9;

ChainResult optimize(Chain& ch, const MinEnergyOptions& opt, double gscale) {
  const BasicCurveMethod& m = opt.method;
  const std::size_t k = ch.node.size();
  const bool cyclic = ch.closed;
  // One block for the arrays every iteration writes, so that it spans whole huge pages (at 10^5
  // nodes each array alone is under the 2 MiB of one, and their fresh 4 KiB pages were faulted
  // in at every fit).
  Scratch block(10 * k);
  Evaluation ev, trial;
  Scratch dir, dd, ee, work, kept_dir;
  {
    double* p = block.begin();
    for (Scratch* a : {&ev.g, &ev.d, &ev.e, &trial.g, &trial.d, &trial.e, &dir}) {
      a->use(p, k);
      p += k;
    }
    work.use(p, 3 * k);  // ldl_solve's 3k (closed chains), the open solve's 2k
  }
  dir.resize(k);
  detail::BlockVector<double> xn;  // swapped with ch.x
  detail::resize_huge(xn, k);
  detail::BlockVector<char> active;  // per iteration: held at its bound (or fixed)
  detail::resize_huge(active, k);
  ChainResult res;
  const double tol = opt.tolerance;  // on the scaled projected gradient (dimensionless)
  double energy = evaluate(ch, m, ch.x, true, ev);
  // Size of the rounding in a computed total energy: cond-G2's E_1 cancels terms of size
  // 6λ² + 12λ + 6 per unit chord; the other bases' sine forms do not cancel.
  double wsum = 0.0;
  for (double w : ch.w) wsum += w;
  const double term =
      m.basis == MinEnergyBasis::kCondG2 ? 6.0 * m.lambda * m.lambda + 12.0 * m.lambda + 6.0 : 0.0;
  // The elastic energies come from root-finds, relative-accurate to ~1e-12 rather than 1e-14.
  const double relative_rounding = is_elastic(m.basis) ? 1e-12 : 1e-14;
  const double rounding_scale =
      relative_rounding * (term * wsum + std::abs(energy)) * std::sqrt(static_cast<double>(k));
  // Elastic bases, after a full step that went down by more than 1.5× what its model
  // predicted (−g·d/2; the projected Hessian is too stiff where E_1 is concave): the step is
  // doubled while that keeps lowering the energy. Without it such a stretch took one Newton
  // iteration per ~10% of progress (a 10⁴-point walk: 50 → 21 iterations; 10⁵: 121 → 43).
  detail::BlockVector<double> xe;  // sized on first use (elastic bases only)
  Evaluation further;
  // Also after a full step in nearly the direction of the last one ("creeping": the PSD
  // projection keeps each step short where E_1 is concave, and the iterate walked out of such a
  // region by ~1e-6 of the gradient per iteration: six of 10⁶ stress walks stopped at the
  // 200-iteration cap with projected gradients 8e-10 … 4e-6, issue 18).
  std::vector<double> last_dir;
  auto creeping = [&] {
    if (last_dir.size() != k) return false;
    double dd_ = 0.0, ll = 0.0, dl = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
      dd_ += dir[i] * dir[i];
      ll += last_dir[i] * last_dir[i];
      dl += dir[i] * last_dir[i];
    }
    return dl > 0.95 * std::sqrt(dd_ * ll);
  };
  auto extrapolate = [&](double e0, double decrease, double& en) {
    // (Not for a decrease within rounding: there the excess is noise; but a creeping step's
    // direction is no noise.)
    const bool creep = creeping();
    if (!creep && (!(e0 - en > -0.75 * decrease) || -decrease <= rounding_scale)) return;
    xe.resize(k);
    for (double f = 2.0; f <= 1024.0; f *= 2.0) {
      for (std::size_t i = 0; i < k; ++i) {
        // Creeping: only the nodes moving on as before (a stiff node whose Newton step is
        // right alternates in sign around its optimum; doubling it overshot, issue 18).
        const double fi = !creep || dir[i] * last_dir[i] > 0.0 ? f : 1.0;
        xe[i] = std::clamp(ch.x[i] + fi * dir[i], ch.lo[i], ch.hi[i]);
      }
      const double e = evaluate(ch, m, xe, true, further);
      if (!(e < en)) return;
      en = e;
      xn.swap(xe);
      std::swap(trial, further);
    }
  };
  bool windows_last = false;
  // Elastic bases: consecutive full steps whose predicted decrease was within the rounding of
  // the total energy. Three, with the residual below kElasticPrecision, is the optimum to double
  // precision: a walk whose chords spanned 10^3.4 (energy 9e9, ulp 2e-6) crept on at projected
  // gradient 1.6e-10 for 2000 iterations, each lowering the energy by about one ulp.
  int flat = 0;
  for (res.iterations = 0; res.iterations <= detail::iteration_limit(opt); ++res.iterations) {
    detail::checkpoint("newton", static_cast<std::size_t>(res.iterations));
    std::size_t n_above = 0;
    const double pg = projected_gradient(ch, ev.g, gscale, res.worst, tol, &n_above, active.data());
    res.pg = pg;
    if (pg <= tol) {
      res.converged = true;
      return res;
    }
    if (flat >= 3 && pg <= kElasticPrecision) {
      res.at_precision = true;
      return res;
    }
    if (res.iterations == detail::iteration_limit(opt)) break;
    // Windows at most every other iteration: a global Newton step joins them up.
    if (k >= kWindowMinNodes && !windows_last) {
      if (solve_windows(ch, opt, gscale, ev.g, n_above, res)) {
        windows_last = true;
        flat = 0;
        ++res.window_passes;
        energy = evaluate(ch, m, ch.x, true, ev);
        continue;
      }
    }
    windows_last = false;
    // Active set: flagged with the stop test unless pg is inside the band.
    if (pg < kActiveBand) {
      for (std::size_t i = 0; i < k; ++i) active[i] = held(ch, ev.g, pg, i);
    }
    auto is_active = [&](std::size_t i) -> bool { return active[i] != 0; };
    // Reduced Newton system (identity rows for active directions), shifted until positive
    // definite. Elastic bases: before any shift, each segment's Hessian projected onto the PSD
    // cone, a local repair where E_1 is concave (towards the box corners), while a global shift
    // shortens every node's step (30 → 9 iterations on a 1000-point walk; the cubic bases keep
    // the shift: there the projection led one reference case to a worse local minimum).
    const bool psd_first = is_elastic(m.basis);
    double dmax = 0.0;
    const double unit_pivot = pivot_unit(gscale);
    // One factorization of the system (the PSD-projected blocks if `projected`, shifted by tau)
    // and, if it succeeds, the direction from it.
    auto solve = [&](bool projected, double tau) -> Factor {
      const double* hd = projected ? ev.pd.begin() : ev.d.begin();
      const double* he = projected ? ev.pe.begin() : ev.e.begin();
      // Row i of the reduced system: diagonal, coupling to i + 1, right-hand side.
      auto row = [&](std::size_t i, bool act, bool next, double& di, double& ei, double& bi) {
        di = act ? unit_pivot : hd[i] + tau;
        ei = (act || next) ? 0.0 : he[i];
        // An active node moves onto its bound: it may sit inside the band, up to eps away, and
        // held there it kept the projected gradient at that distance (issue 18's stalled walk).
        bi = !act          ? -ev.g[i]
             : ch.fixed[i] ? 0.0
                           : unit_pivot * ((ev.g[i] > 0.0 ? ch.lo[i] : ch.hi[i]) - ch.x[i]);
      };
      bool act = is_active(0);
      const bool act0 = act;
      if (!cyclic || k < 3) {
        work.resize(2 * k);
        auto open_row = [&](std::size_t i, double& di, double& ei, double& bi) {
          const bool next = i + 1 < k ? is_active(i + 1) : act0;
          row(i, act, next, di, ei, bi);
          act = next;
        };
        return solve_open_tridiagonal(k, open_row, dir.begin(), work.begin());
      }
      dd.resize(k);
      ee.resize(k);
      for (std::size_t i = 0; i < k; ++i) {
        const bool next = i + 1 < k ? is_active(i + 1) : act0;
        row(i, act, next, dd[i], ee[i], dir[i]);
        act = next;
      }
      return ldl_solve(dd, ee, cyclic, dir, work);
    };
    // The shifts tau_j = 1e-10 max(|H_tt|, gscale) 4^j, j < shifts: the first that factors.
    // Not being positive definite holds for every smaller shift too, so a bisection on it finds
    // the least positive definite shift, and the search goes on up from there one by one (a
    // pivot below the floor can also come from a shift too large for the held rows' pivots, so
    // that failure is not monotone). Same shift as trying each in turn, in fewer
    // factorizations: from the quadratic start 16 became 7 (a 10^5-point walk).
    if (solve(false, 0.0) != Factor::kOk && !(psd_first && solve(true, 0.0) == Factor::kOk)) {
      for (double v : ev.d) dmax = std::max(dmax, std::abs(v));
      const double base = 1e-10 * std::max(dmax, gscale);
      const int shifts = psd_first ? 58 : 59;
      int last = -1;  // the shift whose factorization `dir` holds
      Factor last_result = Factor::kIndefinite;
      auto shifted = [&](int j) {
        last = j;
        last_result = solve(psd_first, std::ldexp(base, 2 * j));
        return last_result;
      };
      // The direction of the least shift that factored so far, kept (swapped out of `dir`) so
      // that the search's answer is not solved a second time when a later try overwrote it.
      int kept = -1;
      int indefinite = -1, definite = shifts;
      while (definite - indefinite > 1) {
        const int mid = (indefinite + definite) / 2;
        const Factor f = shifted(mid);
        (f == Factor::kIndefinite ? indefinite : definite) = mid;
        if (f == Factor::kOk) {
          kept_dir.resize(k);
          std::swap(dir, kept_dir);
          kept = mid;
          last = -1;
        }
      }
      for (int j = definite; j < shifts; ++j) {
        if (kept == j) {
          std::swap(dir, kept_dir);
          break;
        }
        if ((last == j ? last_result : shifted(j)) == Factor::kOk) break;
      }
    }
    // Projected line search (Armijo along the projection arc).
    bool accepted = false;
    for (double step = 1.0; step > 1e-12; step *= 0.5) {
      const double decrease = project_step(ch, dir, step, ev.g, xn);
      // The full step is evaluated with derivatives (it is usually accepted: Newton).
      double en = evaluate(ch, m, xn, step == 1.0, trial);
      // Armijo; near the optimum the decrease falls below the rounding of the total, so a full
      // Newton step that does not raise the energy beyond that rounding is taken too, but only
      // when the decrease it predicts is itself within that rounding: a step predicting more
      // that went up is a bad step, and taking it cycled between two states (issue 18: near-
      // repeated points' 1e9 weights set an allowance above real changes elsewhere).
      const bool rounding =
          step == 1.0 && en <= energy + rounding_scale && -decrease <= rounding_scale;
      if ((en <= energy + 1e-4 * decrease || rounding) && decrease < 0.0) {
        if (step == 1.0 && psd_first) {
          extrapolate(energy, decrease, en);
          last_dir.assign(dir.begin(), dir.end());
        }
        ch.x.swap(xn);
        flat = psd_first && step == 1.0 && -decrease <= rounding_scale ? flat + 1 : 0;
        if (step == 1.0) {
          std::swap(ev, trial);
          energy = en;
        } else {
          energy = evaluate(ch, m, ch.x, true, ev);
        }
        accepted = true;
        break;
      }
    }
    if (accepted && is_elastic(m.basis) && corner_moves(ch, dir, ev.concave)) {
      energy = evaluate(ch, m, ch.x, true, ev);
    }
    if (!accepted) {
      // Newton direction useless here: one projected steepest-descent step.
      dmax = 0.0;
      for (std::size_t i = 0; i < k; ++i) {
        dmax = std::max(dmax, std::abs(ev.d[i]));
        dir[i] = -ev.g[i];
      }
      for (double step = 1.0 / std::max(dmax, 1e-300); step > 1e-30; step *= 0.5) {
        const double decrease = project_step(ch, dir, step, ev.g, xn);
        if (!(decrease < 0.0)) break;
        const double en = evaluate(ch, m, xn, false, trial);
        if (en <= energy + 1e-4 * decrease) {
          ch.x.swap(xn);
          energy = evaluate(ch, m, ch.x, true, ev);
          accepted = true;
          break;
        }
      }
    }
    if (!accepted) break;  // no descent possible at this precision
  }
  const double pg = projected_gradient(ch, ev.g, gscale, res.worst);
  res.pg = pg;
  res.converged = pg <= tol;
  return res;
}

/// A two-sided node's directions within Ω of both chords form two intervals when its stencil
/// turns by more than 2(180° − Ω): one about the chords' bisector, which the offsets a = −ψ/2,
/// b = ψ/2 and the box [lo, hi] describe, and one about the reversed bisector, where one of
/// x + a, x + b leaves (−180°, 180°]. If direction x (from ch.x, its angle from ref) lies in
/// the second, that offset is taken a full turn back and the box is the second interval, so
/// that α and β are again the direction's angles with the chords, as a data-ball optimizer
/// reads them. False, with nothing changed, if x lies in neither.
bool reach_other_arc(Chain& ch, std::size_t t, double omega) {
  constexpr double kTurn = 2.0 * kPi;
  for (const double dx : {0.0, kTurn, -kTurn}) {
    const double x = ch.x[t] + dx;
    for (const auto& [da, db] :
         {std::pair{-kTurn, 0.0}, {0.0, -kTurn}, {kTurn, 0.0}, {0.0, kTurn}}) {
      const double a = ch.a[t] + da, b = ch.b[t] + db;
      if (!(std::abs(x + a) <= omega && std::abs(x + b) <= omega)) continue;
      ch.a[t] = a;
      ch.b[t] = b;
      ch.lo[t] = std::max(-omega - a, -omega - b);
      ch.hi[t] = std::min(omega - a, omega - b);
      ch.x[t] = x;
      return true;
    }
  }
  return false;
}

/// Whether direction x of two-sided node t (its angle from ref) lies within Ω of both chords,
/// in either of its intervals (reach_other_arc).
bool within_both_chords(const Chain& ch, std::size_t t, double x, double omega) {
  constexpr double kTurn = 2.0 * kPi;
  return std::abs(std::remainder(x + ch.a[t], kTurn)) <= omega &&
         std::abs(std::remainder(x + ch.b[t], kTurn)) <= omega;
}

/// The elastic pair constraints |α − β| <= this sit just inside 180°, where E_1 is finite.
constexpr double kPairLimit = detail::kElasticaPairLimit;

/// Which directions a scan tries for a node: offsets from its direction by multiples of `step`
/// round the whole circle, those in its box [lo, hi] (`box`) and, for the elastic basis, those
/// in a two-sided node's second interval (reach_other_arc) for Ω = `other_arc` (0: none).
struct ScanGrid {
  double step = kPi / 180.0;
  bool box = true;
  double other_arc = 0.0;
  /// Second intervals narrower than the step, or at stencils turning by less than this, are
  /// skipped (round a gentle turn the curve would wind).
  double other_turn = 0.0;
  std::string_view stage = "coordinate search";  ///< as progress reports see it
};

/// Each free direction to the best of its grid's offsets (the energy of its spans, neighbours
/// held), Gauss–Seidel sweeps until none moves. True if any moved.
bool scan_directions(Chain& ch, const BasicCurveMethod& m, const ScanGrid& grid) {
  const std::size_t k = ch.node.size();
  const int half = static_cast<int>(std::lround(kPi / grid.step));
  bool moved = false;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t t = 0; t < k; ++t) {
      detail::checkpoint(grid.stage, t, k);
      if (ch.fixed[t]) continue;
      // |b − a| is the stencil's turn |ψ| in its first interval and 2π − |ψ| in its second;
      // the other interval is 2Ω − 2π + |b − a| wide.
      const double ba = std::abs(ch.b[t] - ch.a[t]);
      const bool other = grid.other_arc > 0.0 && (ch.closed || (t > 0 && t + 1 < k)) &&
                         std::min(ba, 2.0 * kPi - ba) >= grid.other_turn &&
                         2.0 * (grid.other_arc - kPi) + ba >= grid.step;
      const double old = ch.x[t];
      double best = old, best_e = std::numeric_limits<double>::quiet_NaN();
      for (int o = -half; o < half; ++o) {
        const double x = old + o * grid.step;
        const bool in_box = ch.lo[t] <= x && x <= ch.hi[t];
        if (o == 0 ||
            (in_box ? !grid.box : !(other && within_both_chords(ch, t, x, grid.other_arc))))
          continue;
        if (std::isnan(best_e)) best_e = local_energy(ch, m, t, old);  // (only with candidates)
        const double e = local_energy(ch, m, t, x);
        if (e < best_e) best_e = e, best = x;
      }
      if (best == old) continue;
      ch.x[t] = best;
      if (!(ch.lo[t] <= best && best <= ch.hi[t])) reach_other_arc(ch, t, grid.other_arc);
      changed = moved = true;
    }
  }
  return moved;
}

/// Curve Ensemble's optimizer: a coordinate search over each free direction, first the best of
/// the one-degree offsets it may take (for the elastic basis a node's second interval too, as
/// Curve Ensemble's angles are not boxed about the bisector), then `levels` refinements with
/// steps 4× smaller each, stepping while the energy goes down.
void coordinate_search(Chain& ch, const BasicCurveMethod& m, int levels) {
  const bool elastic = m.basis == MinEnergyBasis::kElastic;
  scan_directions(ch, m, {.other_arc = elastic ? std::min(m.omega, kPairLimit) : 0.0});
  const std::size_t k = ch.node.size();
  double step = kPi / 180.0;
  for (int level = 1; level <= levels; ++level) {
    step /= 4.0;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t t = 0; t < k; ++t) {
        detail::checkpoint("coordinate search", t, k);
        if (ch.fixed[t]) continue;
        const double old = ch.x[t];
        double best = old, best_e = local_energy(ch, m, t, old);
        for (double dirn : {1.0, -1.0}) {  // steps of the current size while they lower it
          for (double x = best + dirn * step; x >= ch.lo[t] && x <= ch.hi[t]; x += dirn * step) {
            const double e = local_energy(ch, m, t, x);
            if (!(e < best_e)) break;
            best_e = e, best = x;
          }
        }
        if (best != old) {
          ch.x[t] = best;
          changed = true;
        }
      }
    }
  }
}

/// search=global's grid step by basis: every free direction takes the multiples of it round
/// the whole circle (in its box, or for the elastic basis within Ω of both chords). The elastic
/// bases' E_1 costs 1-7 µs a call, the cubics' a few ns; the finer grids about each minimum
/// (kGlobalRefine) resolve what the step does not (docs/methods/min-energy.md, "Which minimum":
/// a 2° step for the cubics found the same minima on the stress data at 5 times the cost).
double global_step(MinEnergyBasis basis) {
  switch (basis) {
    case MinEnergyBasis::kElastic:
      return 10.0 * kPi / 180.0;
    case MinEnergyBasis::kRestrictedElastic:
      return 5.0 * kPi / 180.0;
    default:
      return 4.0 * kPi / 180.0;
  }
}

/// A closed chain keeps every span's energies on the grid (as floats: they only rank the grid's
/// points); past this many entries the step is doubled until they fit (~128 MB).
constexpr std::size_t kGlobalTableEntries = std::size_t{1} << 25;

/// The directions a node takes on search=global's grid, with the cosines and sines of its
/// angles to the next chord (α) and the previous one (β).
struct GridChoices {
  std::vector<double> x, ca, sa, cb, sb;
  std::size_t size() const { return x.size(); }
};

/// The multiples of `step` from node t's direction up to `reach` either way (π: the whole
/// circle) that lie in its box or, for other_arc > 0, in a two-sided node's second interval.
GridChoices grid_choices(const Chain& ch, std::size_t t, double step, double reach,
                         double other_arc) {
  GridChoices g;
  auto add = [&](double x) {
    g.x.push_back(x);
    g.ca.push_back(std::cos(x + ch.a[t]));
    g.sa.push_back(std::sin(x + ch.a[t]));
    g.cb.push_back(std::cos(x + ch.b[t]));
    g.sb.push_back(std::sin(x + ch.b[t]));
  };
  add(ch.x[t]);
  if (ch.fixed[t]) return g;
  const std::size_t k = ch.node.size();
  const bool other = other_arc > 0.0 && (ch.closed || (t > 0 && t + 1 < k));
  const int half = static_cast<int>(std::lround(reach / step));
  const bool circle = reach >= kPi;
  for (int o = -half; o < (circle ? half : half + 1); ++o) {
    const double x = ch.x[t] + o * step;
    const bool in_box = ch.lo[t] <= x && x <= ch.hi[t];
    if (o != 0 && (in_box || (other && within_both_chords(ch, t, x, other_arc)))) add(x);
  }
  // Optima often sit on a bound of the box.
  for (const double x : {ch.lo[t], ch.hi[t]}) {
    if (std::isfinite(x) && x != ch.x[t] && std::abs(x - ch.x[t]) <= reach) add(x);
  }
  return g;
}

/// E_1 of a span on the grid, times its weight: infinite where the elastic bases have no piece
/// or the pair constraint fails (the DP never takes it). `hint` follows the elastic root-find
/// along a row of the grid.
double grid_energy(const BasicCurveMethod& m, double w, const GridChoices& gi, std::size_t u,
                   const GridChoices& gj, std::size_t v, detail::ElasticaHint& hint) {
  if (!is_elastic(m.basis)) return w * energy_cs(m, gi.ca[u], gi.sa[u], gj.cb[v], gj.sb[v]).e;
  const double a = std::atan2(gi.sa[u], gi.ca[u]), b = std::atan2(gj.sb[v], gj.cb[v]);
  if (!(std::abs(a - b) <= kPairLimit) || !detail::elastica_feasible(a, b)) {
    return std::numeric_limits<double>::infinity();
  }
  return w * elastic_energy(a, b, hint).e;
}

/// A point of search=global's grid: a choice per node (an index into its GridChoices) and the
/// energy there.
struct GridPath {
  double energy = std::numeric_limits<double>::infinity();
  std::vector<std::uint16_t> choice;
};

/// search=global's dynamic program over the grid: the energy is a sum over spans of terms in
/// their two end directions, so the grid's least energy is found exactly along the chain with
/// O(n K²) evaluations of E_1 for K choices a node. A closed chain is cut at the node with the
/// fewest choices and solved once per choice there, from tables of the spans' energies.
class GridSearch {
 public:
  /// The grid `step` apart within `reach` of each direction of ch (GridChoices).
  GridSearch(const Chain& ch, const BasicCurveMethod& m, double step, double reach)
      : ch_(ch), m_(m), k_(ch.node.size()) {
    other_arc_ = m.basis == MinEnergyBasis::kElastic ? std::min(m.omega, kPairLimit) : 0.0;
    c_.resize(k_);
    std::size_t entries = 0;
    for (step_ = step;; step_ *= 2.0) {
      entries = 0;
      for (std::size_t t = 0; t < k_; ++t) c_[t] = grid_choices(ch, t, step_, reach, other_arc_);
      for (std::size_t s = 0; s < ch.segments(); ++s) {
        entries += c_[s].size() * c_[(s + 1) % k_].size();
      }
      if (!ch.closed || entries <= kGlobalTableEntries) break;
    }
    if (ch.closed) {
      for (std::size_t t = 1; t < k_; ++t)
        if (c_[t].size() < c_[first_].size()) first_ = t;
    }
    if (entries <= kGlobalTableEntries) {  // filled as the passes need the entries
      table_.resize(ch.segments());
      for (std::size_t q = 0; q < table_.size(); ++q) {
        table_[q].assign(c_[order(q)].size() * c_[order(q + 1)].size(),
                         std::numeric_limits<float>::quiet_NaN());
      }
    }
  }

  /// The grid's least energy first, then up to `alternatives` points of other basins whose
  /// energy is least among those that differ from it by at least two steps at some node: at
  /// each node the best through any choice that far from the first's there (its min-marginal),
  /// and on a closed chain the best for each such choice at the cut, in order of energy.
  std::vector<GridPath> paths(std::size_t alternatives) {
    std::vector<GridPath> out(1);
    std::vector<GridPath> cuts;  // per far choice at the cut
    // A closed chain's choices at the cut in order of a lower bound of their least energy: the
    // spans up to the closing one with a free end (one backward pass), plus the closing span's
    // least energy into the choice. Those whose bound is not below the least energy found are
    // skipped (the bound is nearly tight: most chains take one or two passes, not K).
    std::vector<std::pair<double, std::size_t>> cut_order;
    if (ch_.closed) {
      backward(std::nullopt);
      const std::size_t last = order(k_ - 1);
      for (std::size_t cut = 0; cut < c_[first_].size(); ++cut) {
        double close = kInf;
        detail::ElasticaHint hint;
        for (std::size_t u = 0; u < c_[last].size(); ++u) {
          close = std::min(close, energy(k_ - 1, u, cut, hint));
        }
        cut_order.emplace_back(b_[0][cut] + close, cut);
      }
      std::ranges::sort(cut_order);
    } else {
      cut_order.emplace_back(0.0, 0);
    }
    for (const auto& [bound, cut] : cut_order) {
      if (!(bound < out[0].energy)) break;
      forward(cut);
      GridPath p = best_end(cut);
      if (!(p.energy < kInf)) continue;
      if (p.energy < out[0].energy) std::swap(p, out[0]);
      if (p.energy < kInf) cuts.push_back(std::move(p));
    }
    if (!(out[0].energy < kInf)) return {};
    const GridPath& best = out[0];
    std::vector<GridPath> alt;
    for (GridPath& p : cuts)
      if (far(p, best)) alt.push_back(std::move(p));
    if (alternatives > 0) {
      const std::size_t cut = ch_.closed ? best.choice[first_] : 0;
      forward(cut);
      backward(ch_.closed ? std::optional(cut) : std::nullopt);
      for (std::size_t q = ch_.closed ? 1 : 0; q < k_; ++q) {
        const std::size_t t = order(q);
        double least = kInf;
        std::size_t at = 0;
        for (std::size_t u = 0; u < c_[t].size(); ++u) {
          const double e = f_[q][u] + b_[q][u];
          if (e < least && far_choice(t, u, best.choice[t])) least = e, at = u;
        }
        if (least < kInf) alt.push_back(through(q, at, least));
      }
    }
    std::ranges::sort(alt, {}, &GridPath::energy);
    for (GridPath& p : alt) {
      if (out.size() > alternatives) break;
      if (std::ranges::all_of(out, [&](const GridPath& o) { return far(p, o); })) {
        out.push_back(std::move(p));
      }
    }
    return out;
  }

  /// Sets ch's directions to a grid point, with the offsets of nodes taken to their other
  /// interval (reach_other_arc).
  void apply(const GridPath& p, Chain& ch) const {
    for (std::size_t t = 0; t < k_; ++t) {
      const double x = c_[t].x[p.choice[t]];
      if (x == ch.x[t]) continue;
      ch.x[t] = x;
      if (!(ch.lo[t] <= x && x <= ch.hi[t]) && !reach_other_arc(ch, t, other_arc_)) {
        ch.x[t] = std::clamp(x, ch.lo[t], ch.hi[t]);
      }
    }
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();

  std::size_t order(std::size_t q) const { return (first_ + q) % k_; }

  double energy(std::size_t q, std::size_t u, std::size_t v, detail::ElasticaHint& hint) {
    const std::size_t i = order(q), j = order(q + 1);
    if (table_.empty()) return grid_energy(m_, ch_.w[i], c_[i], u, c_[j], v, hint);
    float& e = table_[q][u * c_[j].size() + v];
    if (std::isnan(e)) e = static_cast<float>(grid_energy(m_, ch_.w[i], c_[i], u, c_[j], v, hint));
    return e;
  }

  /// min over u of from[u] + E(u), taking u = first before the others and skipping every u
  /// whose from[u] alone is not below the least so far (the energies are not negative), which
  /// leaves most of the grid's E_1 unevaluated. Returns the least and its u.
  template <class Span>
  static std::pair<double, std::size_t> least(const std::vector<double>& from, std::size_t first,
                                              Span&& span) {
    double best = kInf;
    std::size_t at = 0;
    auto take = [&](std::size_t u) {
      if (!(from[u] < best)) return;
      const double e = from[u] + span(u);
      if (e < best) best = e, at = u;
    };
    take(first);
    for (std::size_t u = 0; u < from.size(); ++u)
      if (u != first) take(u);
    return {best, at};
  }

  /// f_[q][v]: the least energy of the spans before node order(q) with choice v there (from
  /// choice `cut` at the cut of a closed chain), fb_[q][v] the choice at order(q − 1) it takes.
  void forward(std::size_t cut) {
    f_.resize(k_);
    fb_.resize(k_);
    f_[0].assign(c_[order(0)].size(), ch_.closed ? kInf : 0.0);
    if (ch_.closed) f_[0][cut] = 0.0;
    for (std::size_t q = 0; q + 1 < k_; ++q) {
      detail::checkpoint("global search", q, k_);
      const std::size_t j = order(q + 1);
      f_[q + 1].assign(c_[j].size(), kInf);
      fb_[q + 1].assign(c_[j].size(), 0);
      const std::size_t low =
          static_cast<std::size_t>(std::ranges::min_element(f_[q]) - f_[q].begin());
      for (std::size_t v = 0; v < c_[j].size(); ++v) {
        detail::ElasticaHint hint;
        const auto [e, u] = least(f_[q], low, [&](std::size_t u) { return energy(q, u, v, hint); });
        f_[q + 1][v] = e;
        fb_[q + 1][v] = static_cast<std::uint16_t>(u);
      }
    }
  }

  /// b_[q][u]: the least energy of the spans after node order(q) with choice u there (back to
  /// choice `cut` at the cut; none: up to the last node, free), bb_[q][u] the choice at
  /// order(q + 1) it takes.
  void backward(std::optional<std::size_t> cut) {
    b_.resize(k_);
    bb_.resize(k_);
    const std::size_t last = order(k_ - 1);
    b_[k_ - 1].assign(c_[last].size(), 0.0);
    bb_[k_ - 1].assign(c_[last].size(), static_cast<std::uint16_t>(cut.value_or(0)));
    if (cut) {
      for (std::size_t u = 0; u < c_[last].size(); ++u) {
        detail::ElasticaHint hint;
        b_[k_ - 1][u] = energy(k_ - 1, u, *cut, hint);
      }
    }
    for (std::size_t q = k_ - 1; q-- > 0;) {
      detail::checkpoint("global search", k_ - 1 - q, k_);
      const std::size_t i = order(q);
      b_[q].assign(c_[i].size(), kInf);
      bb_[q].assign(c_[i].size(), 0);
      const std::size_t low =
          static_cast<std::size_t>(std::ranges::min_element(b_[q + 1]) - b_[q + 1].begin());
      for (std::size_t u = 0; u < c_[i].size(); ++u) {
        detail::ElasticaHint hint;
        const auto [e, v] =
            least(b_[q + 1], low, [&](std::size_t v) { return energy(q, u, v, hint); });
        b_[q][u] = e;
        bb_[q][u] = static_cast<std::uint16_t>(v);
      }
    }
  }

  /// The least end of the forward pass from `cut`, and its path.
  GridPath best_end(std::size_t cut) {
    GridPath p;
    std::size_t end = 0;
    const std::size_t last = order(k_ - 1);
    for (std::size_t u = 0; u < c_[last].size(); ++u) {
      double e = f_[k_ - 1][u];
      if (ch_.closed && e < kInf) {
        detail::ElasticaHint hint;
        e += energy(k_ - 1, u, cut, hint);
      }
      if (e < p.energy) p.energy = e, end = u;
    }
    if (p.energy < kInf) p.choice = back_from(k_ - 1, end);
    return p;
  }

  /// The forward pass's path ending at choice u of node order(q) (nodes after it unset).
  std::vector<std::uint16_t> back_from(std::size_t q, std::size_t u) const {
    std::vector<std::uint16_t> choice(k_, 0);
    choice[order(q)] = static_cast<std::uint16_t>(u);
    for (std::size_t p = q; p > 0; --p) choice[order(p - 1)] = fb_[p][choice[order(p)]];
    return choice;
  }

  /// The least path through choice u of node order(q).
  GridPath through(std::size_t q, std::size_t u, double energy) const {
    GridPath p{energy, back_from(q, u)};
    for (std::size_t r = q; r + 1 < k_; ++r) p.choice[order(r + 1)] = bb_[r][p.choice[order(r)]];
    return p;
  }

  bool far_choice(std::size_t t, std::size_t u, std::size_t v) const {
    return std::abs(std::remainder(c_[t].x[u] - c_[t].x[v], 2.0 * kPi)) > 1.5 * step_;
  }
  bool far(const GridPath& p, const GridPath& o) const {
    for (std::size_t t = 0; t < k_; ++t)
      if (far_choice(t, p.choice[t], o.choice[t])) return true;
    return false;
  }

  const Chain& ch_;
  const BasicCurveMethod& m_;
  std::size_t k_;
  double other_arc_ = 0.0, step_ = 0.0;
  std::size_t first_ = 0;
  std::vector<GridChoices> c_;
  std::vector<std::vector<float>> table_;
  std::vector<std::vector<double>> f_, b_;
  std::vector<std::vector<std::uint16_t>> fb_, bb_;
};

bool settled(const ChainResult& r) {
  return r.converged || r.at_precision;
}

/// Adds the work counted in `from` to `to`.
void add_work(ChainResult& to, const ChainResult& from) {
  to.iterations += from.iterations;
  to.window_passes += from.window_passes;
  to.windows += from.windows;
  to.window_iterations += from.window_iterations;
}

/// Takes the directions of `from` (a copy of `to` that an optimizer moved), with the offsets
/// and boxes of the nodes it turned to their other interval.
void take_directions(Chain& to, const Chain& from) {
  to.x = from.x;
  std::ranges::copy(from.a, to.a.begin());
  std::ranges::copy(from.b, to.b.begin());
  std::ranges::copy(from.lo, to.lo.begin());
  std::ranges::copy(from.hi, to.hi.begin());
}

/// How uncertain it is that a chain result is a minimum: 0 settled, 1 settled only with a ridge
/// kept locked against its force (docs/methods/elastic.md, "Ridges"), 2 not settled.
int doubt(const ChainResult& r) {
  return !settled(r) ? 2 : r.ridge_kept ? 1 : 0;
}

/// search=coordinate or global: their minimum (`ch`, from `r`) against search=newton's (`alt`,
/// from `by_newton`). Newton's is kept where it is more certainly a minimum, or as certain and
/// lower; else the search's, marked by_search where it is lower beyond rounding (not the same
/// minimum found twice).
ChainResult keep_lower(Chain& ch, ChainResult r, const Chain& alt, const ChainResult& by_newton,
                       const BasicCurveMethod& m) {
  Evaluation ev;
  const double newton = evaluate(alt, m, alt.x, false, ev), own = evaluate(ch, m, ch.x, false, ev);
  if (doubt(by_newton) != doubt(r) ? doubt(by_newton) < doubt(r) : newton < own) {
    take_directions(ch, alt);
    return by_newton;
  }
  r.by_search = own < newton - 1e-12 * std::abs(newton);
  return r;
}

void start_quadratic(Chain& ch, const BasicCurveMethod& m, double gscale);
ChainResult optimize_global(Chain& ch, const MinEnergyOptions& opt, double gscale);

/// The box-constrained optimum from the start the options' search asks for. search=coordinate
/// or global, `full`: the lower of that and search=newton's (from the quadratic model's start),
/// so never above it.
ChainResult optimize_searched(Chain& ch, const MinEnergyOptions& opt, double gscale, bool full) {
  if (opt.search == MinEnergySearch::kNewton) return optimize(ch, opt, gscale);
  Chain alt;
  ChainResult by_newton;
  if (full) {
    alt = ch;
    start_quadratic(alt, opt.method, gscale);
    by_newton = optimize(alt, opt, gscale);
  }
  ChainResult r;
  if (opt.search == MinEnergySearch::kGlobal) {
    r = optimize_global(ch, opt, gscale);
  } else {
    coordinate_search(ch, opt.method, 0);
    r = optimize(ch, opt, gscale);
  }
  return full ? keep_lower(ch, r, alt, by_newton, opt.method) : r;
}

// ---- the elastic basis: coupled constraints |α − β| <= π between neighbouring directions ----

/// Per segment s (nodes i = s, j = s + 1): lo[s] <= x_i − x_j <= hi[s] keeps |α − β| <= limit.
struct PairBounds {
  std::vector<double> lo, hi;
};

PairBounds pair_bounds(const Chain& ch, double limit) {
  const std::size_t k = ch.node.size(), segs = ch.segments();
  PairBounds p;
  p.lo.resize(segs);
  p.hi.resize(segs);
  for (std::size_t s = 0; s < segs; ++s) {
    const std::size_t i = s, j = s + 1 == k ? 0 : s + 1;
    // α − β = x_i − x_j + (a_i − b_j).
    const double d = ch.a[i] - ch.b[j];
    p.lo[s] = -limit - d;
    p.hi[s] = limit - d;
  }
  return p;
}

/// Groups of nodes joined by active pair constraints: the reduced problem has one unknown per
/// group (its nodes move together), and its Hessian stays (cyclic) tridiagonal.
struct Groups {
  std::vector<std::size_t> of;     ///< per node: its group
  std::vector<std::size_t> first;  ///< per group: its first node (chain order)
  std::vector<std::size_t> size;   ///< per group: its number of nodes
  bool cyclic = false;             ///< the last group couples to the first (closed chain)
};

/// `link[s]` != 0: segment s's pair constraint is active. A closed chain with every link active
/// keeps the last one inactive (one group would otherwise be over-determined).
Groups make_groups(const Chain& ch, std::vector<signed char>& link) {
  const std::size_t k = ch.node.size(), segs = ch.segments();
  Groups g;
  g.of.assign(k, 0);
  std::size_t start = 0;
  if (ch.closed) {
    bool all = true;
    for (std::size_t s = 0; s < segs; ++s) all = all && link[s] != 0;
    if (all && segs > 0) link[segs - 1] = 0;
    // Start after an inactive link so that no group wraps around.
    for (std::size_t s = 0; s < segs; ++s) {
      if (!link[s]) {
        start = s + 1 == k ? 0 : s + 1;
        break;
      }
    }
  }
  for (std::size_t c = 0; c < k; ++c) {
    const std::size_t t = (start + c) % k;
    const std::size_t prev = t == 0 ? k - 1 : t - 1;  // segment from prev to t
    const bool joined = c > 0 && link[prev] != 0;
    if (!joined) {
      g.first.push_back(t);
      g.size.push_back(0);
    }
    g.of[t] = g.first.size() - 1;
    ++g.size.back();
  }
  g.cyclic = ch.closed && g.first.size() > 2;
  return g;
}

/// The end angles of segment s at x.
std::pair<double, double> segment_angles(const Chain& ch, std::span<const double> x,
                                         std::size_t s) {
  const std::size_t j = s + 1 == ch.node.size() ? 0 : s + 1;
  return {x[s] + ch.a[s], x[j] + ch.b[j]};
}

/// On α = β beyond 98.5° E_1 has a convex kink across the diagonal (a V in α − β): a nonsmooth
/// minimum that Newton steps would cross back and forth. A segment there is locked at α = β (a
/// link of state kRidge) while the force through it stays within the kink's subgradient.
using detail::elastica_ridge_capable;

constexpr signed char kRidge = 2;
/// How far a released ridge's start direction is moved off it (radians).
constexpr double kRidgeStep = 1e-7;

/// Replaces the contributions of locked ridge segments by the symmetric (mean) gradient and
/// Hessian at α = β (elastica_energy's value on the diagonal); returns per segment the half
/// width c of the subgradient across the ridge (∂E/∂(α − β) jumps from −c to c), 0 elsewhere.
void apply_ridges(const Chain& ch, std::span<const signed char> link, Evaluation& ev,
                  std::vector<double>& half_jump) {
  const std::size_t k = ch.node.size();
  half_jump.assign(link.size(), 0.0);
  for (std::size_t s = 0; s < link.size(); ++s) {
    if (link[s] != kRidge) continue;
    const std::size_t j = s + 1 == k ? 0 : s + 1;
    const auto [alpha, beta] = segment_angles(ch, ch.x, s);
    const double mid = 0.5 * (alpha + beta), w = ch.w[s];
    const detail::ElasticaEnergy now = detail::elastica_energy(alpha, beta);
    const detail::ElasticaEnergy on = detail::elastica_energy(mid, mid);
    ev.g[s] += w * (on.ea - now.ea);
    ev.g[j] += w * (on.eb - now.eb);
    ev.d[s] += w * (on.eaa - now.eaa);
    ev.d[j] += w * (on.ebb - now.ebb);
    ev.e[s] += w * (on.eab - now.eab);
    half_jump[s] = w * detail::elastica_ridge_half_jump(mid, on);
  }
}

/// Active-set Newton for the elastic basis from a feasible ch.x: boxes on each direction and
/// the pair constraints. Each iteration solves the reduced (cyclic) tridiagonal system in
/// O(n), moves to the first constraint on the way (ratio test) or takes an Armijo step, and,
/// once stationary on the current face, releases the constraint whose multiplier has the
/// wrong sign. The residual is the largest of the reduced gradient and the multipliers' sign
/// violations, relative to the gradient's scale.
ChainResult optimize_coupled(Chain& ch, const MinEnergyOptions& opt, double gscale,
                             const PairBounds& pb) {
  const BasicCurveMethod& m = opt.method;
  const std::size_t k = ch.node.size(), segs = ch.segments();
  Evaluation ev, trial;
  Scratch work;
  detail::BlockVector<double> xn(k);
  std::vector<double> dir(k), dd, ee, rhs, stop;
  std::vector<std::size_t> stop_node;
  std::vector<signed char> box(k, 0), link(segs, 0);
  const double tol = opt.tolerance;
  auto pair_value = [&](std::span<const double> x, std::size_t s) {
    return x[s] - x[s + 1 == k ? 0 : s + 1];
  };
  for (std::size_t t = 0; t < k; ++t) {
    if (ch.fixed[t] || ch.x[t] <= ch.lo[t]) box[t] = -1;
    if (!ch.fixed[t] && ch.x[t] >= ch.hi[t]) box[t] = 1;
  }
  for (std::size_t s = 0; s < segs; ++s) {
    const double v = pair_value(ch.x, s);
    if (v <= pb.lo[s]) link[s] = -1;
    if (v >= pb.hi[s]) link[s] = 1;
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> half_jump;
  // A free segment exactly on a ridge (at the start, or when both its nodes' boxes held it there
  // and one is released) is locked on it: its derivatives there are the kink's, not a side's.
  // Moves node t by `by` if that keeps its box and the pair constraints of its two spans.
  auto nudge = [&](std::size_t t, double by) {
    const double x = ch.x[t] + by;
    if (x < ch.lo[t] || x > ch.hi[t] || ch.fixed[t]) return false;
    const bool has_next = ch.closed || t + 1 < k, has_prev = ch.closed || t > 0;
    const std::size_t next = t + 1 == k ? 0 : t + 1, prev = t == 0 ? k - 1 : t - 1;
    if (has_next && (x - ch.x[next] < pb.lo[t] || x - ch.x[next] > pb.hi[t])) return false;
    if (has_prev && (ch.x[prev] - x < pb.lo[prev] || ch.x[prev] - x > pb.hi[prev])) return false;
    ch.x[t] = x;
    return true;
  };
  auto lock_ridges = [&] {
    for (std::size_t s = 0; s < segs; ++s) {
      const auto [alpha, beta] = segment_angles(ch, ch.x, s);
      if (!link[s] && alpha == beta && elastica_ridge_capable(alpha, beta)) link[s] = kRidge;
    }
  };
  lock_ridges();
  // Every fresh evaluation gets the ridges' mean derivatives.
  auto refresh = [&] {
    const double e = evaluate(ch, m, ch.x, true, ev);
    apply_ridges(ch, link, ev, half_jump);
    return e;
  };
  double energy = refresh();
  ChainResult res;
  int flat = 0;        // consecutive Newton steps that changed the energy by rounding only
  bool stuck = false;  // the last Newton direction had no step that lowered the energy
  std::vector<char> released(segs, 0);  // ridges released since the last step
  // A ridge released and locked again without the energy going down is kept: the estimate of
  // its subgradient (a difference of one-sided gradients) is then not sharp enough to decide.
  std::vector<int> ridge_releases(segs, 0);
  double last_slope = 0.0;
  double last_step = std::numeric_limits<double>::infinity();  // largest |Newton step| (rad)
  if (!std::isfinite(energy)) {  // no feasible start (reported by the caller)
    res.no_start = true;
    for (std::size_t s = 0; s < segs; ++s) {
      const auto [alpha, beta] = segment_angles(ch, ch.x, s);
      if (!detail::elastica_feasible(alpha, beta)) {
        res.worst = s;
        break;
      }
    }
    return res;
  }
  for (res.iterations = 0; res.iterations <= detail::iteration_limit(opt); ++res.iterations) {
    detail::checkpoint("newton", static_cast<std::size_t>(res.iterations));
    const Groups g = make_groups(ch, link);
    const std::size_t G = g.first.size();
    // Reduced gradient, Hessian; a group with a bound or fixed node does not move.
    std::vector<double> gg(G, 0.0), gd(G, 0.0), ge(G, 0.0);
    std::vector<int> bound_nodes(G, 0);
    for (std::size_t t = 0; t < k; ++t) {
      gg[g.of[t]] += ev.g[t];
      gd[g.of[t]] += ev.d[t];
      if (box[t]) ++bound_nodes[g.of[t]];
    }
    for (std::size_t s = 0; s < segs; ++s) {
      const std::size_t i = s, j = s + 1 == k ? 0 : s + 1, a = g.of[i], b = g.of[j];
      if (a == b) {
        gd[a] += 2.0 * ev.e[s];  // both ends move together
      } else if ((a + 1) % G == b) {
        ge[a] += ev.e[s];
      } else {
        ge[b] += ev.e[s];  // (G = 2, closed: both links couple the two groups)
      }
    }
    double residual = 0.0;
    for (std::size_t a = 0; a < G; ++a) {
      if (!bound_nodes[a] && std::abs(gg[a]) / gscale > residual) {
        residual = std::abs(gg[a]) / gscale;
        res.worst = g.first[a];
      }
    }
    // The elastic energy's derivatives come from root-finds: when Newton steps stop changing
    // the energy (the decrease they predict, −g·d/2, below its rounding) or no step lowers it,
    // with the residual below kElasticPrecision, the face is stationary to what double
    // precision allows here; also at any residual when no step lowers the energy and the
    // Newton step itself is below kStepPrecision. (Steps that change the energy by rounding
    // only are still taken: near |α − β| = 180°, where E_1 goes like Θ^{3/2}, the residual
    // fell from 4e-5 to 1e-10 that way.)
    const bool stalled =
        (residual <= kElasticPrecision &&
         (stuck || (flat >= 3 && -0.5 * last_slope <= 1e-13 * std::abs(energy)))) ||
        (stuck && last_step <= kStepPrecision);
    // Multipliers once stationary on the face: the worst sign violation is released. Also when
    // stationary only to precision: a face whose reduced gradient stalls above tol is still
    // the wrong face when a multiplier has the wrong sign (issue 18: closed 3–4-point curves
    // stopped on |α − β| = 180° with the energy going down off it). A wrong sign within the
    // residual itself is not resolved by the derivatives.
    double worst = 0.0, kept_worst = 0.0;  // (kept: over the ridges kept locked)
    std::size_t worst_box = k, worst_link = segs;
    // Per group, its worst wrong-signed box or (non-ridge) link: released together, one per
    // group, when no ridge is the worst (one release per stationary point took a global
    // re-solve each: a 10⁴-point elastic walk reached the 200-iteration cap).
    std::vector<double> group_worst;
    std::vector<std::size_t> group_box, group_link;
    auto note = [&](std::size_t a, double v, std::size_t t, std::size_t s) {
      if (v > group_worst[a]) group_worst[a] = v, group_box[a] = t, group_link[a] = s;
    };
    struct RidgeForce {
      double violation;  ///< |force| beyond the half-jump, relative
      std::size_t s;
      double force;
    };
    std::vector<RidgeForce> ridge_forces;
    if (residual <= tol || stalled) {
      group_worst.assign(G, 0.0);
      group_box.assign(G, k);
      group_link.assign(G, segs);
      for (std::size_t t = 0; t < k; ++t) {
        if (!box[t] || ch.fixed[t] || bound_nodes[g.of[t]] != 1) continue;
        const double v = box[t] < 0 ? -gg[g.of[t]] : gg[g.of[t]];  // > 0: pulls inwards
        if (v / gscale > worst) worst = v / gscale, worst_box = t, worst_link = segs;
        note(g.of[t], v / gscale, t, segs);
      }
      for (std::size_t a = 0; a < G; ++a) {
        // The force through link u (node u to u+1 of the group) balances the gradients on the
        // side that holds no bound node: the prefix sum, or minus the suffix sum.
        const std::size_t first = g.first[a], n = g.size[a];
        std::size_t lo_b = n, hi_b = n;
        for (std::size_t u = 0; u < n; ++u) {
          if (!box[(first + u) % k]) continue;
          if (lo_b == n) lo_b = u;
          hi_b = u;
        }
        double total = 0.0;
        for (std::size_t u = 0; u < n; ++u) total += ev.g[(first + u) % k];
        double prefix = 0.0;
        for (std::size_t u = 0; u + 1 < n; ++u) {
          const std::size_t s = (first + u) % k;  // the segment from this node to the next
          prefix += ev.g[s];
          double force = 0.0;
          if (lo_b == n || u < lo_b) {
            force = prefix;
          } else if (u >= hi_b) {
            force = prefix - total;
          } else {
            continue;  // between two bound nodes: not determined
          }
          // At the upper bound the multiplier is −force (>= 0), at the lower bound +force; a
          // ridge holds while |force| is within its subgradient.
          if (link[s] == kRidge && ridge_releases[s] >= 2) {
            kept_worst = std::max(kept_worst, (std::abs(force) - half_jump[s]) / gscale);
            continue;
          }
          const double v = link[s] == kRidge ? std::abs(force) - half_jump[s]
                           : link[s] > 0     ? force
                                             : -force;
          if (v / gscale > worst) worst = v / gscale, worst_link = s, worst_box = k;
          if (link[s] != kRidge) note(a, v / gscale, k, s);
          if (link[s] == kRidge) ridge_forces.push_back({v / gscale, s, force});
        }
        if (bound_nodes[a] < 2) continue;
        // Between two bound nodes the multipliers are not unique: KKT holds when some choice
        // has every sign right. The link multiplier λ_u = λ_{u−1} − g_u − (box reaction) is
        // propagated as an interval; its distance from what the signs allow is the violation.
        double lam_lo = 0.0, lam_hi = 0.0, gap = 0.0, pull = 0.0;
        std::size_t puller = k;
        for (std::size_t u = 0; u < n; ++u) {
          const std::size_t t = (first + u) % k;
          lam_lo -= ev.g[t];
          lam_hi -= ev.g[t];
          if (box[t] && ch.fixed[t]) lam_lo = -kInf, lam_hi = kInf;
          if (box[t] < 0 && !ch.fixed[t]) lam_hi = kInf;
          if (box[t] > 0) lam_lo = -kInf;
          // A bound node pulled inwards by its own gradient is the one to release.
          const double v = box[t] < 0 ? -ev.g[t] : box[t] > 0 ? ev.g[t] : 0.0;
          if (box[t] && !ch.fixed[t] && v > pull) pull = v, puller = t;
          double allow_lo = 0.0, allow_hi = 0.0;  // past the group's last node: λ = 0
          if (u + 1 < n) {
            const signed char l = link[t];
            const bool kept = l == kRidge && ridge_releases[t] >= 2;
            allow_lo = l > 0 && l != kRidge ? 0.0 : l == kRidge && !kept ? -half_jump[t] : -kInf;
            allow_hi = l < 0 ? 0.0 : l == kRidge && !kept ? half_jump[t] : kInf;
          }
          if (lam_hi < allow_lo) {
            gap = std::max(gap, allow_lo - lam_hi), lam_lo = lam_hi = allow_lo;
          } else if (lam_lo > allow_hi) {
            gap = std::max(gap, lam_lo - allow_hi), lam_lo = lam_hi = allow_hi;
          } else {
            lam_lo = std::max(lam_lo, allow_lo), lam_hi = std::min(lam_hi, allow_hi);
          }
        }
        if (puller == k) continue;  // (then no single box is the one to release)
        if (gap / gscale > worst) worst = gap / gscale, worst_box = puller, worst_link = segs;
        note(a, gap / gscale, puller, segs);
      }
      res.pg = std::max(residual, worst);
      if (worst > residual) res.worst = worst_box < k ? worst_box : worst_link;
      if (worst <= std::max(tol, residual)) {
        res.converged = residual <= tol;
        res.at_precision = !res.converged;
        res.ridge_kept = kept_worst > std::max(tol, residual);
        return res;
      }
      stuck = false;
      flat = 0;
      // Released together: in every group its worst wrong-signed box or link, and every ridge
      // whose force exceeds its kink's half-jump. (One ridge per stationary point cost a Newton
      // re-solve each: 800–1900-point sharp walks with dozens of ridges to leave stopped at the
      // 200-iteration cap; all at once, 64–100 iterations.)
      const double floor_v = std::max(tol, residual);
      for (std::size_t a = 0; a < G; ++a) {
        if (!(group_worst[a] > floor_v)) continue;
        if (group_box[a] < k) box[group_box[a]] = 0;
        if (group_link[a] < segs) link[group_link[a]] = 0;
      }
      for (const RidgeForce& r : ridge_forces) {
        if (!(r.violation > floor_v) || link[r.s] != kRidge) continue;
        // A released ridge may be crossed by the next step (the force says the optimum lies
        // beyond it): it is stepped off to the side where the energy goes down (first order:
        // the force beyond the half-jump), so that the next derivatives are that side's; by its
        // end node when its start node is held at its box.
        // (Only where the move keeps its box and the pair constraints of both its spans: a
        // neighbouring span on |α − β| = 180° went beyond it, to an infinite energy.)
        released[r.s] = 1;
        ++ridge_releases[r.s];
        const std::size_t t = r.s, j = t + 1 == k ? 0 : t + 1;
        const double off = std::copysign(kRidgeStep, r.force);
        if (!nudge(t, -off)) (void)nudge(j, off);
        link[r.s] = 0;
      }
      lock_ridges();
      energy = refresh();
      continue;
    }
    res.pg = residual;
    if (res.iterations == detail::iteration_limit(opt)) break;
    // Reduced Newton step, shifted until positive definite.
    const double unit_pivot = pivot_unit(gscale);
    dd.assign(G, unit_pivot);
    ee.assign(G, 0.0);
    rhs.assign(G, 0.0);
    double tau = 0.0, dmax = 0.0;
    for (double v : gd) dmax = std::max(dmax, std::abs(v));
    for (int attempt = 0; attempt < 60; ++attempt) {
      for (std::size_t a = 0; a < G; ++a) {
        const bool fixed_a = bound_nodes[a] > 0, fixed_b = bound_nodes[(a + 1) % G] > 0;
        dd[a] = fixed_a ? unit_pivot : gd[a] + tau;
        ee[a] = fixed_a || fixed_b ? 0.0 : ge[a];
        rhs[a] = fixed_a ? 0.0 : -gg[a];
      }
      if (!g.cyclic && !(ch.closed && G == 2)) ee[G - 1] = 0.0;
      if (ch.closed && G == 2) {
        ee[0] = bound_nodes[0] || bound_nodes[1] ? 0.0 : ge[0] + ge[1];
        ee[1] = 0.0;
      }
      if (G == 1) ee[0] = 0.0;
      if (ldl_solve(dd, ee, g.cyclic, rhs, work) == Factor::kOk) break;
      tau = tau == 0.0 ? 1e-10 * std::max(dmax, gscale) : 4.0 * tau;
    }
    for (std::size_t t = 0; t < k; ++t) dir[t] = rhs[g.of[t]];
    // The path: each group moves along its Newton direction until something stops it, then
    // stays: its first node reaching its box, or a pair constraint or ridge between it and a
    // neighbouring group (which stops both). The path is feasible and piecewise linear, and
    // everything met on it becomes active, many constraints per step (a ratio test adding one
    // per iteration left a 10⁴-point walk at the iteration cap). Stops are events in time
    // order; a stop changes only the times of the links at its group's two ends.
    stop.assign(G, kInf);
    stop_node.assign(G, k);
    std::vector<double> box_at(G, kInf), link_at(segs, kInf), fired_at(segs, kInf);
    std::vector<std::size_t> box_node(G, k);
    std::vector<signed char> link_state(segs, 0);
    for (std::size_t t = 0; t < k; ++t) {
      if (box[t] || dir[t] == 0.0) continue;
      const double room = dir[t] > 0.0 ? ch.hi[t] - ch.x[t] : ch.lo[t] - ch.x[t];
      const double s = std::max(0.0, room / dir[t]);
      if (s < box_at[g.of[t]]) box_at[g.of[t]] = s, box_node[g.of[t]] = t;
    }
    auto moved = [&](std::size_t t, double sigma) {
      return dir[t] * std::min(sigma, stop[g.of[t]]);
    };
    // First σ at which x_i − x_j (value v0 now, segment s) reaches `level` from below (up) or
    // above, given the stops known so far; kInf if it never does.
    auto reach = [&](std::size_t s, double v0, double level, bool up) {
      const std::size_t i = s, j = s + 1 == k ? 0 : s + 1;
      const double si = stop[g.of[i]], sj = stop[g.of[j]];
      const double at[4] = {0.0, std::min(si, sj), std::max(si, sj), kInf};
      double v = v0;
      for (int p = 0; p < 3; ++p) {
        if (!(at[p + 1] > at[p])) continue;
        const double slope = (at[p] < si ? dir[i] : 0.0) - (at[p] < sj ? dir[j] : 0.0);
        if (up ? slope > 0.0 : slope < 0.0) {
          const double t = at[p] + std::max(0.0, (level - v) / slope);
          if (t <= at[p + 1]) return t;
        }
        if (at[p + 1] < kInf) v += slope * (at[p + 1] - at[p]);
      }
      return kInf;
    };
    using Event = std::pair<double, std::size_t>;  // (σ, segment or segs + group)
    std::priority_queue<Event, std::vector<Event>, std::greater<>> events;
    auto schedule = [&](std::size_t s, double now) {
      link_at[s] = kInf;
      if (link[s] || fired_at[s] < kInf) return;
      const double v = pair_value(ch.x, s);
      const double hi_at = reach(s, v, pb.hi[s], true), lo_at = reach(s, v, pb.lo[s], false);
      if (hi_at < link_at[s]) link_at[s] = hi_at, link_state[s] = 1;
      if (lo_at < link_at[s]) link_at[s] = lo_at, link_state[s] = -1;
      // Crossing the ridge α = β of a U-turn segment: stop on it.
      const auto [alpha, beta] = segment_angles(ch, ch.x, s);
      if (!released[s] && elastica_ridge_capable(alpha, beta) && alpha != beta) {
        const double cross_at = reach(s, alpha - beta, 0.0, alpha < beta);
        if (cross_at < link_at[s]) link_at[s] = cross_at, link_state[s] = kRidge;
      }
      if (link_at[s] < 1.0) link_at[s] = std::max(link_at[s], now), events.push({link_at[s], s});
    };
    auto halt = [&](std::size_t a, double now) {  // group a stops at σ = now
      stop[a] = now;
      const std::size_t f = g.first[a], last = (f + g.size[a] - 1) % k;
      if (ch.closed || f > 0) schedule(f == 0 ? k - 1 : f - 1, now);
      if (ch.closed || last + 1 < k) schedule(last, now);
    };
    for (std::size_t a = 0; a < G; ++a) {
      if (box_at[a] < 1.0) events.push({box_at[a], segs + a});
    }
    for (std::size_t s = 0; s < segs; ++s) schedule(s, 0.0);
    while (!events.empty()) {
      const auto [now, id] = events.top();
      events.pop();
      if (id >= segs) {
        const std::size_t a = id - segs;
        if (stop[a] < kInf) continue;
        stop_node[a] = box_node[a];
        halt(a, now);
        continue;
      }
      if (link_at[id] != now) continue;  // rescheduled since
      fired_at[id] = now;
      const std::size_t ga = g.of[id], gb = g.of[id + 1 == k ? 0 : id + 1];
      if (stop[ga] == kInf) halt(ga, now);
      if (stop[gb] == kInf) halt(gb, now);
    }
    std::fill(released.begin(), released.end(), 0);
    double slope = 0.0;
    for (std::size_t t = 0; t < k; ++t) slope += ev.g[t] * dir[t];
    last_slope = slope;
    last_step = 0.0;
    for (std::size_t t = 0; t < k; ++t) last_step = std::max(last_step, std::abs(dir[t]));
    bool accepted = false;
    double taken = 0.0;
    // A full step whose predicted decrease is within the energy's rounding is judged by that
    // rounding (as in optimize): else a gradient of 1e-6 on a stiff node, whose Newton step
    // lowers the energy by 1e-17 of it, stays unresolved.
    const double rounding = 1e-12 * std::abs(energy) * std::sqrt(static_cast<double>(k));
    for (double step = 1.0; step > 1e-14; step *= 0.5) {
      double predicted = 0.0;
      for (std::size_t t = 0; t < k; ++t) {
        const double dx = moved(t, step);
        predicted += ev.g[t] * dx;
        xn[t] = std::clamp(ch.x[t] + dx, ch.lo[t], ch.hi[t]);
      }
      if (!(predicted < 0.0)) continue;
      const double en = evaluate(ch, m, xn, true, trial);
      const bool within = step == 1.0 && -predicted <= rounding && en <= energy + rounding;
      if (en <= energy + 1e-4 * predicted || (step == 1.0 && en <= energy) || within) {
        ch.x.swap(xn);
        std::swap(ev, trial);
        apply_ridges(ch, link, ev, half_jump);
        flat = energy - en <= 1e-14 * std::abs(energy) ? flat + 1 : 0;
        energy = en;
        accepted = true;
        taken = step;
        break;
      }
    }
    // What the step reached becomes active: the boxes of groups that stopped, and the pairs and
    // ridges that stopped them. Without a step, what the path meets within 1e-9 (a node a
    // rounding error off its bound, whose direction points out of it: no step along the path
    // changes the energy by more than its rounding, and the face must change to go on).
    const double reached = accepted ? taken : 1e-9;
    bool activated = false, snapped = false;
    for (std::size_t a = 0; a < G; ++a) {
      const std::size_t t = stop_node[a];
      if (t == k || stop[a] > reached) continue;
      ch.x[t] = dir[t] > 0.0 ? ch.hi[t] : ch.lo[t];
      box[t] = dir[t] > 0.0 ? 1 : -1;
      activated = snapped = true;
    }
    for (std::size_t s = 0; s < segs; ++s) {
      if (fired_at[s] > reached) continue;
      link[s] = link_state[s];
      activated = true;
      snapped = snapped || link_state[s] == kRidge;
    }
    if (snapped) energy = refresh();
    if (activated) {
      stuck = false;
      continue;
    }
    if (!accepted) {
      // No step lowers the energy: with the residual within the derivatives' own accuracy that
      // is the face's optimum to double precision (the stress suite's walks stopped at 5e-10 to
      // 3e-9); the next iteration checks its multipliers.
      if (residual > kElasticPrecision || stuck) break;
      stuck = true;
      continue;
    }
    stuck = false;
  }
  return res;
}

/// Whether every free direction of ch.x lies in its box with its end angles inside the
/// s-curves' domain (on a box at 180° an angle wraps: a closed curve with a half turn then met
/// an infeasible piece) and meets the pair constraints `pb` to within `slack`.
bool meets_pairs(const Chain& ch, const PairBounds& pb, double slack) {
  const std::size_t k = ch.node.size(), segs = ch.segments();
  for (std::size_t t = 0; t < k; ++t) {
    const double x = ch.x[t];
    if (!ch.fixed[t] && !(ch.lo[t] <= x && x <= ch.hi[t] &&
                          std::max(std::abs(x + ch.a[t]), std::abs(x + ch.b[t])) < kPairLimit)) {
      return false;
    }
  }
  for (std::size_t s = 0; s < segs; ++s) {
    const double v = ch.x[s] - ch.x[s + 1 == k ? 0 : s + 1];
    if (!(pb.lo[s] - slack <= v && v <= pb.hi[s] + slack)) return false;
  }
  return true;
}

/// The restricted elastic spline (boxes |α|, |β| <= 90°, where every pair is feasible; a clamped
/// neighbour's pair becomes a box), then the active-set Newton on the whole s-curve domain from
/// there: the minimum reached from the restricted optimum.
ChainResult elastic_descent(Chain& ch, const MinEnergyOptions& opt, double gscale,
                            const PairBounds& pb) {
  const std::size_t k = ch.node.size();
  Chain start = ch;
  // Held: fixed, or a restricted box found empty below. Each node's box is also bounded by its
  // pair constraints with held neighbours, so that the start satisfies every pair constraint
  // (its free pairs by |α|, |β| <= 90°); a node held later sends its neighbours back here.
  std::vector<char> held(ch.fixed.begin(), ch.fixed.end());
  std::vector<std::size_t> work;
  for (std::size_t t = k; t-- > 0;) {
    if (!ch.fixed[t]) work.push_back(t);
  }
  while (!work.empty()) {
    const std::size_t t = work.back();
    work.pop_back();
    if (held[t]) continue;
    const bool has_next = ch.closed || t + 1 < k, has_prev = ch.closed || t > 0;
    const std::size_t next = t + 1 == k ? 0 : t + 1, prev = t == 0 ? k - 1 : t - 1;
    // What the elastic problem allows this direction given its held neighbours.
    double flo = ch.lo[t], fhi = ch.hi[t];
    if (has_next && held[next]) {  // lo <= x_t − x_next <= hi (segment t)
      flo = std::max(flo, pb.lo[t] + start.x[next]);
      fhi = std::min(fhi, pb.hi[t] + start.x[next]);
    }
    if (has_prev && held[prev]) {  // segment prev: lo <= x_prev − x_t <= hi
      flo = std::max(flo, start.x[prev] - pb.hi[prev]);
      fhi = std::min(fhi, start.x[prev] - pb.lo[prev]);
    }
    // (1e-6 inside the box: its corners (±90°, ∓90°) sit on the pair bound |α − β| = 180°,
    // where the second derivatives do not exist.)
    constexpr double kHalf = kPi / 2.0 - 1e-6;
    const double a = ch.a[t], b = ch.b[t];
    const double blo = std::max(-kHalf - a, -kHalf - b), bhi = std::min(kHalf - a, kHalf - b);
    const double lo = std::max(flo, blo), hi = std::min(fhi, bhi);
    if (lo <= hi) {
      start.lo[t] = lo;
      start.hi[t] = hi;
      start.x[t] = std::clamp(0.0, lo, hi);
      continue;
    }
    // Empty (a stencil within 1e-6 of 180°, or a held neighbour): hold the direction at the
    // allowed point nearest the box's middle. (The middle of box and pair bounds together broke
    // a pair constraint with a clamped neighbour: the coupled phase then started at an infinite
    // energy, closed 3-point curves with a start tangent in issue 18. The whole elastic box
    // instead let this phase break pair constraints, whose infinite energies shrank every step
    // to nothing: a nearly collinear closed 4-point curve.)
    const double x = flo <= fhi ? std::clamp(0.5 * (blo + bhi), flo, fhi) : 0.5 * (flo + fhi);
    start.lo[t] = start.hi[t] = start.x[t] = x;
    held[t] = 1;
    if (has_next) work.push_back(next);
    if (has_prev) work.push_back(prev);
  }
  MinEnergyOptions restricted = opt;
  restricted.method.basis = MinEnergyBasis::kRestrictedElastic;
  const ChainResult first = optimize_searched(start, restricted, gscale, false);
  ch.x = start.x;
  MinEnergyOptions rest = opt;  // the iteration cap bounds both phases together
  rest.max_iterations = std::max(0, detail::iteration_limit(opt) - first.iterations);
  ChainResult r = optimize_coupled(ch, rest, gscale, pb);
  add_work(r, first);
  return r;
}

/// Rounds of looking in the other intervals after an elastic optimum (each a Newton solve).
constexpr int kOtherArcRounds = 4;
/// The default search's grid there, and the least stencil turn it looks at. Measured on 200
/// sharp walks (docs/methods/elastic.md, "Which minimum"): 10° finds as many of the lower
/// minima as 5°, 20° fewer; looking at every stencil finds no more than from 120°, and 120°
/// makes the look cheap on gentler data. (A threshold on the second interval's width instead
/// skipped a 174° turn with Ω = 150°, whose lower minimum had a third of the energy.)
constexpr double kOtherArcStep = 10.0 * kPi / 180.0;
constexpr double kOtherArcTurn = 120.0 * kPi / 180.0;

/// A descent from the bisectors never reaches a node's second interval (reach_other_arc), where
/// the curve turns round the point the other way, and on sharp data a lower minimum often lies
/// there. From the settled optimum `r` of ch: each direction to the best of `grid`'s, Newton
/// from there, taken while that settles lower.
void try_other_arcs(Chain& ch, const MinEnergyOptions& opt, double gscale, const ScanGrid& grid,
                    ChainResult& r) {
  if (!settled(r)) return;
  Evaluation ev;
  double energy = std::numeric_limits<double>::quiet_NaN();
  for (int round = 0; round < kOtherArcRounds; ++round) {
    Chain other = ch;
    if (!scan_directions(other, opt.method, grid)) return;
    if (std::isnan(energy)) energy = evaluate(ch, opt.method, ch.x, false, ev);
    const PairBounds pb = pair_bounds(other, kPairLimit);
    if (!meets_pairs(other, pb, 0.0)) return;
    MinEnergyOptions rest = opt;  // within the iteration cap of the whole fit
    rest.max_iterations = std::max(0, detail::iteration_limit(opt) - r.iterations);
    ChainResult again = optimize_coupled(other, rest, gscale, pb);
    // (Not a minimum held by a kept ridge, which may not be one: the look would trade a
    // certain minimum for an uncertain one.)
    if (!settled(again) || again.ridge_kept) return;
    const double lower = evaluate(other, opt.method, other.x, false, ev);
    if (!(lower < energy)) return;
    energy = lower;
    take_directions(ch, other);
    add_work(again, r);
    r = again;
  }
}

/// A start on a pair bound where an optimum held it, to the rounding of the directions' angles
/// (kPairLimit leaves 3e-12 to 180°), meets it.
constexpr double kOnPairBound = 1e-13;

/// search=global: other basins of the grid refined besides its least point (GridSearch::paths).
constexpr std::size_t kGlobalAlternatives = 6;
/// search=global: each finer grid about the minimum is this many times finer (two levels).
constexpr double kGlobalRefine = 4.0;

/// search=global on one chain: the minimum Newton reaches from the grid's least point, or from
/// another basin's point where that is lower. The grid ranks minima only to its resolution, so
/// the others are refined while their grid energy is within twice the first point's drop under
/// Newton of the least (two minima closer than that may rank either way on the grid).
ChainResult optimize_global(Chain& ch, const MinEnergyOptions& opt, double gscale) {
  const bool elastic = opt.method.basis == MinEnergyBasis::kElastic;
  auto solve = [&](Chain& c) {
    if (!elastic) return optimize(c, opt, gscale);
    const PairBounds pb = pair_bounds(c, kPairLimit);
    return meets_pairs(c, pb, kOnPairBound) ? optimize_coupled(c, opt, gscale, pb) : ChainResult{};
  };
  const double step = global_step(opt.method.basis);
  GridSearch grid(ch, opt.method, step, kPi);
  const std::vector<GridPath> paths = grid.paths(kGlobalAlternatives);
  if (paths.empty()) return solve(ch);  // no finite point on the grid: from the bisectors
  struct Minimum {
    Chain ch;
    ChainResult r;
    double energy;
  };
  auto certain = [](const ChainResult& r) { return doubt(r) == 0; };
  Evaluation ev;
  ChainResult work;
  std::vector<Minimum> minima;  // distinct, certain (or the first point's, whatever it is)
  auto refine = [&](Chain c) {
    ChainResult r = solve(c);
    add_work(work, r);
    const double e = evaluate(c, opt.method, c.x, false, ev);
    return Minimum{std::move(c), r, e};
  };
  auto known = [&](double e) {
    return std::ranges::any_of(
        minima, [&](const Minimum& m) { return std::abs(m.energy - e) <= 1e-12 * std::abs(e); });
  };
  double drop = 0.0;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (i > 0 && paths[i].energy - paths[0].energy > 2.0 * drop) break;
    Chain c = ch;
    grid.apply(paths[i], c);
    Minimum m = refine(std::move(c));
    if (i == 0) drop = std::max(0.0, paths[0].energy - m.energy);
    if (i == 0 || (certain(m.r) && !known(m.energy))) minima.push_back(std::move(m));
  }
  // Minima closer than the grid's step (a few degrees apart at some nodes) rank by chance on
  // it: about each minimum found, a grid `step / kGlobalRefine` apart within a step and a half
  // of its directions, and Newton from that grid's least point while it goes lower.
  for (std::size_t i = 0, found = minima.size(); i < found; ++i) {
    for (double fine = step / kGlobalRefine; fine >= step / (kGlobalRefine * kGlobalRefine);
         fine /= kGlobalRefine) {
      Minimum& at = minima[i];
      if (!certain(at.r)) break;
      GridSearch local(at.ch, opt.method, fine, 1.5 * fine * kGlobalRefine);
      const std::vector<GridPath> near = local.paths(0);
      if (near.empty()) break;
      Chain c = at.ch;
      local.apply(near[0], c);
      Minimum m = refine(std::move(c));
      if (certain(m.r) && m.energy < at.energy) at = std::move(m);
    }
  }
  // The lowest certain minimum, else the first point's.
  const Minimum* best = &minima[0];
  for (const Minimum& m : minima) {
    if (certain(m.r) && (!certain(best->r) || m.energy < best->energy)) best = &m;
  }
  take_directions(ch, best->ch);
  ChainResult r = best->r;
  r.iterations = 0;
  r.window_passes = r.windows = r.window_iterations = 0;
  add_work(r, work);
  return r;
}

/// The elastic basis on one chain: the minimum of elastic_descent, then of the other intervals'
/// (try_other_arcs; with search=coordinate the one-degree scan, and never above search=newton's
/// minimum), or, `warm`, the minimum from ch.x as given where it meets every pair constraint (a
/// data-ball fit refitting its optimum: restarting from the restricted spline found another
/// minimum). Not `full`: elastic_descent's minimum alone (detail::MinimumSearch).
ChainResult optimize_elastic(Chain& ch, const MinEnergyOptions& opt, double gscale, bool warm,
                             bool full) {
  const std::size_t k = ch.node.size();
  const PairBounds pb = pair_bounds(ch, kPairLimit);
  const double omega = std::min(opt.method.omega, kPairLimit);
  if (warm) {
    // Where the warm direction lies outside the node's box it may lie in the box's second
    // interval: one offset a full turn back (reach_other_arc). Undone if the start is not taken.
    struct Turned {
      std::size_t t;
      double a, b, lo, hi;
    };
    std::vector<Turned> turned;
    for (std::size_t t = 0; t < k; ++t) {
      if (ch.fixed[t] || (ch.lo[t] <= ch.x[t] && ch.x[t] <= ch.hi[t])) continue;
      const Turned was{t, ch.a[t], ch.b[t], ch.lo[t], ch.hi[t]};
      const bool two_sided = ch.closed || (t > 0 && t + 1 < k);
      if (two_sided && reach_other_arc(ch, t, omega)) {
        turned.push_back(was);
      } else {
        ch.x[t] = std::clamp(ch.x[t], ch.lo[t], ch.hi[t]);
      }
    }
    const PairBounds wpb = turned.empty() ? pb : pair_bounds(ch, kPairLimit);
    if (meets_pairs(ch, wpb, kOnPairBound)) return optimize_coupled(ch, opt, gscale, wpb);
    for (const Turned& u : turned) {
      ch.a[u.t] = u.a;
      ch.b[u.t] = u.b;
      ch.lo[u.t] = u.lo;
      ch.hi[u.t] = u.hi;
      ch.x[u.t] = std::clamp(ch.x[u.t], u.lo, u.hi);
    }
  }
  if (opt.search == MinEnergySearch::kNewton || !full) {
    ChainResult r = elastic_descent(ch, opt, gscale, pb);
    if (full) {
      try_other_arcs(ch, opt, gscale,
                     {.step = kOtherArcStep,
                      .box = false,
                      .other_arc = omega,
                      .other_turn = kOtherArcTurn,
                      .stage = "newton"},
                     r);
    }
    return r;
  }
  // search=coordinate: search=newton's minimum, or, if lower, Newton's from Curve Ensemble's
  // one-degree scan from the bisectors over every direction (as the reference's first level),
  // followed by the scan's look in the other intervals. search=global: the grid's instead.
  Chain alt = ch;
  MinEnergyOptions newton = opt;
  newton.search = MinEnergySearch::kNewton;
  const ChainResult by_newton = optimize_elastic(alt, newton, gscale, false, true);
  ChainResult r;
  if (opt.search == MinEnergySearch::kGlobal) {
    r = optimize_global(ch, opt, gscale);
  } else {
    coordinate_search(ch, opt.method, 0);
    const PairBounds spb = pair_bounds(ch, kPairLimit);
    if (meets_pairs(ch, spb, 0.0)) {
      r = optimize_coupled(ch, opt, gscale, spb);
      try_other_arcs(ch, opt, gscale, {.other_arc = omega}, r);
    }
  }
  return keep_lower(ch, r, alt, by_newton, opt.method);
}

std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string deg(double rad) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", rad * 180.0 / kPi);
  return buf;
}

/// `shown` in degrees with enough digits to differ from `bound` (as `abs_value` does): an angle
/// just past Ω is not printed as Ω.
std::string deg_apart(double abs_value, double bound, double shown) {
  char a[40], b[40];
  for (int digits = 2; digits < 12; ++digits) {
    std::snprintf(a, sizeof a, "%.*f", digits, abs_value * 180.0 / kPi);
    std::snprintf(b, sizeof b, "%.*f", digits, bound * 180.0 / kPi);
    if (std::string(a) != b) {
      std::snprintf(a, sizeof a, "%.*f", digits, shown * 180.0 / kPi);
      return a;
    }
  }
  return deg(shown);
}

/// A given direction up to this far (radians) past Ω counts as on the bound: a direction read
/// back from a curve whose optimum lies on the bound (a drawn control arm, a result's tangent)
/// comes back a few ulps past it, and clamping it must keep that curve. Far below any angle a
/// user means (1e-9 rad is 6e-8 degrees); not applied past the elastic pair limit, where the
/// s-curves end (docs/methods/min-energy.md, "End conditions and node kinds").
constexpr double kGivenAngleTolerance = 1e-9;

/// The largest omega_deg a basis accepts, as the infeasibility message advises it.
std::string omega_limit(MinEnergyBasis basis) {
  switch (basis) {
    case MinEnergyBasis::kYongCheng:
      return "below 70.52 for basis=yong-cheng";
    case MinEnergyBasis::kJaklicZagar:
      return "below 90 for basis=jaklic-zagar";
    case MinEnergyBasis::kElastic:
      return "at most 180";
    default:
      return "at most 90";
  }
}

/// The chains of the input (split at free sides) with references, bounds and fixed directions.
/// Throws Error(kInfeasible) listing every node whose feasible range is empty.
/// The chains of a fit. With `arena`, their solver-only arrays (and the set-up's chords) come
/// from one it emplaces, and with `kept` the arrays the output reads too.
std::vector<Chain> build_chains(const FitResult& out, const FitInput& input, double omega,
                                MinEnergyBasis basis, std::optional<FitArena>* arena = nullptr,
                                std::optional<FitArena>* kept = nullptr) {
  const std::vector<Point>& P = out.points;
  const std::size_t n = P.size();
  const bool closed = out.closed;
  const std::size_t segs = closed ? n : n - 1;
  // Points alone (no kinds, states, tangents or corners): every node resolves to the default,
  // so none is materialized (the vector was 64 bytes a point, 3% of a fit and its page faults).
  const bool plain = input.kinds.empty() && input.states.empty() && input.tangents.empty() &&
                     input.in_tangents.empty() && input.out_tangents.empty() &&
                     input.corners_deg.empty() && !input.start_tangent && !input.end_tangent;
  const std::vector<detail::ResolvedNode> nodes =
      plain ? std::vector<detail::ResolvedNode>{} : detail::resolve_nodes(input, n);
  const detail::ResolvedNode regular;
  auto node_at = [&](std::size_t i) -> const detail::ResolvedNode& {
    return plain ? regular : nodes[i];
  };
  // Chain boundaries: nodes with a free side (and the ends of an open curve).
  std::vector<std::size_t> cuts;
  for (std::size_t i = 0; i < n; ++i) {
    if (node_at(i).splits() && (closed || (i > 0 && i + 1 < n))) cuts.push_back(i);
  }
  std::vector<Chain> chains;
  std::pmr::memory_resource* solver = std::pmr::get_default_resource();
  std::pmr::memory_resource* kept_arrays = std::pmr::get_default_resource();
  // A chain ends where the next starts (+1 node each); 64 bytes of alignment slack an array.
  const std::size_t chain_nodes = n + cuts.size() + 1, slack = 64 * (cuts.size() + 1);
  if (arena) {
    // Eight doubles and a flag per node.
    arena->emplace((8 * sizeof(double) + 1) * chain_nodes + 9 * slack);
    solver = (*arena)->resource();
  }
  if (kept) {
    kept->emplace((sizeof(std::size_t) + sizeof(Vec2) + 2 * sizeof(double)) * chain_nodes +
                  4 * slack);
    kept_arrays = (*kept)->resource();
  }
  // The chords (a unit vector and a length each) in a block of their own, freed on return (in
  // the solver's arena they raised the optimizer's peak by 24 bytes a node).
  std::optional<FitArena> chord_block;
  if (arena) chord_block.emplace((sizeof(Vec2) + sizeof(double)) * segs + 128);
  std::pmr::memory_resource* chord_arrays =
      chord_block ? chord_block->resource() : std::pmr::get_default_resource();
  std::pmr::vector<Vec2> unit(chord_arrays);  // unit chords
  std::pmr::vector<double> len(chord_arrays);
  detail::resize_huge(unit, segs);
  detail::resize_huge(len, segs);
  for (std::size_t s = 0; s < segs; ++s) {
    const Vec2 c = P[s + 1 == n ? 0 : s + 1] - P[s];
    const double l2 = c.x * c.x + c.y * c.y;  // sqrt is much cheaper than hypot; hypot only
    len[s] = l2 > 1e-290 && l2 < 1e290 ? std::sqrt(l2) : norm(c);  // where squares misbehave
    unit[s] = (1.0 / len[s]) * c;
  }
  auto make = [&](std::size_t first, std::size_t count, bool cyclic) {
    Chain ch(solver, kept_arrays);
    ch.closed = cyclic;
    detail::resize_huge(ch.node, count);
    for (std::size_t k = 0, i = first % n; k < count; ++k, i = i + 1 == n ? 0 : i + 1) {
      ch.node[k] = i;
    }
    chains.push_back(std::move(ch));
  };
  if (!closed) {
    std::size_t start = 0;
    for (std::size_t c : cuts) {
      make(start, c - start + 1, false);
      start = c;
    }
    make(start, n - start, false);
  } else if (cuts.empty()) {
    make(0, n, true);
  } else {
    for (std::size_t k = 0; k < cuts.size(); ++k) {
      const std::size_t a = cuts[k], b = cuts[(k + 1) % cuts.size()];
      make(a, (b + n - a) % n + (b == a ? n : 0) + 1, false);
    }
  }
  const double given_limit = std::max(omega, std::min(omega + kGivenAngleTolerance, kPairLimit));
  std::string bad, apart;
  std::size_t first_bad = n, first_apart = n;
  auto fail = [&](std::size_t i, const std::string& why) {
    if (first_bad == n) first_bad = i;
    if (bad.size() < 600)
      bad += (bad.empty() ? "" : "; ") + std::string("point ") + std::to_string(i) + " " + why;
  };
  for (Chain& ch : chains) {
    const std::size_t k = ch.node.size(), nseg = ch.segments();
    detail::resize_huge(ch.ref, k);
    detail::resize_huge(ch.ca, k);
    detail::resize_huge(ch.sa, k);
    detail::resize_huge(ch.cb, k);
    detail::resize_huge(ch.sb, k);
    detail::resize_huge(ch.a, k);
    detail::resize_huge(ch.b, k);
    detail::resize_huge(ch.lo, k);
    detail::resize_huge(ch.hi, k);
    detail::assign_huge(ch.x, k, 0.0);
    detail::assign_huge(ch.fixed, k, char{0});
    detail::assign_huge(ch.corner, k, 0.0);
    detail::resize_huge(ch.w, nseg);
    // Segment s of the chain runs from node s to node s+1 (cyclic).
    auto seg_of = [&](std::size_t s) { return ch.node[s]; };  // input segment index
    for (std::size_t s = 0; s < nseg; ++s) ch.w[s] = 1.0 / len[seg_of(s)];
    for (std::size_t t = 0; t < k; ++t) {
      const std::size_t i = ch.node[t];
      const detail::ResolvedNode& node = node_at(i);
      const bool has_next = ch.closed || t + 1 < k, has_prev = ch.closed || t > 0;
      // The node's variable is its incoming direction where it has one (the outgoing one at
      // the start of a chain); a corner turns the outgoing direction, so the next chord is
      // seen turned back by it: the node is then a smooth node of stencil angle ψ − corner.
      double corner = 0.0;
      std::optional<Vec2> given;
      if (has_next && has_prev) {
        corner = node.corner;
        const bool in_fixed = node.state.in == SideState::kClamped,
                   out_fixed = node.state.out == SideState::kClamped;
        if (in_fixed && out_fixed && node.in && node.out) {
          corner = std::atan2(cross(*node.in, *node.out), dot(*node.in, *node.out));
        }
        if (in_fixed || out_fixed) given = node.in;
      } else if (has_next) {
        if (node.state.out == SideState::kClamped) given = node.out;
      } else if (node.state.in == SideState::kClamped) {
        given = node.in;
      }
      ch.corner[t] = corner;
      const Vec2 en = !has_next       ? Vec2{}
                      : corner == 0.0 ? unit[seg_of(t)]
                                      : rotate(unit[seg_of(t)], -corner);
      const Vec2 ep = has_prev ? unit[seg_of(t == 0 ? k - 1 : t - 1)] : Vec2{};
      // Reference direction: the bisector of the chords (rotate ep by ψ/2, half-angle
      // formulas, no trigonometry); at a free end the adjacent chord (Remark 2.4 (a)).
      Vec2 ref;
      double hc = 1.0, hs = 0.0, half = 0.0, half_psi = 0.0;
      if (has_next && has_prev) {
        const detail::HalfAngle h = detail::half_angle(dot(ep, en), cross(ep, en));
        hc = h.c, hs = h.s;
        ref = {ep.x * hc - ep.y * hs, ep.y * hc + ep.x * hs};
        // ψ/2 from its cosine hc >= 0 and sine (glibc's atan2 of (sn, c) was 10% of a fit at
        // 10^3 points).
        half_psi = detail::atan2_right(hs, hc);
        half = std::abs(half_psi);
        const double psi = 2.0 * half_psi;  // stencil angle ψ_i (minus the corner)
        if (std::abs(psi) > 2.0 * omega) {
          fail(i, "(stencil angle " + deg(psi) +
                      (corner != 0.0 ? "° after the corner angle " + deg(corner) : std::string()) +
                      "° > 2Ω = " + deg(2.0 * omega) + "°)");
        }
      } else {
        ref = has_next ? en : ep;
      }
      ch.ref[t] = ref;
      ch.ca[t] = hc, ch.sa[t] = -hs;  // α = x − ψ/2
      ch.cb[t] = hc, ch.sb[t] = hs;   // β = x + ψ/2
      // The elastic bases add these angles to x; the others read them only for the start
      // (start_quadratic).
      ch.a[t] = -half_psi;
      ch.b[t] = half_psi;
      ch.lo[t] = -(omega - half);
      ch.hi[t] = omega - half;
      if (given) {
        const Vec2 d = *given / norm(*given);
        const double al = std::atan2(cross(en, d), dot(en, d));
        const double be = std::atan2(cross(ep, d), dot(ep, d));
        if ((has_next && std::abs(al) > given_limit) || (has_prev && std::abs(be) > given_limit)) {
          const double a = has_next && std::abs(al) > given_limit ? al : be;
          fail(i, "(the given tangent makes an angle of " + deg_apart(std::abs(a), omega, a) +
                      "° with a chord, beyond Ω = " + deg(omega) + "°)");
        }
        // The given direction is the reference (x = 0), so that α and β are its angles with the
        // chords, each in (−180°, 180°]: at a U-turn stencil (ψ near ±180°) the bisector's
        // offsets put one of them a full turn out (elastic: no start on closed 3-point curves).
        ch.ref[t] = d;
        ch.ca[t] = has_next ? dot(en, d) : 1.0, ch.sa[t] = has_next ? cross(en, d) : 0.0;
        ch.cb[t] = has_prev ? dot(ep, d) : 1.0, ch.sb[t] = has_prev ? cross(ep, d) : 0.0;
        ch.a[t] = has_next ? al : 0.0;
        ch.b[t] = has_prev ? be : 0.0;
        ch.x[t] = 0.0;
        ch.fixed[t] = 1;
        ch.lo[t] = ch.hi[t] = 0.0;
      }
    }
    if (basis != MinEnergyBasis::kElastic) continue;
    // Elastic: each span's end directions must be less than 180° apart. From each given
    // direction the directions this allows are carried along the chain as an interval, to the
    // next given one (or the open end): an empty interval, or a given direction outside it,
    // means no s-curve joins them (two given tangents on one span, or a free point squeezed
    // between two: a closed 3-point curve had "no start").
    const PairBounds pb = pair_bounds(ch, kPairLimit);
    for (std::size_t f = 0; f < k; ++f) {
      if (!ch.fixed[f]) continue;
      double lo = ch.x[f], hi = ch.x[f];
      for (std::size_t prev = f, step = 0; step < k; ++step) {
        if (!ch.closed && prev + 1 == k) break;
        const std::size_t t = prev + 1 == k ? 0 : prev + 1;
        lo = std::max(ch.lo[t], lo - pb.hi[prev]);  // lo <= x_prev − x_t <= hi
        hi = std::min(ch.hi[t], hi - pb.lo[prev]);
        const bool ok = ch.fixed[t] ? lo <= ch.x[t] && ch.x[t] <= hi : lo <= hi;
        if (!ok) {
          if (first_apart == n) first_apart = ch.node[f];
          if (apart.size() < 600) {
            apart +=
                (apart.empty() ? "" : "; ") +
                (step == 0 ? "points " + std::to_string(ch.node[f]) + " and " +
                                 std::to_string(ch.node[t]) + " (" + deg(ch.a[f]) + "° and " +
                                 deg(ch.b[t]) + "° with the span's chord)"
                           : "points " + std::to_string(ch.node[f]) + " to " +
                                 std::to_string(ch.node[t]) +
                                 (ch.fixed[t] ? " (the given direction at point " +
                                                    std::to_string(ch.node[t]) + " is out of reach)"
                                              : " (no direction at point " +
                                                    std::to_string(ch.node[t]) + " is left)"));
          }
          break;
        }
        if (ch.fixed[t]) break;
        prev = t;
      }
    }
  }
  if (first_apart != n) {
    throw Error(ErrorCode::kInfeasible,
                "no elastic curve joins the given tangents: every piece needs its end "
                "directions less than 180 degrees apart, and the given tangents leave none at " +
                    apart + ". Change or remove one of the tangents",
                first_apart);
  }
  if (first_bad != n) {
    throw Error(ErrorCode::kInfeasible,
                "no admissible curve exists (Theorem 2.3 and Remark 2.4: every stencil angle "
                "needs |ψ| <= 2Ω and every given tangent an angle <= Ω with its chords): " +
                    bad + ". Raise omega_deg (" + omega_limit(basis) +
                    "), change the tangent, split the curve with a corner there, or remove the "
                    "point",
                first_bad);
  }
  return chains;
}

/// Starts each free direction of the chains at the directions `warm` gives its spans (a data-
/// ball fit refitting its optimum), within the node's box (elastic: as given, for
/// optimize_elastic to place in one of the box's intervals).
void start_from(const detail::SpanDirections& warm, std::size_t n, bool elastic,
                std::vector<Chain>& chains) {
  for (Chain& ch : chains) {
    const std::size_t k = ch.node.size();
    for (std::size_t t = 0; t < k; ++t) {
      if (ch.fixed[t]) continue;
      const bool has_prev = ch.closed || t > 0;
      const std::size_t i = ch.node[t];
      const Vec2 d = has_prev ? warm[i == 0 ? n - 1 : i - 1][1] : warm[i][0];
      const double x = std::atan2(cross(ch.ref[t], d), dot(ch.ref[t], d));
      ch.x[t] = elastic ? x : std::clamp(x, ch.lo[t], ch.hi[t]);
    }
  }
}

/// Starts the free directions of a cond-G2 chain at the minimizer of the energy's quadratic
/// model about straight spans (α = β = 0: E_1 ≈ E_0 + (6λ − 2λ²)(α² + β²)/2 + 2λ² αβ), clamped
/// to the boxes: one tridiagonal solve, no trigonometry. It is the optimum's first-order
/// approximation (its error is cubic in the angles), where the bisectors (x = 0) are only
/// zeroth-order, and saves Newton iterations (docs/methods/min-energy.md, "Performance").
/// The model is convex only for λ < 3/2; otherwise, or if the solve fails, x stays 0.
void start_quadratic(Chain& ch, const BasicCurveMethod& m, double gscale) {
  const double p = 6.0 * m.lambda - 2.0 * m.lambda * m.lambda, q = 2.0 * m.lambda * m.lambda;
  if (m.basis != MinEnergyBasis::kCondG2 || !(p > q)) return;
  const std::size_t k = ch.node.size(), segs = ch.segments();
  if (k < 3) return;
  // Only where every α, β at the start is within ±60° (stencil angles within ±120°): beyond,
  // the energy's non-convexity let this start pick another local minimum than the bisectors'
  // in ~1% of walks with turns up to ±150° or ±175° (lower or higher); within, 15000 random
  // walks reached the same minimum from both starts.
  for (std::size_t i = 0; i < k; ++i) {
    if (!(std::abs(ch.a[i]) <= kPi / 3.0 && std::abs(ch.b[i]) <= kPi / 3.0)) return;
  }
  const double unit = pivot_unit(gscale);
  // The solution, clamped into the boxes, unless something in it is not finite (x stays 0).
  auto take = [&](const double* sol) {
    for (std::size_t i = 0; i < k; ++i) {
      if (!std::isfinite(sol[i])) return;
    }
    for (std::size_t i = 0; i < k; ++i) {
      if (!ch.fixed[i]) ch.x[i] = std::clamp(sol[i], ch.lo[i], ch.hi[i]);
    }
  };
  if (!ch.closed) {
    // Rows made inside the factorization's pass, each as the loop below would sum it.
    Scratch block(3 * k);
    const std::span<const double> w = ch.w, a = ch.a, b = ch.b;
    auto row = [&](std::size_t i, double& di, double& ei, double& bi) {
      if (ch.fixed[i]) {  // held at x = 0: an identity row, decoupled
        di = unit, ei = 0.0, bi = 0.0;
        return;
      }
      di = 0.0, bi = 0.0, ei = 0.0;
      if (i > 0) {  // segment i − 1 ends here
        di += w[i - 1] * p;
        bi -= w[i - 1] * (q * a[i - 1] + p * b[i]);
      }
      if (i + 1 < k) {  // segment i starts here
        di += w[i] * p;
        bi -= w[i] * (p * a[i] + q * b[i + 1]);
        ei = ch.fixed[i + 1] ? 0.0 : w[i] * q;
      }
    };
    double* sol = block.begin();
    if (solve_open_tridiagonal(k, row, sol, sol + k) == Factor::kOk) take(sol);
    return;
  }
  // One block for the system and ldl_solve's 3k, so that it spans huge pages from 10^5 nodes
  // (four arrays of 4 KiB pages were ~1200 page faults, a tenth of a fit's time there).
  Scratch block(6 * k), d, e, rhs, work;
  d.use(block.begin(), k);
  e.use(block.begin() + k, k);
  rhs.use(block.begin() + 2 * k, k);
  work.use(block.begin() + 3 * k, 3 * k);
  d.resize(k);
  e.resize(k);
  rhs.resize(k);
  for (std::size_t i = 0; i < k; ++i) d[i] = e[i] = rhs[i] = 0.0;
  for (std::size_t s = 0; s < segs; ++s) {
    const std::size_t i = s, j = s + 1 == k ? 0 : s + 1;
    const double w = ch.w[s], a = ch.a[i], b = ch.b[j];  // α and β at x = 0
    d[i] += w * p;
    d[j] += w * p;
    e[s] = w * q;
    rhs[i] -= w * (p * a + q * b);
    rhs[j] -= w * (q * a + p * b);
  }
  for (std::size_t i = 0; i < k; ++i) {
    if (!ch.fixed[i]) continue;  // held at x = 0: an identity row, decoupled
    d[i] = unit;
    rhs[i] = 0.0;
    e[i] = 0.0;
    if (i > 0 || ch.closed) e[i == 0 ? k - 1 : i - 1] = 0.0;
  }
  if (!ch.closed) e[k - 1] = 0.0;
  if (ldl_solve(d, e, ch.closed, rhs, work) == Factor::kOk) take(rhs.begin());
}

/// Frees what only the optimizer reads, once a chain's directions are final: the output needs
/// the nodes, their directions (ref, x, corner), the weights and the elastic hints.
void release_solver_arrays(Chain& ch) {
  for (std::pmr::vector<double>* v :
       {&ch.ca, &ch.sa, &ch.cb, &ch.sb, &ch.lo, &ch.hi, &ch.a, &ch.b}) {
    std::pmr::vector<double>(v->get_allocator()).swap(*v);
  }
  std::pmr::vector<char>(ch.fixed.get_allocator()).swap(ch.fixed);
}

/// The exact elastic piece of one span and its Béziers within accuracy·|p1 − p0| (at least
/// 1e-12 of it, the approximation's floor); `hint`: the optimizer's last solve of the span.
std::vector<CubicBezier> elastic_span(Point p0, Point p1, double alpha, double beta,
                                      double accuracy, const detail::ElasticaHint* hint,
                                      ElasticSpan& span) {
  const detail::ElasticaArc arc = detail::elastica_arc(p0, p1, alpha, beta, hint);
  using Kind = detail::ElasticaArc::Kind;
  span = {.kind = arc.kind == Kind::kStraight   ? "straight"
                  : arc.kind == Kind::kElastica ? "elastica"
                                                : "u-turn",
          .alpha = alpha,
          .beta = beta,
          .u0 = arc.u0,
          .u1 = arc.u1,
          .straight = arc.segment,
          .reversed = arc.reversed,
          .mirrored = arc.mirrored,
          .energy = arc.energy(),
          .length = arc.length(),
          .beziers = 0};
  std::vector<CubicBezier> pieces = detail::elastica_to_beziers(arc, std::max(accuracy, 1e-12));
  // A piece that rounded to a point (all four control points equal: a U-turn between points
  // 5e-10 apart) is dropped: it has no direction to read, and the others meet without it.
  auto point = [](const CubicBezier& b) {
    return b.p[0] == b.p[1] && b.p[1] == b.p[2] && b.p[2] == b.p[3];
  };
  if (!std::all_of(pieces.begin(), pieces.end(), point)) std::erase_if(pieces, point);
  span.beziers = static_cast<int>(pieces.size());
  return pieces;
}

/// Segments from the spans' Béziers, in span order; a span's knot interval is split in
/// proportion to the pieces' arc lengths (their control-polygon lengths, a close proxy).
void assemble_spans(const std::vector<std::vector<CubicBezier>>& pieces, FitResult& out) {
  out.spline.segments.clear();
  for (std::size_t s = 0; s < pieces.size(); ++s) {
    const double t0 = out.knots[s], t1 = out.knots[s + 1];
    const std::vector<CubicBezier>& span = pieces[s];
    double total = 0.0;
    std::vector<double> len(span.size());
    for (std::size_t q = 0; q < span.size(); ++q) {
      const CubicBezier& b = span[q];
      len[q] = distance(b.p[0], b.p[1]) + distance(b.p[1], b.p[2]) + distance(b.p[2], b.p[3]);
      total += len[q];
    }
    // Breakpoints; a piece a rounding error long (an elastica's first cubic can be 1e-12 of
    // the span) still gets a non-empty interval, at least one ulp, on a span between
    // near-repeated points too.
    const std::size_t np = span.size();
    std::vector<double> at(np + 1);
    at[0] = t0;
    at[np] = t1;
    double acc = 0.0;
    for (std::size_t q = 1; q < np; ++q) {
      acc += len[q - 1];
      at[q] = std::max(t0 + (t1 - t0) * (acc / total), std::nextafter(at[q - 1], t1));
    }
    for (std::size_t q = np - 1; q > 0 && !(at[q] < at[q + 1]); --q) {
      at[q] = std::nextafter(at[q + 1], t0);
    }
    for (std::size_t q = 0; q < np; ++q) {
      out.spline.segments.push_back({span[q], at[q], at[q + 1], s});
    }
  }
}

nlohmann::json spans_json(const std::vector<ElasticSpan>& spans) {
  nlohmann::json a = nlohmann::json::array();
  for (const ElasticSpan& s : spans) {
    a.push_back({{"kind", s.kind},
                 {"alpha_deg", s.alpha * 180.0 / kPi},
                 {"beta_deg", s.beta * 180.0 / kPi},
                 {"u0", s.u0},
                 {"u1", s.u1},
                 {"straight", s.straight},
                 {"reversed", s.reversed},
                 {"mirrored", s.mirrored},
                 {"energy", s.energy},
                 {"length", s.length},
                 {"beziers", s.beziers}});
  }
  return a;
}

constexpr detail::ChoiceTable<MinEnergyBasis, 6> kBasis{
    {{"quasi-elastic", MinEnergyBasis::kCondG2},
     {"cond-g2", MinEnergyBasis::kCondG2},
     {"jaklic-zagar", MinEnergyBasis::kJaklicZagar},
     {"yong-cheng", MinEnergyBasis::kYongCheng},
     {"restricted-elastic", MinEnergyBasis::kRestrictedElastic},
     {"elastic", MinEnergyBasis::kElastic}}};

// Corners split the curve into independent chains (Remark 2.4).
const Capabilities& min_energy_capabilities() {
  static const Capabilities caps{
      .kinds = {PointKind::kSmooth, PointKind::kClamped, PointKind::kCorner},
      .continuity = Continuity::kG2,
      .node_states = true,
      .data_balls = true,
      .examples = {R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0],[8,1],[9,3]]})",
                   R"({"points": [[0,0],[4,0],[4,4],[0,4]], "closed": true})",
                   R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0]],
              "kinds": ["smooth","clamped","corner","smooth","smooth"],
              "tangents": [null,[1,0.5],null,null,null], "end_tangent": [1,-1]})"}};
  return caps;
}

}  // namespace

int detail::default_iteration_limit(std::size_t n, bool data_balls, MinEnergyBasis basis) {
  const double points = static_cast<double>(std::max<std::size_t>(n, 1));
  // The elastic spline's coupled phase crosses ridges one region at a time, and its count grows
  // faster than log n: within ±150°, 241, 369 and 623 iterations at 10⁴, 3·10⁴ and 10⁵ points
  // (docs/methods/elastic.md).
  const double growth = basis == MinEnergyBasis::kElastic ? 2.0 : 1.0;
  const int grown = static_cast<int>(std::ceil(MinEnergyOptions::kDefaultIterations *
                                               std::max(1.0, growth * (std::log10(points) - 2.0))));
  if (!data_balls) return grown;
  // Short curves get more: beside near-repeated pairs the ball optimizer converges linearly
  // along the sliding directions (seed 19: 1251-2714 iterations) at a few µs per node and step,
  // so 4000 cost a 100-point fit ~1.5 s; long ones keep the floor, their steps costing seconds.
  const double ball_cap = std::clamp(4e6 / points, double{MinEnergyOptions::kDefaultBallIterations},
                                     double{MinEnergyOptions::kMostBallIterations});
  return std::max(grown, static_cast<int>(ball_cap));
}

void fit_min_energy(const FitInput& input, const MinEnergyOptions& options, ReportLevel level,
                    FitResult& out, MinEnergyReport* report) {
  const bool balls = detail::has_data_balls(input);
  MinEnergyOptions o = options;
  if (!o.max_iterations) {
    o.max_iterations = detail::default_iteration_limit(input.points.size(), balls, o.method.basis);
  }
  if (balls) {
    detail::fit_data_balls(input, o, level, out, report);
  } else {
    detail::fit_min_energy_at(input, o, level, out, report, nullptr, nullptr,
                              detail::MinimumSearch::kFull);
  }
}

void detail::fit_min_energy_at(const FitInput& input, const MinEnergyOptions& options,
                               ReportLevel level, FitResult& out, MinEnergyReport* report,
                               const SpanDirections* warm, SpanDirections* dirs,
                               MinimumSearch search) {
  const BasicCurveMethod& m = options.method;
  const bool full = search == MinimumSearch::kFull && !warm;
  if (m.basis == MinEnergyBasis::kElastic) {
    if (!(m.omega > 0.0 && m.omega <= kPi + 1e-12)) {
      throw Error(ErrorCode::kBadOption, "elastic: omega_deg must lie in (0, 180]");
    }
  } else if (!(m.omega > 0.0 && m.omega <= kPi / 2.0 + 1e-12)) {
    throw Error(ErrorCode::kBadOption, "min-energy: omega_deg must lie in (0, 90]");
  }
  if (m.basis == MinEnergyBasis::kCondG2 && !(m.lambda > 0.0 && m.lambda < 3.0)) {
    throw Error(ErrorCode::kBadOption, "min-energy: lambda must lie in (0, 3) (Theorem 4.4)");
  }
  if (m.basis == MinEnergyBasis::kYongCheng && !(m.omega < std::acos(1.0 / 3.0))) {
    throw Error(ErrorCode::kBadOption,
                "min-energy: basis=yong-cheng needs omega_deg < 70.52 (acos 1/3): beyond it the "
                "OGH speeds of Example 4.1 can turn negative and reverse a tangent");
  }
  if (m.basis == MinEnergyBasis::kJaklicZagar && !(m.omega < kPi / 2.0)) {
    throw Error(ErrorCode::kBadOption,
                "min-energy: basis=jaklic-zagar needs omega_deg < 90 (s0 = cos α must stay "
                "positive, Example 4.2)");
  }
  detail::prepare_input(input, min_energy_capabilities(), "min-energy", out);
  const std::size_t n = out.points.size();
  // The elastic domain is open at 180°: the boxes stop 1e-12 short of it.
  const double omega =
      m.basis == MinEnergyBasis::kElastic ? std::min(m.omega, kPairLimit) : m.omega;
  // Both outlive the chains; `arena` is released once they are optimized.
  std::optional<FitArena> arena, kept;
  std::vector<Chain> chains = build_chains(out, input, omega, m.basis, &arena, &kept);
  if (warm) start_from(*warm, n, m.basis == MinEnergyBasis::kElastic, chains);
  if (dirs) dirs->resize(out.closed ? n : n - 1);
  const bool elastic = is_elastic(m.basis);
  // Elastic bases: the Béziers of each span, assembled in span order at the end.
  std::vector<std::vector<CubicBezier>> span_pieces(elastic ? (out.closed ? n : n - 1) : 0);

  MinEnergyReport rep;
  bool converged = true, at_precision = false;
  rep.pieces = static_cast<int>(chains.size());
  const std::size_t segs = out.closed ? n : n - 1;
  // Elastic bases: the Béziers' tolerance, relative to the data's size.
  double tolerance = 0.0;
  if (elastic) {
    rep.spans.resize(segs);
    Point lo = out.points[0], hi = out.points[0];
    for (const Point& p : out.points) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
    tolerance = options.accuracy * std::hypot(hi.x - lo.x, hi.y - lo.y);
  }
  for (Chain& ch : chains) {
    // The weights are 1/length; the optimizer measures gradients relative to the largest (fit()
    // has brought the data near unit size, so no weight over- or underflows).
    double gscale = 0.0;
    for (double w : ch.w) gscale = std::max(gscale, w);
    if (!warm && options.search == MinEnergySearch::kNewton) {
      start_quadratic(ch, m, gscale);
    }
    const ChainResult r = m.basis == MinEnergyBasis::kElastic
                              ? optimize_elastic(ch, options, gscale, warm != nullptr, full)
                              : optimize_searched(ch, options, gscale, full);
    rep.iterations = std::max(rep.iterations, r.iterations);
    rep.window_passes += r.window_passes;
    rep.windows += r.windows;
    rep.window_iterations += r.window_iterations;
    rep.projected_gradient = std::max(rep.projected_gradient, r.pg);
    rep.below_newton = rep.below_newton || r.by_search;
    converged = converged && (r.converged || r.at_precision);
    at_precision = at_precision || r.at_precision;
    if (r.no_start) {
      // (Not best effort either: there is no curve to return.)
      throw Error(ErrorCode::kNotConverged,
                  "min-energy: no start for the elastic spline: its start, the restricted "
                  "elastic spline with the given tangents, has no s-curve on the piece from "
                  "this point (end directions 180 degrees or more apart); no other start is "
                  "tried",
                  ch.node[r.worst]);
    }
    if (!r.converged && !r.at_precision && !options.best_effort) {
      throw Error(ErrorCode::kNotConverged,
                  "min-energy: the projected Newton method stopped after " +
                      std::to_string(r.iterations) + " iterations with projected gradient " +
                      sci(r.pg) + " (relative, largest at this point), above the tolerance " +
                      sci(options.tolerance),
                  ch.node[r.worst]);
    }
    for (std::size_t t = 0; t < ch.node.size(); ++t) {
      const double x = ch.x[t];
      if (!ch.fixed[t] && (x <= ch.lo[t] + 1e-12 || x >= ch.hi[t] - 1e-12)) {
        rep.active.push_back(ch.node[t]);
      }
    }
    release_solver_arrays(ch);
  }
  if (arena) arena->release();
  // The result's Béziers and tangents only now, when the optimizer's work arrays are gone (a
  // long fit held both at once: its peak memory).
  out.spline.closed = out.closed;
  // The chains give the segments in index order unless a closed curve is cut (its first chain
  // starts at a cut): then each is written in its place. In order, each is appended, written
  // once (default-constructing them first was a second pass over the result's largest array,
  // ~10 ms of a 10^6-point fit). The elastic bases' pieces are assembled at the end.
  const bool in_order = !out.closed || (chains.size() == 1 && chains[0].closed);
  std::vector<Segment>& segments = out.spline.segments;
  segments.clear();
  if (elastic || in_order) {
    detail::reserve_huge(segments, segs);  // (an elastic span has one piece or more)
  } else {
    detail::resize_huge(segments, segs);
  }
  detail::resize_huge(out.tangents, n);
  for (const Chain& ch : chains) {
    const std::size_t k = ch.node.size();
    // Node t's incoming direction (that of its variable) from cos, sin of x_t; its outgoing
    // one is the tangent.
    auto incoming = [&](std::size_t t, double cx, double sx) {
      return Vec2{ch.ref[t].x * cx - ch.ref[t].y * sx, ch.ref[t].y * cx + ch.ref[t].x * sx};
    };
    // Segment s's cubic from its nodes' unit directions: cos/sin of α, β against the chord.
    auto write_segment = [&](std::size_t s, Vec2 uout, Vec2 uj) {
      const std::size_t seg = ch.node[s];
      const Point p0 = out.points[seg], p1 = out.points[seg + 1 == n ? 0 : seg + 1];
      const double L = 1.0 / ch.w[s];
      const Vec2 c = (p1 - p0) * ch.w[s];
      const double ca = dot(uout, c), sa = cross(c, uout), cb = dot(uj, c), sb = cross(c, uj);
      if (dirs) (*dirs)[seg] = {uout, uj};
      if (elastic) {
        // Relative to the chord; data too large for a finite diagonal: the accuracy itself.
        double relative = tolerance / norm(p1 - p0);
        if (!(relative >= options.accuracy) || !std::isfinite(relative)) {
          relative = options.accuracy;
        }
        span_pieces[seg] = elastic_span(p0, p1, std::atan2(sa, ca), std::atan2(sb, cb), relative,
                                        s < ch.hint.size() ? &ch.hint[s] : nullptr, rep.spans[seg]);
        rep.energy += rep.spans[seg].energy;
        if (m.basis == MinEnergyBasis::kElastic &&
            std::abs(rep.spans[seg].alpha - rep.spans[seg].beta) >= kPi * (1.0 - 1e-9)) {
          rep.active_spans.push_back(seg);
        }
        return;
      }
      rep.energy += ch.w[s] * energy_cs(m, ca, sa, cb, sb).e;
      const BasicSpeeds sp = speeds_cs(m, ca, sa, cb, sb);
      const Segment piece{{{p0, p0 + (L * sp.s0 / 3.0) * uout, p1 - (L * sp.s1 / 3.0) * uj, p1}},
                          out.knots[seg],
                          out.knots[seg + 1],
                          seg};
      if (in_order) {
        segments.push_back(piece);
      } else {
        segments[seg] = piece;
      }
    };
    // One pass: segment t − 1 once node t's direction is known (the closing one at the end).
    // The cosines and sines of a block of nodes at a time, by the evaluation's vectorized
    // polynomial (sincos_block; scalar, it was a third of this pass).
    Vec2 u0, prev_out;
    double cs[2 * kEvalBlock];
    for (std::size_t first = 0; first < k; first += kEvalBlock) {
      const std::size_t count = std::min(kEvalBlock, k - first);
      sincos_block(ch.x, first, count, cs);
      for (std::size_t q = 0; q < count; ++q) {
        const std::size_t t = first + q;
        const Vec2 ut = incoming(t, cs[2 * q], cs[2 * q + 1]);
        if (t == 0) u0 = ut;
        const Vec2 uout = ch.corner[t] == 0.0 ? ut : rotate(ut, ch.corner[t]);
        // The outgoing direction is the point's tangent (a corner keeps its outgoing one).
        if (ch.closed || t + 1 < k || (!out.closed && ch.node[t] == n - 1)) {
          out.tangents[ch.node[t]] = uout;
        }
        if (t > 0) write_segment(t - 1, prev_out, ut);
        prev_out = uout;
      }
    }
    if (ch.closed) write_segment(k - 1, prev_out, u0);
  }
  std::sort(rep.active.begin(), rep.active.end());
  if (elastic) assemble_spans(span_pieces, out);

  out.solver = SolverReport{.status = !converged     ? SolverStatus::kIterationLimit
                                      : at_precision ? SolverStatus::kConditioningLimit
                                                     : SolverStatus::kConverged,
                            .iterations = rep.iterations,
                            .residual = rep.projected_gradient,
                            .tolerance = options.tolerance,
                            .active = rep.active};
  out.method_report = {
      {"iterations", rep.iterations},
      {"energy", rep.energy},
      {"projected_gradient", rep.projected_gradient},
      {"status", !converged     ? "iteration_limit"
                 : at_precision ? "conditioning_limit"
                                : "converged"},
      {"pieces", rep.pieces},
      {"omega_deg", m.omega * 180.0 / kPi},
      {"search", detail::min_energy_search_name(options.search)},
      {"minimum", detail::min_energy_search_name(rep.below_newton ? options.search
                                                                  : MinEnergySearch::kNewton)}};
  if (elastic) out.method_report["bezier_accuracy"] = options.accuracy;
  if (level != ReportLevel::kNone) {  // the per-node and per-span entries
    out.method_report["active"] = rep.active;
    if (elastic) {
      out.method_report["spans"] = spans_json(rep.spans);
      std::sort(rep.active_spans.begin(), rep.active_spans.end());
      out.method_report["active_spans"] = rep.active_spans;
    }
  }
  if (report) *report = std::move(rep);
}

std::vector<CubicBezier> basic_curve_pieces(const BasicCurveMethod& method, Point p0, Point p1,
                                            double alpha, double beta, double accuracy) {
  if (!is_elastic(method.basis)) return {basic_curve(method, p0, p1, alpha, beta)};
  return detail::elastica_to_beziers(detail::elastica_arc(p0, p1, alpha, beta), accuracy);
}

namespace {}  // namespace

MinEnergyReference min_energy_reference(const FitInput& input, const MinEnergyOptions& options) {
  FitResult out;
  detail::prepare_input(input, min_energy_capabilities(), "min-energy", out);
  std::vector<Chain> chains = build_chains(out, input, options.method.omega, options.method.basis);
  const BasicCurveMethod& m = options.method;
  MinEnergyReference ref;
  ref.angles.assign(out.points.size(), 0.0);
  Evaluation ev;
  for (Chain& ch : chains) {
    coordinate_search(ch, m, 10);
    const std::size_t k = ch.node.size();
    ref.energy += evaluate(ch, m, ch.x, false, ev);
    for (std::size_t t = 0; t < k; ++t) {  // outgoing direction at corners, as fit_min_energy
      if (ch.closed || t + 1 < k || (!out.closed && ch.node[t] == out.points.size() - 1)) {
        const Vec2 r = ch.ref[t];
        ref.angles[ch.node[t]] = std::atan2(r.y, r.x) + ch.x[t];
      }
    }
  }
  return ref;
}

}  // namespace fairspline

// ---- registry entries ----
#include "methods/builtin.hpp"

namespace fairspline::detail {

namespace {
constexpr ChoiceTable<MinEnergySearch, 3> kSearch{{{"newton", MinEnergySearch::kNewton},
                                                   {"coordinate", MinEnergySearch::kCoordinate},
                                                   {"global", MinEnergySearch::kGlobal}}};
}  // namespace

OptionSpec min_energy_search_option() {
  return {.name = "search",
          .type = OptionType::kChoice,
          .default_value = "newton",
          .choices = kSearch.names(),
          .doc =
              "which local minimum (the energy is not convex): newton = projected Newton from "
              "the chord bisectors (fast; elastic then also tries passing sharp points the "
              "other way round); coordinate = Curve Ensemble's one-degree coordinate search "
              "first, then Newton from there, or newton's minimum where lower (never above "
              "either; 10-100x slower, elastic over every direction and 40-150x); global = "
              "the least energy over a grid of directions at every node (4 degrees apart, "
              "elastic 10), exactly by dynamic programming, then Newton from there and from "
              "finer grids, or newton's minimum where lower (the lowest of the three on nearly "
              "every input measured; 20-50x slower)"};
}

MinEnergySearch parse_min_energy_search(const nlohmann::json& options) {
  return kSearch.parse(options.at("search").get<std::string>());
}

std::vector<ReportUnit> min_energy_report_units() {
  return {{"energy", -1, 0}, {"spans/*/energy", -1, 0}, {"spans/*/length", 1, 0}};
}

std::string min_energy_search_name(MinEnergySearch search) {
  return std::string(kSearch.name(search));
}

std::vector<MethodInfo> min_energy_methods() {
  auto make = [](std::string name, std::string description, std::string basis) {
    MethodInfo info{
        .name = std::move(name),
        .description = std::move(description),
        .paper =
            "M. J. Johnson, H. S. Johnson, A constructive framework for minimal energy "
            "planar curves, Sections 2-6, Examples 1.1, 4.1, 4.2, Theorem 4.4",
        .options = {{.name = "basis",
                     .type = OptionType::kChoice,
                     .default_value = basis,
                     .choices = kBasis.names(),
                     .doc = "basic curve method: quasi-elastic (conditionally G2 cubic, lambda = "
                            "1), cond-g2 (shape parameter lambda), jaklic-zagar (Example 4.2), "
                            "yong-cheng (OGH cubic, Example 4.1), restricted-elastic and elastic "
                            "(the exact s-curves of least bending energy, methods of their own)"},
                    {.name = "lambda",
                     .type = OptionType::kNumber,
                     .default_value = 1.0,
                     .min = 0.0,
                     .max = 3.0,
                     .doc = "shape parameter of cond-g2, in the open interval (0, 3) (Theorem "
                            "4.4)"},
                    {.name = "omega_deg",
                     .type = OptionType::kNumber,
                     .default_value = nullptr,
                     .min = 0.0,
                     .max = 180.0,
                     .doc = "feasibility bound Ω in degrees: |α|, |β| <= Ω at every chord; "
                            "default 90 (quasi-elastic, cond-g2, restricted-elastic), 80 "
                            "(jaklic-zagar), 60 (yong-cheng), 180 (elastic, the only basis "
                            "beyond 90)"},
                    {.name = "max_iterations",
                     .type = OptionType::kInteger,
                     .default_value = nullptr,
                     .min = 1.0,
                     .max = 100000.0,
                     .doc = kMaxIterationsDoc},
                    min_energy_search_option()},
        .fit =
            [](const FitInput& in, const nlohmann::json& o, const FitOptions& f, FitResult& out) {
              MinEnergyOptions opt;
              const std::string b = o.at("basis").get<std::string>();
              opt.method.basis = kBasis.parse(b);
              // quasi-elastic has no lambda option (its cubic is λ = 1).
              opt.method.lambda = o.contains("lambda") ? o.at("lambda").get<double>() : 1.0;
              if (b == "quasi-elastic" && opt.method.lambda != 1.0) {
                throw Error(ErrorCode::kBadOption,
                            "option lambda applies to basis cond-g2; the quasi-elastic cubic is "
                            "lambda = 1 (set the option basis to cond-g2, or choose the method "
                            "cond-g2, to set lambda)",
                            std::nullopt, OptionHint{"basis", "cond-g2"});
              }
              opt.method.omega = o.contains("omega_deg") && !o.at("omega_deg").is_null()
                                     ? o.at("omega_deg").get<double>() * std::numbers::pi / 180.0
                                     : BasicCurveMethod::default_omega(opt.method.basis);
              if (o.contains("max_iterations"))
                opt.max_iterations = o.at("max_iterations").get<int>();
              opt.search = parse_min_energy_search(o);
              opt.best_effort = f.best_effort;
              opt.accuracy = f.curve_accuracy();
              fit_min_energy(in, opt, f.method_report_level(), out);
            },
        .capabilities = min_energy_capabilities(),
        .report_units = min_energy_report_units(),
    };
    // The quasi-elastic method is the cubic of λ = 1: a lambda option would only ever be an
    // error, and every front end shows the options a method lists.
    if (info.name == "quasi-elastic") {
      std::erase_if(info.options, [](const OptionSpec& o) { return o.name == "lambda"; });
    }
    return info;
  };
  return {make("quasi-elastic",
               "Minimal-energy G1 cubic spline (Johnson-Johnson) with the quasi-elastic basic "
               "curve: tangent directions minimize the total energy subject to |angle to each "
               "chord| <= 90 degrees; G2 wherever no bound is active; regular.",
               "quasi-elastic"),
          make("min-energy",
               "Johnson-Johnson minimal-energy framework over a choice of basic curve methods "
               "(option basis), solved by a projected Newton method with O(n) work per "
               "iteration.",
               "quasi-elastic"),
          make("cond-g2",
               "Minimal-energy curve with the conditionally G2 cubic of shape parameter lambda "
               "(Theorem 4.4).",
               "cond-g2")};
}

}  // namespace fairspline::detail
