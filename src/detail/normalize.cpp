#include "detail/normalize.hpp"
#include "detail/two_threads.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "detail/finite.hpp"
#include "detail/input.hpp"
#include "detail/scale.hpp"
#include "fairspline/error.hpp"
#include "fairspline/parameterization.hpp"

namespace fairspline::detail {

namespace {

/// x·2^e for a real e: exact when e is an integer (scalbn never overflows in between).
double times_power_of_two(double x, double e) {
  const double whole = std::floor(e);
  const double scaled = std::scalbn(x, static_cast<int>(whole));
  return whole == e ? scaled : scaled * std::exp2(e - whole);
}

void scale_tangent(std::optional<Vec2>& v, double e) {
  if (v) *v = {times_power_of_two(v->x, e), times_power_of_two(v->y, e)};
}

void scale_tangents(std::vector<std::optional<Vec2>>& vs, double e) {
  for (std::optional<Vec2>& v : vs) scale_tangent(v, e);
}

void map_number(nlohmann::json& node, std::span<const std::string_view> keys, double e) {
  if (keys.empty()) {
    if (!node.is_number()) return;
    const double v = times_power_of_two(node.get<double>(), e);
    node = std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    return;
  }
  if (keys.front() == "*") {
    if (!node.is_array()) return;
    for (nlohmann::json& element : node) map_number(element, keys.subspan(1), e);
    return;
  }
  if (!node.is_object()) return;
  const auto it = node.find(keys.front());
  if (it != node.end()) map_number(*it, keys.subspan(1), e);
}

std::vector<std::string_view> split_path(std::string_view path) {
  std::vector<std::string_view> keys;
  while (!path.empty()) {
    const std::size_t slash = path.find('/');
    keys.push_back(path.substr(0, slash));
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash + 1);
  }
  return keys;
}

}  // namespace

std::optional<Normalization> normalization_for(const FitInput& input) {
  // Every fit reads all points here: branch-free, with two running maxima so that the loop is
  // not one serial chain of max operations (NaN never wins a max; it is caught by `bad`). A
  // maximum does not depend on the order, so long inputs are scanned in two halves at once.
  struct Scan {
    double big_x = 0.0, big_y = 0.0;
    std::uint64_t bad = 0;
  };
  auto scan = [](std::span<const Point> pts, Scan& s) {
    for (const Point& p : pts) {
      s.bad |= non_finite_bits(p);
      s.big_x = std::max(s.big_x, std::abs(p.x));
      s.big_y = std::max(s.big_y, std::abs(p.y));
    }
  };
  const std::span<const Point> pts = input.points;
  Scan halves[2];
  if (split_in_two(pts.size())) {
    const std::size_t mid = pts.size() / 2;
    on_two_threads([&](int h) { scan(h == 0 ? pts.first(mid) : pts.subspan(mid), halves[h]); });
  } else {
    scan(pts, halves[0]);
  }
  if (halves[0].bad | halves[1].bad) return std::nullopt;
  const double big = std::max({halves[0].big_x, halves[0].big_y, halves[1].big_x, halves[1].big_y});
  if (!(big > 0.0)) return std::nullopt;
  const int e = std::ilogb(big);
  if (std::abs(e) <= kNormalRange) return std::nullopt;
  Normalization nz;
  nz.length_exponent = e & ~1;  // even: 2^(e/2) is the factor of centripetal knots
  const bool alpha_knots = input.knots.empty() && input.alpha >= 0.0 && input.alpha <= 1.0;
  nz.knot_exponent = alpha_knots ? nz.length_exponent * input.alpha : 0.0;
  return nz;
}

void normalize_input(const FitInput& input, const Normalization& nz, const Capabilities& caps,
                     FitInput& out) {
  check_points(input);
  out = input;
  for (Point& p : out.points) p = scaled(p, -nz.length_exponent);
  for (double& r : out.radii) r = times_power_of_two(r, -nz.length_exponent);
  // A C1 method's tangent is dP/dt: its length scales as the points over the knots.
  if (caps.continuity != Continuity::kC1) return;
  const double e = nz.knot_exponent - nz.length_exponent;
  scale_tangents(out.tangents, e);
  scale_tangents(out.in_tangents, e);
  scale_tangents(out.out_tangents, e);
  scale_tangent(out.start_tangent, e);
  scale_tangent(out.end_tangent, e);
}

void denormalize_result(const FitInput& original, const Normalization& nz,
                        std::span<const ReportUnit> units, FitResult& out) {
  const int ex = nz.length_exponent;
  const double ek = nz.knot_exponent;
  for (Point& p : out.points) p = scaled(p, ex);
  for (double& t : out.knots) t = times_power_of_two(t, ek);
  for (Segment& g : out.spline.segments) {
    for (Point& p : g.bezier.p) p = scaled(p, ex);
    g.t0 = times_power_of_two(g.t0, ek);
    g.t1 = times_power_of_two(g.t1, ek);
  }
  for (const double t : out.knots) {
    if (std::isfinite(t)) continue;
    // The knots of the original points overflow: alpha_knots names the cause.
    std::vector<double> knots;
    alpha_knots(original.points, original.alpha, original.closed, knots);
    throw Error(ErrorCode::kNonFinite,
                "the knots of these points overflow double precision (sums of chord lengths "
                "beyond 1e308); use uniform knots (alpha 0)");
  }
  for (const ReportUnit& u : units) {
    const std::vector<std::string_view> keys = split_path(u.path);
    map_number(out.method_report, keys, ex * static_cast<double>(u.length) + ek * u.knots);
  }
}

}  // namespace fairspline::detail
