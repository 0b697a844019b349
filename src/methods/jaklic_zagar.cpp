// Jaklič–Žagar G1 cubic spline with small strain energy. See
// include/fairspline/methods/jaklic_zagar.hpp and docs/methods/jaklic-zagar.md.
#include "fairspline/methods/jaklic_zagar.hpp"

#include <algorithm>
#include <barrier>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "detail/finite.hpp"
#include "detail/format.hpp"
#include "detail/huge_pages.hpp"
#include "detail/input.hpp"
#include "detail/numbers.hpp"
#include "detail/two_threads.hpp"
#include "fairspline/error.hpp"
#include "fairspline/parameterization.hpp"

namespace fairspline {

namespace {

// The per-point helpers of the hot loop must inline into it: out-of-order execution then
// overlaps the square roots of neighbouring points (the loop is latency-bound otherwise).
#if defined(__GNUC__)
#define FAIRSPLINE_JZ_INLINE inline __attribute__((always_inline))
#else
#define FAIRSPLINE_JZ_INLINE inline
#endif

// z_i = 0 (collinear chords) and u_i·v_i = 0 (a right angle) are decided on the unit chord
// vectors: |â × b̂| resp. |â · b̂| at rounding level. Both are dimensionless, so the decision is
// relative to the data's scale by construction.
constexpr double kAngleTol = 8.0 * kEps;
// Floating-point range guards (not geometric tolerances): squares of lengths outside this range
// would overflow or lose precision in subnormals, so such values take a slower exact path.
constexpr double kLenLow = 1e-150, kLenHigh = 1e150;
constexpr double kRangeLow = 1e-140, kRangeHigh = 1e140;
// A bisector / fixed λ is reported as stationary when it equals λ* to this (λ is in [0, 1]).
constexpr double kLambdaMatch = 1e-12;

FAIRSPLINE_JZ_INLINE double length_of(Vec2 v) {
  const double l = std::sqrt(v.x * v.x + v.y * v.y);
  if (l >= kLenLow && l <= kLenHigh) return l;
  return std::hypot(v.x, v.y);
}

// One chord ΔT_j = T_{j+1} − T_j with its unit vector, length and knot interval.
struct Chord {
  Vec2 delta;
  Vec2 unit;
  double len;
  double h;
};

FAIRSPLINE_JZ_INLINE Chord make_chord(Point p, Point q, double h) {
  Chord c;
  c.delta = q - p;
  c.len = length_of(c.delta);
  c.unit = c.delta * (1.0 / c.len);
  c.h = h;
  return c;
}

// k = (w_b − w_a) / (w_b + w_a) ∈ [−1, 1] for the energy weights w_a = |A|²/ha³, w_b = |B|²/hb³
// of the two segments at a node (only their ratio matters), in the log domain so that no
// product can leave the double range.
double weight_balance_slow(double la, double ha, double lb, double hb) {
  const double log_ratio =
      2.0 * (std::log(la) - std::log(lb)) + 3.0 * (std::log(hb) - std::log(ha));
  return -std::tanh(0.5 * log_ratio);
}

enum class NodeCase : std::uint8_t { kTurn, kStraight, kReversal };

// NaN (chords beyond the double range) counts as a turn: it reaches the output, whose check
// reports it as non-finite rather than as a reversal.
FAIRSPLINE_JZ_INLINE NodeCase classify_turn(double c, double s) {
  if (!(std::abs(s) <= kAngleTol)) return NodeCase::kTurn;
  return c > 0.0 ? NodeCase::kStraight : NodeCase::kReversal;
}

// Unnormalized bisector of the angle θ ∈ (0, π) between the unit vectors a and b (signed sin s
// of the turn ≠ 0): a + b (length 2cos(θ/2)) and z·R(a − b) (length 2sin(θ/2)) both point along
// it, so their sum does too, with length >= 2 and no cancellation at any turn (a + b alone
// cancels near 180°, R(a − b) near 0°). No branch either.
FAIRSPLINE_JZ_INLINE Vec2 bisector_vector(Vec2 a, Vec2 b, double s) {
  return (a + b) + std::copysign(1.0, s) * perp(a - b);
}

FAIRSPLINE_JZ_INLINE Vec2 unit_of(Vec2 v) {
  return v * (1.0 / std::sqrt(v.x * v.x + v.y * v.y));
}

// Theorem 6 in the bisector frame (docs: "Evaluating Theorem 6 without cancellation"). With the
// turn θ = ∠(a, b), the bisector m̂ and d = m̂ rotated by ω towards b, the approximate energy of
// the two segments is const + 2w_a sin²(θ/2 + ω) + 2w_b sin²(θ/2 − ω), stationary where
// tan 2ω = k tan θ; the branch |2ω| < π − θ is the one on the admissible arc (the root of ρ in
// (0, 1)), i.e. (cos 2ω, sin 2ω) ∝ (|c|, sign(c) k |s|). By the half-angle identity
// (cos ω, sin ω) ∝ (r + |c|, sign(c) k |s|) with r = |(|c|, k|s|)|, so
//   d ∝ (r + |c|) m + sign(c) k |s| z R m,
// one square root and one normalization, no cancellation (r + |c| >= r >= |k s|).
// The factor w_a + w_b of k is kept on both components when its square is in range.
// Requires |c| > kAngleTol (u·v ≠ 0) and |s| > kAngleTol.
// Written without data-dependent branches: turn signs are random in real data, and
// mispredictions would cost more than the arithmetic.
FAIRSPLINE_JZ_INLINE Vec2 optimal_direction(Vec2 a, Vec2 b, double c, double s, double la,
                                            double ha, double lb, double hb) {
  const double z = std::copysign(1.0, s);
  const Vec2 m = (a + b) + z * perp(a - b);
  const double wa = la * la * (hb * hb * hb);  // w_a · ha³ hb³
  const double wb = lb * lb * (ha * ha * ha);  // w_b · ha³ hb³
  const double sum = wa + wb;
  double kc, ks;  // (|c|, sign(c) k |s|) times a positive factor
  if (sum > kRangeLow && sum < kRangeHigh) [[likely]] {
    kc = std::abs(c) * sum;
    ks = (wb - wa) * std::copysign(s, c);
  } else {
    kc = std::abs(c);
    ks = weight_balance_slow(la, ha, lb, hb) * std::copysign(s, c);
  }
  const double r = std::sqrt(kc * kc + ks * ks);
  return unit_of((r + kc) * m + (ks * z) * perp(m));
}

// (10) for a given λ: w ∝ z·R(λ|A| â − (1 − λ)|B| b̂), scaled so no product can overflow.
inline Vec2 lambda_direction(const Chord& A, const Chord& B, double s, double lambda) {
  const Vec2 v = A.len >= B.len ? lambda * A.unit - ((1.0 - lambda) * (B.len / A.len)) * B.unit
                                : (lambda * (A.len / B.len)) * A.unit - (1.0 - lambda) * B.unit;
  const Vec2 w = s > 0.0 ? perp(v) : -perp(v);
  return w * (1.0 / length_of(w));
}

// How the direction at one interior node is chosen.
enum class Rule : std::uint8_t { kOptimal, kBisector, kFixed, kClamped };

struct NodeSpec {
  Rule rule = Rule::kOptimal;
  double lambda = 0.5;  // kFixed
  Vec2 dir{};           // kClamped (unit)
};

// Direction at an interior node; returns false at a reversal.
bool interior_direction(const Chord& A, const Chord& B, const NodeSpec& spec, Vec2& d) {
  const double c = dot(A.unit, B.unit), s = cross(A.unit, B.unit);
  const NodeCase nc = classify_turn(c, s);
  if (nc == NodeCase::kReversal) return false;
  if (spec.rule == Rule::kClamped) {
    d = spec.dir;
    return true;
  }
  if (nc == NodeCase::kStraight) {
    d = B.unit;  // z_i = 0, same direction: w = ΔT_i (paper, after Lemma 5)
    return true;
  }
  switch (spec.rule) {
    case Rule::kOptimal:
      if (std::abs(c) <= kAngleTol) {
        // Right angle: the approximate energy is monotone (or constant) on the open arc, so
        // no λ in (0, 1) is stationary. Theorem 6's λ ∈ {0, 1} would give a piece with a
        // zero-length arm (zero speed, not regular: docs/methods/jaklic-zagar.md); the
        // bisector (Corollary 7) is used instead.
        d = unit_of(bisector_vector(A.unit, B.unit, s));
      } else {
        d = optimal_direction(A.unit, B.unit, c, s, A.len, A.h, B.len, B.h);
      }
      return true;
    case Rule::kBisector:
      d = unit_of(bisector_vector(A.unit, B.unit, s));
      return true;
    case Rule::kFixed:
      d = lambda_direction(A, B, s, spec.lambda);
      return true;
    case Rule::kClamped:
      break;
  }
  return true;
}

// (11) evaluated without cancellation, scale-free: ρ divided by (Δt_i)³|ΔT_{i-1}||ΔT_i| has the
// coefficients below in p = |A|/|B|, g = (ha/hb)³ and c = cos θ (u·v = −|A||B| c), and
// A2 = (p − g/p)² + 4 g c² is a sum of squares. The root in (0, 1) takes the sign σ = sign(u·v)
// in (11); of its two algebraically equal forms the one without cancellation is used.
double optimal_lambda_scaled(double p, double g, double c) {
  const double m = -c;  // u·v / (|A||B|)
  const double gp = g / p;
  const double c2 = (g - 1.0) * m + p - gp;
  const double c1 = gp + 2.0 * m - p;
  const double root = std::sqrt((p - gp) * (p - gp) + 4.0 * g * m * m);
  const double sigma = m > 0.0 ? 1.0 : -1.0;
  if (sigma * c1 >= 0.0) return 2.0 * m / (c1 + sigma * root);
  return (sigma * root - c1) / (2.0 * c2);
}

// λ of (10) that gives the unit direction d (d on the admissible arc): w·A = (1 − λ)|A×B|,
// w·B = λ|A×B|, so λ = d·B / (d·A + d·B).
double lambda_of_direction(const Chord& A, const Chord& B, Vec2 d) {
  const double da = dot(d, A.unit) * (A.len >= B.len ? 1.0 : A.len / B.len);
  const double db = dot(d, B.unit) * (A.len >= B.len ? B.len / A.len : 1.0);
  return db / (da + db);
}

double optimal_lambda_of(const Chord& A, const Chord& B, double c, double s) {
  if (std::abs(c) <= kAngleTol) return 1.0 / (1.0 + A.len / B.len);  // the bisector's λ
  const double p = A.len / B.len;
  const double r = A.h / B.h;
  const double lam = optimal_lambda_scaled(p, r * r * r, c);
  if (std::isfinite(lam) && lam >= 0.0 && lam <= 1.0) return lam;
  // Ratios beyond the double range: the direction is exact, read λ off it.
  return lambda_of_direction(A, B, optimal_direction(A.unit, B.unit, c, s, A.len, A.h, B.len, B.h));
}

std::string fmt_point(Vec2 v) {
  return detail::format_point(v);
}

[[noreturn]] void throw_reversal(std::size_t index) {
  throw Error(ErrorCode::kReversal,
              "the curve reverses direction at point " + std::to_string(index) +
                  " (its two chords are collinear and opposite, a 180 degree turn): every G1 "
                  "curve through these points folds there (Jaklic-Zagar, Lemma 5). Remove or move "
                  "the point, or set the option reversal to insert, which inserts points there",
              index, OptionHint{"reversal", "insert"});
}

// ---- input preparation ----

// The points and knots live in the FitResult being written (its capacity is reused).
struct Problem {
  Problem(std::vector<Point>& p, std::vector<double>& t) : points(p), knots(t) {}
  std::vector<Point>& points;
  std::vector<double>& knots;
  bool closed = false;
  std::vector<NodeSpec> specs;           // per point; empty = all `global`
  NodeSpec global;                       // rule for points without their own spec
  std::vector<std::size_t> origin;       // output index -> input index (npos: inserted); empty = id
  std::vector<std::size_t> inserted;     // output indices of inserted points
  std::vector<std::size_t> inserted_at;  // for each: input index of the reversal point
};

constexpr std::size_t kInserted = static_cast<std::size_t>(-1);

// Index of output point i in the user's input (i itself for an inserted point).
std::size_t input_index(const Problem& pb, std::size_t i) {
  return pb.origin.empty() || pb.origin[i] == kInserted ? i : pb.origin[i];
}

// The reversal insertion (docs: "Reversals"): at a reversal T_i with incoming unit direction e
// and chord lengths la, lb, the point Q = T_i + s(−e/2 + σ(√3/2) e⊥), s = min(la, lb), e⊥ = e
// rotated +90°, is inserted into the longer chord (after T_i when lb >= la, else before): the
// apex of the equilateral triangle on the shorter chord. σ = ±1 puts the turn-around on the
// side opposite to where the path leaves the line at the far end F of the shorter chord (a
// corner of that triangle; G is the point next to F: σ = −sign(e × (G − F)), +1 when there is
// no G or it lies on the line), so the path does not run back through the turn-around.
void insert_at_reversals(Problem& pb, const FitInput& input) {
  const std::size_t n = pb.points.size();
  const auto& P = pb.points;
  std::vector<char> rev(n, 0), after(n, 0);
  std::vector<Point> q(n);
  bool any = false;
  const std::size_t first = pb.closed ? 0 : 1, last = pb.closed ? n : n - 1;
  for (std::size_t i = first; i < last; ++i) {
    const Point prev = P[i == 0 ? n - 1 : i - 1], next = P[i + 1 == n ? 0 : i + 1];
    const Vec2 A = P[i] - prev, B = next - P[i];
    const double la = length_of(A), lb = length_of(B);
    const Vec2 ea = A / la, eb = B / lb;
    if (classify_turn(dot(ea, eb), cross(ea, eb)) != NodeCase::kReversal) continue;
    any = true;
    rev[i] = 1;
    after[i] = lb >= la;
    // F and G: the far end of the shorter chord (not the one receiving Q) and the point beyond.
    double side = 1.0;
    const bool has_g = pb.closed ? n >= 4 : (after[i] ? i >= 2 : i + 2 < n);
    if (has_g) {
      const std::size_t f = after[i] ? (i + n - 1) % n : (i + 1) % n;
      const std::size_t g = after[i] ? (i + n - 2) % n : (i + 2) % n;
      if (cross(ea, P[g] - P[f]) > 0.0) side = -1.0;
    }
    const double sz = std::min(la, lb);
    q[i] = P[i] + sz * (-0.5 * ea + (side * 0.5 * std::numbers::sqrt3) * perp(ea));
  }
  if (!any) return;

  std::vector<Point> points;
  std::vector<double> knots;
  std::vector<NodeSpec> specs;
  std::vector<std::size_t> origin;
  const bool explicit_knots = !input.knots.empty();
  auto emit = [&](Point p, std::size_t from, const NodeSpec* spec, std::size_t at = 0) {
    points.push_back(p);
    origin.push_back(from);
    if (from == kInserted) {
      pb.inserted.push_back(points.size() - 1);
      pb.inserted_at.push_back(at);
    }
    if (!pb.specs.empty()) specs.push_back(spec ? *spec : pb.global);
  };
  for (std::size_t j = 0; j < n; ++j) {
    emit(P[j], input_index(pb, j), pb.specs.empty() ? nullptr : &pb.specs[j]);
    const std::size_t first_new = points.size();
    if (!pb.closed && j + 1 == n) break;
    const std::size_t next = j + 1 == n ? 0 : j + 1;
    if (rev[j] && after[j]) emit(q[j], kInserted, nullptr, j);
    if (rev[next] && !after[next]) emit(q[next], kInserted, nullptr, next);
    if (explicit_knots) {
      // Split [t_j, t_{j+1}] in proportion to the lengths of the new sub-polyline.
      const std::size_t m = points.size() - first_new;
      std::vector<double> cum(m + 1, 0.0);
      Point a = P[j];
      for (std::size_t k = 0; k <= m; ++k) {
        const Point b = k < m ? points[first_new + k] : P[next];
        cum[k] = (k > 0 ? cum[k - 1] : 0.0) + length_of(b - a);
        a = b;
      }
      const double t0 = pb.knots[j], t1 = pb.knots[j + 1];
      knots.push_back(t0);
      for (std::size_t k = 0; k < m; ++k) knots.push_back(t0 + (t1 - t0) * (cum[k] / cum[m]));
    }
  }
  if (explicit_knots) {
    knots.push_back(pb.knots.back());
  } else {
    alpha_knots(points, input.alpha, pb.closed, knots);
  }
  pb.points = std::move(points);
  pb.knots = std::move(knots);
  pb.specs = std::move(specs);
  pb.origin = std::move(origin);
}

const Capabilities& jaklic_zagar_capabilities() {
  static const Capabilities caps{
      .examples = {R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0],[8,1],[9,3]]})",
                   R"({"points": [[0,0],[4,0],[4,4],[0,4]], "closed": true})",
                   R"({"points": [[0,0],[2,0],[1,0],[3,0]], "options": {"reversal": "insert"}})"}};
  return caps;
}

