#include "fairspline/io/paths.hpp"

#include <charconv>
#include <cmath>

#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/geometry.hpp"

namespace fairspline::io {

namespace {

// Shortest round-trip digits: an SVG path is no JSON, so std::to_chars's are the right ones.
void append_number(std::string& out, double v) {
  char buf[32];
  out.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

void append_point(std::string& out, Point p) {
  append_number(out, p.x);
  out += ' ';
  append_number(out, p.y);
}

}  // namespace

std::string svg_path_data(const Spline& s) {
  if (s.segments.empty()) throw Error(ErrorCode::kInvalidArgument, "the curve has no pieces");
  std::string out = "M";
  append_point(out, s.segments.front().bezier.p[0]);
  for (const Segment& g : s.segments) {
    out += " C";
    for (std::size_t k = 1; k < 4; ++k) {
      if (k > 1) out += ' ';
      append_point(out, g.bezier.p[k]);
    }
  }
  if (s.closed) out += " Z";
  return out;
}

std::string write_geojson(const Spline& s, double tolerance, const nlohmann::json& properties) {
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance)) {
    throw Error(ErrorCode::kInvalidArgument,
                "the GeoJSON tolerance must be a non-negative number (0 for the default)");
  }
  if (tolerance == 0.0) {
    const BBox box = bounds(s);
    tolerance =
        kDefaultGeoJsonRelativeTolerance * std::hypot(box.max.x - box.min.x, box.max.y - box.min.y);
    // A curve with no extent (cannot come from a fit, which needs distinct points).
    if (!(tolerance > 0.0)) tolerance = 1.0;
  }
  const Polyline line = flatten(s, tolerance);
  nlohmann::json coordinates = nlohmann::json::array();
  for (const Point& p : line.points) coordinates.push_back({p.x, p.y});
  nlohmann::json props = properties;
  props["closed"] = s.closed;
  props["tolerance"] = tolerance;
  props["length"] = length(s);
  const nlohmann::json feature = {
      {"type", "Feature"},
      {"geometry", {{"type", "LineString"}, {"coordinates", coordinates}}},
      {"properties", props}};
  return feature.dump() + "\n";
}

std::string write_geojson(const FitResult& result, double tolerance) {
  nlohmann::json properties = {{"method", result.method}};
  if (result.report && result.report->bending_energy) {
    properties["bending_energy"] = *result.report->bending_energy;
  }
  return write_geojson(result.spline, tolerance, properties);
}

}  // namespace fairspline::io
