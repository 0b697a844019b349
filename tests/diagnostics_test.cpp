// Tests of diagnostics.hpp: regularity certificate (validity against dense sampling), cusp and
// fold detection (fold against a brute-force angular range), self-intersections within and
// between pieces (exact known points, no false positives at joints, invariance under similarity
// transforms), joint jumps with exactly known values, and the Report of hand-built splines.
#include "fairspline/diagnostics.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "fairspline/error.hpp"

namespace fairspline {
namespace {

CubicBezier bez(Point a, Point b, Point c, Point d) {
  return {{a, b, c, d}};
}
/// A straight cubic with evenly spaced control points (uniform speed).
CubicBezier line(Point a, Point b) {
  return bez(a, lerp(a, b, 1.0 / 3.0), lerp(a, b, 2.0 / 3.0), b);
}

const double kArcK = 4.0 / 3.0 * (std::numbers::sqrt2 - 1.0);
const CubicBezier kQuarter = bez({1.0, 0.0}, {1.0, kArcK}, {kArcK, 1.0}, {0.0, 1.0});
const CubicBezier kS = bez({0.0, 0.0}, {1.0, 2.0}, {3.0, -1.0}, {4.0, 1.0});
const CubicBezier kLoop = bez({0.0, 0.0}, {2.0, 1.0}, {-1.0, 1.0}, {1.0, 0.0});
// x' = 3(2u-1)², y' = 3(1-2u): the speed is exactly 0 at u = 1/2 (a genuine cusp).
const CubicBezier kCusp = bez({0.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}, {1.0, 0.0});

Spline make_spline(std::vector<CubicBezier> pieces, bool closed = false) {
  Spline s;
  s.closed = closed;
  for (std::size_t k = 0; k < pieces.size(); ++k)
    s.segments.push_back({pieces[k], double(k), double(k + 1), k});
  return s;
}

/// The unit circle as 4 cubic arcs (closed).
Spline circle() {
  const double k = kArcK;
  return make_spline(
      {bez({1, 0}, {1, k}, {k, 1}, {0, 1}), bez({0, 1}, {-k, 1}, {-1, k}, {-1, 0}),
       bez({-1, 0}, {-1, -k}, {-k, -1}, {0, -1}), bez({0, -1}, {k, -1}, {1, -k}, {1, 0})},
      true);
}

CubicBezier random_cubic() {
  CubicBezier b;
  for (auto& q : b.p)
    q = {*rc::gen::inRange(-100, 101) / 10.0, *rc::gen::inRange(-100, 101) / 10.0};
  return b;
}

double chord_of(const CubicBezier& b) {
  const double c = distance(b.p[0], b.p[3]);
  return c > 0.0 ? c
                 : distance(b.p[0], b.p[1]) + distance(b.p[1], b.p[2]) + distance(b.p[2], b.p[3]);
}

// ---------------------------------------------------------------- regularity certificate

TEST(Diagnostics, CertificateOfACircularArc) {
  const RegularityCertificate c = certify_regularity(kQuarter);
  EXPECT_TRUE(c.regular);
  // By symmetry the slowest point is the middle: |b'(1/2)| / chord.
  EXPECT_NEAR(c.u_at_min, 0.5, 1e-12);
  EXPECT_NEAR(c.speed_min, norm(kQuarter.d1(0.5)) / std::numbers::sqrt2, 1e-14);
  EXPECT_LE(c.speed_lower, c.speed_min);
  EXPECT_GE(c.speed_lower, 0.5 * c.speed_min);  // default certificate_tightness
  // A tighter request subdivides more and gets closer.
  DiagnosticsOptions tight;
  tight.certificate_tightness = 0.99;
  const RegularityCertificate t = certify_regularity(kQuarter, tight);
  EXPECT_TRUE(t.regular);
  EXPECT_GT(t.subdivisions, c.subdivisions);
  EXPECT_GE(t.speed_lower, 0.99 * t.speed_min);
  EXPECT_LE(t.speed_lower, t.speed_min);
}

TEST(Diagnostics, CuspIsNotRegular) {
  ASSERT_EQ(norm(kCusp.d1(0.5)), 0.0);
  const RegularityCertificate c = certify_regularity(kCusp);
  EXPECT_FALSE(c.regular);
  EXPECT_NEAR(c.u_at_min, 0.5, 1e-9);
  EXPECT_LE(c.speed_min, 1e-12);
  EXPECT_EQ(c.speed_lower, 0.0);
  EXPECT_TRUE(has_cusp(kCusp));
  EXPECT_TRUE(has_fold(kCusp));  // the direction reverses at the cusp
  // Moved off the cusp by 1e-3: regular, with a proven positive bound, and no cusp.
  const CubicBezier near = bez({0.0, 0.0}, {1.0, 1.0}, {1e-3, 1.0}, {1.0, 0.0});
  const RegularityCertificate n = certify_regularity(near);
  EXPECT_TRUE(n.regular);
  EXPECT_GT(n.speed_lower, 0.0);
  EXPECT_LE(n.speed_lower, n.speed_min);
  EXPECT_FALSE(has_cusp(near));
  // Demanding more than the minimum speed (0.075% of the chord) fails the certificate.
  DiagnosticsOptions strict;
  strict.min_relative_speed = 1e-2;
  EXPECT_FALSE(certify_regularity(near, strict).regular);
  EXPECT_TRUE(has_cusp(near, strict));
}

TEST(Diagnostics, ZeroLengthHandleIsACuspButNotAFold) {
  const CubicBezier handle = bez({0, 0}, {0, 0}, {1, 1}, {2, 0});
  const RegularityCertificate c = certify_regularity(handle);
  EXPECT_FALSE(c.regular);
  EXPECT_EQ(c.u_at_min, 0.0);
  EXPECT_TRUE(has_cusp(handle));
  EXPECT_FALSE(has_fold(handle));  // directions (1,1) -> (1,-1): a quarter turn
  // A degenerate piece: no speed, not regular, neither cusp nor fold.
  const CubicBezier point = bez({1, 1}, {1, 1}, {1, 1}, {1, 1});
  EXPECT_FALSE(certify_regularity(point).regular);
  EXPECT_FALSE(has_cusp(point));
  EXPECT_FALSE(has_fold(point));
}

RC_GTEST_PROP(Diagnostics, CertificateBoundsAreValid, ()) {
  const CubicBezier b = random_cubic();
  const double chord = chord_of(b);
  RC_PRE(chord > 0.0);
  const RegularityCertificate c = certify_regularity(b);
  double sampled = std::numeric_limits<double>::infinity();
  const int n = 4000;
  for (int i = 0; i <= n; ++i) sampled = std::min(sampled, norm(b.d1(double(i) / n)));
  // Proven lower bound below every sample; the reported minimum is attained and not above them
  // (up to the rounding of evaluating b', 64·eps·|hodograph|).
  const QuadBezier h = b.hodograph();
  const double rounding = 64.0 * std::numeric_limits<double>::epsilon() *
                          std::max({norm(h.p[0]), norm(h.p[1]), norm(h.p[2])});
  RC_ASSERT(c.speed_lower * chord <= sampled + rounding);
  RC_ASSERT(c.speed_lower <= c.speed_min);
  // The minimum comes from the roots of the cubic b'·b'': at a stop of higher order (speed
  // ∝ (u−u0)², e.g. p0 = p2 and p1 = p3) that root is only known to eps^(1/3), so the speed
  // there to eps^(2/3)·|b''|.
  RC_ASSERT(c.speed_min * chord <= sampled + rounding + 1e-10 * (norm(b.d2(0)) + norm(b.d2(1))));
  RC_ASSERT(std::abs(norm(b.d1(c.u_at_min)) / chord - c.speed_min) <= 1e-12 * (1.0 + c.speed_min));
  // Sampling misses the true minimum by O(Δu²·|b''|) only.
  RC_ASSERT(c.speed_min * chord >= sampled - 1e-4 * (1.0 + norm(b.d2(0)) + norm(b.d2(1))));
  RC_ASSERT(c.regular == (c.speed_lower > 1e-9));
  if (c.regular) RC_ASSERT(c.speed_lower >= 0.5 * c.speed_min * (1.0 - 1e-12));
}

// ---------------------------------------------------------------- folds

/// Brute force: range of the unwrapped direction angle of b' over dense samples.
double turning_range(const CubicBezier& b) {
  const int n = 20000;
  double a = angle(b.d1(0.0)), lo = 0.0, hi = 0.0, acc = 0.0;
  Vec2 prev = b.d1(0.0);
  for (int i = 1; i <= n; ++i) {
    const Vec2 v = b.d1(double(i) / n);
    acc += signed_angle(prev, v);
    prev = v;
    lo = std::min(lo, acc);
    hi = std::max(hi, acc);
  }
  (void)a;
  return hi - lo;
}

TEST(Diagnostics, FoldDetection) {
  EXPECT_FALSE(has_fold(kQuarter));  // 90°
  EXPECT_FALSE(has_fold(kS));        // turns right then left, range < 180°
  EXPECT_TRUE(has_fold(kLoop));      // a loop turns through more than 180°
  // A U-turn whose end direction (-2,-0.5) is past the reversal of the start (1,0).
  EXPECT_TRUE(has_fold(bez({0, 0}, {2, 0}, {2, 1}, {0, 0.5})));
  // Exactly antiparallel end tangents: the boundary case counts as a fold (closed half-plane).
  EXPECT_TRUE(has_fold(bez({0, 0}, {1, 0}, {1, 1}, {0, 1})));
  // A U-turn of 170°: not a fold.
  const Vec2 e = from_angle(std::numbers::pi * 170.0 / 180.0);
  EXPECT_FALSE(has_fold(bez({0, 0}, {1, 0}, Point{1, 1} - e, {1, 1})));
  // Straight, monotone: not a fold; straight with a reversal: fold.
  EXPECT_FALSE(has_fold(bez({0, 0}, {0.1, 0.2}, {2.5, 5.0}, {3, 6})));
  EXPECT_TRUE(has_fold(bez({0, 0}, {2, 0}, {-1, 0}, {1, 0})));
  for (const CubicBezier& b : {kQuarter, kS, kLoop})
    EXPECT_EQ(has_fold(b), turning_range(b) >= std::numbers::pi);
}

RC_GTEST_PROP(Diagnostics, FoldAgreesWithBruteForceTurning, ()) {
  const CubicBezier b = random_cubic();
  RC_PRE(chord_of(b) > 0.0);
  RC_PRE(certify_regularity(b).speed_min > 1e-3);  // directions well defined everywhere
  const double range = turning_range(b);
  RC_PRE(std::abs(range - std::numbers::pi) > 1e-3);  // not on the boundary
  RC_ASSERT(has_fold(b) == (range > std::numbers::pi));
}

// ---------------------------------------------------------------- self-intersections

TEST(Diagnostics, LoopWithinOneCubic) {
  // x = 6u(1-u)² - 3u²(1-u) + u³, y = 3u(1-u): symmetric in y, the loop closes at
  // u = (1 ∓ √(3/5))/2 at the point (1/2, 3/10).
  const auto hits = find_self_intersections(make_spline({kLoop}));
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].segment_a, 0u);
  EXPECT_EQ(hits[0].segment_b, 0u);
  EXPECT_NEAR(hits[0].u_a, (1.0 - std::sqrt(0.6)) / 2.0, 1e-12);
  EXPECT_NEAR(hits[0].u_b, (1.0 + std::sqrt(0.6)) / 2.0, 1e-12);
  EXPECT_NEAR(hits[0].point.x, 0.5, 1e-12);
  EXPECT_NEAR(hits[0].point.y, 0.3, 1e-12);
  // No loop in an arc, an S or a cusp (s and t merge there).
  EXPECT_TRUE(find_self_intersections(make_spline({kQuarter})).empty());
  EXPECT_TRUE(find_self_intersections(make_spline({kS})).empty());
  EXPECT_TRUE(find_self_intersections(make_spline({kCusp})).empty());
}

