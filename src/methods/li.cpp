#include "fairspline/methods/li.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "detail/finite.hpp"
#include "detail/format.hpp"
#include "detail/huge_pages.hpp"
#include "detail/input.hpp"
#include "detail/tridiagonal.hpp"
#include "fairspline/energy.hpp"
#include "fairspline/error.hpp"

namespace fairspline {

namespace {

// Per-span coefficients of the normal equations (see docs/methods/li.md):
//   span i adds to node i and i+1:  diag += 2 s + q,  coupling = s + q,
//   rhs += (3 s + 2 q) δ_i   with s = w1 / h_i, q = 18 w2 H² / h_i³, δ_i = ΔP_i / h_i.
struct SpanTerms {
  double diag;
  double off;
  Vec2 rhs;
};

inline SpanTerms span_terms(Vec2 dp, double h, double w1, double w2h2) {
  const double inv = 1.0 / h;
  const double s = w1 * inv;
  const double q = 18.0 * w2h2 * inv * inv * inv;
  const Vec2 delta = dp * inv;
  return {2.0 * s + q, s + q, (3.0 * s + 2.0 * q) * delta};
}

struct LiProblem {
  std::span<const Point> points;
  std::span<const double> knots;
  bool closed = false;
  double w1 = 1.0, w2 = 0.0, h2 = 1.0;     // h2 = H², the knot scale squared
  std::vector<std::optional<Vec2>> fixed;  // per node (size n); empty = none fixed
};

std::string singular_message(bool closed) {
  return std::string(
             "the curvature-variation energy alone (Li, system 2.16) has no unique minimizer: "
             "every C1 piecewise-quadratic curve through the points has zero energy, one for "
             "each start tangent. ") +
         (closed ? "Clamp a tangent (a clamped point or a start tangent), use an odd number of "
                   "points, or use li-combined."
                 : "Give a start tangent (or clamp a point), or use li-combined.");
}

[[noreturn]] void throw_singular_numerics() {
  throw Error(ErrorCode::kSingularSystem,
              "the Li system is numerically singular for these points (a knot interval is too "
              "small relative to the others)");
}

// Open curve, nothing clamped, w1 > 0 (the common case): assembly fused into the forward sweep
// of the Thomas algorithm. The matrix is symmetric positive definite, so pivots are positive.
// Leaves the eliminated right-hand sides in m and the multipliers in c (both size n): fit_li
// does the back substitution while it builds the pieces (one pass less over the data).
// A loop of its own: the sweep is one serial chain through a division per node, and a short
// loop body lets the out-of-order core run the independent assembly of later nodes alongside.
void solve_open_free(const LiProblem& pb, std::vector<Vec2>& m, std::vector<double>& c) {
  const std::size_t n = pb.points.size();
  const auto& P = pb.points;
  const auto& t = pb.knots;
  const double w2h2 = pb.w2 * pb.h2;
  detail::resize_huge(m, n);
  detail::resize_huge(c, n);
  SpanTerms prev{0.0, 0.0, {0.0, 0.0}};  // span j-1 (none before node 0)
  double c_prev = 0.0;
  Vec2 y_prev{0.0, 0.0};
  for (std::size_t j = 0; j < n; ++j) {
    const SpanTerms next = j + 1 < n ? span_terms(P[j + 1] - P[j], t[j + 1] - t[j], pb.w1, w2h2)
                                     : SpanTerms{0.0, 0.0, {0.0, 0.0}};
    const double pivot = prev.diag + next.diag - prev.off * c_prev;
    if (!(pivot > 0.0)) throw_singular_numerics();
    const double inv = 1.0 / pivot;
    c_prev = next.off * inv;
    y_prev = (prev.rhs + next.rhs - prev.off * y_prev) * inv;
    c[j] = c_prev;
    m[j] = y_prev;
    prev = next;
  }
}

// Open system on nodes 0..N-1 with spans between consecutive nodes (span j: node j -> j+1).
// `point_at(j)`, `span_h(j)`, `fixed_at(j)` give the system's node data.
template <typename PointAt, typename SpanAt, typename FixedAt>
void solve_open(std::size_t nodes, PointAt&& point_at, SpanAt&& span_h, FixedAt&& fixed_at,
                double w1, double w2h2, std::vector<Vec2>& m) {
  std::vector<double> sub(nodes, 0.0), diag(nodes, 0.0), sup(nodes, 0.0), scratch;
  m.assign(nodes, Vec2{0.0, 0.0});
  for (std::size_t j = 0; j + 1 < nodes; ++j) {
    const SpanTerms t = span_terms(point_at(j + 1) - point_at(j), span_h(j), w1, w2h2);
    diag[j] += t.diag;
    diag[j + 1] += t.diag;
    sup[j] = t.off;
    sub[j + 1] = t.off;
    m[j] += t.rhs;
    m[j + 1] += t.rhs;
  }
  // Fixed tangents: identity rows, their couplings moved to the neighbours' right-hand sides.
  for (std::size_t j = 0; j < nodes; ++j) {
    const std::optional<Vec2> v = fixed_at(j);
    if (!v) continue;
    if (j > 0) {
      m[j - 1] -= sup[j - 1] * *v;
      sup[j - 1] = 0.0;
    }
    if (j + 1 < nodes) {
      m[j + 1] -= sub[j + 1] * *v;
      sub[j + 1] = 0.0;
    }
    diag[j] = 1.0;
    sub[j] = 0.0;
    sup[j] = 0.0;
    m[j] = *v;
  }
  if (!detail::solve_tridiagonal(sub, diag, sup, m, scratch)) throw_singular_numerics();
}

// Solves for the tangent vectors m (size n) of the problem, except the open system with no
// fixed tangent and w1 > 0 (solve_open_free and the back substitution in fit_li).
void solve_tangents(const LiProblem& pb, std::vector<Vec2>& m) {
  const std::size_t n = pb.points.size();
  const auto& P = pb.points;
  const auto& t = pb.knots;
  auto fixed_at_point = [&](std::size_t i) -> std::optional<Vec2> {
    return pb.fixed.empty() ? std::nullopt : pb.fixed[i];
  };
  if (!pb.closed) {
    solve_open(
        n, [&](std::size_t j) { return P[j]; }, [&](std::size_t j) { return t[j + 1] - t[j]; },
        fixed_at_point, pb.w1, pb.w2 * pb.h2, m);
    return;
  }
  // Closed: with a fixed node, rotate it to the front and solve an open system on n+1 nodes
  // whose first and last node are that same fixed point.
  std::size_t first_fixed = n;
  for (std::size_t i = 0; i < n && !pb.fixed.empty(); ++i) {
    if (pb.fixed[i]) {
      first_fixed = i;
      break;
    }
  }
  if (first_fixed < n) {
    const std::size_t r = first_fixed;
    std::vector<Vec2> mr;
    solve_open(
        n + 1, [&](std::size_t j) { return P[(j + r) % n]; },
        [&](std::size_t j) {
          const std::size_t s = (j + r) % n;
          return t[s + 1] - t[s];
        },
        [&](std::size_t j) { return fixed_at_point((j + r) % n); }, pb.w1, pb.w2 * pb.h2, mr);
    detail::resize_huge(m, n);
    for (std::size_t j = 0; j < n; ++j) m[(j + r) % n] = mr[j];
    return;
  }
  if (pb.w1 == 0.0) {
    if (n % 2 == 0) throw Error(ErrorCode::kSingularSystem, singular_message(true));
    // m_i + m_{i+1} = 2 δ_i around an odd cycle has the unique solution
    // m_0 = Σ_k (-1)^k δ_k, then m_{i+1} = 2 δ_i - m_i (zero energy).
    m.assign(n, Vec2{0.0, 0.0});
    Vec2 acc{0.0, 0.0};
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 delta = (P[(k + 1) % n] - P[k]) / (t[k + 1] - t[k]);
      acc += (k % 2 == 0 ? 1.0 : -1.0) * delta;
    }
    m[0] = acc;
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const Vec2 delta = (P[k + 1] - P[k]) / (t[k + 1] - t[k]);
      m[k + 1] = 2.0 * delta - m[k];
    }
    return;
  }
  std::vector<double> off(n), diag(n, 0.0);
  m.assign(n, Vec2{0.0, 0.0});
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const SpanTerms s = span_terms(P[j] - P[i], t[i + 1] - t[i], pb.w1, pb.w2 * pb.h2);
    diag[i] += s.diag;
    diag[j] += s.diag;
    off[i] = s.off;
    m[i] += s.rhs;
    m[j] += s.rhs;
  }
  if (!detail::solve_cyclic_symmetric(off, diag, m)) throw_singular_numerics();
}

