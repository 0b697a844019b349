// Energies of cubic pieces and splines.
//
// Linearized energy: b''(u) = (1-u)A + uB is linear, so ∫_0^1 |b''|² du = (|A|² + A·B + |B|²)/3.
// Bending, curvature variation and length: globally adaptive Gauss–Kronrod 7/15 quadrature
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

struct Setup {
  bool singular = false;
  bool straight = false;
  double floor = 0.0;  ///< absolute speed below which the curvature integrands are dropped
  std::array<double, 1> breaks{};
  std::size_t nbreaks = 0;
};

Setup setup(const CubicBezier& b, const EnergyOptions& o, const SpeedMinimum& m) {
  Setup s;
  const double scale = control_polygon_length(b);
  s.straight = is_straight(b);
  s.floor = std::max(o.speed_floor, 0.0) * scale;
  s.singular = !(m.speed > s.floor) || scale == 0.0;
  // A pronounced interior speed minimum is a (near-)kink of the integrands: split there.
  const double ends = std::min(norm(b.d1(0.0)), norm(b.d1(1.0)));
  if (m.u > 0.0 && m.u < 1.0 && m.speed < 0.25 * ends) {
    s.breaks[0] = m.u;
    s.nbreaks = 1;
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

/// Integrand values {κ²|b'|, (dκ/ds)²|b'|, |b'|} at u (zero curvature terms below `floor`).
inline std::array<double, 3> integrands(const CubicBezier& b, double u, double floor, bool curved) {
  const Vec2 v = b.d1(u);
  const double s2 = norm2(v);
  const double s = std::sqrt(s2);
  if (!curved || !(s > floor) || s2 == 0.0) return {0.0, 0.0, s};
  const Vec2 a = b.d2(u), j = b.d3();
  const double c = cross(v, a);
  const double s5 = s2 * s2 * s;
  const double bend = c * c / s5;
  const double dk = (cross(v, j) * s2 - 3.0 * c * dot(v, a)) / s5;
  return {bend, dk * dk / s, s};
}

template <unsigned kWhich>
PieceEnergies compute(const CubicBezier& b, const EnergyOptions& o, const SpeedMinimum& m) {
  const Setup st = setup(b, o, m);
  const bool curved = !st.straight && (kWhich & (kBending | kVariation));
  PieceEnergies out;
  const std::span<const double> breaks(st.breaks.data(), st.nbreaks);
  if (curved && (kWhich & kLength)) {
    const auto q = integrate_adaptive<3>([&](double u) { return integrands(b, u, st.floor, true); },
                                         breaks, o.accuracy, o.max_depth);
    out.bending = to_quadrature(q.value[0], q.error[0], st.singular);
    out.curvature_variation = to_quadrature(q.value[1], q.error[1], st.singular);
    out.length = to_quadrature(q.value[2], q.error[2], false);
  } else if (curved) {
    const auto q = integrate_adaptive<2>(
        [&](double u) {
          const auto r = integrands(b, u, st.floor, true);
          return std::array<double, 2>{r[0], r[1]};
        },
        breaks, o.accuracy, o.max_depth);
    out.bending = to_quadrature(q.value[0], q.error[0], st.singular);
    out.curvature_variation = to_quadrature(q.value[1], q.error[1], st.singular);
  } else {
    // Straight pieces: κ ≡ 0 wherever it is defined.
    out.bending = to_quadrature(0.0, 0.0, st.singular);
    out.curvature_variation = to_quadrature(0.0, 0.0, st.singular);
    if (kWhich & kLength) {
      const auto q =
          integrate_adaptive<1>([&](double u) { return std::array<double, 1>{norm(b.d1(u))}; },
                                breaks, o.accuracy, o.max_depth);
      out.length = to_quadrature(q.value[0], q.error[0], false);
    }
  }
  return out;
}

}  // namespace

PieceEnergies piece_energies(const CubicBezier& b, const EnergyOptions& options,
                             const SpeedMinimum& m) {
  return compute<kBending | kVariation | kLength>(b, options, m);
}

}  // namespace detail

Quadrature bending_energy(const CubicBezier& b, const EnergyOptions& options) {
  return detail::compute<detail::kBending | detail::kVariation>(b, options, detail::min_speed(b))
      .bending;
}

Quadrature curvature_variation_energy(const CubicBezier& b, const EnergyOptions& options) {
  return detail::compute<detail::kBending | detail::kVariation>(b, options, detail::min_speed(b))
      .curvature_variation;
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
