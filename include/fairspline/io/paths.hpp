// Exports of a curve's geometry for other tools: an SVG path's `d` attribute in data coordinates
// and a GeoJSON Feature whose geometry is the curve flattened within a tolerance.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "fairspline/fit.hpp"
#include "fairspline/spline.hpp"

namespace fairspline::io {

/// The SVG path data of the curve in its own coordinates (no y flip, no scaling): "M x0 y0" and
/// one "C x1 y1 x2 y2 x3 y3" per piece, "Z" for a closed curve; numbers in shortest round-trip
/// form, so that parsing them gives the control points bit for bit.
std::string svg_path_data(const Spline& s);

/// Default flattening tolerance of GeoJSON: this fraction of the diagonal of the curve's bounds.
inline constexpr double kDefaultGeoJsonRelativeTolerance = 1e-4;

/// A GeoJSON (RFC 7946) Feature: a LineString through the curve flattened within `tolerance`
/// (absolute; 0 = kDefaultGeoJsonRelativeTolerance of the bounds' diagonal), closed (its last
/// position equal to its first) for a closed curve; properties: method, closed, tolerance,
/// length (of the curve) and, when reported, bending_energy. Coordinates are written as given:
/// for GIS data that is longitude, latitude, so the tolerance is in degrees.
std::string write_geojson(const FitResult& result, double tolerance = 0.0);
/// The same for a bare curve: properties closed, tolerance and length, plus `properties`.
std::string write_geojson(const Spline& s, double tolerance = 0.0,
                          const nlohmann::json& properties = nlohmann::json::object());

}  // namespace fairspline::io
