#include "fairspline/io/curve_ensemble.hpp"
#include "fairspline/io/file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <vector>

#include "detail/nodes.hpp"
#include "fairspline/energy.hpp"
#include "fairspline/error.hpp"
#include "fairspline/io/csv.hpp"

namespace fairspline::io {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Row {
  double x = 0, y = 0, dir = 0, corner = 0;
  int state = 0;
  double radius = 0;  // a data ball (state < 0 or > 100; or a three-column file's third number)
};

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

/// The sixth column may hold Curve Ensemble's "inf" (an infeasible piece): it is ignored anyway.
bool is_non_finite_word(std::string_view t) {
  std::string s(t);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.erase(0, 1);
  return s == "inf" || s == "infinity" || s == "nan";
}

Row parse_row(std::string_view line, std::size_t line_no, std::size_t node) {
  static constexpr const char* kColumn[] = {"x", "y", "direction", "corner", "state", "energy"};
  const std::string where =
      "line " + std::to_string(line_no) + " (node " + std::to_string(node) + "): ";
  const std::vector<std::string_view> t = tokens(line);
  if (t.size() > 6) {
    throw Error(ErrorCode::kParseError,
                where + "expected at most 6 numbers (x y direction corner state energy), got " +
                    std::to_string(t.size()),
                node);
  }
  double v[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (k == 5 && is_non_finite_word(t[k])) continue;
    if (!parse_number(t[k], v[k], where + kColumn[k], node)) {
      throw Error(
          ErrorCode::kParseError,
          where + "the " + kColumn[k] + " column is not a number: '" + std::string(t[k]) + "'",
          node);
    }
  }
  Row r{v[0], v[1], v[2], v[3], 0};
  const double s = v[4];
  if (s < 0.0 || s > 100.0) {  // a data ball: radius −s, or s − 100 when "marked"
    r.radius = s < 0.0 ? -s : s - 100.0;
    r.dir = r.corner = 0.0;  // the fitted direction and the node's angle on the circle
    return r;
  }
  if (!(s == 0 || s == 1 || s == 3 || s == 5 || s == 7)) {
    throw Error(ErrorCode::kParseError,
                where + "state " + format_double(s) +
                    " is not a Curve Ensemble node state (0 regular, 1 clamped, 3 free-clamped, "
                    "5 clamped-free, 7 free)",
                node);
  }
  r.state = static_cast<int>(s);
  return r;
}

}  // namespace

FitInput parse_curve_ensemble(std::string_view text) {
  std::vector<Row> rows;
  std::vector<std::size_t> columns;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
    ++line_no;
    if (!line.empty() && line.front() == '#') continue;
    if (tokens(line).empty()) continue;
    rows.push_back(parse_row(line, line_no, rows.size()));
    columns.push_back(tokens(line).size());
  }
  if (rows.empty()) {
    throw Error(ErrorCode::kTooFewPoints, "the Curve Ensemble file has no nodes");
  }
  // Three numbers on every line: Curve Ensemble's data-ball file, "x y r" (its DIR column,
  // the other reading, is not used for regular nodes anyway).
  if (std::all_of(columns.begin(), columns.end(), [](std::size_t c) { return c == 3; })) {
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (!(rows[i].dir >= 0.0)) {
        throw Error(ErrorCode::kInvalidArgument,
                    "node " + std::to_string(i) +
                        ": the radius of a data ball (the third number) "
                        "is negative: " +
                        format_double(rows[i].dir),
                    i);
      }
      rows[i].radius = rows[i].dir;
      rows[i].dir = 0.0;
    }
  }
  FitInput in;
  const int first = rows.front().state, last = rows.back().state;
  in.closed = !((first == 7 || first == 3) && (last == 7 || last == 5));
  const std::size_t n = rows.size();
  const SideState R = SideState::kRegular, C = SideState::kClamped, F = SideState::kFree;
  std::vector<std::optional<Vec2>> ins(n), outs(n);
  std::vector<double> corners(n, 0.0);
  bool any_in = false, any_out = false, any_corner = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Row& r = rows[i];
    in.points.push_back({r.x, r.y});
    const Vec2 out_dir = from_angle(r.dir * kDeg), in_dir = from_angle((r.dir - r.corner) * kDeg);
    switch (r.state) {
      case 0:
        in.states.push_back({R, R});
        corners[i] = r.corner;
        any_corner = any_corner || r.corner != 0.0;
        break;
      case 1:
        in.states.push_back({C, C});
        ins[i] = in_dir;
        outs[i] = out_dir;
        any_in = any_out = true;
        break;
      case 3:
        in.states.push_back({F, C});
        outs[i] = out_dir;
        any_out = true;
        break;
      case 5:
        in.states.push_back({C, F});
        ins[i] = in_dir;
        any_in = true;
        break;
      default:
        in.states.push_back({F, F});
        break;
    }
  }
  if (std::any_of(rows.begin(), rows.end(), [](const Row& r) { return r.radius != 0.0; })) {
    for (const Row& r : rows) in.radii.push_back(r.radius);
  }
  if (any_in) in.in_tangents = std::move(ins);
  if (any_out) in.out_tangents = std::move(outs);
  if (any_corner) in.corners_deg = std::move(corners);
  return in;
}

