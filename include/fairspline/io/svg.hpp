// SVG rendering of a fit: the curve, its input points, and optionally the control polygon and
// the curvature comb, with a caption.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fairspline/fit.hpp"

namespace fairspline::io {

/// What write_svg draws. The drawing keeps the data's aspect ratio: it is scaled uniformly to
/// fit width x height (minus margins and the caption line) and centered.
struct SvgOptions {
  double width = 800;            ///< pixels, > 0
  double height = 600;           ///< pixels; 0 = derived from width and the data's aspect ratio
  double margin = 24;            ///< pixels around the drawing
  bool points = true;            ///< input points as circles
  bool control_polygon = false;  ///< dashed Bézier control polygons
  bool comb = false;             ///< curvature comb: teeth along the normal, length ∝ curvature
  /// Tooth length per unit curvature, in data units² (tooth = comb_scale·|κ|);
  /// 0 = automatic: the longest tooth is 10% of the larger side of the curve's bounding box.
  double comb_scale = 0;
  int comb_samples_per_segment = 16;  ///< teeth per piece (>= 1; the piece ends are included)
  bool caption = true;                ///< method, energies and regularity under the drawing
};

/// Renders `result` as a standalone SVG 1.1 document. Math coordinates are drawn with the y
/// axis pointing up. The curve is one <path> with one `C` command per piece.
std::string write_svg(const FitResult& result, const SvgOptions& options = {});

/// Sets one option by name; the "svg." prefix is optional ("svg.comb", "comb").
/// Booleans accept true/false, 1/0 and "true"/"false"; numbers must be finite and in range.
/// Throws kUnknownOption (listing the valid keys) or kBadOption.
void set_svg_option(SvgOptions& options, std::string_view key, const nlohmann::json& value);
/// Builds options from an object such as {"svg.comb": 1, "svg.width": 1000} (or without
/// prefixes) on top of the defaults.
SvgOptions svg_options_from_json(const nlohmann::json& object);

}  // namespace fairspline::io
