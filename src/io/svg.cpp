#include "fairspline/io/svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "fairspline/error.hpp"

namespace fairspline::io {

using nlohmann::json;

namespace {

/// Pixel coordinate text: at most 2 decimals, no trailing zeros, never "nan"/"-0".
std::string px(double v) {
  if (!std::isfinite(v)) v = 0.0;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string escape_xml(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        // Control characters are not allowed in XML 1.0 text.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') {
          out += ' ';
        } else {
          out += c;
        }
    }
  }
  return out;
}

struct Box {
  double xmin = std::numeric_limits<double>::infinity();
  double ymin = std::numeric_limits<double>::infinity();
  double xmax = -std::numeric_limits<double>::infinity();
  double ymax = -std::numeric_limits<double>::infinity();
  void add(Point p) {
    if (!is_finite(p)) return;
    xmin = std::min(xmin, p.x);
    ymin = std::min(ymin, p.y);
    xmax = std::max(xmax, p.x);
    ymax = std::max(ymax, p.y);
  }
  bool empty() const { return !(xmin <= xmax && ymin <= ymax); }
};

struct Tooth {
  Point base;
  Point tip;
  bool valid = false;
};

std::vector<Tooth> comb_teeth(const FitResult& r, const SvgOptions& o, double extent) {
  const int n = std::max(1, o.comb_samples_per_segment);
  struct Sample {
    Point base;
    Vec2 normal;
    double kappa = 0.0;
    bool valid = false;
  };
  std::vector<Sample> samples;
  double kmax = 0.0;
  for (const Segment& seg : r.spline.segments) {
    const CubicBezier& b = seg.bezier;
    double poly = 0.0;
    for (std::size_t k = 0; k < 3; ++k) poly += distance(b.p[k], b.p[k + 1]);
    for (int j = 0; j <= n; ++j) {
      const double u = static_cast<double>(j) / n;
      Sample s;
      s.base = b.eval(u);
      const Vec2 d = b.d1(u);
      const double speed = norm(d);
      if (speed > 1e-9 * poly && std::isfinite(speed)) {
        s.normal = perp(d) / speed;
        s.kappa = b.curvature(u);
        s.valid = std::isfinite(s.kappa);
        if (s.valid) kmax = std::max(kmax, std::abs(s.kappa));
      }
      samples.push_back(s);
    }
  }
  double scale = o.comb_scale;
  if (scale <= 0.0) scale = kmax > 0.0 ? 0.1 * extent / kmax : 0.0;
  std::vector<Tooth> teeth;
  teeth.reserve(samples.size());
  for (const Sample& s : samples) {
    // Teeth point away from the center of curvature (the usual comb on the convex side).
    teeth.push_back({s.base, s.base - (scale * s.kappa) * s.normal, s.valid});
  }
  return teeth;
}

std::string caption_text(const FitResult& r) {
  std::string s = r.method.empty() ? std::string("fairspline") : r.method;
  s += ", " + std::to_string(r.points.size()) + (r.closed ? " points (closed)" : " points");
  if (!r.report) return s + ", no report";
  const Report& rep = *r.report;
  if (rep.energy_singular) {
    s += ", bending energy singular";
  } else if (rep.bending_energy) {
    s += ", bending " + num(*rep.bending_energy);
  }
  s += ", linearized " + num(rep.linearized_energy);
  if (rep.length) s += ", length " + num(*rep.length);
  s += rep.regular ? ", regular" : ", NOT regular";
  if (!rep.segments.empty() && !rep.intersections.empty()) {
    s += ", " + std::to_string(rep.intersections.size()) + " self-intersection" +
         (rep.intersections.size() == 1 ? "" : "s");
  }
  return s;
}

const char* const kSvgKeys[] = {
    "width",           "height", "margin",     "points",
    "control_polygon", "comb",   "comb_scale", "comb_samples_per_segment",
    "caption"};

[[noreturn]] void bad_svg(std::string_view key, const std::string& expected, const json& v) {
  throw Error(ErrorCode::kBadOption, "option 'svg." + std::string(key) + "' must be " + expected +
                                         ", got " +
                                         v.dump(-1, ' ', false, json::error_handler_t::replace));
}

bool as_bool(std::string_view key, const json& v) {
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number_integer() && (v.get<long long>() == 0 || v.get<long long>() == 1)) {
    return v.get<long long>() == 1;
  }
  if (v.is_string() && (v == "true" || v == "false")) return v == "true";
  bad_svg(key, "true or false (or 1/0)", v);
}

double as_number(std::string_view key, const json& v, double min, bool min_inclusive, double max) {
  if (v.is_number()) {
    const double x = v.get<double>();
    if (std::isfinite(x) && (min_inclusive ? x >= min : x > min) && x <= max) return x;
  }
  bad_svg(
      key,
      "a number " + std::string(min_inclusive ? ">= " : "> ") + num(min) + " and <= " + num(max),
      v);
}

}  // namespace

