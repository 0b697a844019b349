// Optimality certificates of an iterative method's result, computed from the output curve alone
// (issue 18): the stress program and tests/stress_regressions_test.cpp share them.
//
// min-energy family (every method with an omega_deg option): each node's direction is read off
// the output Béziers, the energy Σ E_1(α_s, β_s) / L_s is differentiated by central differences
// of the public basic_energy(), and the result must be a KKT point of the box |α|, |β| <= Ω (and,
// for the elastic basis, of the coupled bound |α − β| <= 180°): zero gradient at free nodes, a
// gradient pointing out of the feasible set at nodes on a bound. The residual is measured like
// the solver's projected gradient: angles, with the gradient times the chain's shortest chord.
//
// The elastic energy has a convex kink on α = β beyond 98.56° (U-turn pieces): there the
// subgradients between its one-sided gradients count.
//
// Kozak–Krajnc with g2: the curvature jump at each breakpoint the G2 Newton solves for, read off
// the Béziers and made dimensionless by the mean of the two chords (as (1.4) is).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "detail/ball_energy.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/methods/min_energy.hpp"
#include "fairspline/registry.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline::stress {

/// A returned optimum passes when every node's residual is within this (plus the rounding
/// allowance of reading its direction off the Béziers). The solver stops at 1e-10; the
/// differences are accurate to ~1e-10.
inline constexpr double kKktTolerance = 1e-6;

/// Outcome of a certificate check.
struct KktResult {
  bool checked = false;    ///< false: the method has no certificate here (nothing was checked)
  double residual = 0.0;   ///< worst node residual (dimensionless)
  double allowance = 0.0;  ///< rounding allowance at that node
  std::size_t node = 0;    ///< where
  bool pass = true;        ///< every node within kKktTolerance + its allowance
  std::string what;        ///< a sentence for failures
};