// Unit direction of v; |v| by sqrt(norm2) unless that could under/overflow. Otherwise v is
// divided by its largest component first: v / hypot(v) of a denormal v like (5e-324, 5e-324)
// is (1, 1), as hypot rounds to a denormal too (found by fuzz_fit).
inline Vec2 robust_unit(Vec2 v) {
  const double n2 = norm2(v);
  if (n2 > 1e-290 && n2 < 1e290) return (1.0 / std::sqrt(n2)) * v;
  return normalized(v);
}

// a, b divided by their lengths when both squared lengths are in robust_unit's plain range:
// its first branch, (1 / sqrt(|v|²)) v, for two vectors in SSE2 lanes (same IEEE operations, so
// the same bits). False (nothing changed) otherwise.
inline bool unit_pair(Vec2& a, Vec2& b) {
#if defined(__SSE2__)
  const __m128d x = _mm_set_pd(b.x, a.x), y = _mm_set_pd(b.y, a.y);
  const __m128d n2 = _mm_add_pd(_mm_mul_pd(x, x), _mm_mul_pd(y, y));
  const __m128d in_range =
      _mm_and_pd(_mm_cmpgt_pd(n2, _mm_set1_pd(1e-290)), _mm_cmplt_pd(n2, _mm_set1_pd(1e290)));
  if (_mm_movemask_pd(in_range) != 3) return false;
  const __m128d inv = _mm_div_pd(_mm_set1_pd(1.0), _mm_sqrt_pd(n2));
  const __m128d ux = _mm_mul_pd(inv, x), uy = _mm_mul_pd(inv, y);
  a = {_mm_cvtsd_f64(ux), _mm_cvtsd_f64(uy)};
  b = {_mm_cvtsd_f64(_mm_unpackhi_pd(ux, ux)), _mm_cvtsd_f64(_mm_unpackhi_pd(uy, uy))};
  return true;
#else
  (void)a;
  (void)b;
  return false;
#endif
}

