#include "detail/input.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "detail/finite.hpp"
#include "detail/format.hpp"
#include "detail/huge_pages.hpp"
#include "detail/knots.hpp"
#include "detail/two_threads.hpp"
#include "fairspline/error.hpp"
#include "fairspline/parameterization.hpp"

namespace fairspline::detail {

namespace {
std::string point_text(std::size_t i, Point p) {
  return "point " + std::to_string(i) + " " + format_point(p);
}
}  // namespace

namespace {
// Cheap pre-test for the loop over all points: a difference larger than 4 eps times the sum of
// the coordinates' magnitudes (>= their max) can never be coincident.
inline bool maybe_coincident(Point a, Point b) {
  const double dx = std::abs(a.x - b.x), dy = std::abs(a.y - b.y);
  const double sum = std::abs(a.x) + std::abs(a.y) + std::abs(b.x) + std::abs(b.y);
  return std::max(dx, dy) <= 4.0 * std::numeric_limits<double>::epsilon() * sum;
}
}  // namespace

void check_tangent(Vec2 v, const char* what, std::size_t index) {
  if (!is_finite(v)) {
    throw Error(ErrorCode::kNonFinite, std::string(what) + " is not finite", index);
  }
  if (v.x == 0.0 && v.y == 0.0) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + " is the zero vector", index);
  }
}

namespace {

// The checks of the points, in order, each throwing with the offending index. Run only when
// the fused pass below found something suspicious, so that messages stay exact.
void check_points_slowly(std::span<const Point> pts, std::size_t n, bool closed) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!is_finite(pts[i])) {
      throw Error(ErrorCode::kNonFinite,
                  "point " + std::to_string(i) +
                      " has a NaN or infinite "
                      "coordinate",
                  i);
    }
  }
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (coincident(pts[i], pts[i + 1])) {
      throw Error(ErrorCode::kRepeatedPoint,
                  point_text(i + 1, pts[i + 1]) + " repeats point " + std::to_string(i) +
                      "; remove consecutive duplicates",
                  i + 1);
    }
  }
  if (closed && coincident(pts[n - 1], pts[0])) {
    throw Error(ErrorCode::kRepeatedPoint,
                point_text(n - 1, pts[n - 1]) + " repeats the first point", n - 1);
  }
}

#if defined(__SSE2__)
// The knot intervals of the spans p0 -> p1 and p1 -> p2 at once, for the exponents whose
// |d|^alpha is one or two square roots: span_length<K>'s IEEE operations in two SSE2 lanes (the
// same bits) and half the work of the divide/square-root unit, which bounds this pass. False
// (nothing written) when a squared length is outside safe_norm's plain range.
template <AlphaKind K>
inline bool span_length_pair(Point p0, Point p1, Point p2, double& h0, double& h1) {
  const __m128d dx = _mm_sub_pd(_mm_set_pd(p2.x, p1.x), _mm_set_pd(p1.x, p0.x));
  const __m128d dy = _mm_sub_pd(_mm_set_pd(p2.y, p1.y), _mm_set_pd(p1.y, p0.y));
  const __m128d d2 = _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
  const __m128d in_range =
      _mm_and_pd(_mm_cmpgt_pd(d2, _mm_set1_pd(1e-290)), _mm_cmplt_pd(d2, _mm_set1_pd(1e290)));
  if (_mm_movemask_pd(in_range) != 3) return false;
  __m128d h = _mm_sqrt_pd(d2);
  if constexpr (K == AlphaKind::kCentripetal) h = _mm_sqrt_pd(h);
  h0 = _mm_cvtsd_f64(h);
  h1 = _mm_cvtsd_f64(_mm_unpackhi_pd(h, h));
  return true;
}
#endif

// Points first..last-1 of one pass over the points: finiteness, a cheap repeated-point
// pre-test, the copy into `dst` and (knots given) the alpha knot intervals of their spans.
// Running: knots[i + 1] = t += h_i; else the interval alone, knots[i + 1] = h_i.
struct PassState {
  std::uint64_t bad = 0;
  bool suspect = false;
  double t = 0.0;
};