namespace detail {

inline constexpr double kEps = std::numeric_limits<double>::epsilon();

/// Direction of a Bézier end that may have a zero-length arm.
inline Vec2 start_leg(const CubicBezier& b) {
  for (int j = 1; j < 4; ++j) {
    const Vec2 d = b.p[j] - b.p[0];
    if (d.x != 0.0 || d.y != 0.0) return d;
  }
  return {1.0, 0.0};
}
inline Vec2 end_leg(const CubicBezier& b) {
  for (int j = 2; j >= 0; --j) {
    const Vec2 d = b.p[3] - b.p[j];
    if (d.x != 0.0 || d.y != 0.0) return d;
  }
  return {1.0, 0.0};
}

inline double angle_from(Vec2 chord, Vec2 leg) {
  return signed_angle(chord, leg);
}

inline double magnitude(const CubicBezier& b) {
  double m = 0.0;
  for (const Point& p : b.p) m = std::max({m, std::abs(p.x), std::abs(p.y)});
  return m;
}

/// First and last output segment of each input span (segments come in span order).
inline bool span_ranges(const FitResult& r, std::size_t spans, std::vector<std::size_t>& first,
                        std::vector<std::size_t>& last) {
  const std::size_t none = std::numeric_limits<std::size_t>::max();
  first.assign(spans, none);
  last.assign(spans, none);
  for (std::size_t k = 0; k < r.spline.segments.size(); ++k) {
    const std::size_t s = r.spline.segments[k].span;
    if (s >= spans) return false;
    if (first[s] == none) first[s] = k;
    last[s] = k;
  }
  for (std::size_t s = 0; s < spans; ++s) {
    if (first[s] == none) return false;
  }
  return true;
}

/// span_ranges of a result of n points, or false with `out` set to the failure it is.
inline bool spans_of(const FitResult& r, std::size_t n, std::size_t spans,
                     std::vector<std::size_t>& first, std::vector<std::size_t>& last,
                     KktResult& out) {
  if (n >= 2 && span_ranges(r, spans, first, last)) return true;
  out.pass = false;
  out.residual = std::numeric_limits<double>::infinity();
  out.what = "the output does not have one or more Béziers per span";
  return false;
}

/// The elastic bases' (α, β) moved onto |α − β| = 180° when the directions read off the Béziers
/// lie a rounding error beyond it, where E_1 is infinite. (Not further: the gradient varies
/// like Θ^{1/2} there, 6e-6 at Θ = 1e-12.)
inline void inside(const BasicCurveMethod& m, double& a, double& b) {
  if (!is_elastic(m.basis) || std::abs(a - b) <= std::numbers::pi) return;
  if (std::isfinite(basic_energy(m, a, b).e)) return;
  const double mid = 0.5 * (a + b), half = 0.5 * (a >= b ? std::numbers::pi : -std::numbers::pi);
  a = mid + half;
  b = mid - half;
}
inline BasicEnergy inside_energy(const BasicCurveMethod& m, double a, double b) {
  inside(m, a, b);
  return basic_energy(m, a, b);
}

/// ∂/∂α (which = 0) or ∂/∂β (which = 1) of E_1 at (a, b) by five-point central differences.
/// The elastic energy has kinks outside the box |α|, |β| <= 90°, where the least-energy piece
/// switches between candidates: the step shrinks (×1/4) until two steps agree, so that the
/// stencil stays on the point's side of a kink that is near. Near |α − β| = 180° the
/// derivatives of Θ^{3/2} (Θ = 180° − |α − β|) grow like Θ^{3/2−k}: steps start at Θ/64. On that
/// bound itself (no room for a stencil) the analytic partial of basic_energy is used.
inline double partial(const BasicCurveMethod& m, double a, double b, int which) {
  inside(m, a, b);
  auto f = [&](double d) {
    return which == 0 ? basic_energy(m, a + d, b).e : basic_energy(m, a, b + d).e;
  };
  auto central = [&](double h, double& d) {
    const double fm2 = f(-2 * h), fm1 = f(-h), fp1 = f(h), fp2 = f(2 * h);
    d = (fm2 - 8.0 * fm1 + 8.0 * fp1 - fp2) / (12.0 * h);
    return std::isfinite(d);
  };
  double h = 1e-3;
  const bool elastic = is_elastic(m.basis);
  if (elastic) h = std::min(h, (std::numbers::pi - std::abs(a - b)) / 64.0);
  double d = 0.0, prev = 0.0;
  bool have_prev = false;
  for (int k = 0; k < (elastic ? 6 : 1) && h >= 1e-8; ++k, h *= 0.25) {
    if (!central(h, d)) {
      have_prev = false;
      continue;
    }
    if (!elastic || (have_prev && std::abs(d - prev) <= 1e-7 * (1.0 + std::abs(d)))) return d;
    prev = d;
    have_prev = true;
  }
  const BasicEnergy e = basic_energy(m, a, b);
  return which == 0 ? e.ea : e.eb;
}

/// One column of the stationarity system: entries on at most two unknowns (v == u: one), with
/// its coefficient bounded to [lo, hi] (a constraint's multiplier: [0, ∞); the weight of one
/// side of a kink: [0, 1]).
struct Column {
  std::size_t u = 0, v = 0;
  double cu = 0.0, cv = 0.0;
  double lo = 0.0, hi = std::numeric_limits<double>::infinity();
};

/// The smallest −g − Σ x_j c_j over bounded coefficients x_j: bound-constrained least squares
/// by cyclic coordinate descent (the columns couple at most two neighbouring unknowns, so this
/// converges in a few sweeps). `res` gets the residual vector.
inline void stationarity_residual(const std::vector<double>& g, const std::vector<Column>& cs,
                                  std::vector<double>& res) {
  res.resize(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) res[i] = -g[i];
  if (cs.empty()) return;
  std::vector<double> x(cs.size(), 0.0);
  for (int sweep = 0; sweep < 5000; ++sweep) {
    double change = 0.0;
    for (std::size_t j = 0; j < cs.size(); ++j) {
      const Column& c = cs[j];
      const bool two = c.v != c.u;
      const double cc = c.cu * c.cu + (two ? c.cv * c.cv : 0.0);
      if (!(cc > 0.0)) continue;
      const double t = (c.cu * res[c.u] + (two ? c.cv * res[c.v] : 0.0)) / cc;
      const double next = std::clamp(x[j] + t, c.lo, c.hi);
      const double d = next - x[j];
      if (d == 0.0) continue;
      x[j] = next;
      res[c.u] -= d * c.cu;
      if (two) res[c.v] -= d * c.cv;
      change = std::max(change, std::abs(d) * std::sqrt(cc));
    }
    if (change < 1e-15) break;
  }
}

/// The one-sided gradients of E_1 across the elastic energy's convex kink on the diagonal α = β
/// beyond 98.56° (U-turn pieces with both turns full; docs/methods/elastic.md, "Ridges"), at
/// the diagonal point nearest (a, b): `above` on the side α > β, `below` on α < β.
inline void ridge_gradients(const BasicCurveMethod& m, double a, double b, double above[2],
                            double below[2]) {
  // Each side's analytic partials at δ and 2δ off the ridge, extrapolated to δ = 0: off it by δ
  // they differ from their limit like √δ (E has a |α − β|^{3/2} term), which second-order
  // differences of the energy at 1e-5 missed by 1e-3 of the jump.
  const double c = 0.5 * (a + b), h = 1e-8, r2 = std::numbers::sqrt2;
  auto limit = [&](double sign, double out[2]) {
    const BasicEnergy e1 = basic_energy(m, c + sign * h, c - sign * h);
    const BasicEnergy e2 = basic_energy(m, c + 2 * sign * h, c - 2 * sign * h);
    out[0] = (r2 * e1.ea - e2.ea) / (r2 - 1.0);
    out[1] = (r2 * e1.eb - e2.eb) / (r2 - 1.0);
  };
  limit(1.0, above);
  limit(-1.0, below);
}

/// True when (a, b) sits on that ridge (within the solver's rounding).
inline bool on_ridge(const BasicCurveMethod& m, double a, double b) {
  return is_elastic(m.basis) && std::abs(a - b) < 1e-6 && std::abs(a + b) > std::numbers::pi;
}

}  // namespace detail