TEST(Diagnostics, ClosedSinglePieceJointIsNotALoop) {
  // A teardrop ends where it starts: as an open curve that is a self-contact, as a closed
  // curve it is the curve's own joint.
  const CubicBezier drop = bez({0, 0}, {2, 2}, {-2, 2}, {0, 0});
  const auto open = find_self_intersections(make_spline({drop}, false));
  ASSERT_EQ(open.size(), 1u);
  EXPECT_NEAR(open[0].u_a, 0.0, 1e-12);
  EXPECT_NEAR(open[0].u_b, 1.0, 1e-12);
  EXPECT_TRUE(find_self_intersections(make_spline({drop}, true)).empty());
}

TEST(Diagnostics, CrossingBetweenPieces) {
  // Pieces 0 and 2 are straight and cross at their midpoints (1, 0).
  const Spline s = make_spline({line({0, 0}, {2, 0}), line({2, 0}, {1, 1}), line({1, 1}, {1, -1})});
  const auto hits = find_self_intersections(s);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].segment_a, 0u);
  EXPECT_EQ(hits[0].segment_b, 2u);
  EXPECT_NEAR(hits[0].u_a, 0.5, 1e-12);
  EXPECT_NEAR(hits[0].u_b, 0.5, 1e-12);
  EXPECT_NEAR(hits[0].point.x, 1.0, 1e-12);
  EXPECT_NEAR(hits[0].point.y, 0.0, 1e-12);
}