// The unit tangent at node i from its tangent vector m_i outside robust_unit's fast range. A
// zero derivative (a cusp of the C1 curve) reports the chord direction instead.
[[gnu::noinline]] Vec2 unit_tangent_slow(std::span<const Point> P, bool closed,
                                         const std::vector<Vec2>& m, std::size_t i) {
  const std::size_t n = P.size();
  if (m[i].x != 0.0 || m[i].y != 0.0) return robust_unit(m[i]);
  const Vec2 chord = (closed || (i > 0 && i + 1 < n))
                         ? P[(i + 1) % n] - P[(i + n - 1) % n]
                         : (i == 0 ? P[1] - P[0] : P[n - 1] - P[n - 2]);
  return robust_unit(chord);
}

}  // namespace

namespace {

const Capabilities& li_capabilities() {
  static const Capabilities caps{
      .continuity = Continuity::kC1,
      .regular = false,
      .examples = {R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0],[8,1],[9,3]]})",
                   R"({"points": [[0,0],[4,0],[4,4],[0,4]], "closed": true})",
                   R"({"points": [[0,0],[1,1],[2,0],[3,1]], "start_tangent": [1,0]})"}};
  return caps;
}

}  // namespace

void fit_li(const FitInput& input, const LiOptions& options, ReportLevel level, FitResult& out) {
  const double w1 = options.strain_weight, w2 = options.curvature_variation_weight;
  if (!(w1 >= 0.0 && w2 >= 0.0 && std::isfinite(w1) && std::isfinite(w2) && w1 + w2 > 0.0)) {
    throw Error(ErrorCode::kBadOption,
                "Li weights must be finite and non-negative with a positive sum, got (" +
                    detail::format_number(w1) + ", " + detail::format_number(w2) + ")");
  }
  const std::size_t spans = detail::prepare_input(input, li_capabilities(), "the Li method", out);
  thread_local std::vector<double> scratch;  // multipliers of the sweep, reused across fits
  LiProblem pb;
  pb.points = out.points;
  pb.knots = out.knots;
  pb.closed = out.closed;
  pb.w1 = w1;
  pb.w2 = w2;
  const std::size_t n = pb.points.size();
  const double H = (pb.knots.back() - pb.knots.front()) / static_cast<double>(spans);
  pb.h2 = H * H;

  // Clamped tangents.
  std::vector<std::size_t> clamped;
  auto fix = [&](std::size_t i, Vec2 v) {
    if (pb.fixed.empty()) pb.fixed.resize(n);
    pb.fixed[i] = v;
  };
  for (std::size_t i = 0; i < std::min(input.kinds.size(), n); ++i) {
    if (input.kinds[i] == PointKind::kClamped) fix(i, *input.tangents[i]);
  }
  if (input.start_tangent) fix(0, *input.start_tangent);
  if (input.end_tangent) fix(n - 1, *input.end_tangent);
  for (std::size_t i = 0; i < pb.fixed.size(); ++i) {
    if (pb.fixed[i]) clamped.push_back(i);
  }
  if (w1 == 0.0 && clamped.empty() && !(pb.closed && n % 2 == 1)) {
    throw Error(ErrorCode::kSingularSystem, singular_message(pb.closed));
  }

  // The tangent vectors m_i are solved into out.tangents, then normalized in place. The open
  // free system leaves its back substitution to the pass that builds the pieces.
  std::vector<Vec2>& m = out.tangents;
  const bool open_free = !pb.closed && pb.fixed.empty() && pb.w1 > 0.0;
  if (open_free) {
    solve_open_free(pb, m, scratch);
  } else {
    solve_tangents(pb, m);
  }

  out.spline.closed = pb.closed;
  auto& segments = out.spline.segments;
  // A no-op when the result is reused for same-size fits; a fresh one is mapped in whole.
  detail::resize_huge(segments, spans);
  Segment* seg = segments.data();
  std::uint64_t bad = 0;  // non-finite output, checked while the data is in registers
  const auto& P = pb.points;
  const auto& t = pb.knots;
  // m_i becomes the unit tangent as soon as the last piece using it is built (one pass over
  // the data). A closed curve's last piece uses m_0 again: keep that one raw. The common case
  // inline (robust_unit's first branch); zero, tiny, huge or NaN vectors out of line.
  auto to_unit = [&](std::size_t i) {
    const Vec2 v = m[i];
    const double n2 = norm2(v);
    if (n2 > 1e-290 && n2 < 1e290) [[likely]] {
      m[i] = (1.0 / std::sqrt(n2)) * v;
    } else {
      m[i] = unit_tangent_slow(P, pb.closed, m, i);
    }
    bad |= detail::non_finite_bits(m[i]);
  };
  auto piece = [&](std::size_t i, std::size_t j, Vec2 mi, Vec2 mj) {
    const double h3 = (t[i + 1] - t[i]) * (1.0 / 3.0);
    const Point b1 = P[i] + h3 * mi, b2 = P[j] - h3 * mj;
    bad |= detail::non_finite_bits(b1) | detail::non_finite_bits(b2);
    seg[i] = Segment{CubicBezier{{P[i], b1, b2, P[j]}}, t[i], t[i + 1], i};
  };
  if (open_free) {
    // Back substitution from the last node down, building piece i as soon as m_i is known.
    // Two nodes per step, so that their normalizations share the divide/square-root unit's
    // packed operations (the pass is bound by that unit, not by memory).
    const double* c = scratch.data();
    std::size_t i = n - 1;
    for (; i >= 2; i -= 2) {
      m[i - 1] -= c[i - 1] * m[i];
      piece(i - 1, i, m[i - 1], m[i]);
      m[i - 2] -= c[i - 2] * m[i - 1];
      piece(i - 2, i - 1, m[i - 2], m[i - 1]);
      if (!unit_pair(m[i], m[i - 1])) [[unlikely]] {
        to_unit(i);
        to_unit(i - 1);
      } else {
        bad |= detail::non_finite_bits(m[i]) | detail::non_finite_bits(m[i - 1]);
      }
    }
    for (; i-- > 0;) {
      m[i] -= c[i] * m[i + 1];
      piece(i, i + 1, m[i], m[i + 1]);
      to_unit(i + 1);
    }
    to_unit(0);
  } else {
    const Vec2 m0 = m[0];
    for (std::size_t i = 0; i < spans; ++i) {
      const std::size_t j = (i + 1 == n) ? 0 : i + 1;
      piece(i, j, i == 0 ? m0 : m[i], j == 0 ? m0 : m[j]);
      to_unit(i);
    }
    if (!pb.closed) to_unit(n - 1);
  }
  double strain = 0.0, third = 0.0;
  if (level != ReportLevel::kNone) {
    for (std::size_t i = 0; i < spans; ++i) {
      const double h = t[i + 1] - t[i];
      // From the control points (differences before squares): the expansion in m and
      // delta = dP/h squared coordinates of 1e300 and overflowed where the energy is 0 (found
      // by fuzz_fit). linearized_energy throws kNonFinite if the energy itself overflows.
      const CubicBezier& b = seg[i].bezier;
      strain += linearized_energy(b, h);
      // Third derivative in the local parameter (constant): 6 (b3 - 3 b2 + 3 b1 - b0).
      const Vec2 d3 = 6.0 * ((b.p[3] - b.p[0]) + 3.0 * (b.p[1] - b.p[2]));
      // |d3|²/h⁵ as a square of |d3|/h^2.5: h⁵ underflows for knots near 1e-75 (points near
      // 1e-150 with centripetal knots) although the term itself is representable.
      const double r = norm(d3) / h / h / std::sqrt(h);
      third += r * r;
    }
  }
  // Points were checked by prepare_input; knots are finite there too. Name the culprit.
  if (bad) detail::check_finite_output(out, "the Li method");
  out.method_report = {{"weights", {w1, w2}},
                       {"knot_scale", H},
                       {"system", pb.closed ? "cyclic-tridiagonal" : "tridiagonal"},
                       {"clamped", clamped}};
  if (level != ReportLevel::kNone) {
    if (!std::isfinite(strain) || !std::isfinite(third) ||
        !std::isfinite(w1 * strain + w2 * pb.h2 * third)) {
      throw Error(ErrorCode::kNonFinite,
                  "the Li method: the energy of the curve overflows double precision (points or "
                  "tangents too large for their knot spacing)");
    }
    out.method_report["strain_term"] = strain;
    out.method_report["third_derivative_term"] = third;
    out.method_report["objective"] = w1 * strain + w2 * pb.h2 * third;
  }
}