void set_svg_option(SvgOptions& o, std::string_view key, const json& value) {
  std::string_view k = key;
  if (k.substr(0, 4) == "svg.") k.remove_prefix(4);
  constexpr double kMaxPixels = 1e6;
  if (k == "width") {
    o.width = as_number(k, value, 0.0, false, kMaxPixels);
  } else if (k == "height") {
    o.height = as_number(k, value, 0.0, true, kMaxPixels);
  } else if (k == "margin") {
    o.margin = as_number(k, value, 0.0, true, kMaxPixels);
  } else if (k == "points") {
    o.points = as_bool(k, value);
  } else if (k == "control_polygon") {
    o.control_polygon = as_bool(k, value);
  } else if (k == "comb") {
    o.comb = as_bool(k, value);
  } else if (k == "comb_scale") {
    o.comb_scale = as_number(k, value, 0.0, true, std::numeric_limits<double>::max());
  } else if (k == "comb_samples_per_segment") {
    if (!value.is_number_integer() || value.get<long long>() < 1 ||
        value.get<long long>() > 10000) {
      bad_svg(k, "an integer in [1, 10000]", value);
    }
    o.comb_samples_per_segment = static_cast<int>(value.get<long long>());
  } else if (k == "caption") {
    o.caption = as_bool(k, value);
  } else {
    std::string known;
    for (const char* name : kSvgKeys)
      known += (known.empty() ? "svg." : ", svg.") + std::string(name);
    throw Error(ErrorCode::kUnknownOption,
                "unknown SVG option '" + std::string(key) + "'; valid: " + known);
  }
}

SvgOptions svg_options_from_json(const json& object) {
  SvgOptions o;
  if (object.is_null()) return o;
  if (!object.is_object()) {
    throw Error(ErrorCode::kBadOption,
                "SVG options must be a JSON object, got " +
                    object.dump(-1, ' ', false, json::error_handler_t::replace));
  }
  for (const auto& [key, value] : object.items()) set_svg_option(o, key, value);
  return o;
}

