// Data balls: the minimal-energy curve through discs. The unknowns are the free directions
// (one per regular node, one per side beside a free side) and the positions of the ball
// nodes; a span's energy E_1(α, β)/L depends on its two nodes only, so the Newton system is
// banded (a closed curve adds a border). Derivation: docs/methods/min-energy.md, "Data balls".
#include "methods/data_balls.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "detail/ball_energy.hpp"
#include "detail/banded.hpp"
#include "detail/elastica.hpp"
#include "detail/format.hpp"
#include "detail/input.hpp"
#include "detail/nodes.hpp"
#include "detail/numbers.hpp"
#include "detail/progress.hpp"
#include "fairspline/error.hpp"
#include "methods/min_energy_options.hpp"

namespace fairspline::detail {

namespace {

/// A direction within this fraction of Ω beyond a bound it is held to is on it (rounding).
constexpr double kBoxRounding = 1e-12;

double wrap(double a) {
  // remainder() returns a itself for |a| <= π (the quotient rounds to 0, ties to even), and
  // costs ~40 ns: a tenth of a large data-ball fit went there.
  return std::abs(a) <= kPi ? a : std::remainder(a, 2.0 * kPi);
}

// A quantity with its first and second derivatives with respect to up to ten unknowns (a
// direction tied to one that follows a chord, less another chord's angle: the positions of
// four nodes and one direction; see follow_short_chords).
struct Jet {
  static constexpr int kMax = 10;
  double v = 0.0;
  int m = 0;
  std::array<int, kMax> idx{};
  std::array<double, kMax> d{};
  std::array<std::array<double, kMax>, kMax> h{};
};

// The same for a vector (a position or a chord).
struct VJet {
  Vec2 v{};
  int m = 0;
  std::array<int, 4> idx{};
  std::array<Vec2, 4> d{};
  std::array<std::array<Vec2, 4>, 4> h{};
};

// A direction unknown: a regular node's direction (its incoming one; the outgoing one is
// turned by the corner), or one side's beside a free side. Its box constraints: per adjacent
// span, |θ + offset − φ_span| <= Ω.
struct Slot {
  double theta = 0.0;
  bool fixed = false;
  int nbox = 0;
  std::array<std::size_t, 2> span{};
  std::array<double, 2> offset{};
  int active = -1;  // which box holds it, or −1
  int sign = 0;     // +1 at its upper bound, −1 at its lower one
  int var = -1;
  // Its unknown is measured from this span's chord angle (θ = φ_follow + δ), or −1: at a span
  // much shorter than its neighbours, whose stiff energy pins both ends to its chord while the
  // balls turn that chord (see follow_short_chords).
  int follow = -1;
  // Tied to another slot (the elastic spline's ridges and pair bounds): θ = slot[tie].θ +
  // tie_offset.
  int tie = -1;
  double tie_offset = 0.0;
  std::size_t tie_span = 0;  // the span it holds
  double tie_gap =
      0.0;  // that span's α − β: 0 on a ridge, ±detail::kElasticaPairLimit on its pair bound
};

// A position is kept as its offset from the centre: a chord between near-repeated centres is
// then (q_j − q_i) + (o_j − o_i), the first difference exact (Sterbenz) and the offsets
// relative-accurate, where absolute positions rounded the chord's angle to ε|q|/L (1e-6 rad for
// a chord 1e-10 of the coordinates).
struct Node {
  Point q{};  // centre
  Vec2 o{};   // position − centre
  double r = 0.0;
  bool boundary = false;  // on the disc's circle (one unknown, the angle)
  double scale = 1.0;     // of its position unknowns: the shorter adjacent chord
  Vec2 u{1.0, 0.0};       // free position: its unknowns move it along u (radial) and u⊥
  int var = -1;
  int in = -1, out = -1;  // slots
  double corner = 0.0;    // added to the out slot's θ (a regular node: in == out)
};

struct Problem {
  BasicCurveMethod m;
  double omega = 0.0;
  bool closed = false;
  std::vector<Node> node;
  std::vector<Slot> slot;
  Point position(std::size_t i) const { return node[i].q + node[i].o; }
  Vec2 chord(std::size_t s) const {
    const Node& a = node[s];
    const Node& b = node[next(s)];
    return (b.q - a.q) + (b.o - a.o);
  }
  std::size_t spans() const { return closed ? node.size() : node.size() - 1; }
  std::size_t next(std::size_t i) const { return i + 1 == node.size() ? 0 : i + 1; }
};

// Moves a position radially onto its circle, which becomes its constraint.
void put_on_circle(Node& nd) {
  nd.o = (nd.r / norm(nd.o)) * nd.o;
  nd.boundary = true;
}

// The position's offset from its centre, with its derivatives (chord() adds the centres).
VJet position(const Node& nd) {
  VJet j;
  j.v = nd.o;
  if (nd.var < 0) return j;
  if (nd.boundary) {
    const Vec2 u = nd.o / nd.r;
    j.m = 1;
    j.idx[0] = nd.var;
    j.d[0] = {-nd.r * u.y, nd.r * u.x};
    j.h[0][0] = {-nd.r * u.x, -nd.r * u.y};
  } else {
    j.m = 2;
    j.idx = {nd.var, nd.var + 1, 0, 0};
    j.d[0] = nd.u;
    j.d[1] = {-nd.u.y, nd.u.x};
  }
  return j;
}

VJet chord(const VJet& a, const VJet& b, Vec2 centres) {  // b − a, centres q_b − q_a
  VJet c;
  c.v = centres + (b.v - a.v);
  c.m = a.m + b.m;
  for (int k = 0; k < a.m; ++k) {
    c.idx[k] = a.idx[k];
    c.d[k] = -1.0 * a.d[k];
    for (int l = 0; l < a.m; ++l) c.h[k][l] = -1.0 * a.h[k][l];
  }
  for (int k = 0; k < b.m; ++k) {
    c.idx[a.m + k] = b.idx[k];
    c.d[a.m + k] = b.d[k];
    for (int l = 0; l < b.m; ++l) c.h[a.m + k][a.m + l] = b.h[k][l];
  }
  return c;
}

// φ = atan2(c): ∂φ/∂c = n/L, ∂²φ/∂c² = −(t nᵀ + n tᵀ)/L².
Jet angle(const VJet& c) {
  Jet j;
  const double len = norm(c.v);
  const Vec2 t = c.v / len, n{-t.y, t.x};
  j.v = std::atan2(c.v.y, c.v.x);
  j.m = c.m;
  for (int k = 0; k < c.m; ++k) j.idx[k] = c.idx[k];
  for (int k = 0; k < c.m; ++k) {
    j.d[k] = dot(n, c.d[k]) / len;
    for (int l = 0; l < c.m; ++l) {
      const Vec2 a = c.d[k], b = c.d[l];
      j.h[k][l] =
          -(dot(t, a) * dot(n, b) + dot(n, a) * dot(t, b)) / (len * len) + dot(n, c.h[k][l]) / len;
    }
  }
  return j;
}

struct State {
  std::vector<double> phi, len;  // per span
};

void chord_angles(const Problem& pb, State& st) {
  const std::size_t ns = pb.spans();
  st.phi.resize(ns);
  st.len.resize(ns);
  for (std::size_t s = 0; s < ns; ++s) {
    const Vec2 c = pb.chord(s);
    st.phi[s] = std::atan2(c.y, c.x);
    st.len[s] = norm(c);
  }
}

// The end angles of span s.
/// A direction's angle from the chord of box k's span, less that box's offset (its bound is ±Ω).
double box_deviation(const Slot& sl, int k, const State& st) {
  return wrap(sl.theta + sl.offset[k] - st.phi[sl.span[k]]);
}

// The slot that holds span s (one end's slot tied to the other's: on a ridge α = β, on its pair
// bound α − β = ±detail::kElasticaPairLimit), or null.
const Slot* holding(const Problem& pb, std::size_t s) {
  const int out = pb.node[s].out, in = pb.node[pb.next(s)].in;
  if (pb.slot[in].tie == out) return &pb.slot[in];
  if (pb.slot[out].tie == in) return &pb.slot[out];
  return nullptr;
}

std::pair<double, double> end_angles(const Problem& pb, const State& st, std::size_t s) {
  const Node& a = pb.node[s];
  const Node& b = pb.node[pb.next(s)];
  const double out = pb.slot[a.out].theta + (a.in == a.out ? a.corner : 0.0);
  const double alpha = wrap(out - st.phi[s]);
  // A held span's α − β to the bit, not to θ's rounding: on a ridge the kink's mean derivatives
  // need it, on a pair bound rounding could take it past 180°.
  if (const Slot* h = holding(pb, s)) return {alpha, alpha - h->tie_gap};
  return {alpha, wrap(pb.slot[b.in].theta - st.phi[s])};
}

// E_1 with its value free of cancellation: cond-G2's 2λ²cos(α−β) − 6λ(cos α + cos β) + 4λ² + 6
// is 6(λ−1)² + 12λ(sin²(α/2) + sin²(β/2)) − 4λ² sin²((α−β)/2), whose terms do not cancel as
// the curve straightens (the line search compares energies of nearly straight data).
BasicEnergy span_energy(const BasicCurveMethod& m, double alpha, double beta) {
  BasicEnergy e = basic_energy(m, alpha, beta);
  if (m.basis == MinEnergyBasis::kCondG2) {
    const double l = m.lambda, sa = std::sin(0.5 * alpha), sb = std::sin(0.5 * beta),
                 sd = std::sin(0.5 * (alpha - beta));
    e.e = 6.0 * (l - 1.0) * (l - 1.0) + 12.0 * l * (sa * sa + sb * sb) - 4.0 * l * l * sd * sd;
  }
  return e;
}

double total_energy(const Problem& pb, const State& st) {
  double e = 0.0;
  for (std::size_t s = 0; s < pb.spans(); ++s) {
    const auto [al, be] = end_angles(pb, st, s);
    e += span_energy(pb.m, al, be).e / st.len[s];
  }
  return e;
}

bool tie_span(Problem& pb, std::size_t s, double gap);

// Puts every active slot on its bound and clips the others into their boxes (activating them
// there). False when a box cannot be met (the positions turned a stencil beyond 2Ω, or moved a
// chord off a given direction).
bool settle(Problem& pb, const State& st, bool clip = true) {
  const double om = pb.omega;
  for (Slot& sl : pb.slot) {
    if (sl.tie >= 0) continue;
    if (sl.active >= 0) {
      const int a = sl.active;
      sl.theta = st.phi[sl.span[a]] - sl.offset[a] + sl.sign * om;
    }
    for (int b = 0; b < sl.nbox; ++b) {
      const double dev = box_deviation(sl, b, st);
      // (A bound met to rounding counts as met: a position on its circle moves by ulps.)
      if (std::abs(dev) < om || (clip && std::abs(dev) <= om * (1.0 + kBoxRounding))) continue;
      if (sl.fixed || sl.active >= 0 || !clip) return false;
      sl.theta -= dev - std::copysign(om, dev);
      sl.active = b;
      sl.sign = dev > 0 ? 1 : -1;
      for (int c = 0; c < b; ++c) {
        if (std::abs(box_deviation(sl, c, st)) > om) return false;
      }
    }
  }
  // A tied slot follows its owner; its own boxes are met or the point is not feasible.
  for (Slot& sl : pb.slot) {
    if (sl.tie >= 0) sl.theta = pb.slot[sl.tie].theta + sl.tie_offset;
  }
  // The elastic spline's pair bounds |α − β| <= detail::kElasticaPairLimit (the chord cancels in α
  // − β): a span past one is put on it, held by a tie (its multiplier is the tie's torque).
  for (std::size_t s = 0; s < pb.spans() && pb.m.basis == MinEnergyBasis::kElastic; ++s) {
    if (holding(pb, s)) continue;
    const auto [al, be] = end_angles(pb, st, s);
    if (std::abs(al - be) <= detail::kElasticaPairLimit) continue;
    if (!clip || !tie_span(pb, s, std::copysign(detail::kElasticaPairLimit, al - be))) return false;
  }
  for (Slot& sl : pb.slot) {
    if (sl.tie < 0) continue;
    for (int b = 0; b < sl.nbox; ++b) {
      if (std::abs(box_deviation(sl, b, st)) >= om) return false;
    }
    const double alpha = end_angles(pb, st, sl.tie_span).first;
    if (!(std::abs(alpha - sl.tie_gap) < kPi)) return false;
  }
  return true;
}

/// How far a released ridge's direction is moved off it (radians), as in the interpolation.
constexpr double kRidgeStep = 1e-7;
/// A span whose end angles differ by at most this (rad) on a ridge is on it (rounding).
constexpr double kOnRidge = 1e-9;

// Holds span s of the elastic spline at α − β = gap (0: its ridge; ±detail::kElasticaPairLimit: its
// pair bound) by tying one end's slot (a free one that no other slot is tied to) to the other's. On
// a ridge both move to their mean direction where both are free; on a pair bound the tied one alone
// moves onto it. False, with nothing changed, where no slot is free. The caller settles.
bool tie_span(Problem& pb, std::size_t s, double gap) {
  const int out = pb.node[s].out, in = pb.node[pb.next(s)].in;
  const Node& a = pb.node[s];
  const double corner = a.in == a.out ? a.corner : 0.0;
  auto free = [&](int k) {
    const Slot& sl = pb.slot[static_cast<std::size_t>(k)];
    if (sl.fixed || sl.active >= 0 || sl.tie >= 0) return false;
    return std::none_of(pb.slot.begin(), pb.slot.end(), [&](const Slot& o) { return o.tie == k; });
  };
  if (out == in || pb.slot[out].tie >= 0 || pb.slot[in].tie >= 0) return false;
  const bool in_free = free(in), out_free = free(out);
  if (!in_free && !out_free) return false;
  Slot& so = pb.slot[static_cast<std::size_t>(out)];
  Slot& si = pb.slot[static_cast<std::size_t>(in)];
  // Directions: out's d_out, in's d_in = d_out − gap + turns.
  const double d_out = so.theta + corner;
  const double turns = 2.0 * kPi * std::round((si.theta - (d_out - gap)) / (2.0 * kPi));
  double mean = in_free ? d_out : si.theta - turns + gap;
  if (gap == 0.0 && in_free && out_free) mean = 0.5 * (d_out + si.theta - turns);
  so.theta = mean - corner;
  si.theta = mean - gap + turns;
  Slot& tied = in_free ? si : so;
  tied.tie = in_free ? out : in;
  tied.tie_offset = in_free ? corner - gap + turns : gap - corner - turns;
  tied.tie_span = s;
  tied.tie_gap = gap;
  return true;
}

// Locks span s on its ridge α = β, settled; false, with nothing changed, where that is not
// possible or leaves a box.
bool tie_ridge(Problem& pb, const State& st, std::size_t s, bool clip) {
  const std::vector<Slot> before = pb.slot;
  if (tie_span(pb, s, 0.0) && settle(pb, st, clip)) return true;
  pb.slot = before;
  return false;
}

// Frees tied slot k, moved off its ridge or pair bound by kRidgeStep against the torque on it.
void untie(Problem& pb, std::size_t k, double torque) {
  Slot& sl = pb.slot[k];
  sl.tie = -1;
  sl.tie_offset = 0.0;
  sl.tie_gap = 0.0;
  sl.theta -= std::copysign(kRidgeStep, torque);
}

// Where a closed curve is cut for the border: two consecutive nodes c, c + 1, numbered last.
// Span c also depends on node c − 1 when c's direction sits on its bound at chord c − 1, and on
// node c + 2 when c + 1's sits on its bound at chord c + 1; both at once would couple the two
// ends of the band, whose factorization then is dense (s45-c359: 1525 unknowns, 0.3 s a step).
std::size_t border_start(const Problem& pb) {
  const std::size_t n = pb.node.size();
  auto held_across = [&](int s, std::size_t span) {
    if (s < 0) return false;
    const Slot& sl = pb.slot[static_cast<std::size_t>(s)];
    return sl.active >= 0 && sl.span[static_cast<std::size_t>(sl.active)] != span;
  };
  for (std::size_t c = 0; c < n; ++c) {
    if (!held_across(pb.node[c].out, c) || !held_across(pb.node[pb.next(c)].in, c)) return c;
  }
  return 0;
}

// Numbers the unknowns node by node; a closed curve's two border nodes (border_start) come
// last: the wrap-around couples them with both ends. Returns the number of border unknowns.
std::size_t number_unknowns(Problem& pb, std::vector<double>& scale, bool positions = true) {
  scale.clear();
  auto visit = [&](std::size_t i) {
    Node& nd = pb.node[i];
    for (int s : {nd.in, nd.out}) {
      if (s < 0) continue;
      Slot& sl = pb.slot[s];
      if (sl.var >= 0 && s == nd.out && nd.in == nd.out) continue;  // numbered as in
      sl.var = -1;
      if (sl.fixed || sl.active >= 0 || sl.tie >= 0) continue;
      sl.var = static_cast<int>(scale.size());
      scale.push_back(1.0);
    }
    nd.var = -1;
    if (nd.r > 0.0 && positions) {
      const Vec2 off = nd.o;
      const double d = norm(off);
      nd.u = d > 0.0 ? off / d : Vec2{1.0, 0.0};
      nd.var = static_cast<int>(scale.size());
      if (nd.boundary) {
        scale.push_back(nd.scale / nd.r);
      } else {
        scale.push_back(nd.scale);
        scale.push_back(nd.scale);
      }
    }
  };
  for (Slot& sl : pb.slot) sl.var = -1;
  const std::size_t n = pb.node.size();
  const std::size_t border_nodes = pb.closed && n > 3 ? 2 : 0;
  const std::size_t c = border_nodes ? border_start(pb) : 0;
  for (std::size_t k = border_nodes; k < n; ++k) visit((c + k) % n);
  const std::size_t band = scale.size();
  for (std::size_t k = 0; k < border_nodes; ++k) visit((c + k) % n);
  return scale.size() - band;
}

// Span s's chord angle φ_s as a jet in its ends' position unknowns.
Jet chord_angle(const Problem& pb, std::size_t s) {
  const std::size_t t = pb.next(s);
  return angle(chord(position(pb.node[s]), position(pb.node[t]), pb.node[t].q - pb.node[s].q));
}

Jet slot_jet(const Problem& pb, const Slot& sl) {
  Jet j;
  if (sl.tie >= 0) j = slot_jet(pb, pb.slot[static_cast<std::size_t>(sl.tie)]);
  j.v = sl.theta;
  if (sl.tie >= 0) return j;
  if (sl.var >= 0 && sl.follow >= 0) {
    j = chord_angle(pb, static_cast<std::size_t>(sl.follow));
    j.v = sl.theta;
    j.idx[j.m] = sl.var;
    j.d[j.m] = 1.0;
    for (int k = 0; k <= j.m; ++k) j.h[j.m][k] = j.h[k][j.m] = 0.0;
    ++j.m;
  } else if (sl.var >= 0) {
    j.m = 1;
    j.idx[0] = sl.var;
    j.d[0] = 1.0;
  } else if (sl.active >= 0) {
    j = chord_angle(pb, sl.span[sl.active]);
    j.v = sl.theta;
  }
  return j;
}

// a − b over the union of their unknowns.
Jet difference(const Jet& a, const Jet& b) {
  Jet j = a;
  j.v = a.v - b.v;
  std::array<int, Jet::kMax> at{};
  for (int q = 0; q < b.m; ++q) {
    int k = 0;
    while (k < j.m && j.idx[k] != b.idx[q]) ++k;
    if (k == j.m) {
      j.idx[k] = b.idx[q];
      j.d[k] = 0.0;
      for (int r = 0; r <= k; ++r) j.h[k][r] = j.h[r][k] = 0.0;
      ++j.m;
    }
    at[q] = k;
  }
  for (int q = 0; q < b.m; ++q) {
    j.d[at[q]] -= b.d[q];
    for (int r = 0; r < b.m; ++r) j.h[at[q]][at[r]] -= b.h[q][r];
  }
  return j;
}

// E_1's Hessian in (α, β) made the nearest positive semidefinite matrix (its eigenvalues clamped
// at 0), as the interpolation's Newton matrix does where E_1 is concave.
void project_psd(BasicEnergy& e) {
  const double mid = 0.5 * (e.eaa + e.ebb), rad = std::hypot(0.5 * (e.eaa - e.ebb), e.eab);
  const double lo = mid - rad, hi = mid + rad;
  if (lo >= 0.0) return;
  if (hi <= 0.0) {
    e.eaa = e.eab = e.ebb = 0.0;
    return;
  }
  // hi · v vᵀ, v the eigenvector of hi.
  const double vx = e.eab, vy = hi - e.eaa, nv = vx * vx + vy * vy;
  if (nv == 0.0) {  // diagonal: eaa = hi
    e.eab = 0.0;
    e.ebb = std::max(e.ebb, 0.0);
    e.eaa = std::max(e.eaa, 0.0);
    return;
  }
  e.eaa = hi * vx * vx / nv;
  e.eab = hi * vx * vy / nv;
  e.ebb = hi * vy * vy / nv;
}

// A span this much shorter than a neighbour is short (follow_short_chords).
constexpr double kShortChord = 1e-2;

// The free directions beside a short span measure their unknown from its chord. Its energy,
// 1/L times its neighbours', holds both ends within a hair of that chord while the balls turn
// it: in absolute angles that valley is curved (the chord's angle is nonlinear in the
// positions on the scale of the radii), and Newton steps along it crept at a shift that
// held every other unknown back (s61-c29: 1000 iterations). Measured from the chord, the
// valley is straight.
void follow_short_chords(Problem& pb) {
  const std::size_t ns = pb.spans();
  std::vector<double> len(ns);
  for (std::size_t s = 0; s < ns; ++s) len[s] = distance(pb.node[s].q, pb.node[pb.next(s)].q);
  auto neighbour = [&](std::size_t s, bool before) -> double {
    if (!pb.closed && (before ? s == 0 : s + 1 == ns)) return 0.0;
    return len[before ? (s == 0 ? ns - 1 : s - 1) : (s + 1 == ns ? 0 : s + 1)];
  };
  for (std::size_t s = 0; s < ns; ++s) {
    const std::size_t t = pb.next(s);
    if (pb.node[s].r == 0.0 && pb.node[t].r == 0.0) continue;  // a fixed chord
    if (!(len[s] < kShortChord * std::max(neighbour(s, true), neighbour(s, false)))) continue;
    for (int k : {pb.node[s].out, pb.node[t].in}) {
      Slot& sl = pb.slot[static_cast<std::size_t>(k)];
      if (sl.fixed) continue;
      if (sl.follow < 0 || len[s] < len[static_cast<std::size_t>(sl.follow)]) {
        sl.follow = static_cast<int>(s);
      }
    }
  }
}

// Raw partial derivatives: per slot ∂E/∂θ, per node ∂E/∂p (the other raw quantities held).
struct Raw {
  std::vector<double> slot;
  std::vector<Vec2> node;
  std::vector<double> span;  // each span's energy E_1/L
  double barrier = 0.0;      // the barrier's value (Solver::evaluate)
};

// Energy, reduced gradient and Hessian (scaled: unknown k times scale[k]) into `h` and `g`.
// With `convex`, each span's Hessian in its raw quantities is projected onto the PSD cone (for a
// Newton matrix where the exact one is not definite).
double assemble(const Problem& pb, const State& st, std::span<const double> scale,
                std::size_t border, BorderedBand& h, std::vector<double>& g, Raw& raw,
                bool convex = false) {
  const std::size_t nv = scale.size(), band = nv - border, ns = pb.spans();
  g.assign(nv, 0.0);
  raw.slot.assign(pb.slot.size(), 0.0);
  raw.node.assign(pb.node.size(), Vec2{});
  raw.span.resize(pb.spans());
  // A span's unknowns: the positions of up to six nodes (a tied end follows its owner's chord
  // or bound, one span further) and two directions.
  constexpr int kSpanUnknowns = 14;
  struct Local {
    std::array<int, kSpanUnknowns> idx{};
    int m = 0;
    int at(int v) {
      for (int k = 0; k < m; ++k) {
        if (idx[k] == v) return k;
      }
      idx[m] = v;
      return m++;
    }
  };
  // The band's width: the spread of the unknowns each span depends on (a direction on a
  // bound depends on the positions of its span's nodes).
  std::size_t width = 0;
  for (std::size_t s = 0; s < ns; ++s) {
    std::size_t lo = nv, hi = 0;
    auto see = [&](int v, int count) {
      for (int k = 0; k < count; ++k) {
        if (v < 0 || static_cast<std::size_t>(v + k) >= band) continue;
        lo = std::min(lo, static_cast<std::size_t>(v + k));
        hi = std::max(hi, static_cast<std::size_t>(v + k));
      }
    };
    auto see_node = [&](const Node& nd) { see(nd.var, nd.boundary ? 1 : 2); };
    auto see_slot = [&](const Slot& tied) {
      const Slot& sl = tied.tie >= 0 ? pb.slot[static_cast<std::size_t>(tied.tie)] : tied;
      see(sl.var, 1);
      // (a direction on a bound, or one that follows a chord, moves with that chord's ends)
      const int on =
          sl.active >= 0 ? static_cast<int>(sl.span[sl.active]) : (sl.var >= 0 ? sl.follow : -1);
      if (on >= 0) {
        const std::size_t t = static_cast<std::size_t>(on);
        see_node(pb.node[t]);
        see_node(pb.node[pb.next(t)]);
      }
    };
    see_node(pb.node[s]);
    see_node(pb.node[pb.next(s)]);
    see_slot(pb.slot[pb.node[s].out]);
    see_slot(pb.slot[pb.node[pb.next(s)].in]);
    if (lo <= hi) width = std::max(width, hi - lo);
  }
  h.reset(band, width, border);
  double energy = 0.0;
  for (std::size_t s = 0; s < ns; ++s) {
    const Node& a = pb.node[s];
    const std::size_t j = pb.next(s);
    Jet o = slot_jet(pb, pb.slot[a.out]);
    if (a.in == a.out) o.v += a.corner;
    const Jet in = slot_jet(pb, pb.slot[pb.node[j].in]);
    const VJet c = chord(position(a), position(pb.node[j]), pb.node[j].q - a.q);
    const double phi = st.phi[s];
    const double alpha = wrap(o.v - phi);
    const Slot* held = holding(pb, s);
    BasicEnergy e1 = span_energy(pb.m, alpha, held ? alpha - held->tie_gap : wrap(in.v - phi));
    if (convex) project_psd(e1);
    const SpanDerivatives sd = span_derivatives(e1, c.v);
    energy += sd.e;
    raw.span[s] = sd.e;
    raw.slot[a.out] += sd.g[0];
    raw.slot[pb.node[j].in] += sd.g[1];
    raw.node[s] -= Vec2{sd.g[2], sd.g[3]};
    raw.node[j] += Vec2{sd.g[2], sd.g[3]};
    // Chain rule: J (4 raw × m local) and the raw quantities' own second derivatives.
    Local loc;
    std::array<std::array<double, kSpanUnknowns>, 4> jac{};
    std::array<std::array<double, kSpanUnknowns>, kSpanUnknowns> second{};
    auto scalar = [&](const Jet& x, int row) {
      std::array<int, Jet::kMax> at{};
      for (int k = 0; k < x.m; ++k) at[k] = loc.at(x.idx[k]);
      for (int k = 0; k < x.m; ++k) {
        jac[row][at[k]] += x.d[k];
        for (int l = 0; l < x.m; ++l) second[at[k]][at[l]] += sd.g[row] * x.h[k][l];
      }
    };
    scalar(o, 0);
    scalar(in, 1);
    {
      std::array<int, 4> at{};
      for (int k = 0; k < c.m; ++k) at[k] = loc.at(c.idx[k]);
      for (int k = 0; k < c.m; ++k) {
        jac[2][at[k]] += c.d[k].x;
        jac[3][at[k]] += c.d[k].y;
        for (int l = 0; l < c.m; ++l) {
          second[at[k]][at[l]] += sd.g[2] * c.h[k][l].x + sd.g[3] * c.h[k][l].y;
        }
      }
    }
    std::array<std::array<double, kSpanUnknowns>, 4> hj{};  // h · J
    for (int r = 0; r < 4; ++r) {
      for (int u = 0; u < loc.m; ++u) {
        double sum = 0.0;
        for (int q = 0; q < 4; ++q) sum += sd.h[r][q] * jac[q][u];
        hj[r][u] = sum;
      }
    }
    for (int u = 0; u < loc.m; ++u) {
      const std::size_t gu = static_cast<std::size_t>(loc.idx[u]);
      double gsum = 0.0;
      for (int r = 0; r < 4; ++r) gsum += sd.g[r] * jac[r][u];
      g[gu] += gsum * scale[gu];
      for (int v = 0; v <= u; ++v) {
        const std::size_t gv = static_cast<std::size_t>(loc.idx[v]);
        double sum = second[u][v];
        for (int r = 0; r < 4; ++r) sum += jac[r][u] * hj[r][v];
        h.add(gu, gv, sum * scale[gu] * scale[gv]);
      }
    }
  }
  return energy;
}

struct Outcome {
  int iterations = 0;
  bool converged = false, stalled = false;
  double residual = HUGE_VAL;  // relative KKT residual, each node's over its rounding floor
  double raw = HUGE_VAL;       // the same, without the floors
  double floor = 0.0;          // the largest rounding floor above the tolerance (else 0)
  /// `raw` over the unknowns whose gradient exceeds their resolution (kResolutionUlps) and
  /// the wrong-signed multipliers: what a stall leaves beyond the doubles' reach.
  double unresolved = HUGE_VAL;
  std::size_t worst = 0;  // the node where it is largest
};

/// A node's residual cannot fall below the rounding of its chords' angles: a chord ℓ between
/// points of size S has its angle to ~2εS/ℓ, which turns its spans' torques by up to ~12 times
/// that per weight (E_1's second derivatives); with a margin of 2.
constexpr double kRoundingFloor = 48.0;

/// An unknown whose gradient is within this many times its Hessian diagonal times its own
/// resolution (one rounding unit of the position or direction it sets, or of the chord it
/// changes) is stationary to the precision of doubles: no representable move lowers it further
/// (s41-c1119: a ball on its circle beside a held barrier, diagonal 4e10, stalled at 5.7e-6).
constexpr double kResolutionUlps = 8.0;

/// The barrier phase only finds the neighbourhood of the optimum; the active-set phase ends it.
constexpr double kLastBarrier = 1e-14;

/// The KKT residual the optimizer stops at (relative; the option `tolerance` when larger): a
/// quarter of 1e-8, so that the returned curve (its directions refitted at the positions) is
/// within 1e-8. The positions of inactive balls slide along the curve with almost no change of
/// energy: further down, the last digits took tens of iterations each.
constexpr double kBallTolerance = 2.5e-9;

/// The exact phase's barrier on the boxes that bound positions (relative to the typical torque).
constexpr double kHeldBarrier = 1e-8;
/// A held box's room (relative to Ω) below which its barrier stiffens, and how far it may.
constexpr double kHeldRoom = 1e-10;
constexpr double kHeldMostWeight = 1e6;

// Pivots of the Newton matrix below this fraction of its largest diagonal entry count as zero.
constexpr double kMinPivot = 1e-16;

/// Newton iterations per barrier stage at most (a stage only guides the next one).
constexpr int kStageIterations = 40;

/// A free direction this close to a bound (relative to Ω) counts as on it, if pushed outward.
constexpr double kSqueezed = 1e-9;
/// A free position this close to its circle (relative to r) goes onto it, if pushed outward.
constexpr double kPressed = 1e-6;

/// A free position pushed outward, within this share of its radius from its circle, whose
/// shifted Newton step covers less than this share of that way, is tried on the circle
/// (Solver::snap_pressed).
constexpr double kSnapShare = 1e-2;

/// Positions the barrier left within this fraction of the radius of their circle start on it.
constexpr double kCrossOver = 1e-3;

/// A KKT residual the optimizer may stop at when no step lowers the energy any more.
constexpr double kConditioningResidual = 1e-6;

/// Iterations without the projected gradient falling below 0.9 of its best after which
/// multipliers of the wrong sign are released whatever the projected gradient.
constexpr int kStuckIterations = 10;
/// The longest step expand() tries, in Newton steps.
constexpr double kMostExpansion = 1024.0;

/// The first barrier of a restart after a stall: weak enough to keep the point near where it
/// stalled, strong enough to pull the positions off their circles and re-decide which hold.
constexpr double kRestartBarrier = 1e-6;
/// A released ball that the Newton step takes back out this often descends alone instead.
constexpr int kBounces = 3;

// Stopped at the precision the data allow: converged to every node's rounding floor, or no step
// lowers the energy within kConditioningResidual (or the floor).
bool stopped_at_precision(const Outcome& o) {
  return !o.converged && o.stalled &&
         std::min(o.residual, o.unresolved) <= std::max(kConditioningResidual, o.floor);
}

/// The output interpolation's directions agree with the optimizer's to this angle (rad), and
/// the interpolation from its own start finds no energy lower by this fraction, or the
/// optimizer goes on from its directions, at most kOutputRounds times.
constexpr double kOutputAgreement = 1e-6;
constexpr double kOutputEnergy = 1e-10;
constexpr int kOutputRounds = 3;
/// The least iteration budget of a restart after a stall (see fit_data_balls).
constexpr int kMinRestartIterations = 50;
/// A chord that rounding its ends' positions turns by more than this (rad) has them kept as
/// rounded and the rest optimized again (fit_data_balls).
constexpr double kRoundedChordTurn = 1e-11;

/// What a data-ball fit with the elastic spline that does not converge adds to its message.
constexpr char kElasticKinks[] =
    "where a piece turns by more than a right angle its energy has kinks (half turns, ridges it "
    "cannot lock) the optimizer does not handle; the restricted elastic spline fits these balls";

class Solver {
 public:
  Solver(Problem& pb, State& st, const MinEnergyOptions& options)
      : pb_(pb), st_(st), n_(pb.node.size()), ns_(pb.spans()) {
    for (double l : st.len) {
      gscale_ = std::max(gscale_, 1.0 / l);
      wsum_ += 1.0 / l;
    }
    tol = std::max(options.tolerance, kBallTolerance) * gscale_;
    // Each node's residuals are measured against its own spans' weight, not the largest one:
    // beside a near-repeated pair (weights 1e6 times the rest) the global scale let the other
    // directions stop a tenth of the energy away from the optimum.
    local_.assign(n_, 0.0);
    held_weight_.assign(ns_, 0.0);  // until measure_scales()
    for (std::size_t s = 0; s < ns_; ++s) {
      const double w = 1.0 / st.len[s];
      local_[s] = std::max(local_[s], w);
      local_[pb.next(s)] = std::max(local_[pb.next(s)], w);
    }
    tol_ = std::max(options.tolerance, kBallTolerance);
    floor_.assign(n_, 0.0);
    auto size = [&](std::size_t i) {
      const Node& nd = pb.node[i];
      return std::max(std::abs(nd.q.x), std::abs(nd.q.y));
    };
    for (std::size_t s = 0; s < ns_; ++s) {
      const std::size_t j = pb.next(s);
      const double f = kRoundingFloor * kEps * std::max(size(s), size(j)) / st.len[s];
      floor_[s] = std::max(floor_[s], f);
      floor_[j] = std::max(floor_[j], f);
    }
    // The elastic energies come from root-finds, relative-accurate to ~1e-12.
    relative_rounding_ = is_elastic(pb.m.basis) ? 1e-12 : 1e-15;
    max_iterations_ = detail::iteration_limit(options);
    held_.assign(n_, 0);
    bounced_.assign(n_, 0);
  }

