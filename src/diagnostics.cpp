// Diagnostics: regularity certificate, cusps, folds, self-intersections, joint continuity and
// the Report assembled from them. See diagnostics.hpp for the definitions.
#include "fairspline/diagnostics.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "detail/huge_pages.hpp"
#include "detail/intersections.hpp"
#include "detail/normalize.hpp"
#include "detail/numbers.hpp"
#include "detail/quadrature.hpp"
#include "detail/scale.hpp"
#include "fairspline/error.hpp"

namespace fairspline {
namespace {

constexpr double kUnbounded = std::numeric_limits<double>::max();
/// Pieces whose differences of control points are within 2^±kPieceExponent are integrated
/// directly (the curvature-variation integrand holds tenth powers of them).
constexpr int kPieceExponent = 24;
/// Subdivisions of one piece's regularity certificate (ordinary pieces need a few dozen).
constexpr int kMaxCertificateSubdivisions = 4096;

/// The certificate's length scale: the chord, or the control polygon when the piece is closed.
double chord_scale(const CubicBezier& b) {
  const double chord = distance(b.p[0], b.p[3]);
  return chord > 0.0 ? chord : detail::control_polygon_length(b);
}

/// Squared distance from the origin to the segment [a, b] (of a hodograph scaled to unit size,
/// whose squares neither overflow nor underflow: the certificate takes one root per cell).
double origin_segment_distance2(Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double l2 = norm2(d);
  if (l2 == 0.0) return norm2(a);
  const double t = std::clamp(-dot(a, d) / l2, 0.0, 1.0);
  return norm2(a + t * d);
}

/// Squared distance from the origin to the triangle (convex hull) of h0, h1, h2; 0 when it
/// contains it.
double origin_hull_distance2(Vec2 h0, Vec2 h1, Vec2 h2) {
  const double s0 = cross(h1 - h0, -h0), s1 = cross(h2 - h1, -h1), s2 = cross(h0 - h2, -h2);
  const bool pos = s0 > 0.0 || s1 > 0.0 || s2 > 0.0;
  const bool neg = s0 < 0.0 || s1 < 0.0 || s2 < 0.0;
  if (!(pos && neg) && (pos || neg)) return 0.0;  // inside a proper triangle (or on its boundary)
  return std::min({origin_segment_distance2(h0, h1), origin_segment_distance2(h1, h2),
                   origin_segment_distance2(h2, h0)});
}

RegularityCertificate certify(const CubicBezier& b, const DiagnosticsOptions& o,
                              const detail::SpeedMinimum& m) {
  RegularityCertificate c;
  const double chord = chord_scale(b);
  if (!(chord > 0.0)) return c;  // a point: no speed at all
  c.speed_min = m.speed / chord;
  c.u_at_min = m.u;
  // Everything below is relative to the piece's size: work on the hodograph scaled by a power
  // of two (exact), so that the hull tests' cross products neither overflow (a piece 1e289
  // long gave NaN, never accepted: 2^max_depth subdivisions, 1 s per piece; found by fuzz_fit)
  // nor underflow.
  QuadBezier h = b.hodograph();
  const int ex = detail::scale_exponent(h.p);
  for (Vec2& q : h.p) q = detail::scaled(q, -ex);
  const double scale = std::scalbn(chord, -ex), speed = std::scalbn(m.speed, -ex);
  const double threshold = std::max(o.min_relative_speed, 0.0) * scale;
  const double top = std::sqrt(origin_hull_distance2(h.p[0], h.p[1], h.p[2]));
  if (!(speed > threshold)) {
    // A sampled speed is already below the threshold: no certificate can exist.
    c.speed_lower = std::min(top, speed) / scale;
    return c;
  }
  // Depth-first subdivision of the hodograph. A sub-interval is accepted when its hull distance
  // (a lower bound of the speed there) exceeds the threshold and is within `tightness` of the
  // true minimum speed, so speed_lower is both proven and informative.
  const double tight = std::clamp(o.certificate_tightness, 0.0, 1.0) * speed;
  const int max_depth = std::clamp(o.max_depth, 0, 60);
  struct Item {
    QuadBezier h;
    int depth;
  };
  std::array<Item, 64> stack;
  int top_index = 0;
  stack[top_index++] = {h, 0};
  double lower = std::numeric_limits<double>::infinity();
  while (top_index > 0) {
    const Item it = stack[--top_index];
    const double d =
        (it.depth == 0) ? top : std::sqrt(origin_hull_distance2(it.h.p[0], it.h.p[1], it.h.p[2]));
    // The subdivision budget bounds the work where the tightness goal cannot be met (a minimum
    // speed computed with cancellation, found by fuzz_fit: 2^max_depth cells, 0.4 s per piece):
    // the frontier's hull distances are still a proven lower bound, only a looser one.
    if ((d > threshold && d >= tight) || it.depth >= max_depth ||
        c.subdivisions >= kMaxCertificateSubdivisions) {
      lower = std::min(lower, d);
      continue;
    }
    ++c.subdivisions;
    const Vec2 a = 0.5 * (it.h.p[0] + it.h.p[1]), e = 0.5 * (it.h.p[1] + it.h.p[2]);
    const Vec2 mid = 0.5 * (a + e);
    stack[top_index++] = {QuadBezier{{mid, e, it.h.p[2]}}, it.depth + 1};
    stack[top_index++] = {QuadBezier{{it.h.p[0], a, mid}}, it.depth + 1};
  }
  c.speed_lower = std::min(lower, speed) / scale;
  c.regular = lower > threshold;
  return c;
}

/// Zero to within the rounding of the coordinates of b.
bool negligible(Vec2 v, const CubicBezier& b) {
  double magnitude = 0.0;
  for (const Point& q : b.p) magnitude = std::max({magnitude, std::abs(q.x), std::abs(q.y)});
  return norm(v) <= 16.0 * kEps * magnitude;
}

/// 0 ∈ segment [a, b] (a, b antiparallel or one of them zero), to rounding.
bool segment_through_origin(Vec2 a, Vec2 b) {
  return std::abs(cross(a, b)) <= 64.0 * kEps * norm(a) * norm(b) && dot(a, b) <= 0.0;
}

bool fold(const CubicBezier& b, const detail::SpeedMinimum& m, double threshold) {
  const QuadBezier hq = b.hodograph();
  const Vec2 h0 = hq.p[0], h1 = hq.p[1], h2 = hq.p[2];
  if (!(m.speed > threshold)) {
    if (m.u > 0.0 && m.u < 1.0) return true;  // interior stop: the direction reverses
    const bool z0 = norm(h0) <= threshold, z2 = norm(h2) <= threshold;
    if (z0 && z2) return false;  // h = 2u(1-u)h1: one direction
    // Zero speed at an end: the directions are those of h(u)/u = 2(1-u)h1 + u h2 (or mirrored).
    return z0 ? segment_through_origin(2.0 * h1, h2) : segment_through_origin(h0, 2.0 * h1);
  }
  // Regular piece: the directions fit in an open half-plane iff the origin is outside the convex
  // hull of the hodograph arc, i.e. outside the parabolic segment between the arc and its chord:
  // barycentric coordinates λ_i = c_i / Σc of the origin in (h0,h1,h2), inside iff all λ ≥ 0 and
  // λ1² ≤ 4 λ0 λ2 (the implicit equation of a quadratic Bézier is λ1² = 4 λ0 λ2).
  double c0 = cross(h1, h2), c1 = cross(h2, h0), c2 = cross(h0, h1);
  const double t0 = 16.0 * kEps * norm(h1) * norm(h2), t1 = 16.0 * kEps * norm(h2) * norm(h0),
               t2 = 16.0 * kEps * norm(h0) * norm(h1);
  if (std::abs(c0) <= t0) c0 = 0.0;
  if (std::abs(c1) <= t1) c1 = 0.0;
  if (std::abs(c2) <= t2) c2 = 0.0;
  // All zero: the hodograph lies on a line through the origin and never vanishes, so it keeps
  // one direction.
  if (c0 == 0.0 && c1 == 0.0 && c2 == 0.0) return false;
  const bool pos = c0 > 0.0 || c1 > 0.0 || c2 > 0.0, neg = c0 < 0.0 || c1 < 0.0 || c2 < 0.0;
  if (pos && neg) return false;
  return c1 * c1 <= 4.0 * c0 * c2;
}

/// Unit-free tangent direction leaving b at u = 0 (or arriving at u = 1): the first
/// derivative, or the next non-vanishing one (p1−p0, then p2−p0, then p3−p0).
Vec2 start_direction(const CubicBezier& b) {
  for (int k = 1; k < 4; ++k)
    if (!negligible(b.p[k] - b.p[0], b)) return b.p[k] - b.p[0];
  return {};
}
Vec2 end_direction(const CubicBezier& b) {
  for (int k = 2; k >= 0; --k)
    if (!negligible(b.p[3] - b.p[k], b)) return b.p[3] - b.p[k];
  return {};
}

/// Curvature at an end (u = 0 or 1); kUnbounded when the speed vanishes there on a curved piece.
double end_curvature(const CubicBezier& b, double u) {
  const Vec2 v = b.d1(u);
  if (negligible(v, b)) return detail::is_straight(b) ? 0.0 : kUnbounded;
  const double k = b.curvature(u);
  return std::isfinite(k) ? k : kUnbounded;
}

bool finite_bezier(const CubicBezier& b) {
  return is_finite(b.p[0]) && is_finite(b.p[1]) && is_finite(b.p[2]) && is_finite(b.p[3]);
}

/// Coordinates within 2^±kNormalRange (fit()'s rule, detail/normalize.hpp) are reported
/// directly (the curvature-variation integrand holds tenth powers of coordinates). Scaling by a
/// power of two commutes with every rounding, so the scaled path gives the same bits wherever
/// nothing under- or overflows; the threshold only saves the copy.
constexpr int kScaleExponent = detail::kNormalRange;

/// The binary exponent of the largest |coordinate| of the control points when it is beyond
/// 2^±kScaleExponent, else 0 (also for a curve at the origin or not finite).
int far_exponent(const Spline& s) {
  double big = 0.0;
  for (const Segment& g : s.segments)
    for (const Point& p : g.bezier.p) big = std::max({big, std::abs(p.x), std::abs(p.y)});
  if (!(big > 0.0) || !std::isfinite(big) || std::abs(std::ilogb(big)) <= kScaleExponent) return 0;
  return std::ilogb(big);
}

/// s with every control point scaled by 2^ex (exact where nothing under- or overflows).
Spline scaled_spline(const Spline& s, int ex) {
  Spline t = s;
  for (Segment& g : t.segments)
    for (Point& p : g.bezier.p) p = detail::scaled(p, ex);
  return t;
}

/// Runs worker(next) on min(chunks, cores, 8) threads, this one among them; next() hands out
/// each chunk index in [0, chunks) once, then chunks.
template <class Worker>
void on_every_core(std::size_t chunks, Worker&& worker) {
  std::atomic<std::size_t> counter{0};
  auto run = [&] { worker([&] { return counter.fetch_add(1); }); };
  const std::size_t threads =
      std::min<std::size_t>({chunks, std::max(1u, std::thread::hardware_concurrency()), 8});
  std::vector<std::jthread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(run);
  run();
}

/// Largest number of grid cells the boxes may cover, per box, before the pair search falls
/// back to a sweep (boxes of widely spread sizes: a few long pieces beside many short ones).
constexpr double kMaxCoverPerBox = 16.0;
/// Pairs of pieces per chunk of the intersection search (per thread, with its own budget).
constexpr std::size_t kPairChunk = 4096;

/// Calls f(i, j) once for every pair of the boxes box[live[..]] that overlap (closed).
/// A uniform grid with cells of about the median box size holds every box in the cells it
/// covers, and a pair is taken in the one cell holding the low corner of the two boxes' overlap:
/// O(n + pairs) on curves of pieces of similar size, where a sweep along one axis tests every
/// pair overlapping in that axis (~n·sqrt(n) on a long random walk).
template <class F>
void for_each_overlapping_pair(const std::vector<BBox>& box, const std::vector<std::size_t>& live,
                               const BBox& all, F&& f) {
  using Index = std::uint32_t;  // halves the grid's memory
  const double m = static_cast<double>(live.size());
  const double wx = all.max.x - all.min.x, wy = all.max.y - all.min.y;
  std::vector<double> sizes;
  detail::reserve_to_fill(sizes, live.size());
  for (std::size_t k : live)
    sizes.push_back(std::max(box[k].max.x - box[k].min.x, box[k].max.y - box[k].min.y));
  const auto mid = sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2);
  std::nth_element(sizes.begin(), mid, sizes.end());
  double h = *mid;
  if (!(h > 0.0)) h = std::max(wx, wy);
  // At most about 2 cells per box.
  const double cells = (std::floor(wx / h) + 1.0) * (std::floor(wy / h) + 1.0);
  if (cells > 2.0 * m) h *= std::sqrt(cells / (2.0 * m));
  const double nxd = std::floor(wx / h) + 1.0, nyd = std::floor(wy / h) + 1.0;
  bool grid = std::isfinite(nxd * nyd) && h > 0.0 && nxd * nyd <= 4.0 * m + 4.0 &&
              kMaxCoverPerBox * m < static_cast<double>(std::numeric_limits<Index>::max());
  const auto nx = grid ? static_cast<std::size_t>(nxd) : 1,
             ny = grid ? static_cast<std::size_t>(nyd) : 1;
  auto col = [&](double x) {
    return std::min(nx - 1, static_cast<std::size_t>((x - all.min.x) / h));
  };
  auto row = [&](double y) {
    return std::min(ny - 1, static_cast<std::size_t>((y - all.min.y) / h));
  };
  if (grid) {
    double cover = 0.0;
    for (std::size_t k : live)
      cover += static_cast<double>((col(box[k].max.x) - col(box[k].min.x) + 1) *
                                   (row(box[k].max.y) - row(box[k].min.y) + 1));
    grid = cover <= kMaxCoverPerBox * m;
  }
  if (!grid) {
    // Sweep along the longer axis.
    const bool use_x = wx >= wy;
    auto lo = [&](std::size_t k) { return use_x ? box[k].min.x : box[k].min.y; };
    auto hi = [&](std::size_t k) { return use_x ? box[k].max.x : box[k].max.y; };
    std::vector<std::size_t> order = live;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return lo(a) < lo(b); });
    for (std::size_t i = 0; i < order.size(); ++i)
      for (std::size_t j = i + 1; j < order.size() && lo(order[j]) <= hi(order[i]); ++j)
        if (box[order[i]].min.y <= box[order[j]].max.y &&
            box[order[j]].min.y <= box[order[i]].max.y)
          f(order[i], order[j]);
    return;
  }
  // Pieces by cell (counting sort; end[c] ends cell c's run, and is its start after the fill).
  std::vector<Index> end;
  detail::assign_huge(end, nx * ny, Index{0});
  auto for_cells = [&](std::size_t k, auto&& g) {
    for (std::size_t r = row(box[k].min.y), r1 = row(box[k].max.y); r <= r1; ++r)
      for (std::size_t c = col(box[k].min.x), c1 = col(box[k].max.x); c <= c1; ++c) g(r * nx + c);
  };
  for (std::size_t k : live) for_cells(k, [&](std::size_t cell) { ++end[cell]; });
  for (std::size_t c = 1; c < nx * ny; ++c) end[c] += end[c - 1];
  std::vector<Index> items;
  detail::resize_huge(items, end.back());
  for (std::size_t k : live)
    for_cells(k, [&](std::size_t cell) { items[--end[cell]] = static_cast<Index>(k); });
  for (std::size_t cell = 0; cell < nx * ny; ++cell) {
    const std::size_t first = end[cell], last = cell + 1 < nx * ny ? end[cell + 1] : items.size();
    for (std::size_t a = first; a < last; ++a)
      for (std::size_t b = a + 1; b < last; ++b) {
        const BBox &p = box[items[a]], &q = box[items[b]];
        if (!(q.min.x <= p.max.x && p.min.x <= q.max.x && q.min.y <= p.max.y && p.min.y <= q.max.y))
          continue;
        const double cx = std::max(p.min.x, q.min.x), cy = std::max(p.min.y, q.min.y);
        if (row(cy) * nx + col(cx) == cell) f(items[a], items[b]);
      }
  }
}

}  // namespace