/// The min-energy basic curve method a result was fitted with, from its resolved options
/// (a method with an omega_deg option; the basis is the "basis" option or the method's name).
inline std::optional<BasicCurveMethod> min_energy_method_of(const FitResult& r) {
  const nlohmann::json& o = r.options;
  bool has_omega = false;
  for (const OptionSpec& spec : find_method(r.method).options)
    has_omega |= spec.name == "omega_deg";
  if (!has_omega || !o.is_object()) return std::nullopt;
  const std::string basis = o.contains("basis") && o.at("basis").is_string()
                                ? o.at("basis").get<std::string>()
                                : r.method;
  BasicCurveMethod m;
  if (basis == "quasi-elastic") {
    m.basis = MinEnergyBasis::kCondG2;
  } else if (basis == "cond-g2") {
    m.basis = MinEnergyBasis::kCondG2;
    m.lambda = o.value("lambda", 1.0);
  } else if (basis == "jaklic-zagar") {
    m.basis = MinEnergyBasis::kJaklicZagar;
  } else if (basis == "yong-cheng") {
    m.basis = MinEnergyBasis::kYongCheng;
  } else if (basis == "restricted-elastic") {
    m.basis = MinEnergyBasis::kRestrictedElastic;
  } else if (basis == "elastic") {
    m.basis = MinEnergyBasis::kElastic;
  } else {
    return std::nullopt;
  }
  const nlohmann::json w = o.value("omega_deg", nlohmann::json());
  m.omega = w.is_number() ? w.get<double>() * std::numbers::pi / 180.0
                          : BasicCurveMethod::default_omega(m.basis);
  return m;
}