  double tol = 0.0;
  double tolerance() const { return tol_; }
  double floor_above_tolerance() const {
    double f = 0.0;
    for (double x : floor_) f = x > tol_ ? std::max(f, x) : f;
    return f;
  }

  /// Barrier stages μ = first, first/10 … 1e-12: each minimizes E − μ Σ log(1 − |p − q|²/r²)/ℓ
  /// to a residual of μ.
  Outcome barrier_phase(double first = 1e-1) {
    Outcome total;
    for (Node& nd : pb_.node) {  // strictly inside its disc
      if (!nd.boundary) continue;
      nd.boundary = false;
      nd.o = (1.0 - kCrossOver) * nd.o;
    }
    chord_angles(pb_, st_);
    // The barrier's weights: per ball μ·F·r, F the energy's typical force on a position, so
    // that at the barrier's optimum a disc pressed with force f keeps a slack of about μ·r·F/f;
    // per direction box μ·T, T the typical torque on a direction. The boxes' barriers keep
    // every stencil turning less than 2Ω while the positions move (as constraints they could
    // only be met by rejecting steps).
    const double om = pb_.omega;
    for (Slot& sl : pb_.slot) {
      if (sl.fixed) continue;
      sl.active = -1;
      for (int k = 0; k < sl.nbox; ++k) {  // strictly inside its boxes
        const double dev = box_deviation(sl, k, st_);
        const double lim = om * (1.0 - 1e-3);
        if (std::abs(dev) > lim) sl.theta -= dev - std::copysign(lim, dev);
      }
    }
    measure_scales();
    // Stages until every disc is either pressed to within kCrossOver·r of its circle or no
    // longer moved by the barrier (its slack changed less than a fifth in the last stage).
    std::vector<double> slack(n_, -1.0);
    for (double mu = first; mu >= kLastBarrier && total.iterations < max_iterations_; mu *= 0.1) {
      if (mu < first) measure_scales();
      const Outcome o = run(mu, std::min(kStageIterations, max_iterations_ - total.iterations),
                            std::max(mu, kConditioningResidual * 1e-2) * gscale_);
      total.iterations += o.iterations;
      bool settled = o.converged;
      for (std::size_t i = 0; i < n_; ++i) {
        const Node& nd = pb_.node[i];
        if (nd.r == 0.0) continue;
        const double now = 1.0 - norm(nd.o) / nd.r;
        settled = settled && (now <= kCrossOver || std::abs(now - slack[i]) <= 0.2 * slack[i]);
        slack[i] = now;
      }
      // A stage that no longer converges (the barrier's conditioning near the circles) ends
      // the phase: later stages only drift.
      if (settled || !o.converged) break;
    }
    return total;
  }