RegularityCertificate certify_regularity(const CubicBezier& b, const DiagnosticsOptions& options) {
  return certify(b, options, detail::min_speed(b));
}

bool has_cusp(const CubicBezier& b, const DiagnosticsOptions& options) {
  const double scale = chord_scale(b);
  if (!(scale > 0.0)) return false;
  return !(detail::min_speed(b).speed > std::max(options.min_relative_speed, 0.0) * scale);
}

bool has_fold(const CubicBezier& b, const DiagnosticsOptions& options) {
  const double scale = chord_scale(b);
  if (!(scale > 0.0)) return false;
  return fold(b, detail::min_speed(b), std::max(options.min_relative_speed, 0.0) * scale);
}

double tangent_angle_jump_deg(const CubicBezier& a, const CubicBezier& b) {
  const Vec2 ta = end_direction(a), tb = start_direction(b);
  return std::atan2(std::abs(cross(ta, tb)), dot(ta, tb)) * (180.0 / std::numbers::pi);
}

double curvature_jump(const CubicBezier& a, const CubicBezier& b) {
  const double ka = end_curvature(a, 1.0), kb = end_curvature(b, 0.0);
  if (ka == kUnbounded || kb == kUnbounded) return kUnbounded;
  const double j = std::abs(ka - kb);
  return std::isfinite(j) ? j : kUnbounded;
}