// Checks the options and the input (into out.points, out.knots), resolves per-point rules.
Problem prepare(const FitInput& input, const JaklicZagarOptions& options, FitResult& out) {
  auto bad_lambda = [](double v, const std::string& what, std::optional<std::size_t> index) {
    throw Error(ErrorCode::kBadOption,
                what + " must be a number in the open interval (0, 1), got " +
                    detail::format_number(v) + " (0 and 1 make a tangent length alpha* vanish)",
                index);
  };
  NodeSpec global;
  switch (options.lambda) {
    case JaklicZagarLambda::kOptimal:
      global.rule = Rule::kOptimal;
      break;
    case JaklicZagarLambda::kBisector:
      global.rule = Rule::kBisector;
      break;
    case JaklicZagarLambda::kFixed:
      if (!(options.fixed_lambda > 0.0 && options.fixed_lambda < 1.0)) {
        bad_lambda(options.fixed_lambda, "option 'lambda'", std::nullopt);
      }
      global.rule = Rule::kFixed;
      global.lambda = options.fixed_lambda;
      break;
  }
  detail::prepare_input(input, jaklic_zagar_capabilities(), "the Jaklic-Zagar method", out);
  Problem pb{out.points, out.knots};
  pb.closed = out.closed;
  pb.global = global;
  const std::size_t n = pb.points.size();

  if (!options.lambdas.empty()) {
    if (options.lambdas.size() != n && options.lambdas.size() != input.points.size()) {
      throw Error(ErrorCode::kBadOption,
                  "option 'lambdas' has " + std::to_string(options.lambdas.size()) +
                      " entries but there are " + std::to_string(n) +
                      " points (give one lambda per point; entries at the ends of an open curve "
                      "are ignored)");
    }
    pb.specs.assign(n, global);
    for (std::size_t i = 0; i < n; ++i) {
      if (!pb.closed && (i == 0 || i + 1 == n)) continue;
      const double v = options.lambdas[i];
      if (!(v > 0.0 && v < 1.0)) {
        bad_lambda(v, "entry " + std::to_string(i) + " of option 'lambdas'", i);
      }
      pb.specs[i].rule = Rule::kFixed;
      pb.specs[i].lambda = v;
    }
  }
  // Per-point kinds and clamped tangents; start/end tangents.
  auto clamp = [&](std::size_t i, Vec2 t) {
    if (pb.specs.empty()) pb.specs.assign(n, global);
    pb.specs[i].rule = Rule::kClamped;
    pb.specs[i].dir = t / length_of(t);
  };
  for (std::size_t i = 0; i < std::min(input.kinds.size(), n); ++i) {
    if (input.kinds[i] == PointKind::kClamped) clamp(i, *input.tangents[i]);
  }
  if (input.start_tangent) clamp(0, *input.start_tangent);
  if (input.end_tangent) clamp(n - 1, *input.end_tangent);

  if (options.reversal == JaklicZagarReversal::kInsert) insert_at_reversals(pb, input);
  return pb;
}