FitInput read_curve_ensemble(const std::filesystem::path& path) {
  return parse_curve_ensemble(read_file(path).view());
}

std::string write_curve_ensemble(const FitResult& result) {
  const std::size_t n = result.points.size();
  const FitInput request = refit_input(result);
  const std::vector<detail::ResolvedNode> nodes = detail::resolve_nodes(request, n);
  // A quarter of ∫κ² ds per span (Curve Ensemble's energy), from the pieces.
  std::vector<double> energy(n, 0.0);
  for (const Segment& g : result.spline.segments) {
    if (g.span < n) energy[g.span] += 0.25 * bending_energy(g.bezier).value;
  }
  const auto degrees = [](Vec2 v) { return std::atan2(v.y, v.x) / kDeg; };
  std::string out = "#Curve Ensemble Text File\n";
  const auto put = [&](double v) {
    out += format_double(v);
    out += ' ';
  };
  const SideState C = SideState::kClamped, F = SideState::kFree;
  for (std::size_t i = 0; i < n; ++i) {
    const detail::ResolvedNode& node = nodes[i];
    SideState in = node.state.in, out_state = node.state.out;
    if (!result.closed && i == 0) in = F;  // an open curve has no side before its start
    if (!result.closed && i + 1 == n) out_state = F;
    const Vec2 fitted = i < result.tangents.size() ? result.tangents[i] : Vec2{1.0, 0.0};
    double dir = degrees(fitted), corner = 0.0;
    int state = 0;
    if (in == F || out_state == F) {
      if (in == F && out_state == C) {
        state = 3;
        dir = degrees(*node.out);
      } else if (in == C && out_state == F) {
        state = 5;
        dir = degrees(*node.in);
      } else {
        state = 7;  // a side optimized on its own beside a free one is free (a natural end)
      }
    } else if (in == C || out_state == C) {
      // Both directions are fixed: given, or one given and the other turned by the corner.
      const Vec2 d_in = node.in ? *node.in : rotate(*node.out, -node.corner);
      const Vec2 d_out = node.out ? *node.out : rotate(*node.in, node.corner);
      state = 1;
      dir = degrees(d_out);
      corner = std::atan2(cross(d_in, d_out), dot(d_in, d_out)) / kDeg;
    } else {  // as given, not through radians
      corner = i < request.corners_deg.size() ? request.corners_deg[i] : node.corner / kDeg;
    }
    const double radius = i < request.radii.size() ? request.radii[i] : 0.0;
    if (radius > 0.0) {
      // A data ball: its centre, state −r, and in the corner column the angle of the chosen
      // position from the centre (Curve Ensemble's NODEDIR; 0 at the centre).
      const Vec2 off = result.points[i] - request.points[i];
      put(request.points[i].x);
      put(request.points[i].y);
      put(degrees(fitted));
      put(off.x == 0.0 && off.y == 0.0 ? 0.0 : degrees(off));
      put(-radius);
      put(!result.closed && i + 1 == n ? 0.0 : energy[i]);
      out += '\n';
      continue;
    }
    put(result.points[i].x);
    put(result.points[i].y);
    put(dir);
    put(corner);
    out += std::to_string(state);
    out += ' ';
    put(!result.closed && i + 1 == n ? 0.0 : energy[i]);
    out += '\n';
  }
  return out;
}

}  // namespace fairspline::io