std::vector<Intersection> find_self_intersections(const Spline& s,
                                                  const DiagnosticsOptions& options) {
  // The search squares lengths of sub-pieces: coordinates far from unit size are searched on a
  // copy scaled by a power of two (exact; parameters do not change) and the points scaled back.
  if (const int ex = far_exponent(s); ex != 0) {
    std::vector<Intersection> xs = find_self_intersections(scaled_spline(s, -ex), options);
    for (Intersection& x : xs) x.point = detail::scaled(x.point, ex);
    return xs;
  }
  // Hits with the geometric tolerance they were accepted with (for merging duplicates).
  struct Hit {
    Intersection x;
    double tol;
  };
  std::vector<Hit> result;
  std::vector<Intersection> unique;
  const std::size_t n = s.segments.size();
  if (n == 0) return unique;
  const double rel = std::max(options.intersection_accuracy, 4.0 * kEps);
  const int max_depth = std::clamp(options.intersection_max_depth, 1, 60);

  // Pieces of zero extent are skipped; the pieces around them still share their joint.
  std::vector<double> scale;
  std::vector<std::size_t> live_before;  // number of live pieces before index k
  std::vector<std::size_t> live;
  detail::resize_huge(scale, n);
  detail::assign_huge(live_before, n + 1, std::size_t{0});
  detail::reserve_to_fill(live, n);
  for (std::size_t k = 0; k < n; ++k) {
    if (!finite_bezier(s.segments[k].bezier))
      throw Error(ErrorCode::kNonFinite,
                  "piece " + std::to_string(k) + " has non-finite control points", k);
    scale[k] = detail::control_polygon_length(s.segments[k].bezier);
    live_before[k + 1] = live_before[k] + (scale[k] > 0.0 ? 1 : 0);
    if (scale[k] > 0.0) live.push_back(k);
  }
  if (live.empty()) return unique;
  const std::size_t first_live = live.front(), last_live = live.back();
  const bool single_closed = s.closed && live.size() == 1;

  // 1. Loops within a piece.
  for (std::size_t k : live) {
    const CubicBezier& b = s.segments[k].bezier;
    const double tol = rel * scale[k];
    double u = 0.0, v = 0.0;
    // A straight piece retracing itself is a fold (a degenerate overlap), not a loop.
    if (detail::is_straight(b) || !detail::self_intersection(b, tol, u, v)) continue;
    const Point p = 0.5 * (b.eval(u) + b.eval(v));
    // A single closed piece meets itself at its own joint (u, v) = (0, 1): not a loop.
    if (single_closed && u < 0.5 && v > 0.5 && distance(p, b.p[0]) <= 4.0 * tol) continue;
    result.push_back({{k, k, u, v, p}, tol});
  }

  // 2. Crossings between pieces whose tight boxes overlap.
  std::vector<BBox> box;
  detail::resize_huge(box, n);
  BBox all{{kUnbounded, kUnbounded}, {-kUnbounded, -kUnbounded}};
  for (std::size_t k : live) {
    BBox b = s.segments[k].bezier.bbox();
    const double m = rel * scale[k];
    b.min -= Vec2{m, m};
    b.max += Vec2{m, m};
    box[k] = b;
    all.min = {std::min(all.min.x, b.min.x), std::min(all.min.y, b.min.y)};
    all.max = {std::max(all.max.x, b.max.x), std::max(all.max.y, b.max.y)};
  }
  // The pairs are searched in chunks, each with a workspace of its own (its cell budget
  // halves with each shared arc found in the chunk), on every core: the same bits on any
  // number of threads.
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  // (Mostly each piece with its neighbours and a crossing or two: rarely more than 4 a piece.)
  detail::reserve_huge(pairs, 4 * live.size());
  for_each_overlapping_pair(box, live, all, [&](std::size_t i, std::size_t j) {
    pairs.emplace_back(std::min(i, j), std::max(i, j));
  });
  const std::size_t first_pair_hit = result.size();
  const std::size_t chunks = (pairs.size() + kPairChunk - 1) / kPairChunk;
  std::vector<std::vector<Hit>> found(chunks);
  on_every_core(chunks, [&](auto next) {
    detail::IntersectionWorkspace ws;
    std::vector<detail::CurveHit> hits;
    for (std::size_t c; (c = next()) < chunks;) {
      ws.overlaps = 0;
      for (std::size_t p = c * kPairChunk; p < std::min(pairs.size(), (c + 1) * kPairChunk); ++p) {
        const auto [a, b] = pairs[p];
        unsigned joints = detail::kNoJoint;
        if (live_before[b] - live_before[a + 1] == 0) joints |= detail::kEndToStart;
        if (s.closed && a == first_live && b == last_live) joints |= detail::kStartToEnd;
        hits.clear();
        const double tol = rel * std::max(scale[a], scale[b]);
        detail::intersect_pieces(s.segments[a].bezier, s.segments[b].bezier, joints, tol, max_depth,
                                 ws, hits);
        for (const detail::CurveHit& h : hits)
          found[c].push_back({{a, b, h.u_a, h.u_b, h.point}, tol});
      }
    }
  });
  for (const std::vector<Hit>& f : found) result.insert(result.end(), f.begin(), f.end());

  // 3. A crossing exactly at a joint is found on both pieces of the joint: name it by the later
  //    piece at u = 0, then keep one of each.
  auto next_live = [&](std::size_t k) -> std::size_t {
    for (std::size_t m = k + 1; m < n; ++m)
      if (scale[m] > 0.0) return m;
    return s.closed ? first_live : n;
  };
  for (std::size_t i = first_pair_hit; i < result.size(); ++i) {
    Intersection& x = result[i].x;
    const double tol = result[i].tol;
    auto canon = [&](std::size_t& seg, double& u) {
      const CubicBezier& c = s.segments[seg].bezier;
      if (u <= 0.5 || distance(x.point, c.p[3]) > 4.0 * tol) return;
      const std::size_t nx = next_live(seg);
      if (nx < n && s.segments[nx].bezier.p[0] == c.p[3]) {
        seg = nx;
        u = 0.0;
      }
    };
    canon(x.segment_a, x.u_a);
    canon(x.segment_b, x.u_b);
    if (x.segment_a > x.segment_b) {
      std::swap(x.segment_a, x.segment_b);
      std::swap(x.u_a, x.u_b);
    }
  }
  std::sort(result.begin(), result.end(), [](const Hit& hx, const Hit& hy) {
    const Intersection &x = hx.x, &y = hy.x;
    if (x.segment_a != y.segment_a) return x.segment_a < y.segment_a;
    if (x.segment_b != y.segment_b) return x.segment_b < y.segment_b;
    return x.u_a < y.u_a;
  });
  auto residual = [&](const Intersection& x) {
    return distance(s.segments[x.segment_a].bezier.eval(x.u_a),
                    s.segments[x.segment_b].bezier.eval(x.u_b));
  };
  std::vector<double> unique_tol;
  unique.reserve(result.size());
  unique_tol.reserve(result.size());
  for (const auto& [x, tol] : result) {
    bool dup = false;
    for (std::size_t i = unique.size(); i-- > 0;) {
      const auto it = unique.begin() + static_cast<std::ptrdiff_t>(i);
      if (it->segment_a != x.segment_a || it->segment_b != x.segment_b) break;
      const double t = std::max(tol, unique_tol[i]);
      if (distance(it->point, x.point) <= 16.0 * t) {
        // Representative independent of rounding: the closer contact (an exact root rather than
        // a near miss next to it), else the smaller parameters.
        const double rx = residual(x), ri = residual(*it);
        if (rx < ri - 1e-3 * t ||
            (std::abs(rx - ri) <= 1e-3 * t && x.u_a + x.u_b < it->u_a + it->u_b))
          *it = x;
        dup = true;
        break;
      }
    }
    if (!dup) {
      unique.push_back(x);
      unique_tol.push_back(tol);
    }
  }
  return unique;
}