FitResult fit_li(const FitInput& input, const LiOptions& options, ReportLevel level) {
  FitResult result;
  fit_li(input, options, level, result);
  return result;
}

}  // namespace fairspline

// ---- registry entries ----
#include "methods/builtin.hpp"

namespace fairspline::detail {

namespace {
/// Energies in the knot parameter: |s''|² dt has units length²/knot³, |s'''|² dt length²/knot⁵.
std::vector<ReportUnit> li_report_units() {
  return {{"knot_scale", 0, 1},
          {"strain_term", 2, -3},
          {"third_derivative_term", 2, -5},
          {"objective", 2, -3}};
}
}  // namespace

std::vector<MethodInfo> li_methods() {
  const std::string paper =
      "J. Li, Constructing planar C1 cubic Hermite interpolation curves via approximate energy "
      "minimization, Section 2";
  MethodInfo strain{
      .name = "li-strain",
      .description =
          "C1 cubic minimizing the linearized strain energy ∫|s''|² dt: the natural (closed: "
          "periodic) C2 cubic spline on the knots (Li 2.13, 2.20).",
      .paper = paper + ", system (2.13)/(2.20)",
      .fit =
          [](const FitInput& in, const nlohmann::json&, const FitOptions& f, FitResult& out) {
            fit_li(in, {1.0, 0.0}, f.method_report_level(), out);
          },
      .capabilities = li_capabilities(),
      .checks_own_output = true,
      .report_units = li_report_units()};
  MethodInfo combined{
      .name = "li-combined",
      .description =
          "C1 cubic minimizing w1·∫|s''|² dt + w2·H²·∫|s'''|² dt (Li's combined energy 2.17, "
          "2.21 for weights 1,1 and uniform knots).",
      .paper = paper + ", system (2.17)/(2.21)",
      .options = {{.name = "weights",
                   .type = OptionType::kNumberList,
                   .default_value = nlohmann::json::array({1.0, 1.0}),
                   .min = 0.0,
                   .doc = "[w1, w2]: weights of the strain and curvature-variation terms "
                          "(non-negative, w1 > 0 or a clamped tangent)"}},
      .fit =
          [](const FitInput& in, const nlohmann::json& o, const FitOptions& f, FitResult& out) {
            const auto& w = o.at("weights");
            if (w.size() != 2) {
              throw Error(ErrorCode::kBadOption,
                          "option 'weights' of li-combined must have two entries [w1, w2], got " +
                              w.dump());
            }
            fit_li(in, {w[0].get<double>(), w[1].get<double>()}, f.method_report_level(), out);
          },
      .capabilities = li_capabilities(),
      .checks_own_output = true,
      .report_units = li_report_units()};
  MethodInfo curvature{
      .name = "li-curvature-variation",
      .description =
          "C1 cubic minimizing ∫|s'''|² dt alone (Li 2.16): a C1 piecewise-quadratic curve, "
          "unique only with a clamped start tangent (or a closed curve with an odd number of "
          "points).",
      .paper = paper + ", system (2.16)",
      .fit =
          [](const FitInput& in, const nlohmann::json&, const FitOptions& f, FitResult& out) {
            fit_li(in, {0.0, 1.0}, f.method_report_level(), out);
          },
      .capabilities = li_capabilities(),
      .checks_own_output = true,
      .report_units = li_report_units()};
  curvature.capabilities.needs_clamped_tangent = true;
  curvature.capabilities.examples = {
      R"({"points": [[0,0],[1,1],[2,0],[3,1]], "start_tangent": [1,0]})",
      R"({"points": [[0,0],[4,0],[4,4],[0,4],[-2,2]], "closed": true})"};
  return {strain, combined, curvature};
}

}  // namespace fairspline::detail