  // The energy's typical force on a position and torque on a direction at the current point:
  // the barrier weights' scales, renewed per stage as the curve straightens.
  void measure_scales() {
    evaluate(0.0, number_unknowns(pb_, scale_));
    double sum = 0.0, tsum = 0.0;
    std::size_t balls = 0;
    for (std::size_t i = 0; i < n_; ++i) {
      if (pb_.node[i].r == 0.0) continue;
      sum += dot(force(i), force(i));
      ++balls;
    }
    // The held barriers are per span, relative to its own weight 1/L, so that a near-repeated
    // pair's torques (weights 1e6 times the rest) do not stiffen every other span's barrier.
    double hsum = 0.0;
    for (std::size_t k = 0; k < raw_.slot.size(); ++k) {
      const double t = raw_.slot[k];
      tsum += t * t;
      const Slot& sl = pb_.slot[k];
      double w = 0.0;
      for (int b = 0; b < sl.nbox; ++b) w = std::max(w, 1.0 / st_.len[sl.span[b]]);
      if (w > 0.0) hsum += (t / w) * (t / w);
    }
    const double slots = static_cast<double>(std::max<std::size_t>(raw_.slot.size(), 1));
    force_ = std::sqrt(sum / static_cast<double>(balls));
    torque_ = std::max(std::sqrt(tsum / slots), 1e-3 * gscale_);
    const double unit = std::max(std::sqrt(hsum / slots), 1e-3);
    held_weight_.resize(ns_);
    for (std::size_t s = 0; s < ns_; ++s) held_weight_[s] = kHeldBarrier * unit / st_.len[s];
    base_held_ = held_weight_;
    if (!(force_ > 1e-6 * gscale_ * gscale_)) force_ = 1e-6 * gscale_ * gscale_;
  }

  /// Positions the last barrier stage left within kCrossOver·r of their circle go onto it.
  void cross_over() {
    std::vector<std::size_t> near;
    for (std::size_t i = 0; i < n_; ++i) {
      const Node& nd = pb_.node[i];
      if (nd.r == 0.0 || nd.boundary) continue;
      const double d = norm(nd.o);
      if (d >= nd.r * (1.0 - kCrossOver) && d > 0.0) near.push_back(i);
    }
    // All at once, or (if that leaves a direction no box) one by one, each kept if it does not.
    if (!snap(near)) {
      for (std::size_t i : near) snap({&i, 1});
    }
    // Directions within kCrossOver·Ω of a bound go onto it.
    Problem p = pb_;
    const double om = pb_.omega;
    for (Slot& sl : p.slot) {
      if (sl.fixed || sl.active >= 0) continue;
      for (int k = 0; k < sl.nbox; ++k) {
        const double dev = box_deviation(sl, k, st_);
        if (om - std::abs(dev) <= kCrossOver * om) {
          sl.active = k;
          sl.sign = dev > 0 ? 1 : -1;
          break;
        }
      }
    }
    if (settle(p, st_) && std::isfinite(total_energy(p, st_))) std::swap(pb_, p);
  }

  bool snap(std::span<const std::size_t> which) {
    if (which.empty()) return true;
    Problem p = pb_;
    State s;
    for (std::size_t i : which) {
      put_on_circle(p.node[i]);
    }
    chord_angles(p, s);
    if (!settle(p, s) || !std::isfinite(total_energy(p, s))) return false;
    std::swap(pb_, p);
    std::swap(st_, s);
    return true;
  }

