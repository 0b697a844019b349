// Curve Ensemble's node model, resolved per point: the side states with their directions and
// the corner angle, from FitInput's kinds / states, tangents / in_tangents / out_tangents,
// corners_deg and the end tangents. See docs/methods/min-energy.md, "Node states".
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "fairspline/fit.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline::detail {

struct ResolvedNode {
  NodeState state;
  std::optional<Vec2> in, out;  ///< the directions of clamped sides
  double corner = 0.0;          ///< radians, from the incoming to the outgoing direction

  /// A side of this node is optimized on its own (the curve splits into pieces here).
  bool splits() const { return state.in == SideState::kFree || state.out == SideState::kFree; }
};

/// True when the input uses the node model beyond `kinds` (states, per-side tangents, corners).
bool uses_node_model(const FitInput& input);

/// The nodes of the first n points (n: without a closed curve's repeated end point). Throws
/// Error(kInvalidArgument) for arrays of the wrong length, `kinds` and `states` both given, a
/// side given by both `tangents` and in/out_tangents, a clamped side without a direction, a
/// corner on a node with a free side, and Error(kNonFinite) for a non-finite corner; every
/// error names the point. The open curve's start_tangent clamps point 0's outgoing side and
/// end_tangent the last point's incoming side.
std::vector<ResolvedNode> resolve_nodes(const FitInput& input, std::size_t n);

/// The input with `states` etc. rewritten as `kinds` and `tangents`, for methods that honour
/// only kinds; nullopt when some node is not expressible that way (a half state, a corner,
/// different directions on the two sides), with `bad` set to the first such point.
std::optional<FitInput> as_kinds(const FitInput& input, std::size_t n, std::size_t& bad);

}  // namespace fairspline::detail