template <AlphaKind K, bool Running>
void fused_range(std::span<const Point> pts, std::size_t n, std::size_t spans, double alpha,
                 std::size_t first, std::size_t last, Point* dst, double* knots, PassState& st) {
  std::uint64_t bad = 0;
  bool suspect = false;
  double t = st.t;
  auto interval = [&](std::size_t i, double h) {
    if constexpr (Running) {
      t += h;
      knots[i + 1] = t;
    } else {
      knots[i + 1] = h;
    }
  };
  std::size_t i = first;
#if defined(__SSE2__)
  if constexpr (K == AlphaKind::kCentripetal || K == AlphaKind::kChordal) {
    // Two spans per step while neither wraps around; the scalar loop below does the rest.
    for (; knots && i + 2 <= last && i + 2 < n && i + 1 < spans; i += 2) {
      const Point p0 = pts[i], p1 = pts[i + 1], p2 = pts[i + 2];
      bad |= non_finite_bits(p0) | non_finite_bits(p1);
      dst[i] = p0;
      dst[i + 1] = p1;
      suspect |= maybe_coincident(p0, p1);
      suspect |= maybe_coincident(p1, p2);
      double h0, h1;
      if (!span_length_pair<K>(p0, p1, p2, h0, h1)) [[unlikely]] {
        h0 = span_length<K>(p1 - p0, alpha);
        h1 = span_length<K>(p2 - p1, alpha);
      }
      suspect |= !(h0 > 0.0) | !(h1 > 0.0);
      interval(i, h0);
      interval(i + 1, h1);
    }
  }
#endif
  for (; i < last; ++i) {
    const Point p = pts[i];
    bad |= non_finite_bits(p);
    dst[i] = p;
    if (i < spans) {
      const Point q = pts[i + 1 == n ? 0 : i + 1];
      suspect |= maybe_coincident(p, q);
      if (knots) {
        const double h = span_length<K>(q - p, alpha);
        suspect |= !(h > 0.0);
        interval(i, h);
      }
    }
  }
  st.bad |= bad;
  st.suspect |= suspect;
  st.t = t;
}

// One pass over the points: finiteness, a cheap repeated-point pre-test, the copy into
// out.points and (with_knots) the alpha knots. Returns false when a slow check must decide.
// Long inputs: the second half on a helper thread, its knot intervals summed on after the
// first half's (the same additions in the same order, so the same knots).
template <AlphaKind K>
bool fused_pass(std::span<const Point> pts, std::size_t n, bool closed, double alpha,
                bool with_knots, FitResult& out) {
  const std::size_t spans = closed ? n : n - 1;
  resize_huge(out.points, n);
  if (with_knots) resize_huge(out.knots, spans + 1);
  Point* dst = out.points.data();
  double* knots = with_knots ? out.knots.data() : nullptr;
  if (knots) knots[0] = 0.0;
  PassState st;
  if (!split_in_two(n)) {
    fused_range<K, true>(pts, n, spans, alpha, 0, n, dst, knots, st);
  } else {
    const std::size_t mid = (n / 2) & ~std::size_t{1};  // even: the pairs are those of one pass
    PassState second;
    on_two_threads([&](int h) {
      if (h == 0) {
        fused_range<K, true>(pts, n, spans, alpha, 0, mid, dst, knots, st);
      } else {
        fused_range<K, false>(pts, n, spans, alpha, mid, n, dst, knots, second);
      }
    });
    st.bad |= second.bad;
    st.suspect |= second.suspect;
    if (knots) {
      double t = st.t;
      for (std::size_t i = mid; i < spans; ++i) knots[i + 1] = t += knots[i + 1];
      st.t = t;
    }
  }
  if (knots) st.bad |= non_finite_bits(st.t);
  return st.bad == 0 && !st.suspect;
}

}  // namespace