  /// Projected Newton iterations (at most `budget`) until the residual is below `target`; with
  /// mu > 0 the discs are kept by the barrier, with mu = 0 by active constraints.
  Outcome run(double mu, int budget, double target) {
    Outcome o;
    int flat = 0, stuck = 0;
    double best_pg = HUGE_VAL;
    std::array<double, 4> recent;
    recent.fill(HUGE_VAL);
    // Without a barrier, the point of least residual so far: where the energy's rounding lets
    // steps wander (the elastic energies, to ~1e-12), a stop returns it rather than the last.
    Problem best;
    State best_st;
    Outcome best_o;
    auto stop = [&](Outcome& now) {
      if (mu == 0.0 && best_o.residual < now.residual) {
        std::swap(pb_, best);
        std::swap(st_, best_st);
        best_o.iterations = now.iterations;
        best_o.stalled = !best_o.converged && (now.stalled || best_o.stalled);
        now = best_o;
      }
      return now;
    };
    damping_ = 0.0;
    vertex_.assign(pb_.slot.size(), 0);
    Problem before_release;
    for (;; ++o.iterations) {
      detail::checkpoint("data balls", static_cast<std::size_t>(o.iterations));
      released_.clear();
      // (Not for the elastic spline: across its ridges the polish's line searches over
      // root-found energies took a 320-point U-turn circle from 2.6 to 38 s.)
      if (mu == 0.0 && (o.iterations == 0 || shift_ > 0.0) &&
          pb_.m.basis != MinEnergyBasis::kElastic) {
        polish(mu, target);
      }
      if (mu == 0.0 && !base_held_.empty()) adapt_held();
      std::size_t border = number_unknowns(pb_, scale_);
      double phi = evaluate(mu, border);
      double pg = 0.0, wrong = 0.0;
      std::size_t pg_at = 0, wrong_at = 0;
      residuals(pg, pg_at, wrong, wrong_at);
      o.residual = std::max(pg, wrong) / gscale_;
      o.raw = raw_residual_;
      o.unresolved = unresolved_;
      o.worst = pg >= wrong ? pg_at : wrong_at;
      recent[o.iterations % recent.size()] = std::max(pg, wrong);
      if (pg <= target && wrong <= target) {
        o.converged = true;
        if (mu == 0.0 && release_strict(o, best, best_st, best_o, target)) {
          o.converged = false;
          continue;
        }
        return o;
      }
      if (mu == 0.0 && o.residual < best_o.residual) {
        best = pb_;
        best_st = st_;
        best_o = o;
      }
      if (o.iterations >= budget) return stop(o);
      // A constraint is freed once the point is stationary on its face (else the Newton step
      // can point out through it again).
      // Not when the projected gradient stays where it is, though: then the multipliers'
      // wrong signs are what is left to correct (s41-c1631: 0.13 held for 60 iterations while
      // the projected gradient elsewhere stayed at 2.1).
      stuck = pg >= 0.9 * best_pg ? stuck + 1 : 0;
      const double free_at = stuck >= kStuckIterations ? target : std::max(target, pg);
      if (wrong > free_at) before_release = pb_;
      if (wrong > free_at && release(free_at)) {
        stuck = 0;
        border = number_unknowns(pb_, scale_);
        phi = evaluate(mu, border);
      } else if (mu == 0.0 && activate_squeezed()) {
        border = number_unknowns(pb_, scale_);
        phi = evaluate(mu, border);
      }
      convexify(mu, border);
      newton();
      // Positions the full step takes out of their disc are pinned where their radial unknown
      // reaches the circle and the rest of the step is solved again (the projection in the line
      // search bent the step, which then went a few percent of the way per iteration).
      if (mu == 0.0) {
        std::vector<std::pair<std::size_t, double>> pins;
        for (int pass = 0; pass < 4; ++pass) {
          const std::size_t before = pins.size();
          for (const Node& nd : pb_.node) {
            if (nd.var < 0 || nd.boundary) continue;
            const Vec2 off = nd.o;
            const std::size_t v = static_cast<std::size_t>(nd.var);
            if (norm(off + displacement(nd)) <= nd.r) continue;
            if (std::any_of(pins.begin(), pins.end(),
                            [&](const auto& q) { return q.first == v; })) {
              continue;
            }
            pins.emplace_back(v, (nd.r - dot(off, nd.u)) / scale_[v]);
          }
          if (pins.size() == before) break;
          newton(pins);
        }
        if (!pins.empty() && !(slope_ < 0.0)) newton();  // pinned, the step went uphill
      }
      // A freed position on its circle that the step still takes outward is held there again
      // (until a step is accepted): several freed together can each be pushed out by the rest.
      if (mu == 0.0 && hold_pushed_out()) {
        border = number_unknowns(pb_, scale_);
        phi = evaluate(mu, border);
        convexify(mu, border);
        newton();
      }
      if (mu == 0.0 && shift_ > 0.0 && stuck >= kStuckIterations && snap_pressed(phi)) {
        held_.assign(n_, 0);
        continue;
      }
      // With the barrier the step stays inside the discs (a fraction of the way to the circle).
      // Without, the full step is tried with every position that leaves its disc put on the
      // circle, then the step to where the first one meets it, then shorter ones.
      const double cross = std::max(0.0, to_circle());
      double t = mu > 0.0 ? std::min(1.0, 0.99 * cross) : 1.0;
      bool accepted = false;
      for (int tries = 0; tries < 60 && t > 1e-12; ++tries) {
        if (move(t, mu)) {
          const auto [de, rnd] = change(mu);
          if (std::isfinite(de) && (de <= 1e-4 * t * slope_ || (t == 1.0 && de <= rnd))) {
            accepted = true;
            break;
          }
        }
        t = mu == 0.0 && t == 1.0 && cross < 1.0 && cross > 1e-3 ? cross : 0.5 * t;
      }
      if (!accepted) {
        if (mu == 0.0 && at_vertex(before_release)) continue;
        o.stalled = true;
        if (mu == 0.0 && release_strict(o, best, best_st, best_o, target)) {
          o.stalled = false;
          continue;
        }
        return stop(o);
      }
      const bool expanded = mu == 0.0 && t == 1.0 && stuck >= kStuckIterations && expand();
      if (expanded) t = expansion_;
      // Where the energy cannot tell the step from no step, the KKT residual judges it.
      auto [de, rnd] = change(mu);
      bool shortened = false;
      if (mu == 0.0 && de > -rnd) {
        // With a shifted (indefinite) matrix the residual may rise for a step on the way to
        // the optimum (s41-c940): there the step is measured against the last few residuals.
        double allowance = 0.0;
        if (shift_ > 0.0) {
          for (double r : recent) allowance = std::max(allowance, r);
        }
        shortened = shorten_by_residual(allowance);
        if (shortened) {
          t = 1.0;
          std::tie(de, rnd) = change(mu);
        }
      }
      // (A step that the residual chose changed the energy by its rounding: that change says
      // nothing about how well the model predicted it.)
      if (shortened) {
        damping_ = shift_ / 4.0;
      } else if (expanded) {
        damping_ = shift_ / (4.0 * t);
      } else {
        adapt_damping(t, -de);
      }
      // Steps accepted only within the rounding of φ while the residual does not fall below
      // 0.9 of its best before them: the point is as good as it gets. (Compared with the best
      // including this one, every new best counted as flat: s41-c940 stopped at 2.2e-6 while
      // its residual fell tenfold per step, beside a near-repeated pair whose energy's
      // rounding hid the rest's decrease.)
      flat = de > -rnd && pg >= 0.9 * best_pg ? flat + 1 : 0;
      best_pg = std::min(best_pg, pg);
      lock_crossed_ridges(mu);
      std::swap(pb_, trial_);
      std::swap(st_, tst_);
      held_.assign(n_, 0);
      if (flat >= 5) {
        o.stalled = true;
        if (mu == 0.0 && release_strict(o, best, best_st, best_o, target)) {
          o.stalled = false;
          flat = 0;
          continue;
        }
        ++o.iterations;
        return stop(o);
      }
    }
  }

  // The elastic spline's ridges (docs/methods/elastic.md): a span whose step crossed α = β
  // beyond 98.5° is locked on it, as the interpolation does; Newton steps across the kink went
  // back and forth under a growing shift (noisy-s6-c97: a U-turn piece at 130°).
  void lock_crossed_ridges(double mu) {
    if (pb_.m.basis != MinEnergyBasis::kElastic) return;
    for (std::size_t s = 0; s < ns_; ++s) {
      if (holding(trial_, s)) continue;
      const auto [a0, b0] = end_angles(pb_, st_, s);
      const auto [a1, b1] = end_angles(trial_, tst_, s);
      if (!detail::elastica_ridge_capable(a1, b1) || (a0 - b0) * (a1 - b1) > 0.0) continue;
      tie_ridge(trial_, tst_, s, mu == 0.0);
    }
  }

  // A shifted full step that lowered the energy by nearly all its first-order decrease, while
  // the residual has not fallen for kStuckIterations steps: the energy is nearly linear along
  // it, and the shift (negative curvature elsewhere, by a hair) kept the step short. Doubled
  // (up to 1024 times) while the energy falls further; trial_ becomes the longest such step
  // and expansion_ its length. Without it such fits crept to the iteration cap. Not for the
  // elastic bases, whose root-found energies make the test noisier (no gain measured there).
  bool expand() {
    if (!(shift_ > 0.0) || is_elastic(pb_.m.basis)) return false;
    double best = change(0.0).first;
    if (!(best <= 0.9 * slope_)) return false;
    Problem keep = trial_;
    State keep_st = tst_;
    expansion_ = 1.0;
    for (double t = 2.0; t <= kMostExpansion; t *= 2.0) {
      if (!move(t, 0.0)) break;
      const auto [de, rnd] = change(0.0);
      if (!std::isfinite(de) || !(de < best - rnd)) break;
      best = de;
      keep = trial_;
      keep_st = tst_;
      expansion_ = t;
    }
    std::swap(trial_, keep);
    std::swap(tst_, keep_st);
    return expansion_ > 1.0;
  }

  // The change of φ from the current point to trial_ and its rounding, summed span by span
  // (each span's energy and the barrier at the current point from the last evaluate()): a span
  // whose end angles and chord did not change adds exactly 0. The difference of the totals carried
  // the rounding of every span's energy, and beside a near-repeated pair (10^6 times the rest) that
  // hid the decrease of a step elsewhere: s41-c830 stopped at the precision limit 10^3 times above
  // the tolerance.
  std::pair<double, double> change(double mu) const {
    double d = 0.0, size = 0.0;
    for (std::size_t s = 0; s < ns_; ++s) {
      const auto [a1, b1] = end_angles(trial_, tst_, s);
      const auto [a0, b0] = end_angles(pb_, st_, s);
      if (a0 == a1 && b0 == b1 && st_.len[s] == tst_.len[s]) continue;
      const double e1 = span_energy(trial_.m, a1, b1).e / tst_.len[s];
      d += e1 - raw_.span[s];
      size += std::max(std::abs(e1), std::abs(raw_.span[s]));
    }
    const double b1 = barrier(trial_, tst_, mu);
    d += b1 - raw_.barrier;
    size += std::max(std::abs(b1), std::abs(raw_.barrier));
    return {d, relative_rounding_ * size};
  }

  // The KKT residual (scaled, as residuals() gives it) at trial_ and at the current point; the
  // members (unknowns, gradient, Hessian, residuals) describe the current point again after.
  std::pair<double, double> residual_at_trial() {
    auto measure = [&] {
      evaluate(0.0, number_unknowns(pb_, scale_));
      double pg = 0.0, wrong = 0.0;
      std::size_t pg_at = 0, wrong_at = 0;
      residuals(pg, pg_at, wrong, wrong_at);
      return std::max(pg, wrong);
    };
    std::swap(pb_, trial_);
    std::swap(st_, tst_);
    const double at_trial = measure();
    std::swap(pb_, trial_);
    std::swap(st_, tst_);
    return {at_trial, measure()};
  }

  // A step whose energy change is within the energy's rounding, judged by the KKT residual: it
  // is kept if the residual does not rise above `allowance` (or the current one, if larger);
  // else the step is shortened along the flat directions (a Levenberg–Marquardt shift, tenfold
  // per try) until it halves the residual. Along a curved valley that is flat to the energy's
  // rounding, the full Newton step overshoots the valley's bend and the stiff directions'
  // gradient comes back as large (s41-c1460: 1e-5 for 100 steps, each changing the energy by
  // its rounding). Says whether trial_ is now the shortened step (else it is the given one).
  bool shorten_by_residual(double allowance) {
    const auto [after, now] = residual_at_trial();
    if (after < std::max(now, allowance)) return false;
    Problem keep = trial_;
    State keep_st = tst_;
    const std::vector<double> keep_step = step_;
    const double keep_slope = slope_, keep_sq = step_sq_, keep_shift = shift_,
                 keep_damping = damping_;
    const double dmax = largest_diagonal();
    for (double shift = 1e-8 * dmax; shift <= dmax; shift *= 10.0) {
      factored_ = false;
      damping_ = shift;
      newton();
      if (!move(1.0, 0.0)) continue;
      const auto [de, rnd] = change(0.0);
      if (de <= rnd && residual_at_trial().first <= 0.5 * now) return true;
    }
    std::swap(trial_, keep);
    std::swap(tst_, keep_st);
    step_ = keep_step;
    slope_ = keep_slope, step_sq_ = keep_sq, shift_ = keep_shift, damping_ = keep_damping;
    return false;
  }

  /// At a stationary point: tries each direction pair of a span whose E_1 is concave there
  /// along E_1's concave eigenvector, a few step sizes each way; moves to the first point of
  /// clearly lower energy and says whether it did.
  bool escape() {
    number_unknowns(pb_, scale_);
    const double phi = total_energy(pb_, st_);
    const double margin = 1e-9 * std::abs(phi);
    for (std::size_t s = 0; s < ns_; ++s) {
      const Node& a = pb_.node[s];
      const Node& b = pb_.node[pb_.next(s)];
      Slot& out = pb_.slot[a.out];
      Slot& in = pb_.slot[b.in];
      const double so = out.var >= 0 ? 1.0 : 0.0, si = in.var >= 0 ? 1.0 : 0.0;
      if (so + si == 0.0) continue;
      const auto [al, be] = end_angles(pb_, st_, s);
      const BasicEnergy e1 = span_energy(pb_.m, al, be);
      const double haa = e1.eaa * so, hbb = e1.ebb * si, hab = e1.eab * so * si;
      const double mid = 0.5 * (haa + hbb), rad = std::hypot(0.5 * (haa - hbb), hab);
      if (mid - rad >= 0.0) continue;
      // The eigenvector of the negative eigenvalue lo: (hab, lo − haa), or an axis.
      const double lo = mid - rad;
      double va = hab, vb = lo - haa;
      if (std::hypot(va, vb) == 0.0) {
        va = haa <= hbb ? 1.0 : 0.0;
        vb = 1.0 - va;
      }
      const double nv = std::hypot(va, vb);
      va *= so / nv;
      vb *= si / nv;
      for (double t : {0.4, 0.1, 0.02}) {
        for (double sign : {1.0, -1.0}) {
          trial_ = pb_;
          trial_.slot[a.out].theta += sign * t * va;
          if (b.in != a.out) trial_.slot[b.in].theta += sign * t * vb;
          chord_angles(trial_, tst_);
          if (!settle(trial_, tst_)) continue;
          const double e = total_energy(trial_, tst_);
          if (e < phi - margin) {
            std::swap(pb_, trial_);
            std::swap(st_, tst_);
            return true;
          }
        }
      }
    }
    return false;
  }

