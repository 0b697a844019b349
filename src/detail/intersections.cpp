#include "detail/intersections.hpp"
#include "detail/numbers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace fairspline::detail {
namespace {

/// Subdivision cells of one pair of pieces before they are taken to coincide along an arc.
constexpr std::size_t kMaxCells = std::size_t{1} << 15;
/// Sub-pieces whose control points are within this fraction of their chord from it may be
/// settled by Newton (when transversal): a few halvings instead of ~15 down to tol.
constexpr double kNearlyStraight = 1.0 / 16.0;
/// Least angle (radians) between the tangent lines of two sub-pieces settled by Newton.
constexpr double kTransversal = 1e-3;
/// Slack, as a fraction of a cell's parameter width, within which a Newton hit is in the cell.
constexpr double kInCell = 1e-6;
/// Cells of one pair after which the Newton settlement and the fat lines are skipped.
constexpr std::size_t kQuickCells = 128;
/// Distinct crossings of two cubics that do not share an arc: at most 3·3 (Bezout).
constexpr std::size_t kMaxCrossings = 9;

bool boxes_overlap(const BBox& a, const BBox& b, double margin) {
  return a.min.x <= b.max.x + margin && b.min.x <= a.max.x + margin &&
         a.min.y <= b.max.y + margin && b.min.y <= a.max.y + margin;
}

// find_self_intersections scales coordinates into 2^±kNormalRange, where squares cannot
// overflow: sqrt(norm2) stands in for the slower hypot.
double length(Vec2 v) {
  return std::sqrt(norm2(v));
}

/// Largest distance of the inner control points from the chord (from p0 when the chord is 0).
double flatness(const CubicBezier& c) {
  const Vec2 d = c.p[3] - c.p[0];
  const double len = length(d);
  if (len == 0.0) return std::max(length(c.p[1] - c.p[0]), length(c.p[2] - c.p[0]));
  return std::max(std::abs(cross(d, c.p[1] - c.p[0])), std::abs(cross(d, c.p[2] - c.p[0]))) / len;
}

/// True when b's control points lie on one side of a's fat line (the band around a's chord
/// holding a's control points) widened by tol: then the convex hulls, and so the pieces, are
/// more than tol apart. Catches slanted pieces whose axis-aligned boxes overlap.
bool fat_line_separates(const CubicBezier& a, const CubicBezier& b, double tol) {
  const Vec2 d = a.p[3] - a.p[0];
  const double len = length(d);
  if (len == 0.0) return false;
  const double d1 = cross(d, a.p[1] - a.p[0]), d2 = cross(d, a.p[2] - a.p[0]);
  const double lo = std::min({0.0, d1, d2}) - tol * len, hi = std::max({0.0, d1, d2}) + tol * len;
  bool below = true, above = true;
  for (const Point& q : b.p) {
    const double e = cross(d, q - a.p[0]);
    below = below && e < lo;
    above = above && e > hi;
  }
  return below || above;
}

/// Angular interval (centre, half width) of the nonzero vectors v[0..n) (the first nonzero one
/// is the reference); `shortest` receives the length of the shortest nonzero vector. Returns 0
/// if all vectors are zero, 1 if the interval is narrower than pi, 2 if wide.
int cone(const Vec2* v, int n, double& centre, double& half, double& shortest) {
  int ref = -1;
  shortest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k)
    if (norm2(v[k]) > 0.0) {
      if (ref < 0) ref = k;
      shortest = std::min(shortest, norm2(v[k]));
    }
  if (ref < 0) return 0;
  shortest = std::sqrt(shortest);
  double lo = 0.0, hi = 0.0;
  for (int k = 0; k < n; ++k) {
    if (norm2(v[k]) == 0.0) continue;
    const double a = signed_angle(v[ref], v[k]);
    lo = std::min(lo, a);
    hi = std::max(hi, a);
  }
  if (hi - lo >= std::numbers::pi) return 2;
  centre = angle(v[ref]) + 0.5 * (lo + hi);
  half = 0.5 * (hi - lo);
  return 1;
}