/// KKT certificate of a min-energy result (see the file comment). `in` is the request (node
/// kinds, clamped tangents); `r` the fit.
inline KktResult check_min_energy(const FitInput& in, const FitResult& r,
                                  const BasicCurveMethod& m) {
  using detail::Column;
  KktResult out;
  // The check models node kinds; the per-side node model (states, corner angles, per-side
  // tangents) is not modelled yet: nothing is checked then.
  if (!in.states.empty() || !in.in_tangents.empty() || !in.out_tangents.empty() ||
      !in.corners_deg.empty()) {
    return out;
  }
  out.checked = true;
  const std::size_t n = r.points.size();
  const bool closed = r.closed;
  const std::size_t spans = closed ? n : n - 1;
  std::vector<std::size_t> first, last;
  if (!detail::spans_of(r, n, spans, first, last, out)) return out;
  auto kind = [&](std::size_t i) { return i < in.kinds.size() ? in.kinds[i] : PointKind::kSmooth; };
  auto fixed = [&](std::size_t i) {
    return (kind(i) == PointKind::kClamped && i < in.tangents.size() && in.tangents[i]) ||
           (i == 0 && in.start_tangent) || (!closed && i + 1 == n && in.end_tangent);
  };
  // A corner splits the curve into independent chains, as in the solver, unless its direction
  // is given: a closed curve's start tangent clamps both sides of point 0 whatever its kind
  // (detail::resolve_nodes), so that node joins its neighbours' chain, and L_min with it.
  auto split = [&](std::size_t i) {
    return kind(i) == PointKind::kCorner && (closed || (i > 0 && i + 1 < n)) && !fixed(i);
  };
  // Each span's end legs. At a G1 node both sides carry one direction: it is read off the
  // longer of the two legs (an elastic piece may start with a Bézier 1e-12 long, whose
  // direction is lost in the rounding of coordinates ~1e13 times larger).
  std::vector<Vec2> leg0(spans), leg1(spans);
  std::vector<double> mag0(spans), mag1(spans);
  for (std::size_t s = 0; s < spans; ++s) {
    const CubicBezier& b0 = r.spline.segments[first[s]].bezier;
    const CubicBezier& b1 = r.spline.segments[last[s]].bezier;
    leg0[s] = detail::start_leg(b0), leg1[s] = detail::end_leg(b1);
    mag0[s] = detail::magnitude(b0), mag1[s] = detail::magnitude(b1);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (split(i) || !(closed || (i > 0 && i + 1 < n))) continue;
    const std::size_t next = i, prev = i == 0 ? spans - 1 : i - 1;
    // Relative precision of each: leg length over coordinate size.
    if (norm(leg1[prev]) * mag0[next] > norm(leg0[next]) * mag1[prev]) {
      leg0[next] = leg1[prev], mag0[next] = mag1[prev];
    } else {
      leg1[prev] = leg0[next], mag1[prev] = mag0[next];
    }
  }
  // Angles of each span's end directions against its chord, and their rounding.
  std::vector<double> alpha(spans), beta(spans), len(spans), da(spans), db(spans);
  for (std::size_t s = 0; s < spans; ++s) {
    const Vec2 chord = r.points[s + 1 == n ? 0 : s + 1] - r.points[s];
    alpha[s] = detail::angle_from(chord, leg0[s]);
    beta[s] = detail::angle_from(chord, leg1[s]);
    len[s] = norm(chord);
    const double mag = std::max(mag0[s], mag1[s]);
    da[s] = 8.0 * detail::kEps * mag * (1.0 / norm(leg0[s]) + 1.0 / len[s]);
    db[s] = 8.0 * detail::kEps * mag * (1.0 / norm(leg1[s]) + 1.0 / len[s]);
  }
  // Chains: split at corners; the gradient scale of each is its shortest chord.
  std::vector<std::size_t> chain(spans, 0);
  std::size_t splits = 0;
  for (std::size_t i = 0; i < n; ++i) splits += split(i) ? 1 : 0;
  {
    std::size_t c = 0;
    for (std::size_t s = 0; s < spans; ++s) {
      if (s > 0 && split(s)) ++c;
      chain[s] = c;
    }
    // Closed: the spans before the first corner continue the last chain.
    if (closed && splits > 0 && !split(0)) {
      for (std::size_t s = 0; s < spans && chain[s] == 0; ++s) chain[s] = c;
    }
  }
  std::vector<double> lmin(spans, std::numeric_limits<double>::infinity());
  for (std::size_t s = 0; s < spans; ++s) lmin[chain[s]] = std::min(lmin[chain[s]], len[s]);

  // Unknowns: one direction per free node (two at a corner, one per side). Each moves the α of
  // the span after it and/or the β of the span before it.
  const std::size_t none = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> var_a(spans, none), var_b(spans, none);  // unknown moving α_s, β_s
  std::vector<std::size_t> var_node;
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed(i)) continue;
    const bool has_next = closed || i + 1 < n, has_prev = closed || i > 0;
    const std::size_t next = i, prev = i == 0 ? spans - 1 : i - 1;
    if (split(i)) {
      if (has_next) var_a[next] = var_node.size(), var_node.push_back(i);
      if (has_prev) var_b[prev] = var_node.size(), var_node.push_back(i);
    } else {
      if (has_next) var_a[next] = var_node.size();
      if (has_prev) var_b[prev] = var_node.size();
      var_node.push_back(i);
    }
  }
  const std::size_t nv = var_node.size();
  std::vector<double> g(nv, 0.0), noise(nv, 0.0), scale(nv, 1.0);
  for (std::size_t s = 0; s < spans; ++s) {
    if (var_a[s] != none) scale[var_a[s]] = lmin[chain[s]];
    if (var_b[s] != none) scale[var_b[s]] = lmin[chain[s]];
  }
  std::vector<Column> columns;
  for (std::size_t s = 0; s < spans; ++s) {
    const double w = 1.0 / len[s];
    const BasicEnergy e = detail::inside_energy(m, alpha[s], beta[s]);
    auto cap = [](double v) { return std::isfinite(v) ? std::abs(v) : 1e300; };
    double ga = 0.0, gb = 0.0;
    if (detail::on_ridge(m, alpha[s], beta[s])) {
      // A convex kink: the subgradients are the segment between the one-sided gradients; the
      // weight of `above` is one more unknown in [0, 1].
      double above[2], below[2];
      detail::ridge_gradients(m, alpha[s], beta[s], above, below);
      ga = below[0], gb = below[1];
      const std::size_t u = var_a[s] != none ? var_a[s] : var_b[s];
      const std::size_t v = var_b[s] != none ? var_b[s] : u;
      if (u != none) {
        const double cu = var_a[s] != none ? above[0] - below[0] : above[1] - below[1];
        const double cv = var_b[s] != none && v != u ? above[1] - below[1] : 0.0;
        columns.push_back({u, v, w * scale[u] * cu, w * scale[v] * cv, 0.0, 1.0});
      }
    } else {
      ga = detail::partial(m, alpha[s], beta[s], 0);
      gb = detail::partial(m, alpha[s], beta[s], 1);
    }
    if (var_a[s] != none) {
      g[var_a[s]] += w * ga;
      noise[var_a[s]] += w * (cap(e.eaa) * da[s] + cap(e.eab) * db[s]);
    }
    if (var_b[s] != none) {
      g[var_b[s]] += w * gb;
      noise[var_b[s]] += w * (cap(e.ebb) * db[s] + cap(e.eab) * da[s]);
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    g[v] *= scale[v];
    noise[v] *= scale[v];
  }
  // Active constraints (slack within rounding of the bound), and bound violations.
  const double omega = m.basis == MinEnergyBasis::kElastic
                           ? std::min(m.omega, std::numbers::pi * (1.0 - 1e-12))
                           : m.omega;
  double violation = 0.0;
  std::size_t violation_node = 0;
  auto bound = [&](double slack, double rounding, std::size_t u, double au, std::size_t v,
                   double av, std::size_t node) {
    // Beyond the bound by more than rounding: not a feasible curve.
    if (slack < -(1e-9 + rounding) && -slack > violation) violation = -slack, violation_node = node;
    // Within kKktTolerance of a bound counts as on it: the residual is a distance in angle, as
    // the solver's projected gradient |x − P(x − g)| is (which stops within its tolerance of
    // a bound without stepping onto it).
    if (slack > kKktTolerance + rounding) return;
    if (u == none && v == none) return;
    if (u == none) u = v, au = av;
    if (v == none) v = u, av = au;
    columns.push_back({u, v, au, av});
  };
  for (std::size_t s = 0; s < spans; ++s) {
    const std::size_t j = s + 1 == n ? 0 : s + 1;
    if (var_a[s] != none) {
      bound(omega - alpha[s], da[s], var_a[s], 1.0, none, 0.0, s);
      bound(omega + alpha[s], da[s], var_a[s], -1.0, none, 0.0, s);
    } else {
      bound(omega - std::abs(alpha[s]), da[s], none, 0.0, none, 0.0, s);
    }
    if (var_b[s] != none) {
      bound(omega - beta[s], db[s], var_b[s], 1.0, none, 0.0, j);
      bound(omega + beta[s], db[s], var_b[s], -1.0, none, 0.0, j);
    } else {
      bound(omega - std::abs(beta[s]), db[s], none, 0.0, none, 0.0, j);
    }
    if (m.basis == MinEnergyBasis::kElastic) {
      const double sigma = alpha[s] >= beta[s] ? 1.0 : -1.0;
      bound(std::numbers::pi - std::abs(alpha[s] - beta[s]),
            1e-9 * std::numbers::pi + da[s] + db[s], var_a[s], sigma, var_b[s], -sigma, s);
    }
  }
  // An active constraint on two unknowns shares their residual (the least-squares multiplier
  // splits an error between them), so each may carry the other's allowance.
  for (const Column& c : columns) {
    if (c.u == c.v) continue;
    const double shared = std::max(noise[c.u], noise[c.v]);
    noise[c.u] = noise[c.v] = shared;
  }
  std::vector<double> res;
  detail::stationarity_residual(g, columns, res);
  double worst_excess = -1.0;
  for (std::size_t v = 0; v < nv; ++v) {
    const double a = std::abs(res[v]);
    if (!(a <= kKktTolerance + noise[v])) out.pass = false;
    const double excess = std::isfinite(a) ? a - noise[v] : std::numeric_limits<double>::infinity();
    if (excess > worst_excess || !std::isfinite(a)) {
      worst_excess = excess;
      out.residual = a;
      out.allowance = noise[v];
      out.node = var_node[v];
    }
  }
  if (violation > 0.0) {
    out.pass = false;
    if (violation > out.residual) out.residual = violation, out.node = violation_node;
    out.what = "a direction lies " + std::to_string(violation) + " rad beyond its bound at node " +
               std::to_string(violation_node);
  } else if (!out.pass) {
    out.what = "KKT residual " + std::to_string(out.residual) + " at node " +
               std::to_string(out.node) + " (allowance " + std::to_string(out.allowance) + ")";
  }
  return out;
}