TEST(Diagnostics, AdjacentPiecesCrossingAwayFromTheirJoint) {
  // An arch, then a piece that starts above it at the joint and ends below its start.
  const Spline s =
      make_spline({bez({0, 0}, {1, 1}, {2, 1}, {3, 0}), bez({3, 0}, {2, 2}, {1, 2}, {0, -0.5})});
  const auto hits = find_self_intersections(s);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].segment_a, 0u);
  EXPECT_EQ(hits[0].segment_b, 1u);
  EXPECT_LT(hits[0].u_a, 0.5);  // far from the joint (u_a = 1)
  EXPECT_LT(
      distance(s.segments[0].bezier.eval(hits[0].u_a), s.segments[1].bezier.eval(hits[0].u_b)),
      1e-12);
}

TEST(Diagnostics, NoFalsePositivesAtJoints) {
  EXPECT_TRUE(find_self_intersections(circle()).empty());
  // Collinear straight pieces: G1 joints with the two pieces on one line.
  EXPECT_TRUE(find_self_intersections(
                  make_spline({line({0, 0}, {1, 0}), line({1, 0}, {3, 0}), line({3, 0}, {3.5, 0})}))
                  .empty());
  // A right-angle corner and a sharp 170° corner.
  EXPECT_TRUE(
      find_self_intersections(make_spline({line({0, 0}, {1, 0}), line({1, 0}, {1, 1})})).empty());
  const Vec2 back = from_angle(std::numbers::pi * 170.0 / 180.0);
  EXPECT_TRUE(
      find_self_intersections(make_spline({line({0, 0}, {1, 0}), line({1, 0}, Point{1, 0} + back)}))
          .empty());
  // Cusp joints: the second piece leaves back along the first and curves away (tangential
  // contact at the joint only), or retraces part of it (a common segment next to the joint).
  EXPECT_TRUE(find_self_intersections(make_spline({line({0, 0}, {1, 0}),
                                                   bez({1, 0}, {0.5, 0}, {0.3, 0.2}, {0.2, 0.5})}))
                  .empty());
  EXPECT_TRUE(
      find_self_intersections(make_spline({line({0, 0}, {2, 0}), line({2, 0}, {1, 0})})).empty());
  // Two curved pieces leaving their joint in the same direction with different curvatures
  // (found by the similarity property below): within rounding of each other next to the joint,
  // crossing once further out at u = 0.9683 / 0.0483, also after moving far from the origin.
  for (double shift : {0.0, -1000.0 / 7.0}) {
    const Vec2 d{shift, shift};
    const auto hits =
        find_self_intersections(make_spline({bez(Point{-5, -5} + d, Point{-9.5, -9.7} + d,
                                                 Point{-9.9, -9.4} + d, Point{-9.6, -9.7} + d),
                                             bez(Point{-9.6, -9.7} + d, Point{-9.8, -9.5} + d,
                                                 Point{-9.6, -9.6} + d, Point{-10, -10} + d)}));
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_NEAR(hits[0].u_a, 0.968312909918, 1e-9);
    EXPECT_NEAR(hits[0].u_b, 0.048317197860, 1e-9);
  }
  // Zero-length handles at every joint of a smooth wave (p1 = p0, p2 = p3).
  std::vector<CubicBezier> wave;
  for (int i = 0; i < 20; ++i) {
    const Point a{double(i), std::sin(0.7 * i)}, b{double(i + 1), std::sin(0.7 * (i + 1))};
    wave.push_back(bez(a, a, b, b));
  }
  EXPECT_TRUE(find_self_intersections(make_spline(wave)).empty());
  // A degenerate (point) piece between two pieces: its neighbours share the joint.
  EXPECT_TRUE(find_self_intersections(
                  make_spline({line({0, 0}, {1, 0}), bez({1, 0}, {1, 0}, {1, 0}, {1, 0}),
                               line({1, 0}, {1, 1})}))
                  .empty());
  // A closed curve of two pieces shares both ends.
  EXPECT_TRUE(find_self_intersections(make_spline({bez({0, 0}, {1, 1}, {2, 1}, {3, 0}),
                                                   bez({3, 0}, {2, -1}, {1, -1}, {0, 0})},
                                                  true))
                  .empty());
}