 private:
  double barrier(const Problem& pb, const State& st, double mu) const {
    double b = 0.0;
    for (const Node& nd : pb.node) {
      if (mu == 0.0 || nd.r == 0.0 || nd.boundary) continue;
      const Vec2 off = nd.o;
      b -= mu * force_ * nd.r * std::log1p(-dot(off, off) / (nd.r * nd.r));
    }
    const double om = pb.omega;
    for (const Slot& sl : pb.slot) {
      for (int k = 0; k < sl.nbox; ++k) {
        const double w = box_weight(sl, k, mu);
        if (w == 0.0) continue;
        const double dev = box_deviation(sl, k, st);
        const double room = std::max(om - std::abs(dev), kBoxRounding * om);
        b -= w * std::log(room * (2.0 * om - room) / (om * om));
      }
    }
    if (pb.m.basis == MinEnergyBasis::kElastic) {  // the pair bounds |α − β| <= π
      for (std::size_t s = 0; s < pb.spans(); ++s) {
        const auto [a, be] = end_angles(pb, st, s);
        const double room = std::max(kPi - std::abs(a - be), kBoxRounding * kPi);
        b -= held_weight_[s] * std::log(room * (2.0 * kPi - room) / (kPi * kPi));
      }
    }
    return b;
  }

  // A held box whose room has shrunk below kHeldRoom·Ω is pressed by more than its barrier can
  // hold at a representable room: its span's held weight grows tenfold per iteration (and falls
  // back as the room opens), so that the barrier's force matches the box's multiplier at a room
  // the certificate still counts as on the bound (s41-c1789: a torque 1e4 times the barrier's
  // at the rounding floor of the room).
  void adapt_held() {
    const double om = pb_.omega;
    room_.assign(ns_, HUGE_VAL);
    for (const Slot& sl : pb_.slot) {
      for (int k = 0; k < sl.nbox; ++k) {
        const std::size_t s = sl.span[k];
        if (box_weight(sl, k, 0.0) == 0.0) continue;
        room_[s] = std::min(room_[s], om - std::abs(box_deviation(sl, k, st_)));
      }
    }
    for (std::size_t s = 0; s < ns_; ++s) {
      if (room_[s] < kHeldRoom * om) {
        held_weight_[s] = std::min(10.0 * held_weight_[s], kHeldMostWeight * base_held_[s]);
      } else if (room_[s] > 100.0 * kHeldRoom * om) {
        held_weight_[s] = std::max(0.1 * held_weight_[s], base_held_[s]);
      }
    }
  }

  // The barrier on box k of a slot: every box in the barrier phase; in the exact phase the
  // boxes that are not constraints of their own (a given direction's, and the second box of a
  // direction on a bound: they bound the positions, a stencil turning at most 2Ω) keep a
  // barrier of weight kHeldBarrier, so that the optimum where one holds is reached as the
  // barrier's (its force is that box's multiplier) instead of by rejected steps.
  double box_weight(const Slot& sl, int k, double mu) const {
    if (mu > 0.0) return sl.active < 0 ? mu * torque_ : 0.0;
    if (sl.fixed || sl.tie >= 0 || (sl.active >= 0 && sl.active != k)) {
      return held_weight_[sl.span[k]];
    }
    return 0.0;
  }

  // Adds f(x) to the gradient and Hessian, for a quantity x given as a jet and f's first and
  // second derivatives there.
  void add_function(const Jet& x, double f1, double f2) {
    for (int k = 0; k < x.m; ++k) {
      const std::size_t u = static_cast<std::size_t>(x.idx[k]);
      g_[u] += f1 * x.d[k] * scale_[u];
      for (int l = 0; l <= k; ++l) {
        const std::size_t v = static_cast<std::size_t>(x.idx[l]);
        h_.add(u, v, (f2 * x.d[k] * x.d[l] + f1 * x.h[k][l]) * scale_[u] * scale_[v]);
      }
    }
  }

  double evaluate(double mu, std::size_t border, bool convex = false) {
    factored_ = false;
    double phi = assemble(pb_, st_, scale_, border, h_, g_, raw_, convex);
    raw_.barrier = barrier(pb_, st_, mu);
    phi += raw_.barrier;
    const double om = pb_.omega;
    held_torque_.assign(pb_.slot.size(), 0.0);
    tied_.clear();
    for (std::size_t si = 0; si < pb_.slot.size(); ++si) {
      if (pb_.slot[si].tie >= 0) tied_.push_back(si);
      const Slot& sl = pb_.slot[si];
      for (int k = 0; k < sl.nbox; ++k) {
        const double w = box_weight(sl, k, mu);
        if (w == 0.0) continue;
        // dev = θ + offset − φ_t: θ as the slot's jet (a free unknown, or its own chord's angle
        // when it sits on a bound).
        const Jet dev = difference(slot_jet(pb_, sl), chord_angle(pb_, sl.span[k]));
        const double x = box_deviation(sl, k, st_);
        const double lo = std::max(om + x, kBoxRounding * om),
                     hi = std::max(om - x, kBoxRounding * om);
        const double torque = w * (1.0 / hi - 1.0 / lo);
        add_function(dev, torque, w * (1.0 / (hi * hi) + 1.0 / (lo * lo)));
        if (sl.active >= 0) held_torque_[si] += torque;
      }
    }
    for (const Node& nd : pb_.node) {
      if (mu == 0.0 || nd.var < 0 || nd.boundary) continue;
      const Vec2 off = nd.o;
      const double w = mu * force_ * nd.r, slack = nd.r * nd.r - dot(off, off);
      const double sc = scale_[nd.var];
      const std::size_t v = static_cast<std::size_t>(nd.var);
      g_[v] += 2.0 * w * dot(off, nd.u) / slack * sc;
      g_[v + 1] += 2.0 * w * cross(nd.u, off) / slack * sc;
      // In the node's basis (u, u⊥): off = (ou, ow).
      const Vec2 pu{-nd.u.y, nd.u.x};
      const double ou = dot(off, nd.u), ow = dot(off, pu);
      const double a = 2.0 * w / slack, b = 4.0 * w / (slack * slack);
      h_.add(v, v, (a + b * ou * ou) * sc * sc);
      h_.add(v + 1, v, b * ou * ow * sc * sc);
      h_.add(v + 1, v + 1, (a + b * ow * ow) * sc * sc);
    }
    return phi;
  }

  // The largest scaled gradient entry of a free unknown, and the largest wrong-signed
  // multiplier: an active box holds θ if ∂E/∂θ pushes against it; an active disc holds its
  // position if the energy falls outward (its slots on a bound turning with the chord).
  void residuals(double& pg, std::size_t& pg_at, double& wrong, std::size_t& wrong_at) {
    slot_wrong_.assign(pb_.slot.size(), 0.0);
    slot_strict_.assign(pb_.slot.size(), 0.0);
    node_wrong_.assign(n_, 0.0);
    double raw = 0.0, unresolved = 0.0;
    for (std::size_t i = 0; i < n_; ++i) {
      const Node& nd = pb_.node[i];
      const double over = std::max(1.0, floor_[i] / tol_);
      const double f = gscale_ / local_[i] / over;
      double here = 0.0;  // this node's largest residual, over its floor
      // One rounding unit of the unknown, scaled: a position is known to that of its offset or
      // of the chords it is added to, a direction to that of its angle.
      double chords = 0.0;
      if (pb_.closed || i > 0) chords = norm(pb_.chord(i == 0 ? ns_ - 1 : i - 1));
      if (pb_.closed || i + 1 < n_) chords = std::max(chords, norm(pb_.chord(i)));
      const double at_position = kEps * std::max(norm(nd.o), chords) / nd.scale;
      auto see = [&](int v, double resolution) {
        if (v < 0) return;
        const double gv = std::abs(g_[static_cast<std::size_t>(v)]);
        here = std::max(here, f * gv);
        if (f * gv > pg) {
          pg = f * gv;
          pg_at = i;
        }
        const double hv = std::abs(h_.diagonal(static_cast<std::size_t>(v)));
        if (gv > kResolutionUlps * hv * resolution)
          unresolved = std::max(unresolved, gv / local_[i]);
      };
      for (int s : {nd.in, nd.out}) {
        if (s >= 0) see(pb_.slot[s].var, kEps * std::max(std::abs(pb_.slot[s].theta), 1.0));
      }
      if (nd.var >= 0) {
        see(nd.var, at_position);
        if (!nd.boundary) see(nd.var + 1, at_position);
      }
      for (int s : {nd.in, nd.out}) {
        if (s < 0 || pb_.slot[s].active < 0) continue;
        const Slot& sl = pb_.slot[s];
        // The multiplier of its bound: the energy's torque, plus at a vertex (below) that of
        // the barrier on its other box, which stands in for that box's multiplier there.
        const double torque = raw_.slot[s] + (vertex_[s] ? held_torque_[s] : 0.0);
        slot_strict_[s] = gscale_ * st_.len[sl.span[sl.active]] / over * sl.sign * torque;
        slot_wrong_[s] = std::max(slot_wrong_[s], f * sl.sign * torque);
        here = std::max(here, slot_wrong_[s]);
        if (slot_wrong_[s] > wrong) {
          wrong = slot_wrong_[s];
          wrong_at = i;
        }
      }
      for (int s : {nd.in, nd.out}) {
        if (s < 0 || pb_.slot[s].tie < 0) continue;
        slot_wrong_[s] = f * tie_excess(static_cast<std::size_t>(s));
        here = std::max(here, slot_wrong_[s]);
        if (slot_wrong_[s] > wrong) {
          wrong = slot_wrong_[s];
          wrong_at = i;
        }
      }
      if (nd.boundary) {
        node_wrong_[i] = f * outward(i);
        here = std::max(here, node_wrong_[i]);
        if (node_wrong_[i] > wrong) {
          wrong = node_wrong_[i];
          wrong_at = i;
        }
      }
      raw = std::max(raw, here * over / gscale_);
      for (int s : {nd.in, nd.out}) {
        if (s >= 0) unresolved = std::max(unresolved, slot_wrong_[s] * over / gscale_);
      }
      unresolved = std::max(unresolved, node_wrong_[i] * over / gscale_);
    }
    raw_residual_ = raw;
    unresolved_ = unresolved;
  }

  // How far the torque on tied slot k says its tie should go (0 while it holds). On a ridge: by
  // how much it exceeds the kink's half-width (moving either end alone off the ridge by ε
  // changes E by ε times its torque plus the half-width times |ε|); on a pair bound: its
  // multiplier's wrong sign. A ridge released twice stays locked (the half-width is a
  // difference of one-sided derivatives and may not be sharp enough to decide).
  double tie_excess(std::size_t k) const {
    const Slot& sl = pb_.slot[k];
    if (sl.tie_gap != 0.0) {
      // On a pair bound: the multiplier's wrong sign, the torque that turns k inwards.
      const bool is_in = pb_.node[pb_.next(sl.tie_span)].in == static_cast<int>(k);
      return std::max(0.0, (is_in ? -1.0 : 1.0) * std::copysign(1.0, sl.tie_gap) * raw_.slot[k]);
    }
    if (ridge_releases_.size() > k && ridge_releases_[k] >= 2) return 0.0;
    const std::size_t owner = static_cast<std::size_t>(sl.tie);
    const std::size_t s = sl.tie_span;
    const double alpha = end_angles(pb_, st_, s).first;
    const double half =
        detail::elastica_ridge_half_jump(alpha, detail::elastica_energy(alpha, alpha)) / st_.len[s];
    const Slot& o = pb_.slot[owner];
    double force = std::abs(raw_.slot[k]);
    if (!o.fixed && o.active < 0) force = std::max(force, std::abs(raw_.slot[owner]));
    return std::max(0.0, force - half);
  }

  // ∂E/∂p at node i with the directions on a bound at its chords turning with them.
  Vec2 force(std::size_t i) const {
    Vec2 total = raw_.node[i];
    for (int side = 0; side < 2; ++side) {
      if (!pb_.closed && (side == 0 ? i == 0 : i + 1 == n_)) continue;
      const std::size_t s = side == 0 ? (i ? i - 1 : n_ - 1) : i;
      const std::size_t a = s, b = pb_.next(s);
      const Vec2 c = pb_.chord(s);
      const Vec2 dphi = (side == 1 ? -1.0 : 1.0) / dot(c, c) * Vec2{-c.y, c.x};
      for (int sk : {pb_.node[a].out, pb_.node[b].in}) {
        const Slot& sl = pb_.slot[sk];
        if (sl.active >= 0 && sl.span[sl.active] == s) total += raw_.slot[sk] * dphi;
      }
      // A slot tied to one on a bound at this chord turns with it too.
      for (std::size_t k : tied_) {
        const Slot& o = pb_.slot[static_cast<std::size_t>(pb_.slot[k].tie)];
        if (o.active >= 0 && o.span[o.active] == s) total += raw_.slot[k] * dphi;
      }
    }
    return total;
  }

  // The scaled derivative of E as node i moves away from its centre (0 at the centre).
  double outward(std::size_t i) const {
    const Node& nd = pb_.node[i];
    const Vec2 off = nd.o;
    const double d = norm(off);
    return d > 0.0 ? dot(force(i), off) / d * nd.scale : 0.0;
  }

  // The full step's move of a free position.
  Vec2 displacement(const Node& nd) const {
    const double a = step_[nd.var] * scale_[nd.var], b = step_[nd.var + 1] * scale_[nd.var + 1];
    return a * nd.u + b * Vec2{-nd.u.y, nd.u.x};
  }

  bool hold_pushed_out() {
    bool any = false;
    for (std::size_t i = 0; i < n_; ++i) {
      Node& nd = pb_.node[i];
      if (nd.var < 0 || nd.boundary) continue;
      const Vec2 off = nd.o;
      const Vec2 d = displacement(nd);
      if (norm(off) < nd.r * (1.0 - 1e-12) || dot(off, d) <= 0.0) continue;
      if (++bounced_[i] > kBounces && descend_inward(i)) {
        bounced_[i] = 0;
        any = true;
        continue;
      }
      put_on_circle(nd);
      held_[i] = 1;
      any = true;
    }
    return any;
  }

  // A ball released for a wrong-signed multiplier that every Newton step since took outward
  // again (kBounces times): it moves alone along the energy's descent, into its disc, with a
  // backtracking search (the directions held). Else it went back onto its circle each time,
  // the multiplier unchanged, to the iteration cap (s19-c499, 8e-5 at one ball).
  bool descend_inward(std::size_t i) {
    const Vec2 g = force(i);
    const double gn = norm(g);
    if (!(gn > 0.0)) return false;
    const double e0 = total_energy(pb_, st_);
    for (double t = 0.5; t >= 1e-6; t *= 0.25) {
      Problem p = pb_;
      Node& nd = p.node[i];
      const Vec2 off = nd.o - (t * nd.r / gn) * g;
      if (!(norm(off) < nd.r)) continue;
      nd.o = off;
      nd.boundary = false;
      State s;
      chord_angles(p, s);
      if (!settle(p, s, false)) continue;
      const double e = total_energy(p, s);
      if (e < e0 - 1e-4 * t * nd.r * gn) {
        std::swap(pb_, p);
        std::swap(st_, s);
        return true;
      }
    }
    return false;
  }