void check_radii(const FitInput& input, std::size_t n) {
  const std::vector<double>& r = input.radii;
  if (!r.empty() && r.size() != input.points.size() && r.size() != n) {
    throw Error(ErrorCode::kInvalidArgument, "radii has " + std::to_string(r.size()) +
                                                 " entries but there are " + std::to_string(n) +
                                                 " points");
  }
  for (std::size_t i = 0; i < std::min(r.size(), n); ++i) {
    if (!std::isfinite(r[i])) {
      throw Error(ErrorCode::kNonFinite,
                  "the data-ball radius of point " + std::to_string(i) + " is not finite", i);
    }
    if (r[i] < 0.0) {
      throw Error(ErrorCode::kInvalidArgument,
                  "the data-ball radius of point " + std::to_string(i) + " is negative (" +
                      format_number(r[i]) + "); a radius is 0 (pass through the point) or more",
                  i);
    }
  }
}

namespace {

// The checks of what a method accepts, after the points, knots and tangents are known good.
void check_capabilities(const FitInput& input, const Capabilities& caps, std::string_view method,
                        std::size_t n, bool count_rule_relaxed) {
  const std::string name(method);
  if (input.closed && !caps.closed) {
    throw Error(ErrorCode::kInvalidArgument,
                name +
                    " interpolates open curves only; give an open curve or use a method that "
                    "closes curves");
  }
  const std::size_t step = caps.points.step;
  if (!input.closed && step > 1 && !count_rule_relaxed && (n - 1) % step != 0) {
    const std::size_t rest = (n - 1) % step;
    std::string s = std::to_string(step);
    throw Error(
        ErrorCode::kWrongPointCount,
        name + " needs " + s + "m+1 points (" + std::to_string(step + 1) + ", " +
            std::to_string(2 * step + 1) + ", " + std::to_string(3 * step + 1) + ", ...); got " +
            std::to_string(n) + ". Drop " + std::to_string(rest) + " point(s)" +
            (caps.points.relaxed_by.empty()
                 ? std::string()
                 : " or set the option " + std::string(caps.points.relaxed_by) + " to " +
                       std::string(caps.points.relaxed_value) +
                       " to finish the remaining span(s) otherwise"),
        n - 1,
        caps.points.relaxed_by.empty()
            ? std::nullopt
            : std::optional<OptionHint>(OptionHint{std::string(caps.points.relaxed_by),
                                                   std::string(caps.points.relaxed_value)}));
  }
  check_radii(input, n);
  for (std::size_t i = 0; i < n && i < input.radii.size() && !caps.data_balls; ++i) {
    if (input.radii[i] > 0.0) {
      throw Error(ErrorCode::kInvalidArgument,
                  "point " + std::to_string(i) + " is a data ball (radius " +
                      format_number(input.radii[i]) + "), but " + name +
                      " interpolates its points; give radius 0 or use a method that fits data "
                      "balls (the min-energy family, restricted-elastic)",
                  i);
    }
  }
  for (std::size_t i = 0; i < std::min(input.kinds.size(), n); ++i) {
    if (!caps.honours(input.kinds[i])) {
      throw Error(ErrorCode::kInvalidArgument,
                  "point " + std::to_string(i) + " is " +
                      (input.kinds[i] == PointKind::kCorner ? "a corner" : "of a kind") + ", but " +
                      name + " builds one " + std::string(continuity_name(caps.continuity)) +
                      " curve through every point; split the input there or use a method that "
                      "honours corners (e.g. min-energy)",
                  i);
    }
  }
  if (caps.tangents == TangentUse::kRequired) {
    for (std::size_t i = 0; i < n; ++i) {
      const bool given = (i < input.tangents.size() && input.tangents[i]) ||
                         (i == 0 && input.start_tangent) ||
                         (i + 1 == n && !input.closed && input.end_tangent);
      if (!given) {
        throw Error(ErrorCode::kInvalidArgument,
                    name + " needs a tangent vector at every point, but point " +
                        std::to_string(i) +
                        " has none: give tangents in the input, or set the option "
                        "tangents_from to a method that chooses directions from points alone "
                        "(e.g. jaklic-zagar)",
                    i, OptionHint{std::string(kTangentsFromOption), ""});
      }
    }
  }
}

}  // namespace

