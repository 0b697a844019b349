// Helpers shared by the fuzz targets (tests/fuzz/fuzz_*.cpp): a byte reader that turns the
// fuzzer's bytes into values, and the checks every target applies to the library's output.
// Plain C++20 (no FuzzedDataProvider, which ships only with clang) so that the same targets
// also build with g++ for the regression replay (replay_main.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fairspline/fit.hpp"

namespace fairspline::fuzz {

/// Longest method name (or name-valued option) that fuzz_fit reads (ByteReader::name).
inline constexpr std::size_t kMaxNameLength = 64;

/// Reads values from the fuzzer's bytes, front to back. Past the end every read returns zero
/// (false, the first choice, an empty string), so any input decodes to something.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::size_t remaining() const { return size_ - pos_; }
  bool empty() const { return pos_ >= size_; }

  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }

  std::uint64_t bits(int nbytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < nbytes; ++i) v = (v << 8) | byte();
    return v;
  }

  bool boolean() { return (byte() & 1) != 0; }

  /// Uniform-ish integer in [lo, hi] (inclusive); lo when out of bytes.
  std::size_t range(std::size_t lo, std::size_t hi) {
    if (hi <= lo) return lo;
    const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
    const int nbytes = span <= 0x100 ? 1 : span <= 0x10000 ? 2 : 4;
    return lo + static_cast<std::size_t>(bits(nbytes) % span);
  }

  /// Any 64-bit pattern reinterpreted as a double (NaN, Inf and denormals included).
  double raw_double() {
    const std::uint64_t b = bits(8);
    double d;
    std::memcpy(&d, &b, sizeof d);
    return d;
  }

  /// A small "ordinary" number: a signed 16-bit integer divided by a power of two.
  double ordinary() {
    const auto i = static_cast<std::int16_t>(bits(2));
    return std::ldexp(static_cast<double>(i), -static_cast<int>(byte() % 12));
  }

  /// A double drawn from a mix of ordinary values and extremes.
  double number() {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    constexpr double kExtremes[] = {0.0,
                                    -0.0,
                                    1.0,
                                    -1.0,
                                    1e-300,
                                    -1e-300,
                                    1e300,
                                    -1e300,
                                    std::numeric_limits<double>::quiet_NaN(),
                                    kInf,
                                    -kInf,
                                    std::numeric_limits<double>::denorm_min(),
                                    -std::numeric_limits<double>::denorm_min(),
                                    std::numeric_limits<double>::min(),
                                    std::numeric_limits<double>::max(),
                                    -std::numeric_limits<double>::max(),
                                    std::numeric_limits<double>::epsilon(),
                                    1e8,
                                    1e-8,
                                    0.5};
    constexpr std::size_t kCount = sizeof kExtremes / sizeof kExtremes[0];
    const std::uint8_t mode = byte();
    if (mode < 160) return ordinary();
    if (mode < 224) return kExtremes[byte() % kCount];
    if (mode < 240) return ordinary() * std::ldexp(1.0, static_cast<int>(byte() % 64) - 32);
    return raw_double();
  }

  /// A string of up to `max_len` bytes.
  std::string string(std::size_t max_len) {
    const std::size_t n = range(0, max_len);
    std::string s;
    for (std::size_t i = 0; i < n && !empty(); ++i) s += static_cast<char>(byte());
    return s;
  }

  /// A name: the bytes up to the first NUL byte (which is skipped), at most `max_len` bytes, or
  /// up to the end of the input, whichever comes first.
  std::string name(std::size_t max_len) {
    std::string s;
    while (!empty() && s.size() < max_len) {
      const auto c = static_cast<char>(byte());
      if (c == '\0') break;
      s += c;
    }
    return s;
  }

  /// The rest of the bytes as text.
  std::string_view rest() {
    const auto* p = reinterpret_cast<const char*>(data_ + pos_);
    const std::size_t n = remaining();
    pos_ = size_;
    return {p, n};
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// Reports a broken promise of the library and aborts (libFuzzer records the input).
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

inline void check_finite(double x, const char* what) {
  if (!std::isfinite(x)) fail(std::string("non-finite ") + what + " in a result");
}

inline void check_finite(Vec2 v, const char* what) {
  check_finite(v.x, what);
  check_finite(v.y, what);
}

/// Every number in a JSON value is finite (nlohmann keeps NaN/Inf as floats).
inline void check_finite_json(const nlohmann::json& j, const char* what) {
  if (j.is_number_float()) {
    check_finite(j.get<double>(), what);
  } else if (j.is_structured()) {
    for (const auto& v : j) check_finite_json(v, what);
  }
}

/// The promise of fit(): a valid curve whose every number is finite. Checks the points, knots,
/// tangents, control points and parameter ranges, the report and the method report, and the
/// structure (one tangent and knot per point, pieces joined end to start in parameter order).
inline void check_result(const FitResult& r) {
  if (r.points.empty()) fail("a result without points");
  if (r.spline.segments.empty()) fail("a result without segments");
  for (const Point& p : r.points) check_finite(p, "point");
  for (double t : r.knots) check_finite(t, "knot");
  for (const Vec2& t : r.tangents) {
    check_finite(t, "tangent");
    if (std::abs(std::hypot(t.x, t.y) - 1.0) > 1e-6) fail("a tangent that is not a unit vector");
  }
  const std::size_t n = r.points.size();
  if (r.tangents.size() != n) fail("tangents.size() != points.size()");
  if (r.knots.size() != n + (r.closed ? 1 : 0)) fail("wrong number of knots");
  for (std::size_t i = 1; i < r.knots.size(); ++i) {
    if (!(r.knots[i] > r.knots[i - 1])) fail("knots not strictly increasing");
  }
  for (std::size_t k = 0; k < r.spline.segments.size(); ++k) {
    const Segment& s = r.spline.segments[k];
    check_finite(s.t0, "segment t0");
    check_finite(s.t1, "segment t1");
    for (const Point& p : s.bezier.p) check_finite(p, "control point");
    if (!(s.t1 > s.t0)) fail("a segment with t1 <= t0");
    if (s.span >= n) fail("a segment span out of range");
  }
  // Continuity and interpolation, to within rounding relative to the data's scale (methods
  // that solve for their pieces accept residuals of 1e-9 of the chords, e.g. kozak-krajnc).
  double scale = 0.0;
  BBox box{r.points[0], r.points[0]};
  for (const Point& p : r.points) {
    scale = std::max({scale, std::abs(p.x), std::abs(p.y)});
    box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y)};
    box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y)};
  }
  scale = std::max(scale, std::hypot(box.max.x - box.min.x, box.max.y - box.min.y));
  const double tol = 1e-8 * scale;
  const auto far = [tol](Point a, Point b) {
    return std::abs(a.x - b.x) > tol || std::abs(a.y - b.y) > tol;
  };
  const auto& segs = r.spline.segments;
  for (std::size_t k = 0; k + 1 < segs.size(); ++k) {
    if (far(segs[k].bezier.p[3], segs[k + 1].bezier.p[0])) fail("pieces do not join");
  }
  if (r.closed && far(segs.back().bezier.p[3], segs.front().bezier.p[0])) {
    fail("a closed curve that does not close");
  }
  if (r.report && !(r.report->max_interpolation_residual <= tol)) {
    fail("the curve misses a point (max_interpolation_residual " +
         std::to_string(r.report->max_interpolation_residual) + ", scale " + std::to_string(scale) +
         ")");
  }
  check_finite_json(r.options, "option");
  check_finite_json(r.method_report, "method_report number");
  if (r.report) {
    const Report& rep = *r.report;
    if (rep.bending_energy) check_finite(*rep.bending_energy, "bending energy");
    if (rep.curvature_variation_energy) {
      check_finite(*rep.curvature_variation_energy, "curvature variation energy");
    }
    if (rep.length) check_finite(*rep.length, "length");
    check_finite(rep.linearized_energy, "linearized energy");
    check_finite(rep.max_tangent_angle_jump_deg, "max tangent jump");
    check_finite(rep.max_curvature_jump, "max curvature jump");
    check_finite(rep.min_relative_speed, "min relative speed");
    check_finite(rep.max_interpolation_residual, "interpolation residual");
    for (const SegmentReport& s : rep.segments) {
      check_finite(s.linearized_energy, "segment linearized energy");
      check_finite(s.bending_energy, "segment bending energy");
      check_finite(s.curvature_variation_energy, "segment curvature variation energy");
      check_finite(s.length, "segment length");
      check_finite(s.min_relative_speed, "segment min relative speed");
    }
    for (const Intersection& x : rep.intersections) {
      check_finite(x.u_a, "intersection parameter");
      check_finite(x.u_b, "intersection parameter");
      check_finite(x.point, "intersection point");
    }
  }
}

}  // namespace fairspline::fuzz