  // A free direction on a bound to rounding (kSqueezed·Ω) whose torque pushes it out goes onto
  // it, so that its other box becomes a held one: a free direction squeezed between both bounds
  // blocks every step that turns its chords further. Likewise a free position within kPressed·r
  // of its circle and pushed outward (a move that lowers the energy): shortened steps only ever
  // cover part of that gap.
  bool activate_squeezed() {
    const double om = pb_.omega;
    bool any = false;
    Problem p = pb_;
    for (Node& nd : p.node) {
      if (nd.var < 0 || nd.boundary || nd.r == 0.0) continue;
      if (norm(nd.o) < nd.r * (1.0 - kPressed) || g_[nd.var] >= 0.0) continue;
      put_on_circle(nd);
      any = true;
    }
    for (Slot& sl : p.slot) {
      if (sl.var < 0) continue;
      for (int k = 0; k < sl.nbox; ++k) {
        const double dev = box_deviation(sl, k, st_);
        if (om - std::abs(dev) > kSqueezed * om || g_[sl.var] * dev >= 0.0) continue;
        sl.active = k;
        sl.sign = dev > 0 ? 1 : -1;
        any = true;
        break;
      }
    }
    if (!any) return false;
    State s;
    chord_angles(p, s);
    if (!settle(p, s) || !std::isfinite(total_energy(p, s))) return false;
    std::swap(pb_, p);
    std::swap(st_, s);
    return true;
  }

  // Under a shift (negative curvature elsewhere), a free position that the energy pushes
  // outward may cover only a tiny part of its way to the circle per step (noisy-s3-c165: 1e-3 r
  // inside, force 25, 5e-10 r per step under shifts of 1e4, to the iteration limit). Such
  // positions are tried on their circles together, kept if that lowers φ.
  bool snap_pressed(double phi) {
    std::vector<std::size_t> near;  // pressed outward, within kSnapShare r of the circle
    std::size_t best = 0;
    double most = 0.0;  // the largest first-order decrease of one of them
    for (std::size_t i = 0; i < n_; ++i) {
      const Node& nd = pb_.node[i];
      if (nd.var < 0 || nd.boundary || nd.r == 0.0 || g_[nd.var] >= 0.0) continue;
      const double gap = nd.r - norm(nd.o);
      const double radial = std::abs(step_[nd.var] * scale_[nd.var]);
      if (!(gap > 0.0) || gap > kSnapShare * nd.r || radial >= kSnapShare * gap) continue;
      near.push_back(i);
      const double decrease = -g_[nd.var] * gap / scale_[nd.var];
      if (decrease > most) most = decrease, best = i;
    }
    auto attempt = [&](std::span<const std::size_t> which) {
      Problem p = pb_;
      for (std::size_t i : which) put_on_circle(p.node[i]);
      State s;
      chord_angles(p, s);
      if (!settle(p, s)) return false;
      const double e = total_energy(p, s) + barrier(p, s, 0.0);
      if (!(e < phi)) return false;
      std::swap(pb_, p);
      std::swap(st_, s);
      return true;
    };
    if (near.empty()) return false;
    return attempt(near) || (near.size() > 1 && attempt(std::span<const std::size_t>(&best, 1)));
  }

  // Where the run would end (converged, or stalled at the precision limit): a direction on a
  // bound whose multiplier has the wrong sign by more than the tolerance of the span it bounds
  // (not of the node's largest weight) is released and the run goes on, the point kept as the
  // best to return if it ends worse. Beside a near-repeated pair (weight 1e9) a wrong sign of
  // 1e-8 of the pair's torques passes the node's test, yet held the long span's ball 0.2 of
  // its force from stationary (s19-c89). Once per slot and solve, and not at every step: such
  // a direction, stiff with the pair's weight, returns to its bound at every step, and
  // releasing it each time crept to the iteration limit (s19-c419).
  bool release_strict(const Outcome& o, Problem& best, State& best_st, Outcome& best_o,
                      double target) {
    if (!o.converged && !stopped_at_precision(o)) return false;  // the restart's business
    strict_released_.resize(pb_.slot.size(), 0);
    auto due = [&](std::size_t k) {
      return pb_.slot[k].active >= 0 && slot_strict_[k] > target && !strict_released_[k];
    };
    bool any = false;
    for (std::size_t k = 0; k < pb_.slot.size() && !any; ++k) any = due(k);
    if (!any) return false;
    if (o.converged || !(best_o.residual < o.residual)) {
      best = pb_;
      best_st = st_;
      best_o = o;
    }
    for (std::size_t k = 0; k < pb_.slot.size(); ++k) {
      if (!due(k)) continue;
      pb_.slot[k].active = -1;
      strict_released_[k] = 1;
    }
    return true;
  }

  // A direction on one bound of its box whose other box is held at its own bound (a stencil
  // turning 2Ω) has the held barrier's torque as that box's multiplier: the energy's torque
  // alone can read as a wrong sign there, and releasing the bound gives a step that no length
  // of it can take. When no step was found after this iteration's release, the released
  // directions whose torque with the barrier's has the right sign go back onto their bound as
  // vertices, judged with it from then on. Only then: where a step is found, releasing the
  // vertex is how the positions open the stencil (docs/hardening.md).
  bool at_vertex(Problem& before) {
    bool any = false;
    for (const auto& [k, pressed] : released_) {
      if (vertex_[k] || pressed > 0.0) continue;
      vertex_[k] = 1;
      any = true;
    }
    if (any) std::swap(pb_, before);
    return any;
  }

  // Frees every constraint whose multiplier has the wrong sign by more than `target`.
  bool release(double target) {
    bool any = false;
    ridge_releases_.resize(pb_.slot.size(), 0);
    for (std::size_t k = 0; k < pb_.slot.size(); ++k) {
      if (slot_wrong_[k] > target && pb_.slot[k].tie >= 0) {
        // Off the ridge on the side where the larger force points downhill; off a pair bound
        // inwards (the torque's wrong sign).
        const std::size_t owner = static_cast<std::size_t>(pb_.slot[k].tie);
        const Slot& o = pb_.slot[owner];
        const bool by_owner = pb_.slot[k].tie_gap == 0.0 && !o.fixed && o.active < 0 &&
                              std::abs(raw_.slot[owner]) > std::abs(raw_.slot[k]);
        const double torque = by_owner ? -raw_.slot[owner] : raw_.slot[k];
        untie(pb_, k, torque);
        ++ridge_releases_[k];
        any = true;
        continue;
      }
      if (slot_wrong_[k] > target) {
        pb_.slot[k].active = -1;
        released_.emplace_back(k, pb_.slot[k].sign * (raw_.slot[k] + held_torque_[k]));
        any = true;
      }
    }
    for (std::size_t i = 0; i < n_; ++i) {
      if (node_wrong_[i] > target && !held_[i]) {
        pb_.node[i].boundary = false;
        any = true;
      }
    }
    return any;
  }

  // The Newton matrix's largest diagonal entry (in absolute value): the scale of its shifts and
  // pivots.
  double largest_diagonal() const {
    double dmax = 0.0;
    for (std::size_t k = 0; k < scale_.size(); ++k) dmax = std::max(dmax, std::abs(h_.diagonal(k)));
    return dmax;
  }

  // Where the Newton matrix is not positive definite, each span's part of it is made so (its
  // Hessian projected onto the PSD cone) instead of shifting the whole matrix: a shift that one
  // concave span needed (cond-G2 with λ > 3/2 is concave around a straight span) slowed every
  // unknown to a gradient step, hundreds of iterations on five points.
  void convexify(double mu, std::size_t border) {
    const double dmax = largest_diagonal();
    factored_ = h_.factor(0.0, kMinPivot * std::max(dmax, gscale_));
    if (!factored_) evaluate(mu, border, true);
  }

  // The Newton step on the scaled unknowns, shifted until the matrix is positive definite.
  void newton(std::span<const std::pair<std::size_t, double>> pins = {}) {
    step_.assign(g_.size(), 0.0);
    for (std::size_t k = 0; k < g_.size(); ++k) step_[k] = -g_[k];
    BorderedBand* h = &h_;
    if (!pins.empty()) {
      hp_ = h_;
      for (const auto& [i, v] : pins) hp_.pin(i, v, step_);
      h = &hp_;
    }
    const double dmax = largest_diagonal();
    const double min_pivot = kMinPivot * std::max(dmax, gscale_);
    // (convexify factored the same matrix already: definite, no shift)
    if (factored_) damping_ = 0.0;
    shift_ = damping_;
    bool factored = pins.empty() && factored_;
    for (int tries = 0; tries < 60 && !factored; ++tries) {
      factored = h->factor(shift_, min_pivot);
      if (!factored) shift_ = shift_ == 0.0 ? 1e-10 * std::max(dmax, gscale_) : shift_ * 4.0;
    }
    // (Not factored: the matrix is not finite; a gradient step, which the line search rejects
    // if it does not help.)
    if (factored) h->solve(step_);
    slope_ = step_sq_ = 0.0;
    for (std::size_t k = 0; k < g_.size(); ++k) {
      slope_ += g_[k] * step_[k];
      step_sq_ += step_[k] * step_[k];
    }
  }

  // Newton steps on the directions alone at the current positions, until they are stationary
  // there. The full step then starts on the valley floor of the short spans: off it, a short
  // span's stiff torque times the curvature of its chord's angle in the positions makes the
  // Newton matrix indefinite along the valley (a shift, then steps of a few percent).
  void polish(double mu, double target) {
    const double damping = damping_;
    damping_ = 0.0;
    for (int k = 0; k < 8; ++k) {
      const std::size_t border = number_unknowns(pb_, scale_, false);
      const double phi = evaluate(mu, border);
      double pg = 0.0;
      for (double v : g_) pg = std::max(pg, std::abs(v));
      if (g_.empty() || pg <= 0.1 * target) break;
      convexify(mu, border);
      newton();
      bool accepted = false;
      for (double t = 1.0; t > 1e-6 && !accepted; t *= 0.5) {
        trial_ = pb_;
        for (Slot& sl : trial_.slot) {
          if (sl.var >= 0) sl.theta += t * step_[sl.var] * scale_[sl.var];
        }
        if (!settle(trial_, st_)) continue;
        const double e = total_energy(trial_, st_) + barrier(trial_, st_, mu);
        accepted = std::isfinite(e) && e <= phi + 1e-4 * t * slope_;
      }
      if (!accepted) break;
      std::swap(pb_, trial_);
    }
    damping_ = damping;
  }

  // Where the Newton matrix needed a shift (negative curvature), the shift is carried to the
  // next iteration and adapted to how well the quadratic model predicted the accepted step:
  // the least shift that makes the matrix definite gives a step along the near-null direction
  // that the line search cut to a few percent, alternating with tiny steps.
  void adapt_damping(double t, double actual) {
    if (shift_ == 0.0) {
      damping_ = 0.0;
      return;
    }
    const double predicted = -t * slope_ + 0.5 * t * t * (slope_ + shift_ * step_sq_);
    const double rho = predicted > 0.0 ? actual / predicted : 0.0;
    if (t == 1.0 && rho > 0.25) {
      damping_ = shift_ / 4.0;
    } else {  // a step that long along the flat directions was too long
      damping_ = shift_ / std::max(t, 0.01) * (rho < 0.25 ? 2.0 : 1.0);
    }
  }

  // How far along the step (as a fraction) the first free position reaches its circle.
  double to_circle() const {
    double t = HUGE_VAL;
    for (const Node& nd : pb_.node) {
      if (nd.var < 0 || nd.boundary) continue;
      const Vec2 d = displacement(nd);
      const Vec2 off = nd.o;
      const double qa = dot(d, d), qb = dot(off, d), qc = dot(off, off) - nd.r * nd.r;
      if (qa == 0.0) continue;
      t = std::min(t, (-qb + std::sqrt(std::max(0.0, qb * qb - qa * qc))) / qa);
    }
    return t;
  }

  // The point t along the step: directions and positions moved, positions leaving their disc
  // put on its circle (activated), the directions settled into their boxes.
  bool move(double t, double mu) {
    trial_ = pb_;
    for (std::size_t i = 0; i < n_; ++i) {
      Node& nd = trial_.node[i];
      for (int s : {nd.in, nd.out}) {
        if (s >= 0 && trial_.slot[s].var >= 0) {
          const int v = trial_.slot[s].var;
          trial_.slot[s].theta = pb_.slot[s].theta + t * step_[v] * scale_[v];
        }
      }
      if (nd.var < 0) continue;
      if (nd.boundary) {
        const Vec2 u = nd.o / nd.r;
        const double dt = t * step_[nd.var] * scale_[nd.var];
        nd.o = nd.r * Vec2{u.x * std::cos(dt) - u.y * std::sin(dt),
                           u.y * std::cos(dt) + u.x * std::sin(dt)};
      } else {
        nd.o = nd.o + t * displacement(nd);
        const Vec2 off = nd.o;
        if (mu > 0.0 && norm(off) >= nd.r) return false;
        if (norm(off) >= nd.r * (1.0 - 1e-12)) put_on_circle(nd);
      }
    }
    chord_angles(trial_, tst_);
    for (Slot& sl : trial_.slot) {
      if (sl.var >= 0 && sl.follow >= 0) {
        const std::size_t f = static_cast<std::size_t>(sl.follow);
        sl.theta += wrap(tst_.phi[f] - st_.phi[f]);
      }
    }
    return settle(trial_, tst_, mu == 0.0);
  }