namespace {

/// A geometric quantity scaled back by 2^ex; one that no double can hold is an Error, not Inf.
/// `size_ex`: the exponent of the size the quantity was computed at (for the message).
double unscale(double v, int ex, int size_ex, const char* what,
               const char* omitted_by = "no report") {
  const double w = std::scalbn(v, ex);
  if (!std::isfinite(w))
    throw Error(ErrorCode::kNonFinite,
                std::string("the ") + what +
                    " of this curve is beyond double precision at the scale of its coordinates "
                    "(pieces about 2^" +
                    std::to_string(size_ex) + " long); rescale the points, or ask for " +
                    omitted_by + ", which omits it");
  return w;
}

/// Bending, curvature-variation energy and length of one piece, in its own units. Pieces far
/// from unit size (1e±300, or 1e-8 next to 1e8 in one curve) are integrated translated to the
/// origin and scaled by a power of two to unit size: the integrands hold fifth and tenth powers
/// of the derivatives, which over- or underflow otherwise. Length scales as size, bending as
/// 1/size, curvature variation as 1/size³.
detail::PieceEnergies piece_energies_in_units(const CubicBezier& b, const EnergyOptions& options,
                                              bool variation,
                                              const detail::SpeedMinimum* known = nullptr) {
  const std::array<Vec2, 3> legs{b.p[1] - b.p[0], b.p[2] - b.p[1], b.p[3] - b.p[2]};
  const int ex = detail::scale_exponent(legs);
  if (std::abs(ex) <= kPieceExponent)
    return detail::piece_energies(b, options, known ? *known : detail::min_speed(b), variation);
  CubicBezier u;
  for (int j = 0; j < 4; ++j) u.p[j] = detail::scaled(b.p[j] - b.p[0], -ex);
  detail::PieceEnergies e = detail::piece_energies(u, options, detail::min_speed(u), variation);
  e.length.value = unscale(e.length.value, ex, ex, "length");
  e.bending.value = unscale(e.bending.value, -ex, ex, "bending energy");
  if (variation) {
    e.curvature_variation.value = unscale(e.curvature_variation.value, -3 * ex, ex,
                                          "curvature-variation energy", "the basic report");
  }
  return e;
}

/// Pieces per unit of the report's work (and of its sums): chunks run on several threads.
constexpr std::size_t kReportChunk = 8192;

/// The report of `s`, whose linearized energies and piece energies are those of `energy_source`
/// (the same pieces and knots at another scale; see make_report).
Report report_of(const Spline& s, const Spline& energy_source, std::span<const Point> points,
                 ReportLevel level, const DiagnosticsOptions& options) {
  Report r;
  if (level == ReportLevel::kNone) return r;
  const bool full = level == ReportLevel::kFull;
  const std::size_t n = s.segments.size();
  r.bending_energy = 0.0;
  r.length = 0.0;
  if (full) {
    r.curvature_variation_energy = 0.0;
    detail::resize_huge(r.segments, n);
  }
  if (n == 0) return r;

  // The pieces in chunks of kReportChunk, summed per chunk and then in order: the same bits
  // on any number of threads. Long curves take several threads (the report is 2-3 times the
  // default fit's time on one).
  struct Partial {
    double linearized = 0.0, bending = 0.0, variation = 0.0, length = 0.0;
    double min_speed = std::numeric_limits<double>::infinity();
    bool regular = true, singular = false;
  };
  auto pieces = [&](std::size_t begin, std::size_t end, Partial& p) {
    for (std::size_t k = begin; k < end; ++k) {
      const Segment& g = s.segments[k];
      const CubicBezier& b = g.bezier;
      if (!finite_bezier(b))
        throw Error(ErrorCode::kNonFinite,
                    "piece " + std::to_string(k) + " has non-finite control points", k);
      const double dt = g.t1 - g.t0;
      if (!(dt > 0.0) || !std::isfinite(dt))
        throw Error(
            ErrorCode::kInvalidArgument,
            "piece " + std::to_string(k) + " spans an empty or non-finite parameter interval", k);
      const double lin = linearized_energy(energy_source.segments[k].bezier, dt);
      p.linearized += lin;
      const detail::SpeedMinimum m = detail::min_speed(b);
      const RegularityCertificate cert = certify(b, options, m);
      p.regular = p.regular && cert.regular;
      p.min_speed = std::min(p.min_speed, cert.speed_lower);
      // min_speed of the same piece when the energies come from it (not a rescaled copy).
      const detail::PieceEnergies e =
          piece_energies_in_units(energy_source.segments[k].bezier, options.energy, full,
                                  &energy_source == &s ? &m : nullptr);
      p.singular = p.singular || e.bending.singular || e.curvature_variation.singular;
      p.bending += e.bending.value;
      p.variation += e.curvature_variation.value;
      p.length += e.length.value;
      if (full) {
        SegmentReport& sr = r.segments[k];
        sr.linearized_energy = lin;
        sr.regular = cert.regular;
        // A lower bound: 0 when none is finite (no accepted sub-interval, or a speed divided
        // by a denormal chord overflowed; found by fuzz_fit), as for the whole spline below.
        sr.min_relative_speed = std::isfinite(cert.speed_lower) ? cert.speed_lower : 0.0;
        const double scale = chord_scale(b);
        const double threshold = std::max(options.min_relative_speed, 0.0) * scale;
        sr.has_cusp = scale > 0.0 && !(m.speed > threshold);
        sr.has_fold = scale > 0.0 && fold(b, m, threshold);
        sr.bending_energy = e.bending.value;
        sr.curvature_variation_energy = e.curvature_variation.value;
        sr.length = e.length.value;
      }
    }
  };
  const std::size_t chunks = (n + kReportChunk - 1) / kReportChunk;
  std::vector<Partial> part(chunks);
  std::vector<std::exception_ptr> failed(chunks);
  // The intersection search runs beside the pieces on long curves (it takes its own chunks of
  // pairs on every core); its result and its error are taken after theirs, as in order.
  std::vector<Intersection> intersections;
  std::exception_ptr intersections_failed;
  auto search = [&] {
    try {
      intersections = find_self_intersections(s, options);
    } catch (...) {
      intersections_failed = std::current_exception();
    }
  };
  const bool beside_pieces = full && chunks > 1 && std::thread::hardware_concurrency() > 1;
  {
    std::jthread beside;
    if (beside_pieces) beside = std::jthread(search);
    on_every_core(chunks, [&](auto next) {
      for (std::size_t c; (c = next()) < chunks;) {
        try {
          pieces(c * kReportChunk, std::min(n, (c + 1) * kReportChunk), part[c]);
        } catch (...) {
          failed[c] = std::current_exception();
        }
      }
    });
  }
  if (full && !beside_pieces) search();
  double min_speed = std::numeric_limits<double>::infinity();
  double bending = 0.0, variation = 0.0, length = 0.0;
  for (std::size_t c = 0; c < chunks; ++c) {
    if (failed[c]) std::rethrow_exception(failed[c]);  // the first piece's error, as in order
    r.linearized_energy += part[c].linearized;
    r.regular = r.regular && part[c].regular;
    r.energy_singular = r.energy_singular || part[c].singular;
    min_speed = std::min(min_speed, part[c].min_speed);
    bending += part[c].bending;
    variation += part[c].variation;
    length += part[c].length;
  }
  r.min_relative_speed = std::isfinite(min_speed) ? min_speed : 0.0;

  // Joints (closed: including last -> first).
  const std::size_t joints = s.closed ? n : n - 1;
  for (std::size_t k = 0; k < joints; ++k) {
    const CubicBezier& a = s.segments[k].bezier;
    const CubicBezier& b = s.segments[(k + 1) % n].bezier;
    r.max_tangent_angle_jump_deg =
        std::max(r.max_tangent_angle_jump_deg, tangent_angle_jump_deg(a, b));
    r.max_curvature_jump = std::max(r.max_curvature_jump, curvature_jump(a, b));
  }

  // Interpolation: the first piece of span i starts at points[i]; an open curve ends at the last.
  if (!points.empty()) {
    std::vector<unsigned char> seen(points.size(), 0);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = s.segments[k].span;
      if (i >= points.size())
        throw Error(ErrorCode::kInvalidArgument,
                    "piece " + std::to_string(k) + " refers to point " + std::to_string(i) +
                        " but there are only " + std::to_string(points.size()) + " points",
                    k);
      if (seen[i]) continue;
      seen[i] = 1;
      r.max_interpolation_residual =
          std::max(r.max_interpolation_residual, distance(s.segments[k].bezier.p[0], points[i]));
    }
    if (!s.closed)
      r.max_interpolation_residual = std::max(
          r.max_interpolation_residual, distance(s.segments.back().bezier.p[3], points.back()));
    if (!std::isfinite(r.max_interpolation_residual))
      throw Error(ErrorCode::kNonFinite, "the points to interpolate are not finite");
  }