/// True when the control polygons of a (ending at J when a_ends_at_joint, else starting there)
/// and b (starting at J when b_starts_at_joint, else ending there) lie in cones from J that
/// meet only at J, with a margin for the rounding of the directions (control points of
/// magnitude M are known to about eps·M, so a direction of a vector of length r to eps·M/r):
/// cones touching along a boundary ray are not separated (the pieces may touch there).
bool separated_at_joint(const CubicBezier& a, bool a_ends_at_joint, const CubicBezier& b,
                        bool b_starts_at_joint) {
  const Point j = a_ends_at_joint ? a.p[3] : a.p[0];
  Vec2 va[3], vb[3];
  double magnitude = 0.0;
  for (const CubicBezier* c : {&a, &b})
    for (const Point& q : c->p) magnitude = std::max({magnitude, std::abs(q.x), std::abs(q.y)});
  for (int k = 0; k < 3; ++k) {
    va[k] = (a_ends_at_joint ? a.p[2 - k] : a.p[k + 1]) - j;
    vb[k] = (b_starts_at_joint ? b.p[k + 1] : b.p[2 - k]) - j;
  }
  double ca = 0.0, ha = 0.0, ra = 0.0, cb = 0.0, hb = 0.0, rb = 0.0;
  const int ka = cone(va, 3, ca, ha, ra), kb = cone(vb, 3, cb, hb, rb);
  if (ka == 0 || kb == 0) return true;  // a sub-piece collapsed onto J
  if (ka == 2 || kb == 2) return false;
  const double d = std::abs(std::remainder(ca - cb, 2.0 * std::numbers::pi));
  const double margin = 64.0 * kEps * (1.0 + magnitude / std::min(ra, rb));
  return d > ha + hb + margin;
}

/// Crossing of the chords of a and b at chord parameters (sa, sb), clamped to [0,1]; false when
/// they miss each other by more than 2·tol. Parallel chords give (0.5, 0.5).
bool chords_cross(const CubicBezier& a, const CubicBezier& b, double tol, double& sa, double& sb) {
  const Vec2 r = a.p[3] - a.p[0], w = b.p[3] - b.p[0], q = b.p[0] - a.p[0];
  const double den = cross(r, w);
  const double lr = length(r), lw = length(w);
  sa = sb = 0.5;
  if (!(std::abs(den) > 64.0 * kEps * lr * lw)) return true;
  sa = cross(q, w) / den;
  sb = cross(q, r) / den;
  const double slack_a = lr > 0.0 ? 2.0 * tol / lr : 1.0;
  const double slack_b = lw > 0.0 ? 2.0 * tol / lw : 1.0;
  if (sa < -slack_a || sa > 1.0 + slack_a || sb < -slack_b || sb > 1.0 + slack_b) return false;
  sa = std::clamp(sa, 0.0, 1.0);
  sb = std::clamp(sb, 0.0, 1.0);
  return true;
}

/// True when every tangent of a crosses every tangent of b at more than kTransversal radians,
/// on the same side: cross(a'(s), b'(t)) is a positive combination of the crosses of their
/// hodographs' control vectors, so these all of one sign suffice. Then a and b meet at most
/// once (the chord between two meeting points would be parallel to a tangent of each) and
/// Newton's Jacobian is regular on the whole cell.
bool transversal(const CubicBezier& a, const CubicBezier& b) {
  int sign = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec2 u = a.p[i + 1] - a.p[i];
    const double uu = norm2(u);
    if (uu == 0.0) continue;
    for (int j = 0; j < 3; ++j) {
      const Vec2 v = b.p[j + 1] - b.p[j];
      const double vv = norm2(v);
      if (vv == 0.0) continue;
      const double c = cross(u, v);
      if (!(c * c > kTransversal * kTransversal * uu * vv)) return false;
      const int sg = c > 0.0 ? 1 : -1;
      if (sign != 0 && sg != sign) return false;
      sign = sg;
    }
  }
  return sign != 0;
}

/// Newton on A(s) − B(t) = 0 from (s, t), staying in [0,1]². Returns the final distance.
double newton(const CubicBezier& A, const CubicBezier& B, double& s, double& t) {
  Vec2 f = A.eval(s) - B.eval(t);
  double dist = length(f);
  for (int it = 0; it < 12 && dist > 0.0; ++it) {
    const Vec2 c1 = A.d1(s), c2 = -B.d1(t);
    const double det = cross(c1, c2);
    if (!(std::abs(det) > 64.0 * kEps * std::sqrt(norm2(c1) * norm2(c2)))) break;  // tangential
    const Vec2 r = -f;
    const double ns = std::clamp(s + cross(r, c2) / det, 0.0, 1.0);
    const double nt = std::clamp(t + cross(c1, r) / det, 0.0, 1.0);
    const Vec2 nf = A.eval(ns) - B.eval(nt);
    const double nd = length(nf);
    if (!(nd < dist)) break;
    s = ns;
    t = nt;
    f = nf;
    dist = nd;
  }
  return dist;
}

