// Fuzz target: io::parse_csv_points on arbitrary text. The promise: finite points or a
// fairspline::Error; and what parses writes back (shortest round-trip text) to the same points.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "fairspline/error.hpp"
#include "fairspline/io/csv.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<fairspline::Point> points;
  try {
    points = fairspline::io::parse_csv_points(text);
  } catch (const fairspline::Error& e) {
    if (std::string_view(e.what()).empty()) fairspline::fuzz::fail("an error without a message");
    return 0;
  } catch (const std::exception& e) {
    fairspline::fuzz::fail(std::string("exception other than fairspline::Error: ") + e.what());
  }
  std::string again = "x,y\n";
  for (const fairspline::Point& p : points) {
    fairspline::fuzz::check_finite(p, "parsed coordinate");
    again += fairspline::io::format_double(p.x) + "," + fairspline::io::format_double(p.y) + "\n";
  }
  try {
    const std::vector<fairspline::Point> back = fairspline::io::parse_csv_points(again);
    if (back.size() != points.size()) fairspline::fuzz::fail("round trip changed the count");
    for (std::size_t i = 0; i < back.size(); ++i) {
      // Bitwise (-0.0 must stay -0.0): compare through the text of each.
      if (fairspline::io::format_double(back[i].x) != fairspline::io::format_double(points[i].x) ||
          fairspline::io::format_double(back[i].y) != fairspline::io::format_double(points[i].y)) {
        fairspline::fuzz::fail("round trip changed point " + std::to_string(i));
      }
    }
  } catch (const fairspline::Error& e) {
    fairspline::fuzz::fail(std::string("written points do not parse back: ") + e.what());
  }
  return 0;
}