/// Curvature at the start (u = 0) or end (u = 1) of a Bézier, from its control points.
inline double end_curvature(const CubicBezier& b, bool at_end) {
  const Vec2 d1 = at_end ? b.p[3] - b.p[2] : b.p[1] - b.p[0];
  const Vec2 d2 =
      at_end ? (b.p[3] - b.p[2]) - (b.p[2] - b.p[1]) : (b.p[2] - b.p[1]) - (b.p[1] - b.p[0]);
  const double s = norm(d1);
  return 2.0 * cross(d1, d2) / (3.0 * s * s * s);
}

/// G2 certificate of a Kozak–Krajnc result with g2: every breakpoint 3l (0 < l < m, m = ⌊(n −
/// 1) / 3⌋ pieces; a Hermite remainder after the last piece) whose direction is not given has
/// equal curvature on both sides, to kKktTolerance relative to the mean of its two chords.
inline KktResult check_g2_breakpoints(const FitInput& in, const FitResult& r) {
  KktResult out;
  out.checked = true;
  const std::size_t n = r.points.size();
  const std::size_t spans = r.closed ? n : n - 1;
  std::vector<std::size_t> first, last;
  if (!detail::spans_of(r, n, spans, first, last, out)) return out;
  const std::size_t m = (n - 1) / 3;
  double worst_excess = -1.0;
  for (std::size_t l = 1; l < m; ++l) {
    const std::size_t i = 3 * l;
    const bool given = i < in.kinds.size() && in.kinds[i] == PointKind::kClamped &&
                       i < in.tangents.size() && in.tangents[i];
    if (given) continue;
    const CubicBezier& left = r.spline.segments[last[i - 1]].bezier;
    const CubicBezier& right = r.spline.segments[first[i]].bezier;
    const double kl = end_curvature(left, true), kr = end_curvature(right, false);
    const double chord =
        0.5 * (norm(r.points[i] - r.points[i - 1]) + norm(r.points[i + 1] - r.points[i]));
    const double a = std::abs(kl - kr) * chord;
    // Rounding of the control points: relative error ~eps·size/arm in each curvature.
    const double arm = std::min(norm(left.p[3] - left.p[2]), norm(right.p[1] - right.p[0]));
    const double mag = std::max(detail::magnitude(left), detail::magnitude(right));
    const double allowance =
        16.0 * detail::kEps * (mag / arm) * (std::abs(kl) + std::abs(kr) + 1.0 / arm) * chord;
    if (!(a <= kKktTolerance + allowance)) out.pass = false;
    const double excess =
        std::isfinite(a) ? a - allowance : std::numeric_limits<double>::infinity();
    if (excess > worst_excess) {
      worst_excess = excess;
      out.residual = a;
      out.allowance = allowance;
      out.node = i;
    }
  }
  if (!out.pass) {
    out.what = "scaled curvature jump " + std::to_string(out.residual) + " at breakpoint " +
               std::to_string(out.node);
  }
  return out;
}