TEST(Diagnostics, CrossingAtAJointIsReportedOnce) {
  // Piece 4 passes through the joint of pieces 0 and 1 at (1, 0): found on both, reported once,
  // named by the later piece at u = 0.
  const Spline s = make_spline({line({0, 0}, {1, 0}), line({1, 0}, {2, 0}), line({2, 0}, {2, 1}),
                                line({2, 1}, {1, 1}), line({1, 1}, {1, -1})});
  const auto hits = find_self_intersections(s);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].segment_a, 1u);
  EXPECT_EQ(hits[0].segment_b, 4u);
  EXPECT_EQ(hits[0].u_a, 0.0);
  EXPECT_NEAR(hits[0].u_b, 0.5, 1e-12);
  // A closed curve of two pieces crossing each other once in the middle.
  const auto x = find_self_intersections(make_spline(
      {bez({0, 0}, {1, 1}, {2, -1}, {3, 0}), bez({3, 0}, {2, 1}, {1, -1}, {0, 0})}, true));
  ASSERT_EQ(x.size(), 1u);
  EXPECT_NEAR(x[0].point.x, 1.5, 1e-12);
  EXPECT_NEAR(x[0].point.y, 0.0, 1e-12);
}

TEST(Diagnostics, ManyCrossingsOfASpiralAgainstItsChord) {
  // A spiral of 40 arcs (5 turns) closed by one long straight piece back to the start: the
  // straight piece crosses each turn it passes; count them against the geometry. The spiral
  // r = 1 + θ/(2π) around the origin: the chord from its end (r = 6, θ = 10π) to its start
  // (r = 1, θ = 0) runs along the positive x axis from x = 6 to x = 1 and meets the spiral at
  // r = 2, 3, 4, 5 (θ = 2π k): 4 crossings, plus its two joints (not counted).
  std::vector<CubicBezier> pieces;
  const int n = 40;
  const double dtheta = 10.0 * std::numbers::pi / n;
  auto pt = [](double th) {
    const double r = 1.0 + th / (2.0 * std::numbers::pi);
    return Point{r * std::cos(th), r * std::sin(th)};
  };
  auto der = [](double th) {
    const double r = 1.0 + th / (2.0 * std::numbers::pi), dr = 1.0 / (2.0 * std::numbers::pi);
    return Vec2{dr * std::cos(th) - r * std::sin(th), dr * std::sin(th) + r * std::cos(th)};
  };
  for (int i = 0; i < n; ++i) {
    const double a = i * dtheta, b = (i + 1) * dtheta;
    pieces.push_back(
        bez(pt(a), pt(a) + dtheta / 3.0 * der(a), pt(b) - dtheta / 3.0 * der(b), pt(b)));
  }
  pieces.push_back(line(pt(10.0 * std::numbers::pi), pt(0.0)));
  const auto hits = find_self_intersections(make_spline(pieces, true));
  ASSERT_EQ(hits.size(), 4u);
  for (const Intersection& h : hits) {
    EXPECT_EQ(h.segment_b, static_cast<std::size_t>(n));
    EXPECT_NEAR(h.point.y, 0.0, 1e-9);
    EXPECT_NEAR(h.point.x, std::round(h.point.x), 1e-3);  // the Bézier spiral is approximate
  }
}

// Found by fuzz_fit (tests/fuzz/corpus/fuzz_fit/regression-retracing-min-energy): points going
// back and forth between two places give pieces that coincide along their whole length. Every
// subdivision cell along the shared arc overlapped, so the cells doubled per level and each flat
// pair added a hit that the duplicate merge compared with all others: the full report hung.
// Coinciding pieces now give one intersection standing for the shared arc, at once.
TEST(Diagnostics, PiecesRetracingEachOtherGiveOneIntersectionQuickly) {
  const CubicBezier a = kS, back = kS.reversed();
  for (double size : {1.0, 1e-9, 1e9}) {
    std::vector<CubicBezier> pieces;
    for (const CubicBezier& c : {a, back, a, back, a}) {
      CubicBezier scaled = c;
      for (Point& q : scaled.p) q = size * q + Vec2{1.5, 7.5};
      pieces.push_back(scaled);
    }
    const auto hits = find_self_intersections(make_spline(pieces));
    // Pairs (0,2), (0,4), (2,4), (1,3) coincide; adjacent pieces share their joints only.
    EXPECT_GE(hits.size(), 4u) << size;
    EXPECT_LE(hits.size(), 10u) << size;
    for (const Intersection& h : hits) {
      EXPECT_LT(h.segment_a, h.segment_b);
      EXPECT_LE(distance(h.point, pieces[h.segment_a].eval(h.u_a)), 1e-6 * size) << size;
    }
  }
}

