// The common input and output of every fitting method.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "fairspline/spline.hpp"
#include "fairspline/vec2.hpp"

namespace fairspline {

/// Role of an input point (Johnson–Johnson / Curve Ensemble node kinds).
enum class PointKind {
  kSmooth,   ///< the method chooses the tangent
  kClamped,  ///< the tangent given in FitInput::tangents is kept
  kCorner,   ///< G0 point: the curve splits into independent pieces here
};

/// State of one side (incoming or outgoing direction) of a node: Curve Ensemble's node model
/// (docs/methods/min-energy.md, "Node states").
enum class SideState {
  kRegular,  ///< optimized together with the other side, which keeps the node's corner angle
  kClamped,  ///< given: FitInput::in_tangents / out_tangents, or tangents for both sides
  kFree,     ///< optimized on its own: the adjacent piece ends free here (Remark 2.4 (a))
};

/// The states of a node's incoming and outgoing sides.
struct NodeState {
  SideState in = SideState::kRegular;
  SideState out = SideState::kRegular;
  bool operator==(const NodeState&) const = default;
};

/// What a fit is asked to do. Everything but `points` is optional.
struct FitInput {
  std::vector<Point> points;
  bool closed = false;
  /// Exponent of the alpha-parameterization (0 uniform, 0.5 centripetal, 1 chordal).
  double alpha = kDefaultAlpha;
  /// Explicit knots; when non-empty they replace the alpha-parameterization.
  std::vector<double> knots;
  /// Per-point tangent vectors (empty, or one optional entry per point).
  std::vector<std::optional<Vec2>> tangents;
  /// Per-point kinds (empty = all smooth). smooth = regular/regular, clamped = clamped/clamped,
  /// corner = free/free in the node model; give `kinds` or `states`, not both.
  std::vector<PointKind> kinds;
  /// Per-point side states (empty = from `kinds`).
  std::vector<NodeState> states;
  /// Per-point clamped directions of one side (empty, or one optional entry per point); a
  /// side given here must not also be given by `tangents`, which sets both sides.
  std::vector<std::optional<Vec2>> in_tangents, out_tangents;
  /// Per-point corner angle in degrees, from the incoming to the outgoing direction
  /// (counterclockwise positive), kept by a regular node while its direction is optimized;
  /// with one clamped direction it gives the other side's (empty = all 0).
  std::vector<double> corners_deg;
  /// Per-point data-ball radius (empty = all 0): a point with radius r > 0 is a disc the curve
  /// passes through anywhere, its position chosen with the directions to minimize the energy
  /// (min-energy family; docs/methods/min-energy.md, "Data balls"). r = 0 interpolates.
  std::vector<double> radii;
  /// Clamped end tangents of an open curve (derivative with respect to the knot parameter
  /// for C1 methods; only the direction matters for G1 methods).
  std::optional<Vec2> start_tangent;
  std::optional<Vec2> end_tangent;