[[noreturn]] void throw_inadmissible(const Problem& pb, std::size_t i, Vec2 d, bool at_start,
                                     bool at_end) {
  const std::size_t idx = input_index(pb, i);
  std::string what = at_start && !pb.closed ? "the start tangent"
                     : at_end               ? "the end tangent"
                                            : "the tangent clamped at point " + std::to_string(idx);
  throw Error(ErrorCode::kInfeasible,
              what + " " + fmt_point(d) + " does not point along the adjacent chord" +
                  (at_start || at_end ? "" : "s") +
                  " (its angle with a chord is 90 degrees or more), so a tangent length alpha* = "
                  "d.dT/dt of Theorem 2 is not positive and the segment would fold",
              idx);
}

// ---- the construction ----

inline Segment make_segment(const Chord& ch, Point p0, Point p1, Vec2 d0, Vec2 d1, double t0,
                            double t1, std::size_t span) {
  Segment seg;
  seg.bezier.p[0] = p0;
  seg.bezier.p[1] = p0 + (dot(d0, ch.delta) * (1.0 / 3.0)) * d0;
  seg.bezier.p[2] = p1 - (dot(d1, ch.delta) * (1.0 / 3.0)) * d1;
  seg.bezier.p[3] = p1;
  seg.t0 = t0;
  seg.t1 = t1;
  seg.span = span;
  return seg;
}

