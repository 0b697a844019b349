#include "detail/finite.hpp"

#include <string>

#include "fairspline/error.hpp"

namespace fairspline::detail {

void check_finite_output(const FitResult& r, std::string_view method) {
  std::uint64_t bad = 0;
  for (const Segment& s : r.spline.segments) bad |= non_finite_bits(s);
  for (const Vec2& v : r.tangents) bad |= non_finite_bits(v);
  if (bad == 0) return;
  for (std::size_t k = 0; k < r.spline.segments.size(); ++k) {
    const Segment& s = r.spline.segments[k];
    if (non_finite_bits(s)) {
      throw Error(ErrorCode::kNonFinite,
                  std::string(method) + " produced a non-finite control point in segment " +
                      std::to_string(k) + " (span " + std::to_string(s.span) +
                      "); the input is likely beyond the range of double precision",
                  s.span);
    }
  }
  for (std::size_t i = 0; i < r.tangents.size(); ++i) {
    if (non_finite_bits(r.tangents[i])) {
      throw Error(
          ErrorCode::kNonFinite,
          std::string(method) + " produced a non-finite tangent at point " + std::to_string(i), i);
    }
  }
}

}  // namespace fairspline::detail