RC_GTEST_PROP(Diagnostics, IntersectionsAreInvariantUnderSimilarities, ()) {
  // A random open chain of 2-5 regular pieces (degenerate pieces — zero-length handles, straight
  // pieces retracing themselves, pieces ending where they start — make tangential contacts at a
  // joint depend on rounding; they are covered by the example tests above).
  const int n = *rc::gen::inRange(2, 6);
  std::vector<CubicBezier> pieces;
  Point start{*rc::gen::inRange(-50, 51) / 10.0, *rc::gen::inRange(-50, 51) / 10.0};
  for (int k = 0; k < n; ++k) {
    CubicBezier b = random_cubic();
    b.p[0] = start;
    start = b.p[3];
    RC_PRE(certify_regularity(b).regular);
    RC_PRE(distance(b.p[0], b.p[3]) > 0.1);  // not returning onto its own start
    pieces.push_back(b);
  }
  const Spline s = make_spline(pieces);
  const auto hits = find_self_intersections(s);
  for (const Intersection& h : hits) {  // every hit is a genuine contact
    const Point pa = s.segments[h.segment_a].bezier.eval(h.u_a);
    const Point pb = s.segments[h.segment_b].bezier.eval(h.u_b);
    RC_ASSERT(distance(pa, pb) <= 1e-7);
  }
  const double phi = *rc::gen::inRange(0, 628) / 100.0;
  const double scale = *rc::gen::inRange(1, 100) / 10.0;
  const Vec2 shift{*rc::gen::inRange(-1000, 1001) / 7.0, *rc::gen::inRange(-1000, 1001) / 7.0};
  Spline t = s;
  for (Segment& g : t.segments)
    for (Point& q : g.bezier.p) q = scale * rotate(q, phi) + shift;
  const auto moved = find_self_intersections(t);
  RC_ASSERT(moved.size() == hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const Intersection& h = hits[i];
    RC_ASSERT(moved[i].segment_a == h.segment_a);
    RC_ASSERT(moved[i].segment_b == h.segment_b);
    RC_ASSERT(distance(moved[i].point, scale * rotate(h.point, phi) + shift) <=
              1e-6 * (1.0 + scale));
    // Parameters are well conditioned only where the curves cross at an angle (near a
    // tangency they are known to about the square root of the rounding).
    const Vec2 da = s.segments[h.segment_a].bezier.d1(h.u_a),
               db = s.segments[h.segment_b].bezier.d1(h.u_b);
    if (std::abs(cross(da, db)) > 1e-3 * norm(da) * norm(db)) {
      RC_ASSERT(std::abs(moved[i].u_a - h.u_a) <= 1e-6);
      RC_ASSERT(std::abs(moved[i].u_b - h.u_b) <= 1e-6);
    }
  }
}

/// A Catmull–Rom chain through a seeded random walk (turns within ±120°, steps 0.5 to 2):
/// regular pieces that cross each other often, as a fit of such a walk does.
Spline walk_chain(std::uint64_t seed, int n, bool closed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> turn(-2.0 * std::numbers::pi / 3.0,
                                              2.0 * std::numbers::pi / 3.0);
  std::uniform_real_distribution<double> step(0.5, 2.0);
  std::vector<Point> q;
  Point p{0.0, 0.0};
  double heading = 0.0;
  for (int i = 0; i < n; ++i) {
    q.push_back(p);
    heading += turn(rng);
    p = p + step(rng) * from_angle(heading);
  }
  const int m = static_cast<int>(q.size());
  auto at = [&](int i) {
    return closed ? q[static_cast<std::size_t>((i + m) % m)]
                  : q[static_cast<std::size_t>(std::clamp(i, 0, m - 1))];
  };
  std::vector<CubicBezier> pieces;
  for (int i = 0; i < (closed ? m : m - 1); ++i)
    pieces.push_back(bez(at(i), at(i) + (at(i + 1) - at(i - 1)) / 6.0,
                         at(i + 1) - (at(i + 2) - at(i)) / 6.0, at(i + 1)));
  return make_spline(pieces, closed);
}

struct PolylineCrossing {
  std::size_t a, b;
  Point point;
  double sin_angle;
};

/// Brute-force reference: every pair of pieces whose control polygons' boxes overlap (the curve
/// lies in them), flattened into `steps` chords each, all chord pairs intersected; crossings at a
/// joint shared by the two pieces are left out.
std::vector<PolylineCrossing> polyline_crossings(const Spline& s, int steps) {
  const std::size_t n = s.segments.size();
  std::vector<std::vector<Point>> poly(n);
  for (std::size_t k = 0; k < n; ++k)
    for (int i = 0; i <= steps; ++i)
      poly[k].push_back(s.segments[k].bezier.eval(double(i) / steps));
  std::vector<PolylineCrossing> out;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a; b < n; ++b) {
      const BBox p = s.segments[a].bezier.control_bbox(), q = s.segments[b].bezier.control_bbox();
      if (p.max.x < q.min.x || q.max.x < p.min.x || p.max.y < q.min.y || q.max.y < p.min.y)
        continue;
      for (std::size_t i = 0; i < static_cast<std::size_t>(steps); ++i)
        for (std::size_t j = (a == b ? i + 2 : 0); j < static_cast<std::size_t>(steps); ++j) {
          const Point p = poly[a][i], q = poly[b][j];
          const Vec2 r = poly[a][i + 1] - p, w = poly[b][j + 1] - q;
          const double den = cross(r, w);
          if (den == 0.0) continue;
          const double u = cross(q - p, w) / den, v = cross(q - p, r) / den;
          if (u < 0.0 || u >= 1.0 || v < 0.0 || v >= 1.0) continue;
          const Point x = p + u * r;
          const bool end_start = b == a + 1 || (s.closed && a == 0 && b == n - 1);
          if (end_start && (distance(x, s.segments[a].bezier.p[3]) < 1e-9 ||
                            distance(x, s.segments[a].bezier.p[0]) < 1e-9))
            continue;
          out.push_back({a, b, x, std::abs(den) / (norm(r) * norm(w))});
        }
    }
  return out;
}