// Direction at node i between chords A (into i) and B (out of i), with checks.
inline Vec2 node_direction(const Problem& pb, std::size_t i, const Chord& A, const Chord& B) {
  const NodeSpec& spec = pb.specs.empty() ? pb.global : pb.specs[i];
  Vec2 d;
  if (!interior_direction(A, B, spec, d)) throw_reversal(input_index(pb, i));
  if (spec.rule == Rule::kClamped && !(dot(d, A.delta) > 0.0 && dot(d, B.delta) > 0.0)) {
    throw_inadmissible(pb, i, d, false, false);
  }
  return d;
}

Vec2 end_direction(const Problem& pb, std::size_t i, const Chord& ch, bool at_start) {
  if (!pb.specs.empty() && pb.specs[i].rule == Rule::kClamped) {
    const Vec2 d = pb.specs[i].dir;
    if (!(dot(d, ch.delta) > 0.0)) throw_inadmissible(pb, i, d, at_start, !at_start);
    return d;
  }
  return ch.unit;
}

// The common case at an interior node (λ optimal, no clamping): a proper turn goes straight to
// Theorem 6; straight points, right angles and reversals take the general path. Returns false
// at a reversal.
FAIRSPLINE_JZ_INLINE bool optimal_node(const Chord& A, const Chord& B, Vec2& d) {
  const double c = dot(A.unit, B.unit), s = cross(A.unit, B.unit);
  if (std::abs(s) > kAngleTol && std::abs(c) > kAngleTol) [[likely]] {
    d = optimal_direction(A.unit, B.unit, c, s, A.len, A.h, B.len, B.h);
    return true;
  }
  return interior_direction(A, B, NodeSpec{}, d);
}

// Chords of one block of nodes in structure-of-arrays form: chord k of the block is the one
// entering node (first + k) of the block, so node k sits between chords k and k + 1.
constexpr std::size_t kBlock = 256;
struct ChordBlock {
  alignas(16) double ux[kBlock + 1];
  alignas(16) double uy[kBlock + 1];
  alignas(16) double len[kBlock + 1];
  alignas(16) double h[kBlock + 1];
  void set(std::size_t k, const Chord& c) {
    ux[k] = c.unit.x;
    uy[k] = c.unit.y;
    len[k] = c.len;
    h[k] = c.h;
  }
  Chord get(std::size_t k) const { return Chord{{}, {ux[k], uy[k]}, len[k], h[k]}; }
};

#if defined(__SSE2__)
// make_chord for the chords P[j] -> P[j+1] and P[j+1] -> P[j+2] into block slots k, k + 1, in
// SSE2 lanes with the scalar code's operations. Returns false (nothing written) if a length is
// outside the range where the plain square root is exact.
inline bool chord_pair(const Point* P, const double* t, std::size_t j, ChordBlock& cb,
                       std::size_t k) {
  const __m128d p0 = _mm_loadu_pd(&P[j].x), p1 = _mm_loadu_pd(&P[j + 1].x),
                p2 = _mm_loadu_pd(&P[j + 2].x);
  const __m128d d0 = _mm_sub_pd(p1, p0), d1 = _mm_sub_pd(p2, p1);
  const __m128d dx = _mm_unpacklo_pd(d0, d1), dy = _mm_unpackhi_pd(d0, d1);
  const __m128d len = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)));
  const __m128d ok =
      _mm_and_pd(_mm_cmpge_pd(len, _mm_set1_pd(kLenLow)), _mm_cmple_pd(len, _mm_set1_pd(kLenHigh)));
  if (_mm_movemask_pd(ok) != 3) return false;
  const __m128d inv = _mm_div_pd(_mm_set1_pd(1.0), len);
  _mm_storeu_pd(cb.ux + k, _mm_mul_pd(dx, inv));
  _mm_storeu_pd(cb.uy + k, _mm_mul_pd(dy, inv));
  _mm_storeu_pd(cb.len + k, len);
  _mm_storeu_pd(cb.h + k, _mm_sub_pd(_mm_loadu_pd(t + j + 1), _mm_loadu_pd(t + j)));
  return true;
}