/// Data balls: the directions must be optimal for the returned positions (check_min_energy at
/// them), and the positions for the directions: the energy's force on each position (from the
/// curve's own end directions, src/detail/ball_energy) vanishes at a ball inside its disc and
/// is radial, pushing outward, at a ball on its circle. A free direction on a bound of its box
/// turns with that chord, so its torque (the bound's multiplier) adds to the forces on the
/// chord's ends; next to a given direction on a bound, or a direction on both of its bounds (a
/// stencil at 2Ω), the multiplier of a constraint on positions is not known here: those balls
/// are not checked, nor the ends of a chord below 1e-6 of the coordinates, nor those of an
/// elastic span on its pair bound |α − β| = π. Forces are measured as
/// the solver measures them: times the shorter adjacent chord ℓ, over the node's own weight 1/ℓ
/// (not the largest weight of the curve, which beside a near-repeated pair let forces a tenth of
/// the energy pass). Positions must lie in
/// their discs to the rounding of their coordinates.
inline KktResult check_balls(const FitInput& in, const FitResult& r, const BasicCurveMethod& m) {
  FitInput at = in;
  at.points = r.points;
  at.radii.clear();
  KktResult out = check_min_energy(at, r, m);
  if (!out.checked || !out.pass) return out;
  const std::size_t n = r.points.size(), spans = r.closed ? n : n - 1;
  std::vector<std::size_t> first, last;
  KktResult legs;
  if (!detail::spans_of(r, n, spans, first, last, legs)) return legs;
  std::vector<Vec2> force(n), unit_n(spans), pull(spans);
  std::vector<double> g_out(spans), g_in(spans), al(spans), be(spans), len(spans), e(spans);
  for (std::size_t s = 0; s < spans; ++s) {
    const std::size_t j = s + 1 == n ? 0 : s + 1;
    const Vec2 c = r.points[j] - r.points[s];
    const Vec2 d0 = detail::start_leg(r.spline.segments[first[s]].bezier);
    const Vec2 d1 = detail::end_leg(r.spline.segments[last[s]].bezier);
    const double phi = std::atan2(c.y, c.x);
    al[s] = std::remainder(std::atan2(d0.y, d0.x) - phi, 2 * std::numbers::pi);
    be[s] = std::remainder(std::atan2(d1.y, d1.x) - phi, 2 * std::numbers::pi);
    // Read off the Béziers, a direction on its bound can come out beyond it by rounding, where
    // some energies are infinite (restricted-elastic beyond 90°).
    for (double* x : {&al[s], &be[s]}) {
      if (std::abs(*x) > m.omega && std::abs(*x) <= m.omega * (1.0 + 1e-9))
        *x = std::copysign(m.omega, *x);
    }
    const fairspline::detail::SpanDerivatives sd =
        fairspline::detail::span_derivatives(basic_energy(m, al[s], be[s]), c);
    pull[s] = Vec2{sd.g[2], sd.g[3]};
    e[s] = sd.e;
    g_out[s] = sd.g[0], g_in[s] = sd.g[1];
    len[s] = norm(c);
    unit_n[s] = Vec2{-c.y, c.x} / len[s];
  }
  auto kind = [&](std::size_t i) { return i < in.kinds.size() ? in.kinds[i] : PointKind::kSmooth; };
  auto fixed = [&](std::size_t i) {
    return (kind(i) == PointKind::kClamped && i < in.tangents.size() && in.tangents[i]) ||
           (i == 0 && in.start_tangent) || (!r.closed && i + 1 == n && in.end_tangent);
  };
  const double bound = m.omega * (1.0 - 1e-9);
  // The solver holds a direction's second box (a stencil at 2Ω) and a given direction's box by
  // a barrier, which keeps them a little inside: near them counts as on them.
  const double near_bound = m.omega * (1.0 - 1e-5);
  std::vector<char> unchecked(n, 0);
  // A direction on a bound turns with its chord (θ = φ_s + const), so its torque moves the
  // chord's ends. Recorded first: where both end directions of a span turn with it, its (α, β)
  // stay put as the chord turns, and its own torques cancel with its chord-angle force (they are
  // infinite at some box corners, e.g. restricted-elastic at (90°, −90°)).
  struct Turn {
    std::size_t span;
    double other;  // the torque not from `span` itself (the node's other span's)
    bool start;    // the node is the span's start
  };
  std::vector<Turn> turns;
  auto skip_span = [&](std::size_t s) { unchecked[s] = unchecked[s + 1 == n ? 0 : s + 1] = 1; };
  // A chord below 1e-6 of the coordinates' size: its end directions, read off the Béziers,
  // keep fewer than ten digits, too few for the forces (check_min_energy's allowance covers
  // the directions, not the positions).
  double size = 0.0;
  for (const Point& q : r.points) size = std::max({size, std::abs(q.x), std::abs(q.y)});
  std::vector<char> tiny(spans, 0);
  for (std::size_t s = 0; s < spans; ++s) {
    if (len[s] < 1e-6 * size) skip_span(s), tiny[s] = 1;
    // The elastic spline's pair bound |α − β| = π (held by the solver's barrier): E_1's
    // partial derivatives are infinite there (only their sum, the turn of both, is finite).
    if (m.basis == MinEnergyBasis::kElastic &&
        std::abs(al[s] - be[s]) >= std::numbers::pi * (1.0 - 1e-5)) {
      skip_span(s);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const bool has_out = r.closed || i + 1 < n, has_in = r.closed || i > 0;
    const std::size_t so = i, si = i == 0 ? spans - 1 : i - 1;
    const bool on_out = has_out && std::abs(al[so]) >= bound;
    const bool on_in = has_in && std::abs(be[si]) >= bound;
    const bool tied = has_out && has_in && !(kind(i) == PointKind::kCorner && !fixed(i));
    if (fixed(i)) {
      // A given direction's box bounds the positions; the solver holds it by a barrier, which
      // keeps a chord a little inside (s41-c167: 1.6e-7° inside the bound 90°, a tangential
      // force of 0.86 on the ball, which turning the ball either way along its circle confirmed
      // as the bound's: one way is infeasible, the other raises the energy).
      if (has_out && std::abs(al[so]) >= near_bound) skip_span(so);
      if (has_in && std::abs(be[si]) >= near_bound) skip_span(si);
    } else if (tied) {
      if ((on_out && std::abs(be[si]) >= near_bound) || (on_in && std::abs(al[so]) >= near_bound)) {
        skip_span(so), skip_span(si);
      } else if (on_out && tiny[si]) {  // the torque carried over is that short span's: noise
        skip_span(so);
      } else if (on_out) {
        turns.push_back({so, g_in[si], true});
      } else if (on_in && tiny[so]) {
        skip_span(si);
      } else if (on_in) {
        turns.push_back({si, g_out[so], false});
      }
    } else {
      if (on_out) turns.push_back({so, 0.0, true});
      if (on_in) turns.push_back({si, 0.0, false});
    }
  }
  std::vector<int> ends(spans, 0);  // 1: the start turns with it, 2: the end, 3: both
  for (const Turn& t : turns) ends[t.span] |= t.start ? 1 : 2;
  for (std::size_t s = 0; s < spans; ++s) {
    const std::size_t j = s + 1 == n ? 0 : s + 1;
    // Both ends turning: E_1 is constant, only 1/L changes.
    const Vec2 f = ends[s] == 3 ? (e[s] / len[s]) * Vec2{-unit_n[s].y, unit_n[s].x} : pull[s];
    force[s] -= f;
    force[j] += f;
  }
  for (const Turn& t : turns) {
    const std::size_t j = t.span + 1 == n ? 0 : t.span + 1;
    const double own = t.start ? g_out[t.span] : g_in[t.span];
    const double torque = ends[t.span] == 3 ? t.other : t.other + own;
    force[t.span] -= (torque / len[t.span]) * unit_n[t.span];
    force[j] += (torque / len[t.span]) * unit_n[t.span];
  }
  double worst = 0.0;
  std::size_t at_node = 0;
  std::string what;
  for (std::size_t i = 0; i < n && i < in.radii.size(); ++i) {
    const double radius = in.radii[i];
    if (!(radius > 0.0)) continue;
    double ell = HUGE_VAL;
    if (r.closed || i > 0)
      ell = std::min(ell, distance(in.points[i], in.points[i ? i - 1 : n - 1]));
    if (r.closed || i + 1 < n) ell = std::min(ell, distance(in.points[i], in.points[(i + 1) % n]));
    const Vec2 off = r.points[i] - in.points[i], f = force[i] * (ell * ell);
    const double here = std::max({std::abs(in.points[i].x), std::abs(in.points[i].y),
                                  std::abs(r.points[i].x), std::abs(r.points[i].y)});
    const double rounding = 16.0 * detail::kEps * here;  // of p − q and of the projection
    double res = 0.0;
    const char* kind_text = "force at an inactive ball";
    if (norm(off) > radius * (1.0 + 1e-12) + rounding) {
      res = HUGE_VAL, kind_text = "position outside its disc";
    } else if (unchecked[i]) {
      continue;
    } else if (norm(off) >= radius * (1.0 - 1e-9) - rounding) {
      const Vec2 u = off / norm(off);
      res = std::max(std::abs(cross(u, f)), dot(f, u));
      kind_text = "tangential or inward force at an active ball";
    } else {
      res = norm(f);
    }
    if (res > worst) worst = res, at_node = i, what = kind_text;
  }
  if (worst > out.residual) {
    out.residual = worst, out.allowance = 0.0, out.node = at_node;
    out.pass = worst <= kKktTolerance;
    if (!out.pass) {
      out.what = what + " " + std::to_string(worst) + " at point " + std::to_string(at_node);
    }
  }
  return out;
}

/// The certificate that applies to `r`: min-energy (an omega_deg option), G2 breakpoints (an
/// option g2 that is on), else nothing checked.
inline KktResult check_optimum(const FitInput& in, const FitResult& r) {
  const bool balls = std::any_of(in.radii.begin(), in.radii.end(), [](double x) { return x > 0; });
  if (const auto m = min_energy_method_of(r)) {
    return balls ? check_balls(in, r, *m) : check_min_energy(in, r, *m);
  }
  if (r.options.is_object() && r.options.value("g2", false)) return check_g2_breakpoints(in, r);
  return {};
}

}  // namespace fairspline::stress