  static constexpr double kDefaultAlpha = 0.5;
};

/// How much of the report to compute. Timing a fit should use kNone.
enum class ReportLevel {
  kNone,   ///< no report
  kBasic,  ///< the default: linearized energy, joints, regularity certificate, residual, and
           ///< the quadratures of bending energy and length (about 2× the default fit's time)
  kFull,   ///< + per-piece reports, curvature-variation energy, cusps, folds and loops,
           ///< self-intersections (about 10× the fit's time)
};

/// Per-segment diagnostics (full report).
struct SegmentReport {
  double linearized_energy = 0.0;           ///< ∫|s''(t)|² dt over the piece
  double bending_energy = 0.0;              ///< ∫κ² ds
  double curvature_variation_energy = 0.0;  ///< ∫(dκ/ds)² ds
  double length = 0.0;
  bool regular = true;              ///< speed certified positive
  double min_relative_speed = 0.0;  ///< min |c'(u)| / chord, lower bound from certificate
  bool has_loop = false;            ///< self-intersection within the piece
  bool has_cusp = false;
  bool has_fold = false;
};

/// A self-intersection found between or within pieces.
struct Intersection {
  std::size_t segment_a = 0;
  std::size_t segment_b = 0;
  double u_a = 0.0;
  double u_b = 0.0;
  Point point;
};

/// The report of a fitted spline; fields not computed at the requested level stay nullopt.
struct Report {
  std::optional<double> bending_energy;
  double linearized_energy = 0.0;
  std::optional<double> curvature_variation_energy;
  std::optional<double> length;
  bool regular = true;
  double max_tangent_angle_jump_deg = 0.0;
  double max_curvature_jump = 0.0;
  double min_relative_speed = 0.0;
  double max_interpolation_residual = 0.0;
  /// Bending / curvature-variation quadratures that met a vanishing speed are flagged here
  /// instead of returning a meaningless number.
  bool energy_singular = false;
  std::vector<SegmentReport> segments;      ///< full level only
  std::vector<Intersection> intersections;  ///< full level only
};

/// How an iterative step of a method ended.
enum class SolverStatus {
  kConverged,          ///< the stopping test holds at the returned point
  kConditioningLimit,  ///< the tolerance is below what double precision allows at this
                       ///< conditioning; the point is optimal to that limit (not an error)
  kIterationLimit,  ///< stopped at the iteration cap (returned only with FitOptions::best_effort)
  kStalled,         ///< no admissible step improves the residual (returned only with best_effort)
};

/// The outcome of a method's iterative step (min-energy's projected Newton, Kozak–Krajnc's G2
/// Newton, ...), the same for every method that has one.
struct SolverReport {
  SolverStatus status = SolverStatus::kConverged;
  int iterations = 0;
  double residual = 0.0;              ///< final value of the stopping test's quantity
  double tolerance = 0.0;             ///< what it had to reach
  std::vector<std::size_t> active{};  ///< points whose unknowns sit on a bound (constraint)
};

/// What every method returns.
struct FitResult {
  std::string method;
  bool closed = false;
  nlohmann::json options = nlohmann::json::object();  ///< resolved options, defaults filled in
  std::vector<Point> points;                          ///< the points actually interpolated
  std::vector<double> knots;                          ///< t_i at each point (+1 when closed)
  std::vector<Vec2> tangents;                         ///< unit tangent direction at each point
  Spline spline;
  std::optional<Report> report;
  /// The iterative step's outcome; nullopt for methods that are closed-form.
  std::optional<SolverReport> solver;
  nlohmann::json method_report = nlohmann::json::object();
  /// The request as fit() received it (node model, kinds, tangents, alpha, knots), so that
  /// the same curve can be fitted again (refit_input): its `points` are empty when they equal
  /// `points` above (they differ when a closed curve's repeated last point was dropped or a
  /// method inserted points).
  FitInput input;
  /// The approximation accuracy that was asked for (FitOptions::accuracy).
  std::optional<double> accuracy;
};

/// Whether the calling thread keeps a fit's large temporary blocks (64 KiB and more) for its
/// next fit: true, the default, so that fits in a loop reuse mapped memory (a steady-state fit
/// takes no page fault; a thread holds up to ~200 MB after a 10^6-point fit); false frees the
/// blocks kept so far and every one given back from then on, so that a single fit's result is
/// not written beside its freed work memory (the command line's `fit`: 2·10^5 points, peak
/// 84 MB kept against 57 MB freed).
void keep_fit_memory(bool keep);

/// The input that fits `result` again: result.input with its points filled in. With
/// result.method, result.options and result.accuracy, fit() gives the same curve bit for bit.
FitInput refit_input(const FitResult& result);

/// How far a long fit has come: what FitOptions::progress is called with.
struct FitProgress {
  /// What runs: "newton" (a min-energy method's projected Newton), "coordinate search",
  /// "global search", "data balls", "g2" (Kozak–Krajnc's G2 Newton), "g2 scan" (its search
  /// for G2 starts), "report".
  std::string_view stage;
  std::size_t done = 0;   ///< steps of the stage done (iterations, nodes of a pass, pieces)
  std::size_t total = 0;  ///< the stage's steps at most; 0 when not known in advance
  double seconds = 0.0;   ///< since the fit began
};

/// How a fit runs and what it reports, the same for every method.
struct FitOptions {
  ReportLevel level = ReportLevel::kBasic;
  /// Relative accuracy of every approximation: quadratures of the report and the intersection
  /// search (relative to the quantity, or to the piece's size), approximations of
  /// non-polynomial curves by Béziers (Hausdorff distance relative to the data's size, the
  /// diagonal of the points' bounding box). Not given: each approximation's default,
  /// kDefaultAccuracy for the report, kDefaultCurveAccuracy for the curve.
  std::optional<double> accuracy{};
  /// Per-node and per-segment entries in method_report (false: only what is O(1) in size, as
  /// with level kNone). At 10^6 points those entries cost several times the fit itself.
  bool diagnostics = true;
  /// A solver that stops short of its tolerance (iteration cap, no admissible step) returns its
  /// curve with that status (FitResult::solver) instead of failing with code not_converged.
  bool best_effort = false;

  /// Seconds a fit may take: past them it stops with Error(cancelled). The iterative methods
  /// look at the clock between their steps (a Newton iteration, a node of a grid pass, a data
  /// ball step), so the stop comes within one step; a closed-form method is only stopped
  /// before its report.
  std::optional<double> time_limit{};
  /// Called on the fit's thread between the steps of long work, at most every
  /// `progress_interval` seconds and first after it (a fit shorter than that never calls it).
  /// Returning false stops the fit with Error(cancelled); an exception it throws ends the fit
  /// and reaches the caller.
  std::function<bool(const FitProgress&)> progress{};
  double progress_interval = 0.5;

  static constexpr double kDefaultAccuracy = 1e-9;
  /// Béziers of non-polynomial curves (the elastic splines): far below what any drawing shows,
  /// a few cubics per span.
  static constexpr double kDefaultCurveAccuracy = 1e-6;
  double report_accuracy() const { return accuracy.value_or(kDefaultAccuracy); }
  /// The level a method builds its method_report at: `level`, or kNone without diagnostics.
  ReportLevel method_report_level() const { return diagnostics ? level : ReportLevel::kNone; }
  double curve_accuracy() const { return accuracy.value_or(kDefaultCurveAccuracy); }
};

}  // namespace fairspline