// optimal_direction for the two nodes k and k + 1 of a block, in the two lanes of SSE2 registers:
// the same operations in the same order, so the results are bitwise those of the scalar code
// (IEEE arithmetic is exact per lane; -ffp-contract=off keeps multiply and add separate).
// Returns false if either node needs the general path (a straight point, a right angle, a
// reversal, or weights outside the fast range); nothing is written then.
inline bool optimal_pair(const ChordBlock& cb, std::size_t k, Vec2& d0, Vec2& d1) {
  const __m128d sign = _mm_set1_pd(-0.0);
  const __m128d one = _mm_set1_pd(1.0);
  const __m128d ax = _mm_loadu_pd(cb.ux + k), ay = _mm_loadu_pd(cb.uy + k);
  const __m128d bx = _mm_loadu_pd(cb.ux + k + 1), by = _mm_loadu_pd(cb.uy + k + 1);
  const __m128d la = _mm_loadu_pd(cb.len + k), lb = _mm_loadu_pd(cb.len + k + 1);
  const __m128d ha = _mm_loadu_pd(cb.h + k), hb = _mm_loadu_pd(cb.h + k + 1);
  const __m128d c = _mm_add_pd(_mm_mul_pd(ax, bx), _mm_mul_pd(ay, by));
  const __m128d s = _mm_sub_pd(_mm_mul_pd(ax, by), _mm_mul_pd(ay, bx));
  const __m128d abs_c = _mm_andnot_pd(sign, c), abs_s = _mm_andnot_pd(sign, s);
  const __m128d wa = _mm_mul_pd(_mm_mul_pd(la, la), _mm_mul_pd(_mm_mul_pd(hb, hb), hb));
  const __m128d wb = _mm_mul_pd(_mm_mul_pd(lb, lb), _mm_mul_pd(_mm_mul_pd(ha, ha), ha));
  const __m128d sum = _mm_add_pd(wa, wb);
  const __m128d tol = _mm_set1_pd(kAngleTol);
  const __m128d ok = _mm_and_pd(_mm_and_pd(_mm_cmpgt_pd(abs_s, tol), _mm_cmpgt_pd(abs_c, tol)),
                                _mm_and_pd(_mm_cmpgt_pd(sum, _mm_set1_pd(kRangeLow)),
                                           _mm_cmplt_pd(sum, _mm_set1_pd(kRangeHigh))));
  if (_mm_movemask_pd(ok) != 3) return false;
  const __m128d z = _mm_or_pd(_mm_and_pd(s, sign), one);  // copysign(1, s)
  // m = (a + b) + z * perp(a - b), perp(v) = (-v.y, v.x)
  const __m128d mx =
      _mm_add_pd(_mm_add_pd(ax, bx), _mm_mul_pd(z, _mm_xor_pd(_mm_sub_pd(ay, by), sign)));
  const __m128d my = _mm_add_pd(_mm_add_pd(ay, by), _mm_mul_pd(z, _mm_sub_pd(ax, bx)));
  const __m128d kc = _mm_mul_pd(abs_c, sum);
  const __m128d ks =
      _mm_mul_pd(_mm_sub_pd(wb, wa), _mm_or_pd(_mm_and_pd(c, sign), abs_s));  // copysign(s, c)
  const __m128d r = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(kc, kc), _mm_mul_pd(ks, ks)));
  const __m128d t1 = _mm_add_pd(r, kc), t2 = _mm_mul_pd(ks, z);
  // v = t1 * m + t2 * perp(m)
  const __m128d vx = _mm_add_pd(_mm_mul_pd(t1, mx), _mm_mul_pd(t2, _mm_xor_pd(my, sign)));
  const __m128d vy = _mm_add_pd(_mm_mul_pd(t1, my), _mm_mul_pd(t2, mx));
  const __m128d inv =
      _mm_div_pd(one, _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(vx, vx), _mm_mul_pd(vy, vy))));
  alignas(16) double x[2], y[2];
  _mm_store_pd(x, _mm_mul_pd(vx, inv));
  _mm_store_pd(y, _mm_mul_pd(vy, inv));
  d0 = {x[0], y[0]};
  d1 = {x[1], y[1]};
  return true;
}
#endif

// Pass 1: the unit tangent directions at points first..last-1 (0 <= first < last <= n), in
// order, each handed to emit(d).
template <class Emit>
void directions(const Problem& pb, std::size_t first, std::size_t last, Emit&& emit) {
  const auto& P = pb.points;
  const auto& t = pb.knots;
  const std::size_t n = P.size();
  const bool fast = pb.specs.empty() && pb.global.rule == Rule::kOptimal;
  auto chord = [&](std::size_t j) {
    return make_chord(P[j], P[j + 1 == n ? 0 : j + 1], t[j + 1] - t[j]);
  };
  // Nodes first..last-1 between chords j-1 and j; `prev` holds chord first-1 on entry.
  auto interior = [&](std::size_t first, std::size_t last, Chord& prev) {
    if (first >= last) return;
    if (!fast) {
      for (std::size_t i = first; i < last; ++i) {
        const Chord next = chord(i);
        emit(node_direction(pb, i, prev, next));
        prev = next;
      }
      return;
    }
    // Blocks: first the chords (a short loop whose square roots overlap well), then the nodes
    // from them, two at a time where SSE2 is available. One fused loop leaves too few nodes in
    // flight to hide the latency of a node's chain of square roots and divisions.
    ChordBlock cb;
    auto scalar_node = [&](std::size_t k, std::size_t i) {
      Vec2 d;
      if (!optimal_node(cb.get(k), cb.get(k + 1), d)) [[unlikely]] {
        throw_reversal(input_index(pb, i));
      }
      emit(d);
    };
    for (std::size_t b = first; b < last; b += kBlock) {
      const std::size_t m = std::min(kBlock, last - b);
      cb.set(0, prev);
      std::size_t k = 0;
#if defined(__SSE2__)
      for (; k + 2 <= m && b + k + 2 < n; k += 2) {
        if (!chord_pair(P.data(), t.data(), b + k, cb, k + 1)) [[unlikely]] {
          cb.set(k + 1, chord(b + k));
          cb.set(k + 2, chord(b + k + 1));
        }
      }
#endif
      for (; k < m; ++k) cb.set(k + 1, chord(b + k));
      k = 0;
#if defined(__SSE2__)
      for (; k + 2 <= m; k += 2) {
        Vec2 d0, d1;
        if (optimal_pair(cb, k, d0, d1)) [[likely]] {
          emit(d0);
          emit(d1);
        } else {
          scalar_node(k, b + k);
          scalar_node(k + 1, b + k + 1);
        }
      }
#endif
      for (; k < m; ++k) scalar_node(k, b + k);
      prev = chord(b + m - 1);
    }
  };
  if (!pb.closed) {
    Chord prev = chord(first == 0 ? 0 : first - 1);
    if (first == 0) emit(end_direction(pb, 0, prev, true));
    interior(std::max<std::size_t>(first, 1), std::min(last, n - 1), prev);
    if (last == n) emit(end_direction(pb, n - 1, chord(n - 2), false));
  } else {
    // Closed: every point is interior; chord n-1 closes the curve.
    Chord prev = chord(first == 0 ? n - 1 : first - 1);
    interior(first, last, prev);
  }
}