  Problem& pb_;
  State& st_;
  std::size_t n_, ns_;
  double force_ = 0.0, torque_ = 0.0;  // the barrier's scales
  std::vector<double> held_weight_;    // per span: the exact phase's barrier on position bounds
  std::vector<double> base_held_;      // held_weight_ as measure_scales() set it
  std::vector<double> room_;           // per span: its held boxes' least room (adapt_held)
  double gscale_ = 0.0, wsum_ = 0.0, relative_rounding_ = 1e-15;
  std::vector<double> local_;        // per node: its spans' largest weight
  std::vector<double> floor_;        // per node: the residual its chords' rounding allows
  std::vector<int> ridge_releases_;  // per slot: how often its ridge was released
  std::vector<std::size_t> tied_;    // the tied slots (evaluate())
  double tol_ = 0.0, raw_residual_ = 0.0, unresolved_ = 0.0;
  int max_iterations_ = 200;
  std::vector<double> scale_, g_, step_, slot_wrong_, node_wrong_;
  std::vector<double> held_torque_;  // per slot on a bound: its held box's barrier's torque
  std::vector<char> vertex_;         // per slot: on a bound, its other box held at its own
  // The slots this iteration's release() freed, each with its torque and the held barrier's
  // (times the sign of its bound: > 0 is a wrong sign).
  std::vector<std::pair<std::size_t, double>> released_;
  std::vector<double> slot_strict_;    // per slot: its multiplier's wrong sign, span-scaled
  std::vector<char> strict_released_;  // per slot: released by release_strict this solve
  std::vector<char> held_;
  std::vector<int> bounced_;  // per node: how often a step took it back out (hold_pushed_out)
  BorderedBand h_, hp_;
  Raw raw_;
  Problem trial_;
  State tst_;
  double shift_ = 0.0, slope_ = 0.0, step_sq_ = 0.0;
  double expansion_ = 1.0;  // the length of the step expand() took
  double damping_ = 0.0;    // the Levenberg–Marquardt shift carried between iterations
  bool factored_ = false;   // h_ holds its own factor at shift 0
};

// Collinear-capable data: an open curve whose discs a straight line passes through in order
// has a least-energy curve of energy 0, that line (for the bases with E_1(0, 0) = 0: all but
// cond-G2 with λ ≠ 1, whose straight pieces still cost 6(λ−1)²/L). The optimizer only
// approached it, the energy falling a few percent per step. Returns the positions on the line,
// or nothing when no such line exists or the node model constrains the directions.
std::optional<std::vector<Point>> straight_line(const Problem& pb) {
  const std::size_t n = pb.node.size();
  if (pb.closed || n < 2 || basic_energy(pb.m, 0.0, 0.0).e != 0.0) return std::nullopt;
  for (const Slot& sl : pb.slot) {
    if (sl.fixed) return std::nullopt;
  }
  for (const Node& nd : pb.node) {
    if (nd.corner != 0.0) return std::nullopt;
  }
  double size = 0.0;
  for (const Node& nd : pb.node) size = std::max({size, std::abs(nd.q.x), std::abs(nd.q.y)});
  const double slack = 4.0 * std::numeric_limits<double>::epsilon() * size;
  // The room a line of direction ψ has: the intersection of the discs' strips across it.
  auto room = [&](double psi, double& offset) {
    const Vec2 nrm{-std::sin(psi), std::cos(psi)};
    double lo = -HUGE_VAL, hi = HUGE_VAL;
    for (const Node& nd : pb.node) {
      const double c = dot(nrm, nd.q);
      lo = std::max(lo, c - nd.r);
      hi = std::min(hi, c + nd.r);
    }
    offset = 0.5 * (lo + hi);
    return hi - lo;
  };
  std::vector<std::size_t> fixed;
  for (std::size_t i = 0; i < n; ++i) {
    if (pb.node[i].r == 0.0) fixed.push_back(i);
  }
  const Vec2 span = pb.node[n - 1].q - pb.node[0].q;
  double psi = std::atan2(span.y, span.x), offset = 0.0, best = -HUGE_VAL;
  if (fixed.size() >= 2) {  // two points fix the line
    const Vec2 d = pb.node[fixed.back()].q - pb.node[fixed.front()].q;
    psi = std::atan2(d.y, d.x);
    best = room(psi, offset);
  } else {  // the best direction over a grid, refined by golden sections
    const int grid = 720;
    double at = psi;
    for (int k = 0; k < grid; ++k) {
      const double a = psi + kPi * k / grid, r = room(a, offset);
      if (r > best) best = r, at = a;
    }
    double a = at - kPi / grid, b = at + kPi / grid;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 80; ++it) {
      const double x1 = b - g * (b - a), x2 = a + g * (b - a);
      double o1, o2;
      if (room(x1, o1) > room(x2, o2)) {
        b = x2;
      } else {
        a = x1;
      }
    }
    psi = 0.5 * (a + b);
    best = room(psi, offset);
  }
  if (!(best >= -slack)) return std::nullopt;
  // Along the line, in the curve's order: each disc meets it in an interval; positions strictly
  // increasing, each as near its centre's projection as the order allows.
  Vec2 u{std::cos(psi), std::sin(psi)};
  if (dot(u, span) < 0.0) u = -1.0 * u;
  const Vec2 nrm{-u.y, u.x};
  const double c = dot(nrm, Vec2{-std::sin(psi), std::cos(psi)}) * offset;
  std::vector<Point> p(n);
  double last = -HUGE_VAL;
  for (std::size_t i = 0; i < n; ++i) {
    const Node& nd = pb.node[i];
    const double d = dot(nrm, nd.q) - c, t = dot(u, nd.q);
    const double h = std::sqrt(std::max(0.0, nd.r * nd.r - d * d));
    const double lo = std::max(t - h, last), hi = t + h;
    if (nd.r == 0.0 ? !(t > last) : !(lo < hi)) return std::nullopt;
    const double at = nd.r == 0.0 ? t : std::clamp(t, std::nextafter(lo, hi), hi);
    p[i] = nd.r == 0.0 ? nd.q : c * nrm + at * u;
    if (nd.r > 0.0 && distance(p[i], nd.q) > nd.r) {
      p[i] = nd.q + (nd.r / distance(p[i], nd.q)) * (p[i] - nd.q);
    }
    last = dot(u, p[i]);
  }
  return p;
}

}  // namespace

// The optimizer's phases on pb from its current point: the barrier phase (only from the
// interpolation's start), the cross-over, the exact phase, and saddle escapes.
Outcome solve(Problem& pb, State& st, const MinEnergyOptions& options, bool barrier) {
  // Spans the elastic interpolation left on a ridge start locked on it.
  for (std::size_t s = 0; s < pb.spans() && pb.m.basis == MinEnergyBasis::kElastic; ++s) {
    const auto [al, be] = end_angles(pb, st, s);
    if (!holding(pb, s) && std::abs(al - be) <= kOnRidge &&
        detail::elastica_ridge_capable(al, be)) {
      tie_ridge(pb, st, s, true);
    }
  }
  Solver solver(pb, st, options);
  Outcome res;
  if (barrier) {
    res = solver.barrier_phase();
    solver.cross_over();
  } else {
    solver.measure_scales();  // the held barriers' weights
  }
  Outcome exact = solver.run(0.0, detail::iteration_limit(options), solver.tol);
  // A stationary point where a span's E_1 is concave may be a saddle (by symmetry: a straight
  // span between free ends for cond-G2 with λ > 3/2): leave it downhill, go on.
  for (int k = 0; k < 8 && exact.converged && solver.escape(); ++k) {
    const Outcome more = solver.run(0.0, detail::iteration_limit(options), solver.tol);
    exact.converged = more.converged;
    exact.stalled = more.stalled;
    exact.residual = more.residual;
    exact.raw = more.raw;
    exact.unresolved = more.unresolved;
    exact.worst = more.worst;
    exact.iterations += more.iterations + 1;
  }
  // A stall short of the tolerance (no step lowers the energy, e.g. an active set that the
  // exact phase keeps releasing and taking back): once more along the barrier's path from
  // here, from a weak barrier (kRestartBarrier), kept if it ends better.
  if (!exact.converged && exact.stalled && exact.residual > kConditioningResidual) {
    const Problem before = pb;
    const State before_st = st;
    const Outcome again_barrier = solver.barrier_phase(kRestartBarrier);
    solver.cross_over();
    Outcome again = solver.run(0.0, detail::iteration_limit(options), solver.tol);
    again.iterations += exact.iterations + again_barrier.iterations;
    if (again.converged || again.residual < exact.residual) {
      exact = again;
    } else {
      pb = before;
      st = before_st;
      exact.iterations = again.iterations;
    }
  }
  exact.iterations += res.iterations;
  // Converged only to a rounding floor above the tolerance: the precision the data allow.
  exact.floor = solver.floor_above_tolerance();
  if (exact.converged && exact.raw > solver.tolerance())
    exact.converged = false, exact.stalled = true;
  exact.residual = exact.raw;
  return exact;
}

bool has_data_balls(const FitInput& input) {
  return std::any_of(input.radii.begin(), input.radii.end(), [](double r) { return r != 0.0; });
}

namespace {

/// The first ball beside a span of `rep` on its pair bound where a move of 1e-5 of its radius
/// (along its circle, or inwards or outwards where the disc allows) lowers the interpolation's
/// energy by more than `drop`.
std::optional<std::size_t> descent_beside_half_turns(const Problem& pb, const FitInput& at,
                                                     const MinEnergyOptions& options,
                                                     const MinEnergyReport& rep, double drop) {
  for (std::size_t s : rep.active_spans) {
    for (std::size_t i : {s, pb.next(s)}) {
      const Node& nd = pb.node[i];
      if (nd.r == 0.0) continue;
      const Vec2 off = nd.o;
      const double d = norm(off);
      const Vec2 radial = d > 0.0 ? off / d : Vec2{1.0, 0.0};
      const Vec2 along{-radial.y, radial.x};
      const double h = 1e-5 * nd.r;
      for (const Vec2 step : {along, -along, radial, -radial}) {
        FitInput moved = at;
        const Point p = pb.position(i) + h * step;
        if (norm(nd.o + h * step) > nd.r) continue;
        moved.points[i] = p;
        if (i == 0 && moved.points.size() > pb.node.size()) moved.points.back() = p;
        FitResult scratch;
        MinEnergyReport e;
        try {
          fit_min_energy_at(moved, options, ReportLevel::kNone, scratch, &e, nullptr, nullptr);
        } catch (const Error&) {
          continue;
        }
        if (e.energy < rep.energy - drop) return i;
      }
    }
  }
  return std::nullopt;
}

}  // namespace