void check_points(const FitInput& input) {
  const std::span<const Point> pts = input.points;
  std::size_t n = pts.size();
  if (input.closed && n >= 2 && coincident(pts[0], pts[n - 1])) --n;
  check_points_slowly(pts, n, input.closed && n >= 2);
}

std::size_t prepare_input(const FitInput& input, const Capabilities& caps, std::string_view method,
                          FitResult& out, bool count_rule_relaxed) {
  const std::string name(method);
  out.closed = input.closed;
  const std::span<const Point> pts = input.points;
  std::size_t n = pts.size();
  // A closed curve given with its first point repeated at the end: drop the duplicate.
  if (input.closed && n >= 2 && coincident(pts[0], pts[n - 1])) --n;
  const std::size_t need = input.closed ? caps.points.min_closed : caps.points.min_open;
  if (n < need) {
    check_points_slowly(pts, 0, false);  // a NaN is the clearer message
    throw Error(ErrorCode::kTooFewPoints,
                name + " needs at least " + std::to_string(need) + " distinct points for " +
                    (input.closed ? "a closed" : "an open") + " curve, got " + std::to_string(n));
  }
  const bool with_knots = input.knots.empty();
  const bool clean = with_alpha_kind(input.alpha, [&](auto kind) {
    return fused_pass<kind.value>(pts, n, input.closed, input.alpha, with_knots, out);
  });
  if (!clean) {
    check_points_slowly(pts, n, input.closed);
    // Points are fine: the knots were the problem (alpha out of range, overflow), or the
    // pre-test was merely cautious. alpha_knots throws the precise error if there is one.
    if (with_knots) alpha_knots(out.points, input.alpha, input.closed, out.knots);
  }
  if (with_knots && !(input.alpha >= 0.0 && input.alpha <= 1.0)) {
    alpha_knots(out.points, input.alpha, input.closed, out.knots);  // throws kBadOption
  }
  if (!input.tangents.empty() && input.tangents.size() != pts.size() &&
      input.tangents.size() != n) {
    throw Error(ErrorCode::kInvalidArgument,
                "tangents has " + std::to_string(input.tangents.size()) +
                    " entries but there are " + std::to_string(n) + " points");
  }
  for (std::size_t i = 0; i < std::min(input.tangents.size(), n); ++i) {
    if (input.tangents[i]) check_tangent(*input.tangents[i], "tangent", i);
  }
  if (!input.kinds.empty() && input.kinds.size() != pts.size() && input.kinds.size() != n) {
    throw Error(ErrorCode::kInvalidArgument, "kinds has " + std::to_string(input.kinds.size()) +
                                                 " entries but there are " + std::to_string(n) +
                                                 " points");
  }
  for (std::size_t i = 0; i < std::min(input.kinds.size(), n); ++i) {
    if (input.kinds[i] == PointKind::kClamped &&
        (i >= input.tangents.size() || !input.tangents[i])) {
      throw Error(ErrorCode::kInvalidArgument,
                  "point " + std::to_string(i) + " is clamped but has no tangent", i);
    }
  }
  if (input.start_tangent) check_tangent(*input.start_tangent, "start tangent", 0);
  if (input.end_tangent) check_tangent(*input.end_tangent, "end tangent", n - 1);
  if (input.closed && input.end_tangent) {
    throw Error(ErrorCode::kInvalidArgument,
                "a closed curve has no end tangent; clamp a point with kinds/tangents or use the "
                "start tangent");
  }

  if (!with_knots) {
    validate_knots(input.knots, n, input.closed);
    out.knots.assign(input.knots.begin(), input.knots.end());
  }
  check_capabilities(input, caps, method, n, count_rule_relaxed);
  return out.knots.size() - 1;
}

}  // namespace fairspline::detail
