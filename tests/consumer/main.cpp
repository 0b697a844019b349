// Downstream use of an installed fairspline: fit Li's example and print the piece count.
#include <cstdio>
#include <exception>

#include <fairspline/fairspline.hpp>

int main() {
  fairspline::FitInput input;
  input.points = {{1, 90}, {3, 105}, {6, 120}, {10, 100}, {12, 85}, {15, 104}, {17, 80}};
  try {
    const fairspline::FitResult r =
        fairspline::fit("li-strain", input, {}, fairspline::ReportLevel::kNone);
    std::printf("segments: %zu\n", r.spline.segments.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