// Pass 2: the Bézier piece of span j of Theorem 4's proof from the points and directions (a
// separate pass measured faster than emitting them per block). Non-finite control points or
// directions set bits of `bad` (checked while in registers; points and knots were checked by
// prepare_input).
// Whether a value seen was not finite: x − x is +0 for a finite x and NaN otherwise, and the
// bitwise OR of those stays all zero bits until one is NaN. In SSE2 registers, so that the
// pieces' loop moves nothing to integer registers (the bit tests were the largest share of it).
struct FiniteCheck {
#if defined(__SSE2__)
  __m128d acc = _mm_setzero_pd();
  FAIRSPLINE_JZ_INLINE void add(Vec2 v) {
    const __m128d x = _mm_set_pd(v.y, v.x);
    acc = _mm_or_pd(acc, _mm_sub_pd(x, x));
  }
  bool bad() const {
    const __m128i zero = _mm_setzero_si128();
    return _mm_movemask_epi8(_mm_cmpeq_epi8(_mm_castpd_si128(acc), zero)) != 0xFFFF;
  }
#else
  std::uint64_t bits = 0;
  void add(Vec2 v) {
    bits |= detail::non_finite_bits(v);
  }
  bool bad() const {
    return bits != 0;
  }
#endif
};

FAIRSPLINE_JZ_INLINE Segment piece(const Problem& pb, const Vec2* dirs, std::size_t j,
                                   FiniteCheck& check) {
  const auto& P = pb.points;
  const std::size_t n = P.size();
  const std::size_t k = j + 1 == n ? 0 : j + 1;
  const Vec2 delta = P[k] - P[j];
  const Vec2 d0 = dirs[j], d1 = dirs[k];
  const Point p1 = P[j] + (dot(d0, delta) * (1.0 / 3.0)) * d0;
  const Point p2 = P[k] - (dot(d1, delta) * (1.0 / 3.0)) * d1;
  check.add(d0);
  check.add(p1);
  check.add(p2);
  return Segment{CubicBezier{{P[j], p1, p2, P[k]}}, pb.knots[j], pb.knots[j + 1], j};
}

// Pieces first..last-1 into out[first..last-1].
bool pieces_into(const Problem& pb, const Vec2* dirs, std::size_t first, std::size_t last,
                 Segment* out) {
  FiniteCheck check;
  for (std::size_t j = first; j < last; ++j) out[j] = piece(pb, dirs, j, check);
  return check.bad();
}

// Both passes on two threads, each on half the points: the same operations per point as on
// one, so the same bits. A reversal in both halves is reported at the first, as on one thread.
bool build_on_two_threads(const Problem& pb, std::vector<Vec2>& dirs, std::vector<Segment>& segs) {
  const std::size_t n = pb.points.size(), spans = segs.size(), mid = n / 2;
  std::exception_ptr failed[2];
  bool bad[2] = {false, false};
  std::barrier directions_done(2);
  detail::on_two_threads([&](int h) {
    const std::size_t first = h == 0 ? 0 : mid, last = h == 0 ? mid : n;
    try {
      Vec2* out = dirs.data() + first;
      directions(pb, first, last, [&out](Vec2 d) { *out++ = d; });
    } catch (...) {
      failed[h] = std::current_exception();
    }
    directions_done.arrive_and_wait();  // each half's pieces read a direction of the other's
    if (failed[0] || failed[1]) return;
    bad[h] = pieces_into(pb, dirs.data(), h == 0 ? 0 : mid, h == 0 ? mid : spans, segs.data());
  });
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  // The last direction of an open curve is no piece's d0.
  return bad[0] || bad[1] || (!pb.closed && detail::non_finite_bits(dirs[n - 1]) != 0);
}

void build(const Problem& pb, FitResult& result) {
  std::vector<Vec2>& dirs = result.tangents;
  std::vector<Segment>& segs = result.spline.segments;
  const std::size_t n = pb.points.size(), spans = pb.closed ? n : n - 1;
  bool bad = false;
  // On two threads when the result's arrays already have their sizes (a reused result:
  // fit_into in a loop). Fresh arrays would have to be zeroed first, which costs about what the
  // second core saves.
  if (detail::split_in_two(n) && dirs.size() == n && segs.size() == spans) {
    bad = build_on_two_threads(pb, dirs, segs);
  } else {
    dirs.clear();
    detail::reserve_to_fill(dirs, n);
    directions(pb, 0, n, [&dirs](Vec2 d) { dirs.push_back(d); });
    bad = !pb.closed && detail::non_finite_bits(dirs[n - 1]) != 0;
    if (segs.size() == spans) {
      bad |= pieces_into(pb, dirs.data(), 0, spans, segs.data());  // in place: no size updates
    } else {
      segs.clear();
      detail::reserve_to_fill(segs, spans);
      FiniteCheck check;
      for (std::size_t j = 0; j < spans; ++j) segs.push_back(piece(pb, dirs.data(), j, check));
      bad |= check.bad();
    }
  }
  if (bad) [[unlikely]] {
    detail::check_finite_output(result, "jaklic-zagar");  // throws, naming the piece
  }
}

// ---- report ----

