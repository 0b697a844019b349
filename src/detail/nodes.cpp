#include "detail/nodes.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "detail/finite.hpp"
#include "detail/format.hpp"
#include "detail/input.hpp"
#include "fairspline/error.hpp"

namespace fairspline::detail {

namespace {

std::string point(std::size_t i) {
  return "point " + std::to_string(i);
}

Vec2 rotated(Vec2 v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}

NodeState state_of(PointKind kind) {
  switch (kind) {
    case PointKind::kClamped:
      return {SideState::kClamped, SideState::kClamped};
    case PointKind::kCorner:
      return {SideState::kFree, SideState::kFree};
    case PointKind::kSmooth:
      break;
  }
  return {};
}

template <class T>
std::optional<T> entry(const std::vector<std::optional<T>>& v, std::size_t i) {
  return i < v.size() ? v[i] : std::nullopt;
}

}  // namespace

bool uses_node_model(const FitInput& input) {
  return !input.states.empty() || !input.in_tangents.empty() || !input.out_tangents.empty() ||
         !input.corners_deg.empty();
}

std::vector<ResolvedNode> resolve_nodes(const FitInput& input, std::size_t n) {
  const std::size_t given = input.points.size();
  auto check_size = [&](std::size_t size, const char* what) {
    if (size != 0 && size != given && size != n) {
      throw Error(ErrorCode::kInvalidArgument, std::string(what) + " has " + std::to_string(size) +
                                                   " entries but there are " + std::to_string(n) +
                                                   " points");
    }
  };
  check_size(input.states.size(), "states");
  check_size(input.in_tangents.size(), "in_tangents");
  check_size(input.out_tangents.size(), "out_tangents");
  check_size(input.corners_deg.size(), "corners_deg");
  if (!input.kinds.empty() && !input.states.empty()) {
    throw Error(ErrorCode::kInvalidArgument,
                "the node kinds are given twice, as kinds and as states; give one of them");
  }
  const bool open = !input.closed;
  std::vector<ResolvedNode> nodes(n);
  for (std::size_t i = 0; i < n; ++i) {
    ResolvedNode& r = nodes[i];
    if (i < input.states.size()) {
      r.state = input.states[i];
    } else if (i < input.kinds.size()) {
      r.state = state_of(input.kinds[i]);
    }
    const std::optional<Vec2> both = entry(input.tangents, i);
    const std::optional<Vec2> in = entry(input.in_tangents, i), out = entry(input.out_tangents, i);
    if (both && (in || out)) {
      throw Error(ErrorCode::kInvalidArgument,
                  point(i) + " has a direction in tangents and in " +
                      (in ? "in_tangents" : "out_tangents") +
                      "; tangents sets both sides, so give one or the other",
                  i);
    }
    if (in) check_tangent(*in, "incoming tangent", i);
    if (out) check_tangent(*out, "outgoing tangent", i);
    r.in = in ? in : both;
    r.out = out ? out : both;
    if (i < input.corners_deg.size()) {
      const double c = input.corners_deg[i];
      if (!std::isfinite(c)) {
        throw Error(ErrorCode::kNonFinite, point(i) + " has a corner angle that is not finite", i);
      }
      if (!(std::abs(c) < 180.0)) {
        throw Error(ErrorCode::kInvalidArgument,
                    point(i) + " has the corner angle " + format_number(c) +
                        "°; it must lie strictly between -180° and 180°",
                    i);
      }
      r.corner = c * std::numbers::pi / 180.0;
    }
    if (r.corner != 0.0) {
      const bool end = open && (i == 0 || i + 1 == n);
      if (end || r.splits()) {
        throw Error(ErrorCode::kInvalidArgument,
                    point(i) + " has a corner angle, but " +
                        (end ? "it is an end of the open curve"
                             : "a side of it is free (a corner is kept only between two "
                               "directions that are regular or clamped)"),
                    i);
      }
      if (in && out) {
        throw Error(ErrorCode::kInvalidArgument,
                    point(i) +
                        " has both directions and a corner angle; give the two directions or "
                        "one of them and the corner",
                    i);
      }
      // One direction for both sides (tangents) and a corner: the corner turns the outgoing.
      if (both && r.state.out == SideState::kClamped) r.out = rotated(*both, r.corner);
    }
  }
  if (open && n > 0) {
    if (input.start_tangent) {
      nodes[0].state.out = SideState::kClamped;
      nodes[0].out = input.start_tangent;
    }
    if (input.end_tangent) {
      nodes[n - 1].state.in = SideState::kClamped;
      nodes[n - 1].in = input.end_tangent;
    }
  } else if (n > 0 && input.start_tangent) {
    nodes[0].state = {SideState::kClamped, SideState::kClamped};
    nodes[0].in = nodes[0].out = input.start_tangent;
  }
  for (std::size_t i = 0; i < n; ++i) {
    ResolvedNode& r = nodes[i];
    const bool has_in = !open || i > 0, has_out = !open || i + 1 < n;
    // A clamped side without a direction of its own takes the other clamped side's, turned by
    // the corner; a regular side beside a clamped one is held by the corner too.
    const bool joined = !r.splits();
    if (joined && !r.in && r.out && has_in) r.in = rotated(*r.out, -r.corner);
    if (joined && !r.out && r.in && has_out) r.out = rotated(*r.in, r.corner);
    if (has_in && r.state.in == SideState::kClamped && !r.in) {
      throw Error(ErrorCode::kInvalidArgument,
                  point(i) +
                      " is clamped on its incoming side but has no direction there: give "
                      "tangents or in_tangents",
                  i);
    }
    if (has_out && r.state.out == SideState::kClamped && !r.out) {
      throw Error(ErrorCode::kInvalidArgument,
                  point(i) +
                      " is clamped on its outgoing side but has no direction there: give "
                      "tangents or out_tangents",
                  i);
    }
  }
  return nodes;
}

std::optional<FitInput> as_kinds(const FitInput& input, std::size_t n, std::size_t& bad) {
  FitInput plain = input;
  plain.states.clear();
  plain.in_tangents.clear();
  plain.out_tangents.clear();
  plain.corners_deg.clear();
  plain.kinds.assign(n, PointKind::kSmooth);
  plain.tangents.assign(n, std::nullopt);
  const bool open = !input.closed;
  for (std::size_t i = 0; i < n; ++i) {
    bad = i;
    NodeState s = i < input.states.size()  ? input.states[i]
                  : i < input.kinds.size() ? state_of(input.kinds[i])
                                           : NodeState{};
    const double corner = i < input.corners_deg.size() ? input.corners_deg[i] : 0.0;
    std::optional<Vec2> in = entry(input.in_tangents, i), out = entry(input.out_tangents, i);
    const std::optional<Vec2> both = entry(input.tangents, i);
    if (!in) in = both;
    if (!out) out = both;
    // At the ends of an open curve only one side exists: the other takes its state.
    if (open && i == 0) s.in = s.out, in = out;
    if (open && i + 1 == n) s.out = s.in, out = in;
    if (corner != 0.0) return std::nullopt;
    if (s.in == SideState::kFree || s.out == SideState::kFree) {
      if (!(s.in == SideState::kFree && s.out == SideState::kFree) &&
          !(open && (i == 0 || i + 1 == n))) {
        return std::nullopt;  // a half state
      }
      plain.kinds[i] = open && (i == 0 || i + 1 == n) ? PointKind::kSmooth : PointKind::kCorner;
    } else if (s.in == SideState::kClamped || s.out == SideState::kClamped) {
      if (s.in != s.out || !in || !out || !(in->x == out->x && in->y == out->y)) {
        return std::nullopt;
      }
      plain.kinds[i] = PointKind::kClamped;
      plain.tangents[i] = in;
    }
    if (plain.kinds[i] != PointKind::kClamped && both) plain.tangents[i] = both;
  }
  return plain;
}

}  // namespace fairspline::detail