  r.bending_energy = bending;
  r.length = length;
  if (full) {
    r.curvature_variation_energy = variation;
    if (intersections_failed) std::rethrow_exception(intersections_failed);
    r.intersections = std::move(intersections);
    for (const Intersection& x : r.intersections)
      if (x.segment_a == x.segment_b) r.segments[x.segment_a].has_loop = true;
  }
  if (!std::isfinite(r.linearized_energy))
    throw Error(ErrorCode::kNonFinite, "the linearized energy of the spline overflows");
  return r;
}

}  // namespace

// Quantities of curves with coordinates near 1e±300 (squares of 1e300 overflow, of 1e-300
// underflow) are computed on a copy scaled by a power of two, which is exact, and scaled back:
// residuals by 2^ex, curvature jumps by 2^-ex; angles, relative speeds and the flags do not
// change with scale. Piece energies and lengths come from the original pieces, each at its own
// scale (piece_energies_in_units), and so does the linearized energy, which depends on the
// knots too (linearized_energy scales internally).
Report make_report(const Spline& s, std::span<const Point> points, ReportLevel level,
                   const DiagnosticsOptions& options) {
  const int ex = far_exponent(s);
  if (ex == 0) return report_of(s, s, points, level, options);
  const Spline unit = scaled_spline(s, -ex);
  std::vector<Point> unit_points(points.begin(), points.end());
  for (Point& p : unit_points) p = detail::scaled(p, -ex);
  Report r = report_of(unit, s, unit_points, level, options);
  // Curvature jumps and residuals come from the scaled copy; piece energies and lengths are
  // already in the input's units (piece_energies_in_units).
  r.max_curvature_jump = unscale(r.max_curvature_jump, -ex, ex, "curvature jump");
  r.max_interpolation_residual =
      unscale(r.max_interpolation_residual, ex, ex, "interpolation residual");
  for (Intersection& x : r.intersections) x.point = detail::scaled(x.point, ex);
  return r;
}

}  // namespace fairspline