void fit_data_balls(const FitInput& input, const MinEnergyOptions& options, ReportLevel level,
                    FitResult& out, MinEnergyReport* report) {
  // The elastic spline: first the restricted elastic one (the same energy within |α|, |β| <=
  // 90°), whose optimum is the elastic one's unless a direction is on that box; then, from it,
  // the elastic energy with the box widened to Ω.
  const bool elastic = options.method.basis == MinEnergyBasis::kElastic;
  MinEnergyOptions opt = options;
  if (elastic) {
    opt.method.basis = MinEnergyBasis::kRestrictedElastic;
    opt.method.omega = std::min(
        options.method.omega, BasicCurveMethod::default_omega(MinEnergyBasis::kRestrictedElastic));
  }
  // The interpolation through the centres: the input's checks, the start, the node model.
  SpanDirections dirs;
  MinEnergyOptions start = opt;
  start.best_effort = true;
  try {
    fit_min_energy_at(input, start, ReportLevel::kNone, out, nullptr, nullptr, &dirs);
  } catch (const Error& e) {
    // Centres that turn beyond 2·90° somewhere: the elastic energy from the start.
    if (!elastic || e.code() != ErrorCode::kInfeasible) throw;
    opt = options;
    start = opt;
    start.best_effort = true;
    fit_min_energy_at(input, start, ReportLevel::kNone, out, nullptr, nullptr, &dirs);
  }
  const std::size_t n = out.points.size();
  Problem pb;
  pb.m = opt.method;
  pb.omega = opt.method.omega;
  pb.closed = out.closed;
  pb.node.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Node& nd = pb.node[i];
    nd.q = out.points[i];
    nd.r = i < input.radii.size() ? input.radii[i] : 0.0;
  }
  const std::size_t ns = pb.spans();
  for (std::size_t s = 0; s < ns; ++s) {
    const std::size_t j = pb.next(s);
    const double gap = distance(pb.node[s].q, pb.node[j].q);
    if (!(gap > pb.node[s].r + pb.node[j].r)) {
      throw Error(ErrorCode::kInvalidArgument,
                  "the data balls of points " + std::to_string(s) + " and " + std::to_string(j) +
                      " overlap (centres " + format_number(gap) + " apart, radii " +
                      format_number(pb.node[s].r) + " and " + format_number(pb.node[j].r) +
                      "): neighbouring balls must be apart, so that the curve's points stay "
                      "distinct; make the radii smaller or drop one of the points",
                  s);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const bool has_prev = pb.closed || i > 0, has_next = pb.closed || i + 1 < n;
    double shortest = HUGE_VAL;
    if (has_prev)
      shortest = std::min(shortest, distance(pb.node[i].q, pb.node[i ? i - 1 : n - 1].q));
    if (has_next) shortest = std::min(shortest, distance(pb.node[i].q, pb.node[pb.next(i)].q));
    pb.node[i].scale = shortest;
  }
  // Slots from the node model, started at the interpolation's directions.
  const std::vector<ResolvedNode> nodes = resolve_nodes(input, n);
  for (std::size_t i = 0; i < n; ++i) {
    Node& nd = pb.node[i];
    const ResolvedNode& rn = nodes[i];
    const bool has_prev = pb.closed || i > 0, has_next = pb.closed || i + 1 < n;
    const std::size_t prev = i ? i - 1 : n - 1;
    auto add = [&](bool fixed, Vec2 d) {
      Slot sl;
      sl.fixed = fixed;
      sl.theta = std::atan2(d.y, d.x);
      pb.slot.push_back(sl);
      return static_cast<int>(pb.slot.size() - 1);
    };
    if (has_prev && has_next && !rn.splits()) {
      const bool fixed = rn.state.in == SideState::kClamped || rn.state.out == SideState::kClamped;
      const Vec2 din = dirs[prev][1], dout = dirs[i][0];
      nd.in = nd.out = add(fixed, din);
      nd.corner = std::atan2(cross(din, dout), dot(din, dout));
    } else {
      if (has_prev) nd.in = add(rn.state.in == SideState::kClamped, dirs[prev][1]);
      if (has_next) nd.out = add(rn.state.out == SideState::kClamped, dirs[i][0]);
    }
  }
  for (std::size_t s = 0; s < ns; ++s) {
    const Node& a = pb.node[s];
    const Node& b = pb.node[pb.next(s)];
    Slot& so = pb.slot[a.out];
    so.span[so.nbox] = s;
    so.offset[so.nbox++] = a.in == a.out ? a.corner : 0.0;
    Slot& si = pb.slot[b.in];
    si.span[si.nbox] = s;
    si.offset[si.nbox++] = 0.0;
  }
  follow_short_chords(pb);
  State st;
  chord_angles(pb, st);
  // Directions the interpolation left on a bound start active there.
  for (Slot& sl : pb.slot) {
    if (sl.fixed) continue;
    for (int b = 0; b < sl.nbox; ++b) {
      const double dev = box_deviation(sl, b, st);
      if (std::abs(dev) >= pb.omega - 1e-12) {
        sl.active = b;
        sl.sign = dev > 0 ? 1 : -1;
        break;
      }
    }
  }
  settle(pb, st);

  // Newton over the directions and positions: first with a barrier that keeps the positions
  // inside their discs (no choice of active discs, which took one Newton step per disc), then
  // with the discs the barrier pressed against as constraints (the exact optimum).
  Outcome res;
  if (const std::optional<std::vector<Point>> line = straight_line(pb)) {
    for (std::size_t i = 0; i < n; ++i) {
      Node& nd = pb.node[i];
      nd.o = (*line)[i] - nd.q;
      nd.boundary = nd.r > 0.0 && norm(nd.o) >= nd.r * (1.0 - 1e-9);
    }
    chord_angles(pb, st);
    for (std::size_t i = 0; i < n; ++i) {  // every direction along its chords
      Node& nd = pb.node[i];
      const std::size_t s = i + 1 < n ? i : i - 1;
      for (int k : {nd.in, nd.out}) {
        if (k >= 0) pb.slot[k].theta = st.phi[s], pb.slot[k].active = -1;
      }
    }
    res.converged = true;
    res.residual = 0.0;
  } else {
    res = solve(pb, st, opt, true);
    if (elastic && pb.m.basis != MinEnergyBasis::kElastic && (res.converged || res.stalled) &&
        std::any_of(pb.slot.begin(), pb.slot.end(),
                    [](const Slot& sl) { return sl.active >= 0; })) {
      const int before = res.iterations;
      pb.m = options.method;
      pb.omega = options.method.omega;
      for (Slot& sl : pb.slot) sl.active = -1;
      res = solve(pb, st, options, false);
      res.iterations += before;
    }
  }
  // Beside a near-repeated pair the output's positions, rounded to doubles, turn the pair's
  // chord against the optimizer's (centres and offsets subtracted apart) by up to ~ε|p|/L:
  // 1e-4 rad for a chord of 3e-10 at coordinates near 1e3. The directions the output fits to
  // its chord then differ from the optimum's, and the balls beside the pair are no longer
  // stationary (s41-c1297: a tangential force of 1e-4 at an active ball). The balls at the
  // ends of such chords keep their rounded positions as plain points, and the rest is
  // optimized again for them.
  std::vector<std::pair<std::size_t, Node>> frozen;  // each as it was, for the report
  if (res.converged || stopped_at_precision(res)) {
    std::vector<char> freeze(n, 0);
    for (std::size_t s = 0; s < pb.spans(); ++s) {
      const Vec2 exact = pb.chord(s);
      const Vec2 rounded = pb.position(pb.next(s)) - pb.position(s);
      const double turn = std::abs(std::atan2(cross(exact, rounded), dot(exact, rounded)));
      if (turn > kRoundedChordTurn) freeze[s] = freeze[pb.next(s)] = 1;
    }
    Problem before = pb;
    State before_st = st;
    for (std::size_t i = 0; i < n; ++i) {
      Node& nd = pb.node[i];
      if (!freeze[i] || nd.r == 0.0) continue;
      frozen.emplace_back(i, nd);
      nd.q = pb.position(i);
      nd.o = {0.0, 0.0};
      nd.r = 0.0;
      nd.boundary = false;
    }
    if (!frozen.empty()) {
      chord_angles(pb, st);
      Outcome again;
      if (settle(pb, st)) again = solve(pb, st, options, false);
      // Kept when it converges or stops at the precision limit: the curve is built on the
      // rounded chords, so this is its optimum as far as doubles resolve it (reverted, the
      // output refit turned a 2e-11 chord's directions by 7e-5 rad to follow it: s63-c237).
      // After a first solve that stopped at that limit too, only if no worse.
      if (again.converged ||
          (stopped_at_precision(again) && (res.converged || again.residual <= res.residual))) {
        again.iterations += res.iterations;
        res = again;
      } else {
        pb = std::move(before);
        st = std::move(before_st);
        frozen.clear();
      }
    }
  }
  int iterations = res.iterations;
  bool converged = res.converged;
  bool at_precision = stopped_at_precision(res);
  double residual = res.residual;
  const std::size_t worst = res.worst;
  if (!converged && !at_precision && !options.best_effort) {
    if (!std::isfinite(residual)) {
      throw Error(ErrorCode::kNotConverged,
                  "the data-ball optimizer cannot start: the curve through the centres turns by "
                  "the most its directions allow (2 omega) at a point whose position bounds it; "
                  "give the balls there radius 0 or remove a point",
                  worst);
    }
    if (!elastic) {
      throw Error(ErrorCode::kNotConverged,
                  "the data-ball optimizer stopped after " + std::to_string(iterations) +
                      " iterations with a KKT residual of " + format_number(residual) +
                      " (relative, largest at this point), above the tolerance " +
                      format_number(std::max(options.tolerance, kBallTolerance)),
                  worst);
    }
    // The elastic spline stalled at a kink: the refits below handle its ridges and may settle
    // it (else the stall is reported after them).
  }

  // The curve: the interpolation through the chosen positions, from the optimum's directions.
  // The elastic interpolation handles the energy's ridges, which this Newton does not: where it
  // moves the directions on (a lower energy across a ridge) the positions are no longer
  // stationary, so the ball optimizer goes on from its directions, a few times at most.
  auto optimum_directions = [&] {
    SpanDirections best(ns);
    for (std::size_t s = 0; s < ns; ++s) {
      const Node& a = pb.node[s];
      const Node& b = pb.node[pb.next(s)];
      const double o = pb.slot[a.out].theta + (a.in == a.out ? a.corner : 0.0);
      best[s] = {Vec2{std::cos(o), std::sin(o)},
                 Vec2{std::cos(pb.slot[b.in].theta), std::sin(pb.slot[b.in].theta)}};
    }
    return best;
  };
  FitInput moved = input;
  moved.radii.clear();
  MinEnergyReport rep;
  // The energy of every span turning by a radian: the scale below which energies are rounding.
  double unit_turns = 0.0;
  for (double l : st.len) unit_turns += 1.0 / l;
  // The last solve, if it stopped short (then reported unless a later restart settles).
  bool unsettled = !converged && !at_precision;
  Outcome stall = res;
  for (int round = 0;; ++round) {
    for (std::size_t i = 0; i < n; ++i) moved.points[i] = pb.position(i);
    if (moved.points.size() > n) moved.points[n] = pb.position(0);  // a closed curve's repeat
    const SpanDirections best = optimum_directions();
    const double e_opt = total_energy(pb, st);
    SpanDirections got;
    rep = MinEnergyReport{};
    try {
      fit_min_energy_at(moved, options, level, out, &rep, &best, &got);
    } catch (const Error&) {
      // A warm start the interpolation cannot go on from: its own start (as before warm starts
      // were honoured by the elastic spline), whose errors are the fit's.
      rep = MinEnergyReport{};
      fit_min_energy_at(moved, options, level, out, &rep, nullptr, &got);
    }
    // The directions can have several local minima at the same positions: where the
    // interpolation's own start finds a lower one (what a refit of the result gives), the
    // optimizer goes on from it.
    const MinEnergyReport* target = &rep;
    MinEnergyReport fresh;
    SpanDirections fresh_got;
    try {
      FitResult scratch;
      fit_min_energy_at(moved, options, ReportLevel::kNone, scratch, &fresh, nullptr, &fresh_got);
      if (fresh.energy < rep.energy - kOutputEnergy * (std::abs(rep.energy) + unit_turns)) {
        target = &fresh;
        got = std::move(fresh_got);
      }
    } catch (const Error&) {
      // Not a lower minimum: the optimum's directions are feasible here.
    }
    if (target == &rep && pb.m.basis != MinEnergyBasis::kElastic) break;
    // A span the interpolation puts on its pair bound |α − β| = π: there the two optimizers
    // stop within their tolerances of the bound but apart (up to ~1e-5 rad), so its slots are
    // neither compared nor taken. Unless the interpolation's directions are a lower minimum:
    // then the optimizer goes on from all of them (a mix of the two minima is neither).
    const bool lower = target->energy < e_opt - kOutputEnergy * (std::abs(e_opt) + unit_turns);
    std::vector<char> on_pair(ns, 0);
    for (std::size_t s : target->active_spans) {
      if (s < ns && !lower) on_pair[s] = 1;
    }
    std::vector<char> keep(pb.slot.size(), 0);
    for (std::size_t s = 0; s < ns; ++s) {
      if (!on_pair[s]) continue;
      keep[static_cast<std::size_t>(pb.node[s].out)] = 1;
      keep[static_cast<std::size_t>(pb.node[pb.next(s)].in)] = 1;
    }
    double moved_by = target == &rep ? 0.0 : HUGE_VAL;
    for (std::size_t s = 0; s < ns && s < got.size() && target == &rep; ++s) {
      if (keep[static_cast<std::size_t>(pb.node[s].out)] ||
          keep[static_cast<std::size_t>(pb.node[pb.next(s)].in)]) {
        continue;
      }
      for (int e = 0; e < 2; ++e) {
        moved_by = std::max(moved_by, std::abs(std::atan2(cross(best[s][e], got[s][e]),
                                                          dot(best[s][e], got[s][e]))));
      }
    }
    if (moved_by <= kOutputAgreement) break;
    if (round == kOutputRounds) {
      if (options.best_effort || unsettled) break;
      if (target != &rep) {
        throw Error(ErrorCode::kNotConverged,
                    "the data-ball optimizer did not settle: through its positions the "
                    "interpolation still finds directions of lower energy (" +
                        format_number(target->energy) + " against " + format_number(rep.energy) +
                        ") after " + std::to_string(kOutputRounds) + " restarts from them",
                    0);
      }
      throw Error(ErrorCode::kNotConverged,
                  "the data-ball optimizer did not converge with the elastic spline: its "
                  "directions and the elastic interpolation's through the same positions differ "
                  "by " +
                      format_number(moved_by) + " rad; " + kElasticKinks,
                  0);
    }
    for (Slot& sl : pb.slot) sl.tie = -1;  // the interpolation decides the ridges again
    for (std::size_t i = 0; i < n; ++i) {  // each slot from its side of the interpolation
      const Node& nd = pb.node[i];
      const bool has_prev = pb.closed || i > 0, has_next = pb.closed || i + 1 < n;
      const std::size_t prev = i ? i - 1 : n - 1;
      auto take = [&](int k, Vec2 d) {
        if (k < 0 || pb.slot[k].fixed || keep[static_cast<std::size_t>(k)]) return;
        Slot& sl = pb.slot[k];
        sl.theta += wrap(std::atan2(d.y, d.x) - sl.theta);
        sl.active = -1;
      };
      if (has_prev) take(nd.in, got[prev][1]);
      if (has_next && nd.out != nd.in) take(nd.out, got[i][0]);
    }
    settle(pb, st);
    // After a stall, a restart that settles does so quickly (s47-c172: 6 iterations); one
    // that does not is cut at the stalled solve's own count (a 300-point walk spent 20 s at
    // the cap before reporting the same failure).
    MinEnergyOptions budget = options;
    if (unsettled) {
      budget.max_iterations = std::min(detail::iteration_limit(options),
                                       std::max(stall.iterations, kMinRestartIterations));
    }
    const Outcome more = solve(pb, st, budget, false);
    iterations += more.iterations;
    residual = more.residual;
    converged = more.converged;
    at_precision = stopped_at_precision(more);
    // A restart that stalls (at a kink) may still settle from the next refit's directions;
    // after a stall only full convergence settles it (a stop at the precision limit there
    // was a kink the optimizer sat on: s63-c14 then read a force of 0.8 off its curve).
    if (!converged && (!at_precision || unsettled)) {
      if (!at_precision) stall = more;
      unsettled = true;
    } else {
      unsettled = false;
    }
  }
  if (unsettled && !options.best_effort) {
    if (!elastic) {
      throw Error(ErrorCode::kNotConverged,
                  "the data-ball optimizer stopped with a KKT residual of " +
                      format_number(stall.residual) +
                      " (relative, largest at this point) after restarting from the "
                      "interpolation's directions of lower energy",
                  stall.worst);
    }
    throw Error(ErrorCode::kNotConverged,
                "the data-ball optimizer did not converge with the elastic spline (KKT "
                "residual " +
                    format_number(stall.residual) + ", largest at this point): " + kElasticKinks,
                stall.worst);
  }
  // A ball beside a span on its pair bound (a half turn) is where the optimizer's barrier and
  // the interpolation's active bound part: its stationarity is checked on the interpolation
  // itself, by small moves within the ball.
  if (pb.m.basis == MinEnergyBasis::kElastic && converged && !options.best_effort) {
    if (const std::optional<std::size_t> at = descent_beside_half_turns(
            pb, moved, options, rep, kOutputEnergy * 10.0 * (std::abs(rep.energy) + unit_turns))) {
      throw Error(ErrorCode::kNotConverged,
                  "the data-ball optimizer did not converge with the elastic spline: moving this "
                  "point within its ball lowers the energy, beside a piece on its half-turn "
                  "bound (end directions 180 degrees apart), which the optimizer does not "
                  "handle; the restricted elastic spline fits these balls",
                  *at);
    }
  }
  for (const auto& [i, as] : frozen) {  // balls again, for the report
    pb.node[i].r = as.r;
    pb.node[i].boundary = as.boundary;
  }
  std::vector<std::size_t> active;
  for (std::size_t i = 0; i < n; ++i) {
    if (pb.node[i].r > 0.0 && pb.node[i].boundary) active.push_back(i);
  }
  const char* status = converged      ? "converged"
                       : at_precision ? "conditioning_limit"
                                      : "iteration_limit";
  out.method_report["balls"] = {{"count", std::count_if(pb.node.begin(), pb.node.end(),
                                                        [](const Node& nd) { return nd.r > 0.0; })},
                                {"active", active},
                                {"iterations", iterations},
                                {"kkt_residual", residual},
                                {"status", status}};
  out.method_report["energy"] = rep.energy;
  if (out.solver) {
    out.solver->iterations = iterations + out.solver->iterations;
    out.solver->residual = std::max(residual, out.solver->residual);
    if (!converged) {
      out.solver->status =
          at_precision ? SolverStatus::kConditioningLimit : SolverStatus::kIterationLimit;
    }
  }
  if (report) *report = std::move(rep);
}

}  // namespace fairspline::detail