/// Direction in which c leaves c.p[0]: the first non-vanishing of p1−p0, p2−p0, p3−p0.
Vec2 leaving_direction(const CubicBezier& c) {
  for (int k = 1; k < 4; ++k)
    if (norm2(c.p[k] - c.p[0]) > 0.0) return c.p[k] - c.p[0];
  return {};
}

/// Distance from p to c, by Newton projection started at s (updated; clamped to [0,1]).
double project(const CubicBezier& c, Point p, double& s) {
  for (int it = 0; it < 16; ++it) {
    const Vec2 d = c.eval(s) - p, v = c.d1(s);
    const double g = dot(d, v), h = dot(v, v) + dot(d, c.d2(s));
    if (!(h > 0.0)) break;
    const double ns = std::clamp(s - g / h, 0.0, 1.0);
    if (ns == s) break;
    s = ns;
  }
  return distance(c.eval(s), p);
}

/// l1 and l2 both start at the joint J. The largest t such that l2 stays within `accept` of l1
/// on [0, t] (doubling then bisection from J; the contact zone is connected to J).
double contact_zone(const CubicBezier& l1, const CubicBezier& l2, double accept) {
  double s = 0.0;
  auto near = [&](double t) {
    double guess = s;
    const bool ok = project(l1, l2.eval(t), guess) <= accept;
    if (ok) s = guess;
    return ok;
  };
  double lo = 0.0, hi = std::ldexp(1.0, -40);
  while (hi < 1.0 && near(hi)) {
    lo = hi;
    hi = std::min(1.0, 2.0 * hi);
  }
  if (hi == 1.0 && near(1.0)) return 1.0;
  for (int it = 0; it < 40 && hi - lo > kEps * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (near(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

void intersect_pieces(const CubicBezier& A, const CubicBezier& B, unsigned joints, double tol,
                      int max_depth, IntersectionWorkspace& ws, std::vector<CurveHit>& out) {
  auto& stack = ws.stack;
  auto& hits = ws.hits;
  stack.clear();
  hits.clear();
  if (boxes_overlap(A.control_bbox(), B.control_bbox(), tol))
    stack.push_back({A, B, 0.0, 1.0, 0.0, 1.0, 0});
  const double accept = 4.0 * tol;
  // Pieces that coincide along an arc (a curve retracing itself) meet in a continuum: every cell
  // along the shared arc survives, so their number doubles with each level. The cell budget
  // ends the search there (the test suite's pieces need at most ~3000 cells).
  bool overlap = false;
  std::size_t cells = 0;
  const std::size_t max_cells = kMaxCells >> std::min<std::size_t>(ws.overlaps, 5);
  while (!stack.empty()) {
    if (++cells > max_cells) {
      overlap = true;
      ++ws.overlaps;
      break;
    }
    const IntersectionWorkspace::Cell c = stack.back();
    stack.pop_back();
    const bool end_start = (joints & kEndToStart) && c.a1 == 1.0 && c.b0 == 0.0;
    const bool start_end = (joints & kStartToEnd) && c.a0 == 0.0 && c.b1 == 1.0;
    if (end_start != start_end) {  // exactly one shared joint in this cell
      if (separated_at_joint(c.a, end_start, c.b, end_start)) continue;
      if (c.depth >= max_depth) continue;  // cusp joint: overlap at J is not a crossing
    }
    const double fa = flatness(c.a), fb = flatness(c.b);
    const bool flat_a = fa <= tol, flat_b = fb <= tol;
    const bool has_joint = end_start || start_end;
    const bool last = (flat_a && flat_b && !has_joint) || c.depth >= max_depth;
    // A hit is the Newton solution from the chords' crossing; it counts where the pieces meet
    // within 4·tol, except where Newton slid into a shared joint (not a crossing).
    auto refine = [&](double sa, double sb, double& s, double& t) {
      s = c.a0 + sa * (c.a1 - c.a0);
      t = c.b0 + sb * (c.b1 - c.b0);
      if (!(newton(A, B, s, t) <= accept)) return false;
      const Point p = 0.5 * (A.eval(s) + B.eval(t));
      if (!((joints & kEndToStart) && distance(p, A.p[3]) <= 4.0 * tol && s > 0.5 && t < 0.5) &&
          !((joints & kStartToEnd) && distance(p, A.p[0]) <= 4.0 * tol && s < 0.5 && t > 0.5))
        hits.push_back({s, t, p});
      return true;
    };
    double sa = 0.5, sb = 0.5, s = 0.0, t = 0.0;
    if (last) {
      if (chords_cross(c.a, c.b, tol, sa, sb)) refine(sa, sb, s, t);
      continue;
    }
    // Transversal, nearly straight sub-pieces cross at most once: Newton from the chords'
    // crossing finds that crossing long before the sub-pieces are flat to tol. The hit settles
    // the cell only if it lies in the cell; otherwise the subdivision goes on.
    // A pair past kQuickCells cells is tangential or shares an arc (most pairs need a few
    // dozen): there the two tests below only add to every cell's cost.
    const bool quick = cells <= kQuickCells;
    if (quick && !has_joint && fa <= kNearlyStraight * length(c.a.p[3] - c.a.p[0]) &&
        fb <= kNearlyStraight * length(c.b.p[3] - c.b.p[0]) &&
        chords_cross(c.a, c.b, tol, sa, sb) && transversal(c.a, c.b)) {
      const double ma = kInCell * (c.a1 - c.a0), mb = kInCell * (c.b1 - c.b0);
      const std::size_t before = hits.size();
      if (refine(sa, sb, s, t) && s >= c.a0 - ma && s <= c.a1 + ma && t >= c.b0 - mb &&
          t <= c.b1 + mb)
        continue;
      hits.resize(before);
    }
    if (quick && (fat_line_separates(c.a, c.b, tol) || fat_line_separates(c.b, c.a, tol))) continue;
    // Subdivide the non-flat pieces (both when a joint must be isolated); sub-pairs whose
    // control boxes are apart are not pushed (each half's box computed once).
    const double am = 0.5 * (c.a0 + c.a1), bm = 0.5 * (c.b0 + c.b1);
    const bool split_a = !flat_a || has_joint, split_b = !flat_b || has_joint;
    const auto [a0, a1] = split_a ? c.a.split(0.5) : std::pair{c.a, c.a};
    const auto [b0, b1] = split_b ? c.b.split(0.5) : std::pair{c.b, c.b};
    const BBox ba0 = a0.control_bbox(), ba1 = split_a ? a1.control_bbox() : ba0;
    const BBox bb0 = b0.control_bbox(), bb1 = split_b ? b1.control_bbox() : bb0;
    const int d = c.depth + 1;
    auto push = [&](const CubicBezier& a, const BBox& ba, double u0, double u1,
                    const CubicBezier& b, const BBox& bb, double v0, double v1) {
      if (boxes_overlap(ba, bb, tol))
        stack.push_back({a, b, u0, u1, v0, v1, d});
      else
        ++cells;  // counted as before, when cells were tested after the pop
    };
    if (split_a && split_b) {
      push(a0, ba0, c.a0, am, b0, bb0, c.b0, bm);
      push(a0, ba0, c.a0, am, b1, bb1, bm, c.b1);
      push(a1, ba1, am, c.a1, b0, bb0, c.b0, bm);
      push(a1, ba1, am, c.a1, b1, bb1, bm, c.b1);
    } else if (split_a) {
      push(a0, ba0, c.a0, am, c.b, bb0, c.b0, c.b1);
      push(a1, ba1, am, c.a1, c.b, bb0, c.b0, c.b1);
    } else {
      push(c.a, ba0, c.a0, c.a1, b0, bb0, c.b0, bm);
      push(c.a, ba0, c.a0, c.a1, b1, bb1, bm, c.b1);
    }
  }
  // Pieces leaving a shared joint J into the same half-plane touch tangentially near J (a
  // cusp joint): the hits in that contact zone are the joint, not crossings.
  for (unsigned joint : {unsigned{kEndToStart}, unsigned{kStartToEnd}}) {
    if (!(joints & joint)) continue;
    const bool end_start = joint == kEndToStart;
    const CubicBezier l1 = end_start ? A.reversed() : A;  // both leave J at parameter 0
    const CubicBezier l2 = end_start ? B : B.reversed();
    if (!(dot(leaving_direction(l1), leaving_direction(l2)) > 0.0)) continue;
    const double t_zone = contact_zone(l1, l2, accept);
    const Point j = l2.p[0];
    const double radius = distance(l2.eval(t_zone), j) + accept;
    std::erase_if(hits, [&](const CurveHit& h) {
      const double t = end_start ? h.u_b : 1.0 - h.u_b;
      return t <= t_zone && distance(h.point, j) <= radius;
    });
  }
  // Merge duplicates (neighbouring cells converge to the same point).
  std::sort(hits.begin(), hits.end(),
            [](const CurveHit& x, const CurveHit& y) { return x.u_a < y.u_a; });
  // One point of the plane is one intersection; where B passes it twice (retracing), keep the
  // smaller parameters so the choice does not depend on rounding.
  const std::size_t first = out.size();
  for (const CurveHit& h : hits) {
    bool dup = false;
    for (std::size_t i = first; i < out.size(); ++i)
      if (distance(out[i].point, h.point) <= 16.0 * tol) {
        if (h.u_b < out[i].u_b - 16.0 * kEps) out[i] = h;
        dup = true;
        break;
      }
    if (!dup) out.push_back(h);
    // Two cubics meet in at most 9 points unless they share an arc (Bezout).
    if (out.size() - first > kMaxCrossings) {
      overlap = true;
      break;
    }
  }
  // Coinciding pieces: one intersection stands for the shared arc, the hit of smallest u_a.
  if (overlap) {
    out.resize(first);
    if (!hits.empty()) out.push_back(hits.front());
  }
}

bool self_intersection(const CubicBezier& b, double tol, double& s, double& t) {
  // Power form b(u) = a0 + a1 u + a2 u² + a3 u³; for s ≠ t,
  // (b(s) − b(t))/(s − t) = a1 + a2 σ + a3 (σ² − π) with σ = s + t, π = s t.
  const Vec2 a1 = 3.0 * (b.p[1] - b.p[0]);
  const Vec2 a2 = 3.0 * (b.p[2] - 2.0 * b.p[1] + b.p[0]);
  const Vec2 a3 = b.p[3] - 3.0 * b.p[2] + 3.0 * b.p[1] - b.p[0];
  const double k32 = cross(a3, a2);
  if (!(std::abs(k32) > 64.0 * kEps * norm(a3) * norm(a2))) return false;
  double sigma = -cross(a3, a1) / k32;
  double pi = sigma * sigma + cross(a1, a2) / k32;  // σ² − π = cross(a2,a1)/cross(a3,a2)
  // Polish (σ, π) by Newton on G(σ, π) = a1 + a2 σ + a3 (σ² − π) = 0.
  for (int it = 0; it < 3; ++it) {
    const Vec2 g = a1 + sigma * a2 + (sigma * sigma - pi) * a3;
    const Vec2 js = a2 + 2.0 * sigma * a3, jp = -a3;
    const double det = cross(js, jp);
    if (det == 0.0 || !std::isfinite(det)) break;
    sigma -= cross(g, jp) / det;
    pi -= cross(js, g) / det;
  }
  const double disc = sigma * sigma - 4.0 * pi;
  if (!(disc > 0.0) || !std::isfinite(disc)) return false;
  const double r = std::sqrt(disc);
  // Stable roots of z² − σ z + π.
  const double q = 0.5 * (sigma + std::copysign(r, sigma));
  double z1 = q, z2 = q != 0.0 ? pi / q : 0.0;
  if (z1 > z2) std::swap(z1, z2);
  // Roots a little outside [0,1] (rounding grows with |coordinates| / size) are clamped; the
  // geometric check below decides whether the ends really meet.
  const double slack = 1e-6;
  if (z1 < -slack || z2 > 1.0 + slack) return false;
  s = std::clamp(z1, 0.0, 1.0);
  t = std::clamp(z2, 0.0, 1.0);
  // Reject a cusp (s and t merged: the "loop" has no extent).
  const double extent = distance(b.eval(s), b.eval(0.5 * (s + t)));
  if (!(extent > tol)) return false;
  return distance(b.eval(s), b.eval(t)) <= 4.0 * tol;
}

}  // namespace fairspline::detail
