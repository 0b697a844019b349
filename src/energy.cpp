// Energies of cubic pieces and splines.
//
// Linearized energy: b''(u) = (1-u)A + uB is linear, so ∫_0^1 |b''|² du = (|A|² + A·B + |B|²)/3.
// Bending, curvature variation and length: globally adaptive Gauss–Kronrod 15/31 quadrature
// (detail/quadrature.hpp) of, per unit local parameter,
//   κ²|b'|        = cross(b',b'')² / |b'|⁵
//   (dκ/ds)²|b'|  = (dκ/du)² / |b'|,  dκ/du = (cross(b',b''')|b'|² − 3 cross(b',b'')(b'·b'')) /
//   |b'|⁵ |b'|
// A piece whose minimum speed (exact, from the roots of the cubic b'·b'') is below
// speed_floor·(control polygon length) is singular: the curvature integrands are dropped where
// the speed is below that floor (so the value stays finite) and the result is flagged.
#include "fairspline/energy.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <string>

#include "detail/format.hpp"
#include "detail/quadrature.hpp"
#include "detail/scale.hpp"
#include "fairspline/error.hpp"

namespace fairspline {

double linearized_energy_local(const CubicBezier& b) {
  const Vec2 a = 6.0 * (b.p[2] - 2.0 * b.p[1] + b.p[0]);
  const Vec2 c = 6.0 * (b.p[3] - 2.0 * b.p[2] + b.p[1]);
  return (norm2(a) + dot(a, c) + norm2(c)) / 3.0;
}

namespace {

/// Below this a result of the direct formula may have lost precision to underflow.
constexpr double kTinyEnergy = 1e-250;

double linearized_energy_scaled(const CubicBezier& b, double dt) {
  const int ex = detail::scale_exponent(b.p);
  CubicBezier u;
  for (int j = 0; j < 4; ++j) u.p[j] = detail::scaled(b.p[j], -ex);
  const double r = std::scalbn(std::sqrt(linearized_energy_local(u)), ex) / dt / std::sqrt(dt);
  return r * r;
}

}  // namespace

double linearized_energy(const CubicBezier& b, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw Error(ErrorCode::kInvalidArgument,
                "a spline piece must span a positive, finite parameter interval (got " +
                    detail::format_number(dt) + ")");
  double e = linearized_energy_local(b) / (dt * dt * dt);
  if (!(std::isfinite(e) && (e == 0.0 || e >= kTinyEnergy))) {
    // Coordinates near 1e±300 (or a parameter interval near 1e±100) overflow or underflow the
    // squares and dt³ above although the energy itself may be representable: scale the
    // control points by a power of two (exact) and take the square root first,
    //   e = (2^ex·sqrt(E_local(2^-ex·b)) / dt / sqrt(dt))².
    e = linearized_energy_scaled(b, dt);
  }
  if (!std::isfinite(e))
    throw Error(ErrorCode::kNonFinite,
                "the linearized energy of a piece overflows (control points too large or the "
                "parameter interval too short)");
  return e;
}

double linearized_energy(const Spline& s) {
  double e = 0.0;
  for (std::size_t k = 0; k < s.segments.size(); ++k) {
    const Segment& g = s.segments[k];
    try {
      e += linearized_energy(g.bezier, g.t1 - g.t0);
    } catch (const Error& err) {
      throw Error(err.code(), std::string(err.what()) + " in piece " + std::to_string(k), k);
    }
  }
  return e;
}

namespace detail {
namespace {

enum Which : unsigned { kBending = 1, kVariation = 2, kLength = 4 };

/// Breaks around a pronounced speed minimum at most (see setup).
constexpr std::size_t kMaxBreaks = 64;
/// Peaks of κ narrower than this (in the piece's parameter) get breaks around them.
constexpr double kNarrowPeak = 1e-3;

struct Setup {
  bool singular = false;
  bool straight = false;
  double floor = 0.0;  ///< absolute speed below which the curvature integrands are dropped
  std::array<double, kMaxBreaks> breaks{};
  std::size_t nbreaks = 0;
};

/// |v| as √(x² + y²) where the squares neither over- nor underflow, else hypot (overflow-safe
/// and several times slower; the report's pieces are at unit scale).
double quick_norm(Vec2 v) {
  const double s2 = norm2(v);
  return s2 > 1e-280 && s2 < 1e280 ? std::sqrt(s2) : norm(v);
}

Setup setup(const CubicBezier& b, const EnergyOptions& o, const SpeedMinimum& m) {
  Setup s;
  const double scale =
      quick_norm(b.p[1] - b.p[0]) + quick_norm(b.p[2] - b.p[1]) + quick_norm(b.p[3] - b.p[2]);
  s.straight = is_straight(b);
  s.floor = std::max(o.speed_floor, 0.0) * scale;
  s.singular = !(m.speed > s.floor) || scale == 0.0;
  // A pronounced interior speed minimum is a (near-)kink of the integrands: split there, and
  // at u0 ± w·4^k, w = s_min/|b''(u0)| the width of the peak of κ (|b'|² ≈ s_min² +
  // |b''|²(u − u0)²). Without them a narrow peak fooled the error estimate, Gauss and Kronrod
  // both missing it (half of a bending energy of 1.4e17 near a cusp), unless a sharper
  // integrand (the curvature variation) made the refinement go on.
  const double ends = std::min(quick_norm(b.d1(0.0)), quick_norm(b.d1(1.0)));
  if (m.u > 0.0 && m.u < 1.0 && m.speed < 0.25 * ends) {
    auto add = [&](double u) {
      if (u > 0.0 && u < 1.0 && s.nbreaks < kMaxBreaks) s.breaks[s.nbreaks++] = u;
    };
    add(m.u);
    // Only for narrow peaks: a bump wider than kNarrowPeak is one that bisection finds.
    const double curve = norm(b.d2(m.u));
    const double w = curve > 0.0 ? m.speed / curve : 1.0;
    for (double d = std::max(w, 1e-14); w < kNarrowPeak && d < 0.1; d *= 4.0) {
      add(m.u - d);
      add(m.u + d);
    }
    std::sort(s.breaks.begin(), s.breaks.begin() + static_cast<std::ptrdiff_t>(s.nbreaks));
  }
  return s;
}

Quadrature to_quadrature(double value, double error, bool singular) {
  Quadrature q;
  q.value = std::isfinite(value) ? value : 0.0;
  q.error_estimate = std::isfinite(error) ? error : 0.0;
  q.singular = singular || !std::isfinite(value);
  return q;
}

/// The integrands of the energies in kWhich, in the order bending κ²|b'|, curvature variation
/// (dκ/ds)²|b'|, length |b'| (the curvature terms zero below `floor`). Only what is asked for
/// is computed: the default report wants bending and length, not the third derivative.
template <unsigned kWhich>
inline std::array<double, std::popcount(kWhich)> integrands(const CubicBezier& b, double u,
                                                            double floor) {
  std::array<double, std::popcount(kWhich)> r{};
  const Vec2 v = b.d1(u);
  const double s2 = norm2(v);
  const double s = std::sqrt(s2);
  if constexpr ((kWhich & kLength) != 0) r.back() = s;
  if constexpr ((kWhich & (kBending | kVariation)) != 0) {
    if (!(s > floor) || s2 == 0.0) return r;
    const Vec2 a = b.d2(u);
    const double c = cross(v, a);
    const double s5 = s2 * s2 * s;
    std::size_t k = 0;
    if constexpr ((kWhich & kBending) != 0) r[k++] = c * c / s5;
    if constexpr ((kWhich & kVariation) != 0) {
      const double dk = (cross(v, b.d3()) * s2 - 3.0 * c * dot(v, a)) / s5;
      r[k] = dk * dk / s;
    }
  }
  return r;
}

/// The integrands of kWhich as an object: one node at a time, or all nodes of a rule at once
/// (gauss_kronrod's batch), node by node the same arithmetic as integrands<kWhich> written
/// as loops over the nodes, which the compiler vectorizes (half the report's time was here).
template <unsigned kWhich>
struct Integrands {
  static constexpr std::size_t kN = std::popcount(kWhich);
  const CubicBezier& b;
  double floor;