std::string write_svg(const FitResult& r, const SvgOptions& opt) {
  // Bounding box of what is drawn, in data coordinates.
  Box box;
  for (const Segment& s : r.spline.segments) {
    const BBox b = s.bezier.bbox();
    box.add(b.min);
    box.add(b.max);
    if (opt.control_polygon) {
      for (const Point& p : s.bezier.p) box.add(p);
    }
  }
  for (const Point& p : r.points) box.add(p);
  // Data balls: the discs around the request's points (the centres).
  // (The request keeps its points only where they differ from the result's.)
  const std::vector<double>& radii = r.input.radii;
  const std::vector<Point>& centres = r.input.points.empty() ? r.points : r.input.points;
  const bool balls = opt.points && !radii.empty();
  if (balls) {
    for (std::size_t i = 0; i < radii.size() && i < centres.size(); ++i) {
      box.add(centres[i] - Vec2{radii[i], radii[i]});
      box.add(centres[i] + Vec2{radii[i], radii[i]});
    }
  }
  if (box.empty()) box = Box{0.0, 0.0, 1.0, 1.0};
  const double extent = std::max(box.xmax - box.xmin, box.ymax - box.ymin);
  std::vector<Tooth> teeth;
  if (opt.comb) {
    teeth = comb_teeth(r, opt, extent);
    for (const Tooth& t : teeth) {
      if (t.valid) box.add(t.tip);
    }
  }
  const double dx = box.xmax - box.xmin, dy = box.ymax - box.ymin;

  // Canvas and data -> pixel transform (uniform scale, y up, centered).
  const double width = opt.width > 0.0 && std::isfinite(opt.width) ? opt.width : 800.0;
  const double margin = std::isfinite(opt.margin) && opt.margin >= 0.0 ? opt.margin : 0.0;
  const double font = std::clamp(width / 60.0, 9.0, 14.0);
  const double caption_h = opt.caption ? font + 8.0 : 0.0;
  const double aw = std::max(1.0, width - 2.0 * margin);
  double height = opt.height;
  if (!(height > 0.0) || !std::isfinite(height)) {
    const double content = dx > 0.0 ? std::min(dy * aw / dx, 4.0 * aw) : aw;
    height = std::max(content, 1.0) + 2.0 * margin + caption_h;
  }
  const double ah = std::max(1.0, height - 2.0 * margin - caption_h);
  double s = std::min(dx > 0.0 ? aw / dx : std::numeric_limits<double>::infinity(),
                      dy > 0.0 ? ah / dy : std::numeric_limits<double>::infinity());
  if (!std::isfinite(s)) s = 1.0;
  const double ox = margin + 0.5 * (aw - dx * s);
  const double oy = margin + 0.5 * (ah - dy * s);
  const auto X = [&](Point p) { return px(ox + (p.x - box.xmin) * s); };
  const auto Y = [&](Point p) { return px(oy + (box.ymax - p.y) * s); };
  const auto XY = [&](Point p) { return X(p) + " " + Y(p); };

  std::string out;
  out += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + px(width) +
         "\" height=\"" + px(height) + "\" viewBox=\"0 0 " + px(width) + " " + px(height) + "\">\n";
  out += "<title>" + escape_xml("fairspline: " + r.method) + "</title>\n";
  out += "<rect x=\"0\" y=\"0\" width=\"" + px(width) + "\" height=\"" + px(height) +
         "\" fill=\"#ffffff\"/>\n";

  if (opt.comb) {
    std::string d_teeth, d_env;
    bool pen_down = false;
    for (const Tooth& t : teeth) {
      if (!t.valid) {
        pen_down = false;
        continue;
      }
      d_teeth += (d_teeth.empty() ? "M" : " M") + XY(t.base) + " L" + XY(t.tip);
      d_env += (d_env.empty() ? "" : " ") + std::string(pen_down ? "L" : "M") + XY(t.tip);
      pen_down = true;
    }
    out += "<g class=\"comb\" fill=\"none\">\n";
    out += "<path class=\"comb-teeth\" stroke=\"#6baed6\" stroke-width=\"0.8\" d=\"" + d_teeth +
           "\"/>\n";
    out +=
        "<path class=\"comb-envelope\" stroke=\"#2171b5\" stroke-width=\"1.2\" "
        "stroke-linejoin=\"round\" d=\"" +
        d_env + "\"/>\n";
    out += "</g>\n";
  }

  if (opt.control_polygon && !r.spline.segments.empty()) {
    std::string d;
    for (const Segment& seg : r.spline.segments) {
      const auto& p = seg.bezier.p;
      d +=
          (d.empty() ? "M" : " M") + XY(p[0]) + " L" + XY(p[1]) + " L" + XY(p[2]) + " L" + XY(p[3]);
    }
    out += "<g class=\"control-polygon\">\n";
    out +=
        "<path fill=\"none\" stroke=\"#888888\" stroke-width=\"1\" stroke-dasharray=\"4 3\" d=\"" +
        d + "\"/>\n";
    for (const Segment& seg : r.spline.segments) {
      for (std::size_t k : {1u, 2u}) {
        out += "<circle cx=\"" + X(seg.bezier.p[k]) + "\" cy=\"" + Y(seg.bezier.p[k]) +
               "\" r=\"2.5\" fill=\"#ffffff\" stroke=\"#888888\" stroke-width=\"1\"/>\n";
      }
    }
    out += "</g>\n";
  }

  if (!r.spline.segments.empty()) {
    std::string d = "M" + XY(r.spline.segments.front().bezier.p[0]);
    for (const Segment& seg : r.spline.segments) {
      const auto& p = seg.bezier.p;
      d += " C" + XY(p[1]) + " " + XY(p[2]) + " " + XY(p[3]);
    }
    if (r.closed) d += " Z";
    out +=
        "<path class=\"curve\" fill=\"none\" stroke=\"#111111\" stroke-width=\"2\" "
        "stroke-linejoin=\"round\" stroke-linecap=\"round\" d=\"" +
        d + "\"/>\n";
  }

  if (balls) {
    out +=
        "<g class=\"balls\" fill=\"#d62728\" fill-opacity=\"0.08\" stroke=\"#d62728\" "
        "stroke-opacity=\"0.5\" stroke-width=\"1\">\n";
    for (std::size_t i = 0; i < radii.size() && i < centres.size(); ++i) {
      if (!(radii[i] > 0.0)) continue;
      out += "<circle cx=\"" + X(centres[i]) + "\" cy=\"" + Y(centres[i]) + "\" r=\"" +
             px(radii[i] * s) + "\"/>\n";
    }
    out += "</g>\n";
  }

  if (opt.points && !r.points.empty()) {
    out += "<g class=\"points\" fill=\"#d62728\" stroke=\"#ffffff\" stroke-width=\"1\">\n";
    for (const Point& p : r.points) {
      out += "<circle cx=\"" + X(p) + "\" cy=\"" + Y(p) + "\" r=\"3.5\"/>\n";
    }
    out += "</g>\n";
  }

  if (opt.caption) {
    out += "<text class=\"caption\" x=\"" + px(margin) + "\" y=\"" + px(height - margin - 4.0) +
           "\" font-family=\"sans-serif\" font-size=\"" + px(font) + "\" fill=\"#333333\">" +
           escape_xml(caption_text(r)) + "</text>\n";
  }
  out += "</svg>\n";
  return out;
}

}  // namespace fairspline::io