// The search against the brute-force reference on long random walks, open and closed, and with
// a few long chords across the walk among the short pieces (which makes the pair search fall
// back from its grid to a sweep). Every transversal crossing of the flattened pieces away from
// the joints is found within the flattening error, and every hit is a genuine contact.
TEST(Diagnostics, CrossingsOfRandomWalksMatchABruteForceSearch) {
  std::size_t compared = 0;
  for (std::uint64_t seed = 1; seed <= 16; ++seed) {
    Spline s = walk_chain(seed, 100, seed % 3 == 0);
    if (seed % 4 == 1) {  // a star of chords ~30 times the walk's extent across it
      s.closed = false;
      for (int k = 1; k <= 20; ++k)
        s.segments.push_back(
            {line(s.segments.back().bezier.p[3], 300.0 * from_angle(2.8 * k)), 0.0, 1.0, 0});
    }
    const auto hits = find_self_intersections(s);
    const auto reference = polyline_crossings(s, 200);
    // The flattened pieces are within ~|b''|/8·(1/200)² ≈ 4e-5 of the curve.
    constexpr double kNear = 1e-3;
    auto joint_near = [&](Point x) {
      for (const Segment& g : s.segments)
        if (distance(x, g.bezier.p[0]) < kNear || distance(x, g.bezier.p[3]) < kNear) return true;
      return false;
    };
    for (const Intersection& h : hits) {
      const CubicBezier &A = s.segments[h.segment_a].bezier, &B = s.segments[h.segment_b].bezier;
      EXPECT_LE(distance(A.eval(h.u_a), B.eval(h.u_b)), 1e-8) << seed;
      const Vec2 da = A.d1(h.u_a), db = B.d1(h.u_b);
      if (std::abs(cross(da, db)) < 0.05 * norm(da) * norm(db) || joint_near(h.point)) continue;
      const bool found = std::ranges::any_of(reference, [&](const PolylineCrossing& c) {
        return c.a == h.segment_a && c.b == h.segment_b && distance(c.point, h.point) < kNear;
      });
      EXPECT_TRUE(found) << "seed " << seed << ": hit of pieces " << h.segment_a << ", "
                         << h.segment_b << " at (" << h.point.x << ", " << h.point.y << ")";
    }
    for (const PolylineCrossing& c : reference) {
      if (c.sin_angle < 0.05 || joint_near(c.point)) continue;
      ++compared;
      const bool found = std::ranges::any_of(hits, [&](const Intersection& h) {
        return h.segment_a == c.a && h.segment_b == c.b && distance(c.point, h.point) < kNear;
      });
      EXPECT_TRUE(found) << "seed " << seed << ": crossing of pieces " << c.a << ", " << c.b
                         << " at (" << c.point.x << ", " << c.point.y << ") not found";
    }
  }
  EXPECT_GT(compared, 600u);  // the walks cross themselves often enough to mean something
}

// The search scales far-away coordinates by a power of two, which is exact: the same parameters
// and the scaled points, bit for bit.
TEST(Diagnostics, IntersectionsOfAScaledCurveAreTheScaledOnes) {
  const Spline s = walk_chain(7, 100, false);
  const auto hits = find_self_intersections(s);
  ASSERT_GT(hits.size(), 10u);
  for (int ex : {-300, -100, -40, 40, 100, 300}) {
    Spline t = s;
    for (Segment& g : t.segments)
      for (Point& q : g.bezier.p) q = {std::ldexp(q.x, ex), std::ldexp(q.y, ex)};
    const auto moved = find_self_intersections(t);
    ASSERT_EQ(moved.size(), hits.size()) << ex;
    for (std::size_t i = 0; i < hits.size(); ++i) {
      EXPECT_EQ(moved[i].segment_a, hits[i].segment_a) << ex;
      EXPECT_EQ(moved[i].segment_b, hits[i].segment_b) << ex;
      EXPECT_EQ(moved[i].u_a, hits[i].u_a) << ex;
      EXPECT_EQ(moved[i].u_b, hits[i].u_b) << ex;
      EXPECT_EQ(moved[i].point.x, std::ldexp(hits[i].point.x, ex)) << ex;
      EXPECT_EQ(moved[i].point.y, std::ldexp(hits[i].point.y, ex)) << ex;
    }
  }
}

// ---------------------------------------------------------------- joints

TEST(Diagnostics, TangentAngleJumpIsExact) {
  const Vec2 d30 = from_angle(std::numbers::pi / 6.0);
  const CubicBezier a = line({-1, 0}, {0, 0});
  const CubicBezier b = bez({0, 0}, Point{0, 0} + 0.5 * d30, {1, 1}, {2, 1});
  EXPECT_NEAR(tangent_angle_jump_deg(a, b), 30.0, 1e-12);
  EXPECT_NEAR(tangent_angle_jump_deg(a, line({0, 0}, {1, 0})), 0.0, 1e-12);
  EXPECT_NEAR(tangent_angle_jump_deg(a, line({0, 0}, {-1, 0})), 180.0, 1e-12);
  EXPECT_NEAR(tangent_angle_jump_deg(a, line({0, 0}, {0, -1})), 90.0, 1e-12);
  // Zero-length handles: the next control point gives the direction.
  const CubicBezier a0 = bez({-2, 1}, {-1, 0}, {0, 0}, {0, 0});           // arrives along (1, 0)
  const CubicBezier b0 = bez({0, 0}, {0, 0}, Point{0, 0} + d30, {2, 1});  // leaves along 30°
  EXPECT_NEAR(tangent_angle_jump_deg(a0, b0), 30.0, 1e-12);
  const CubicBezier b00 = bez({0, 0}, {0, 0}, {0, 0}, Point{0, 0} + d30);
  EXPECT_NEAR(tangent_angle_jump_deg(a0, b00), 30.0, 1e-12);
}

TEST(Diagnostics, CurvatureJumpIsExact) {
  // κ(0) = (2/3)·cross(p1-p0, p2-p1)/|p1-p0|³ = (2/3)·cross((1,0),(1,1)) = 2/3.
  const CubicBezier b = bez({0, 0}, {1, 0}, {2, 1}, {3, 3});
  EXPECT_NEAR(curvature_jump(line({-1, 0}, {0, 0}), b), 2.0 / 3.0, 1e-15);
  // Matching curvature (the same arc split in two): no jump.
  const auto [l, r] = kQuarter.split(0.3);
  EXPECT_NEAR(curvature_jump(l, r), 0.0, 1e-12);
  // A zero-speed end on a curved piece: curvature unbounded, reported as the largest double.
  const CubicBezier handle = bez({0, 0}, {0, 0}, {1, 1}, {2, 0});
  EXPECT_EQ(curvature_jump(line({-1, 0}, {0, 0}), handle), std::numeric_limits<double>::max());
  // ... but a straight piece with zero-length handles has curvature 0.
  EXPECT_EQ(curvature_jump(line({-1, 0}, {0, 0}), bez({0, 0}, {0, 0}, {1, 0}, {2, 0})), 0.0);
}