  std::array<double, kN> operator()(double u) const { return integrands<kWhich>(b, u, floor); }

  template <std::size_t M>
  void batch(const std::array<double, M>& u, std::array<std::array<double, kN>, M>& out) const {
    const Vec2 q0 = b.p[1] - b.p[0], q1 = b.p[2] - b.p[1], q2 = b.p[3] - b.p[2];
    const Vec2 e0 = b.p[2] - 2.0 * b.p[1] + b.p[0], e1 = b.p[3] - 2.0 * b.p[2] + b.p[1];
    const Vec2 j = b.d3();
    std::array<double, M> vx, vy, s2, s, bend, var;
    for (std::size_t i = 0; i < M; ++i) {  // d1(u)
      const double w = 1.0 - u[i];
      const double c0 = w * w, c1 = 2.0 * u[i] * w, c2 = u[i] * u[i];
      vx[i] = 3.0 * (c0 * q0.x + c1 * q1.x + c2 * q2.x);
      vy[i] = 3.0 * (c0 * q0.y + c1 * q1.y + c2 * q2.y);
      s2[i] = vx[i] * vx[i] + vy[i] * vy[i];
      s[i] = std::sqrt(s2[i]);
    }
    if constexpr ((kWhich & (kBending | kVariation)) != 0) {
      for (std::size_t i = 0; i < M; ++i) {
        const double w = 1.0 - u[i];
        const double ax = 6.0 * (w * e0.x + u[i] * e1.x), ay = 6.0 * (w * e0.y + u[i] * e1.y);
        const double c = vx[i] * ay - vy[i] * ax;
        const double s5 = s2[i] * s2[i] * s[i];
        // Divided unconditionally, then selected (a division under a condition is not
        // vectorized): below the floor the quotient is discarded.
        const bool curved = s[i] > floor && s2[i] != 0.0;
        const double bent = c * c / s5;
        bend[i] = curved ? bent : 0.0;
        if constexpr ((kWhich & kVariation) != 0) {
          const double dk =
              ((vx[i] * j.y - vy[i] * j.x) * s2[i] - 3.0 * c * (vx[i] * ax + vy[i] * ay)) / s5;
          const double varied = dk * dk / s[i];
          var[i] = curved ? varied : 0.0;
        }
      }
    }
    for (std::size_t i = 0; i < M; ++i) {
      std::size_t k = 0;
      if constexpr ((kWhich & kBending) != 0) out[i][k++] = bend[i];
      if constexpr ((kWhich & kVariation) != 0) out[i][k++] = var[i];
      if constexpr ((kWhich & kLength) != 0) out[i][k] = s[i];
    }
  }
};

template <unsigned kWhich>
PieceEnergies compute(const CubicBezier& b, const EnergyOptions& o, const SpeedMinimum& m) {
  const Setup st = setup(b, o, m);
  const bool curved = !st.straight && (kWhich & (kBending | kVariation));
  PieceEnergies out;
  const std::span<const double> breaks(st.breaks.data(), st.nbreaks);
  if (curved) {
    const auto q = integrate_adaptive<std::popcount(kWhich)>(Integrands<kWhich>{b, st.floor},
                                                             breaks, o.accuracy, o.max_depth);
    std::size_t k = 0;
    if constexpr ((kWhich & kBending) != 0) {
      out.bending = to_quadrature(q.value[k], q.error[k], st.singular);
      ++k;
    }
    if constexpr ((kWhich & kVariation) != 0) {
      out.curvature_variation = to_quadrature(q.value[k], q.error[k], st.singular);
      ++k;
    }
    if constexpr ((kWhich & kLength) != 0)
      out.length = to_quadrature(q.value[k], q.error[k], false);
    return out;
  }
  // Straight pieces: κ ≡ 0 wherever it is defined.
  out.bending = to_quadrature(0.0, 0.0, st.singular);
  out.curvature_variation = to_quadrature(0.0, 0.0, st.singular);
  if constexpr ((kWhich & kLength) != 0) {
    const auto q =
        integrate_adaptive<1>([&](double u) { return integrands<kLength>(b, u, st.floor); }, breaks,
                              o.accuracy, o.max_depth);
    out.length = to_quadrature(q.value[0], q.error[0], false);
  }
  return out;
}

}  // namespace

PieceEnergies piece_energies(const CubicBezier& b, const EnergyOptions& options,
                             const SpeedMinimum& m, bool variation) {
  // Two quadratures when the variation is wanted, so that bending and length are the same
  // numbers at every report level (the adaptive refinement follows its slowest integrand).
  PieceEnergies e = compute<kBending | kLength>(b, options, m);
  if (variation) e.curvature_variation = compute<kVariation>(b, options, m).curvature_variation;
  return e;
}

}  // namespace detail

// The same quadratures as the report's (detail::piece_energies), so that the numbers agree.
Quadrature bending_energy(const CubicBezier& b, const EnergyOptions& options) {
  return detail::compute<detail::kBending | detail::kLength>(b, options, detail::min_speed(b))
      .bending;
}

Quadrature curvature_variation_energy(const CubicBezier& b, const EnergyOptions& options) {
  return detail::compute<detail::kVariation>(b, options, detail::min_speed(b)).curvature_variation;
}

Quadrature arc_length(const CubicBezier& b, const EnergyOptions& options) {
  // Length needs no singularity handling: |b'| is continuous (a kink at a cusp is a breakpoint).
  const detail::Setup st = detail::setup(b, options, detail::min_speed(b));
  const auto q = detail::integrate_adaptive<1>(
      [&](double u) { return std::array<double, 1>{norm(b.d1(u))}; },
      std::span<const double>(st.breaks.data(), st.nbreaks), options.accuracy, options.max_depth);
  return detail::to_quadrature(q.value[0], q.error[0], false);
}

namespace {
template <class F>
Quadrature total(const Spline& s, F f) {
  Quadrature q;
  for (const Segment& g : s.segments) {
    const Quadrature r = f(g.bezier);
    q.value += r.value;
    q.error_estimate += r.error_estimate;
    q.singular = q.singular || r.singular;
  }
  return q;
}
}  // namespace

Quadrature bending_energy(const Spline& s, const EnergyOptions& o) {
  return total(s, [&](const CubicBezier& b) { return bending_energy(b, o); });
}
Quadrature curvature_variation_energy(const Spline& s, const EnergyOptions& o) {
  return total(s, [&](const CubicBezier& b) { return curvature_variation_energy(b, o); });
}
Quadrature arc_length(const Spline& s, const EnergyOptions& o) {
  return total(s, [&](const CubicBezier& b) { return arc_length(b, o); });
}

}  // namespace fairspline