// (7) with (8) at Theorem 2's minimum: 2|Δ|²(sin²β0 + sin²β1)/dt³, |Δ| sin βk = |dk × Δ| (no
// cancellation for small angles).
double approx_energy(Vec2 chord, double dt, Vec2 d0, Vec2 d1) {
  const double x0 = cross(d0, chord) / dt, x1 = cross(d1, chord) / dt;
  return 2.0 * (x0 * x0 + x1 * x1) / dt;
}

const char* rule_name(const Problem& pb, const JaklicZagarOptions& o) {
  if (!o.lambdas.empty()) return "per-point";
  switch (pb.global.rule) {
    case Rule::kOptimal:
      return "optimal";
    case Rule::kBisector:
      return "bisector";
    default:
      return "fixed";
  }
}

void add_report(const Problem& pb, const JaklicZagarOptions& options, ReportLevel level,
                FitResult& result) {
  const auto& P = pb.points;
  const auto& t = pb.knots;
  const std::size_t n = P.size();
  const std::size_t spans = pb.closed ? n : n - 1;
  nlohmann::json& rep = result.method_report;
  rep = nlohmann::json::object();
  rep["lambda_mode"] = rule_name(pb, options);
  rep["reversal"] = options.reversal == JaklicZagarReversal::kInsert ? "insert" : "error";
  rep["inserted"] = pb.inserted;
  rep["inserted_at"] = pb.inserted_at;
  if (level == ReportLevel::kNone) return;

  auto chord = [&](std::size_t j) {
    return make_chord(P[j], P[j + 1 == n ? 0 : j + 1], t[j + 1] - t[j]);
  };
  nlohmann::json lambdas = nlohmann::json::array();
  nlohmann::json kinds = nlohmann::json::array();
  std::size_t counts[4] = {0, 0, 0, 0};
  const auto& dirs = result.tangents;
  for (std::size_t i = 0; i < n; ++i) {
    const NodeSpec& spec = pb.specs.empty() ? pb.global : pb.specs[i];
    StationaryKind kind = StationaryKind::kNone;
    std::optional<double> lam;
    if (!pb.closed && (i == 0 || i + 1 == n)) {
      // An end: d along the end chord minimizes its segment's energy 2|ΔT|² sin²β/Δt³.
      kind = spec.rule == Rule::kClamped ? StationaryKind::kNone : StationaryKind::kMinimum;
    } else if (spec.rule != Rule::kClamped) {
      const Chord A = chord(i == 0 ? n - 1 : i - 1), B = chord(i);
      const double c = dot(A.unit, B.unit), s = cross(A.unit, B.unit);
      if (classify_turn(c, s) == NodeCase::kStraight) {
        kind = StationaryKind::kMinimum;  // energy 0: the global minimum
      } else {
        const double lstar = optimal_lambda_of(A, B, c, s);
        const StationaryKind at_star = std::abs(c) <= kAngleTol ? StationaryKind::kBoundary
                                       : c > 0.0                ? StationaryKind::kMinimum
                                                                : StationaryKind::kMaximum;
        if (spec.rule == Rule::kOptimal) {
          lam = lstar;
          kind = at_star;
        } else {
          lam = spec.rule == Rule::kBisector ? 1.0 / (1.0 + A.len / B.len) : spec.lambda;
          kind = std::abs(*lam - lstar) <= kLambdaMatch ? at_star : StationaryKind::kNone;
        }
      }
    }
    counts[static_cast<int>(kind)]++;
    lambdas.push_back(lam ? nlohmann::json(*lam) : nlohmann::json(nullptr));
    kinds.push_back(std::string(stationary_kind_name(kind)));
  }
  nlohmann::json energies = nlohmann::json::array();
  double total = 0.0;
  for (std::size_t j = 0; j < spans; ++j) {
    const Chord ch = chord(j);
    const double e = approx_energy(ch.delta, ch.h, dirs[j], dirs[j + 1 == n ? 0 : j + 1]);
    total += e;
    // An energy beyond the double range (extreme knot intervals) is reported as null.
    energies.push_back(std::isfinite(e) ? nlohmann::json(e) : nlohmann::json(nullptr));
  }
  rep["lambda"] = std::move(lambdas);
  rep["stationary_kind"] = std::move(kinds);
  rep["approx_energy"] = std::move(energies);
  rep["approx_energy_total"] =
      std::isfinite(total) ? nlohmann::json(total) : nlohmann::json(nullptr);
  rep["counts"] = {
      {"minimum", counts[0]}, {"maximum", counts[1]}, {"boundary", counts[2]}, {"none", counts[3]}};
}

}  // namespace

std::string_view stationary_kind_name(StationaryKind kind) {
  switch (kind) {
    case StationaryKind::kMinimum:
      return "minimum";
    case StationaryKind::kMaximum:
      return "maximum";
    case StationaryKind::kBoundary:
      return "boundary";
    case StationaryKind::kNone:
      return "none";
  }
  return "none";
}

namespace {
void check_chords(Vec2 a, Vec2 b, double ha, double hb) {
  if (!is_finite(a) || !is_finite(b) || !(a.x != 0.0 || a.y != 0.0) ||
      !(b.x != 0.0 || b.y != 0.0)) {
    throw Error(ErrorCode::kInvalidArgument, "chords must be finite and non-zero");
  }
  if (!(ha > 0.0 && hb > 0.0 && std::isfinite(ha) && std::isfinite(hb))) {
    throw Error(ErrorCode::kInvalidArgument, "knot intervals must be finite and positive");
  }
}
}  // namespace

namespace {
[[noreturn]] void throw_overflow(const char* what) {
  throw Error(ErrorCode::kNonFinite,
              std::string(what) + " is not finite: the input is beyond the range of doubles");
}
}  // namespace

JaklicZagarNode jaklic_zagar_optimal_node(Vec2 a, Vec2 b, double ha, double hb) {
  check_chords(a, b, ha, hb);
  const Chord A = make_chord({0.0, 0.0}, a, ha), B = make_chord({0.0, 0.0}, b, hb);
  const double c = dot(A.unit, B.unit), s = cross(A.unit, B.unit);
  JaklicZagarNode node;
  const NodeCase nc = classify_turn(c, s);
  if (nc == NodeCase::kReversal) throw_reversal(1);
  if (nc == NodeCase::kStraight) {
    node.direction = B.unit;
    node.kind = StationaryKind::kMinimum;
    return node;
  }
  interior_direction(A, B, NodeSpec{}, node.direction);
  node.lambda = optimal_lambda_of(A, B, c, s);
  if (!is_finite(node.direction) || !std::isfinite(*node.lambda)) throw_overflow("the direction");
  node.kind = std::abs(c) <= kAngleTol ? StationaryKind::kBoundary
              : c > 0.0                ? StationaryKind::kMinimum
                                       : StationaryKind::kMaximum;
  return node;
}