// ---------------------------------------------------------------- report

/// Three pieces through (-3,0), (0,0), (3,1), (6,2): a 30° G1 break at (0,0), a G1 joint with a
/// curvature jump at (3,1). Parameter spans 1, 2, 0.5.
Spline hand_built() {
  const Vec2 d30 = from_angle(std::numbers::pi / 6.0);
  Spline s;
  s.segments.push_back({line({-3, 0}, {0, 0}), 0.0, 1.0, 0});
  s.segments.push_back({bez({0, 0}, Point{0, 0} + d30, {2, 1}, {3, 1}), 1.0, 3.0, 1});
  s.segments.push_back({bez({3, 1}, {4, 1}, {5, 2}, {6, 2}), 3.0, 3.5, 2});
  return s;
}
const std::vector<Point> kHandPoints{{-3, 0}, {0, 0}, {3, 1}, {6, 2}};

TEST(Diagnostics, ReportOfAHandBuiltSpline) {
  const Spline s = hand_built();
  // End curvatures from the control points: κ(0) = (2/3) cross(p1-p0, p2-p1)/|p1-p0|³,
  // κ(1) = (2/3) cross(p2-p1, p3-p2)/|p3-p2|³.
  const auto k0 = [](const CubicBezier& b) {
    return 2.0 / 3.0 * cross(b.p[1] - b.p[0], b.p[2] - b.p[1]) / std::pow(norm(b.p[1] - b.p[0]), 3);
  };
  const auto k1 = [](const CubicBezier& b) {
    return 2.0 / 3.0 * cross(b.p[2] - b.p[1], b.p[3] - b.p[2]) / std::pow(norm(b.p[3] - b.p[2]), 3);
  };
  const CubicBezier& b1 = s.segments[1].bezier;
  const CubicBezier& b2 = s.segments[2].bezier;
  const double jump1 = std::abs(k0(b1)), jump2 = std::abs(k1(b1) - k0(b2));
  EXPECT_GT(jump2, 0.1);

  const Report basic = make_report(s, kHandPoints, ReportLevel::kBasic);
  EXPECT_NEAR(basic.max_tangent_angle_jump_deg, 30.0, 1e-12);
  EXPECT_NEAR(basic.max_curvature_jump, std::max(jump1, jump2), 1e-12);
  EXPECT_EQ(basic.max_interpolation_residual, 0.0);
  const double lin = linearized_energy_local(s.segments[0].bezier) / 1.0 +
                     linearized_energy_local(b1) / 8.0 + linearized_energy_local(b2) / 0.125;
  EXPECT_NEAR(basic.linearized_energy, lin, 1e-12 * lin);
  EXPECT_TRUE(basic.regular);
  double lower = 1e300;
  for (const Segment& g : s.segments)
    lower = std::min(lower, certify_regularity(g.bezier).speed_lower);
  EXPECT_EQ(basic.min_relative_speed, lower);
  // The basic level has the bending energy and length (the same numbers as the full one's,
  // checked below), not the curvature variation.
  ASSERT_TRUE(basic.bending_energy.has_value());
  ASSERT_TRUE(basic.length.has_value());
  EXPECT_FALSE(basic.curvature_variation_energy.has_value());
  EXPECT_TRUE(basic.segments.empty());
  EXPECT_FALSE(basic.energy_singular);

  const Report full = make_report(s, kHandPoints, ReportLevel::kFull);
  EXPECT_EQ(full.linearized_energy, basic.linearized_energy);
  EXPECT_EQ(full.max_tangent_angle_jump_deg, basic.max_tangent_angle_jump_deg);
  ASSERT_TRUE(full.bending_energy && full.length && full.curvature_variation_energy);
  double bend = 0.0, len = 0.0, cv = 0.0;
  ASSERT_EQ(full.segments.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const CubicBezier& b = s.segments[k].bezier;
    const double dt = s.segments[k].t1 - s.segments[k].t0;
    const SegmentReport& r = full.segments[k];
    EXPECT_NEAR(r.bending_energy, bending_energy(b).value, 1e-9 * (1.0 + r.bending_energy));
    EXPECT_NEAR(r.length, arc_length(b).value, 1e-9 * r.length);
    EXPECT_NEAR(r.curvature_variation_energy, curvature_variation_energy(b).value,
                1e-9 * (1.0 + r.curvature_variation_energy));
    EXPECT_DOUBLE_EQ(r.linearized_energy, linearized_energy(b, dt));
    EXPECT_TRUE(r.regular);
    EXPECT_EQ(r.min_relative_speed, certify_regularity(b).speed_lower);
    EXPECT_FALSE(r.has_loop || r.has_cusp || r.has_fold);
    bend += r.bending_energy;
    len += r.length;
    cv += r.curvature_variation_energy;
  }
  EXPECT_EQ(full.segments[0].bending_energy, 0.0);  // straight
  EXPECT_NEAR(full.segments[0].length, 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(*full.bending_energy, bend);
  EXPECT_EQ(*basic.bending_energy, *full.bending_energy);
  EXPECT_EQ(*basic.length, *full.length);
  EXPECT_DOUBLE_EQ(*full.length, len);
  EXPECT_DOUBLE_EQ(*full.curvature_variation_energy, cv);
  EXPECT_FALSE(full.energy_singular);
  EXPECT_TRUE(full.intersections.empty());

  // A point off the curve shows up as the residual; so does a wrong end point.
  std::vector<Point> moved = kHandPoints;
  moved[2] = {3.0, 1.25};
  EXPECT_DOUBLE_EQ(make_report(s, moved, ReportLevel::kBasic).max_interpolation_residual, 0.25);
  moved = kHandPoints;
  moved[3] = {6.0, 2.5};
  EXPECT_DOUBLE_EQ(make_report(s, moved, ReportLevel::kBasic).max_interpolation_residual, 0.5);
  // None: nothing computed.
  const Report none = make_report(s, kHandPoints, ReportLevel::kNone);
  EXPECT_EQ(none.linearized_energy, 0.0);
}

TEST(Diagnostics, ReportOfAClosedSplineIncludesTheClosingJoint) {
  Spline s = hand_built();
  s.closed = true;
  // Back from (6,2) to (-3,0): leaves G1 along (1,0), swings below the curve and arrives along
  // (-2,4), while the first piece leaves along (1,0): a closing jump of 180° − atan(2).
  s.segments.push_back({bez({6, 2}, {8, 2}, {-1, -4}, {-3, 0}), 3.5, 4.5, 3});
  const double closing = 180.0 - std::atan(2.0) * 180.0 / std::numbers::pi;  // 116.565°
  const Report r = make_report(s, kHandPoints, ReportLevel::kFull);
  EXPECT_NEAR(r.max_tangent_angle_jump_deg, closing, 1e-12);
  EXPECT_EQ(r.max_interpolation_residual, 0.0);
  EXPECT_EQ(r.segments.size(), 4u);
  // It stays away from pieces 0 and 1 (dense sampling with NumPy: distance >= 1.3) and meets
  // pieces 2 and 0 only at the joints: no intersection.
  EXPECT_TRUE(r.intersections.empty());
  // Open, the closing joint does not count.
  s.closed = false;
  std::vector<Point> pts = kHandPoints;
  pts.push_back({-3, 0});
  EXPECT_NEAR(make_report(s, pts, ReportLevel::kBasic).max_tangent_angle_jump_deg, 30.0, 1e-12);
}

TEST(Diagnostics, ReportFlagsCuspsLoopsAndSingularEnergies) {
  const Spline s = make_spline({kLoop, bez(kLoop.p[3], {1.5, 0}, {2, 0}, {2.5, 0}),
                                bez({2.5, 0}, {3.5, 1}, {2.5, 1}, {3.5, 0})});
  const std::vector<Point> pts{kLoop.p[0], kLoop.p[3], {2.5, 0}, {3.5, 0}};
  const Report r = make_report(s, pts, ReportLevel::kFull);
  ASSERT_EQ(r.segments.size(), 3u);
  EXPECT_TRUE(r.segments[0].has_loop);
  EXPECT_TRUE(r.segments[0].has_fold);
  EXPECT_FALSE(r.segments[0].has_cusp);
  EXPECT_TRUE(r.segments[2].has_cusp);  // kCusp's shape: (0,0),(1,1),(0,1),(1,0) shifted
  EXPECT_TRUE(r.segments[2].has_fold);
  EXPECT_FALSE(r.segments[2].regular);
  EXPECT_FALSE(r.regular);
  EXPECT_EQ(r.min_relative_speed, 0.0);
  EXPECT_TRUE(r.energy_singular);
  ASSERT_TRUE(r.bending_energy.has_value());
  EXPECT_TRUE(std::isfinite(*r.bending_energy));
  EXPECT_TRUE(std::isfinite(*r.curvature_variation_energy));
  ASSERT_EQ(r.intersections.size(), 1u);
  EXPECT_EQ(r.intersections[0].segment_a, 0u);
  EXPECT_EQ(r.intersections[0].segment_b, 0u);
}

// Found by fuzz_fit (tests/fuzz/corpus/fuzz_fit/regression-denormal-span): a closed li-strain
// curve whose last point is (5e-324, 5e-324), next to its first point (0, 0), has a piece with a
// denormal chord; its minimum speed relative to that chord overflowed to Inf in the segment
// report. A lower bound that is not finite is reported as 0, as for the whole spline.
TEST(Diagnostics, SegmentSpeedBoundOfADenormalChordIsFinite) {
  const double d = std::numeric_limits<double>::denorm_min();
  const Spline s = make_spline({bez({d, d}, {1, 1}, {-1, 2}, {0, 0})});
  const std::vector<Point> points = {{d, d}, {0, 0}};
  const Report r = make_report(s, points, ReportLevel::kFull);
  ASSERT_EQ(r.segments.size(), 1u);
  EXPECT_TRUE(std::isfinite(r.segments[0].min_relative_speed));
  EXPECT_TRUE(std::isfinite(r.min_relative_speed));
}

TEST(Diagnostics, ReportRejectsBadSplines) {
  Spline s = hand_built();
  s.segments[2].span = 7;
  try {
    make_report(s, kHandPoints, ReportLevel::kBasic);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(e.index(), std::optional<std::size_t>(2));
  }
  s = hand_built();
  s.segments[1].t1 = s.segments[1].t0;
  EXPECT_THROW(make_report(s, kHandPoints, ReportLevel::kBasic), Error);
  s = hand_built();
  s.segments[1].bezier.p[2].x = std::numeric_limits<double>::quiet_NaN();
  try {
    make_report(s, kHandPoints, ReportLevel::kFull);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNonFinite);
    EXPECT_EQ(e.index(), std::optional<std::size_t>(1));
  }
  // An empty spline has an empty report.
  const Report empty = make_report(Spline{}, {}, ReportLevel::kFull);
  EXPECT_EQ(empty.linearized_energy, 0.0);
  EXPECT_TRUE(empty.regular);
  EXPECT_EQ(*empty.length, 0.0);
}

}  // namespace
}  // namespace fairspline