std::optional<double> jaklic_zagar_optimal_lambda(Vec2 a, Vec2 b, double ha, double hb) {
  return jaklic_zagar_optimal_node(a, b, ha, hb).lambda;
}

Vec2 jaklic_zagar_direction(Vec2 a, Vec2 b, double lambda) {
  check_chords(a, b, 1.0, 1.0);
  if (!(lambda >= 0.0 && lambda <= 1.0)) {
    throw Error(ErrorCode::kInvalidArgument,
                "lambda must be in [0, 1], got " + detail::format_number(lambda));
  }
  const Chord A = make_chord({0.0, 0.0}, a, 1.0), B = make_chord({0.0, 0.0}, b, 1.0);
  const double c = dot(A.unit, B.unit), s = cross(A.unit, B.unit);
  const NodeCase nc = classify_turn(c, s);
  if (nc == NodeCase::kReversal) throw_reversal(1);
  if (nc == NodeCase::kStraight) return B.unit;
  // The bisector λ gives the exact bisector (no cancellation).
  const Vec2 d = lambda == 1.0 / (1.0 + A.len / B.len) ? unit_of(bisector_vector(A.unit, B.unit, s))
                                                       : lambda_direction(A, B, s, lambda);
  if (!is_finite(d)) throw_overflow("the direction");
  return d;
}

CubicBezier jaklic_zagar_segment(Point p0, Point p1, Vec2 d0, Vec2 d1) {
  const Chord ch = make_chord(p0, p1, 1.0);
  const CubicBezier b = make_segment(ch, p0, p1, d0, d1, 0.0, 1.0, 0).bezier;
  for (const Point& q : b.p) {
    if (!is_finite(q)) throw_overflow("a control point");
  }
  return b;
}

double jaklic_zagar_segment_energy(Vec2 chord, double dt, Vec2 d0, Vec2 d1) {
  const double e = approx_energy(chord, dt, d0, d1);
  if (!std::isfinite(e)) throw_overflow("the segment energy");
  return e;
}

void fit_jaklic_zagar(const FitInput& input, const JaklicZagarOptions& options, ReportLevel level,
                      FitResult& out) {
  const Problem pb = prepare(input, options, out);
  out.closed = pb.closed;
  out.spline.closed = pb.closed;
  build(pb, out);
  add_report(pb, options, level, out);
}

FitResult fit_jaklic_zagar(const FitInput& input, const JaklicZagarOptions& options,
                           ReportLevel level) {
  FitResult result;
  fit_jaklic_zagar(input, options, level, result);
  return result;
}

}  // namespace fairspline

// ---- registry entry ----
#include "detail/choices.hpp"
#include "methods/builtin.hpp"

namespace fairspline::detail {

namespace {
constexpr ChoiceTable<JaklicZagarLambda, 2> kLambdaRule{
    {{"optimal", JaklicZagarLambda::kOptimal}, {"bisector", JaklicZagarLambda::kBisector}}};
constexpr ChoiceTable<JaklicZagarReversal, 2> kReversal{
    {{"error", JaklicZagarReversal::kError}, {"insert", JaklicZagarReversal::kInsert}}};
}  // namespace

std::vector<MethodInfo> jaklic_zagar_methods() {
  return {{
      .name = "jaklic-zagar",
      .description =
          "Local G1 cubic spline: tangent directions from the stationary point of an approximate "
          "strain energy (or the bisector), magnitudes minimizing it; regular, loop-, cusp- and "
          "fold-free.",
      .paper =
          "G. Jaklic, E. Zagar, Planar cubic G1 interpolatory splines with small strain energy, "
          "J. Comput. Appl. Math. 235 (2011), Theorems 2, 4, 6 and (10), (11)",
      .options = {{.name = "lambda",
                   .type = OptionType::kChoiceOrNumber,
                   .default_value = "optimal",
                   .min = 0.0,
                   .max = 1.0,
                   .choices = kLambdaRule.names(),
                   .doc = "shape parameter of (10) at interior points: optimal (Theorem 6, (11): "
                          "the stationary point of the approximate energy, a maximum for turns "
                          "above 90 degrees), bisector (Corollary 7's direction), or one number "
                          "in the open interval (0, 1)"},
                  {.name = "lambdas",
                   .type = OptionType::kNumberList,
                   .default_value = nullptr,
                   .min = 0.0,
                   .max = 1.0,
                   .doc = "per-point lambda (one entry per point, each in (0, 1)); replaces "
                          "'lambda'; entries at the ends of an open curve are ignored"},
                  {.name = "reversal",
                   .type = OptionType::kChoice,
                   .default_value = "error",
                   .choices = kReversal.names(),
                   .doc = "at a 180 degree reversal: error (default), or insert one point next "
                          "to it (apex of the equilateral triangle on the shorter chord, "
                          "inserted into the longer chord, on the side away from where the path "
                          "continues)"}},
      .fit =
          [](const FitInput& in, const nlohmann::json& o, const FitOptions& f, FitResult& out) {
            JaklicZagarOptions opt;
            const nlohmann::json& lam = o.at("lambda");
            if (lam.is_string()) {
              opt.lambda = kLambdaRule.parse(lam.get<std::string>());
            } else {
              opt.lambda = JaklicZagarLambda::kFixed;
              opt.fixed_lambda = lam.get<double>();
            }
            if (o.contains("lambdas")) opt.lambdas = o.at("lambdas").get<std::vector<double>>();
            opt.reversal = kReversal.parse(o.at("reversal").get<std::string>());
            fit_jaklic_zagar(in, opt, f.method_report_level(), out);
          },
      .capabilities = jaklic_zagar_capabilities(),
      .checks_own_output = true,
      // (7): 2|Δ|²(sin²β0 + sin²β1)/Δt³.
      .report_units = {{"approx_energy/*", 2, -3}, {"approx_energy_total", 2, -3}},
  }};
}

}  // namespace fairspline::detail
