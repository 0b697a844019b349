#include "fairspline/methods/elastic.hpp"

#include <cmath>
#include <numbers>

#include "fairspline/error.hpp"
#include "methods/builtin.hpp"
#include "methods/min_energy_options.hpp"

namespace fairspline {

void fit_elastic(const FitInput& input, const ElasticOptions& options, ReportLevel level,
                 FitResult& out, MinEnergyReport* report) {
  MinEnergyOptions o;
  o.method.basis =
      options.restricted ? MinEnergyBasis::kRestrictedElastic : MinEnergyBasis::kElastic;
  const double omega_deg =
      std::isnan(options.omega_deg)
          ? BasicCurveMethod::default_omega(o.method.basis) * 180.0 / std::numbers::pi
          : options.omega_deg;
  if (options.restricted && !(omega_deg > 0.0 && omega_deg <= 90.0)) {
    throw Error(ErrorCode::kBadOption,
                "restricted-elastic: omega_deg must lie in (0, 90] (the elastic method allows "
                "up to 180)");
  }
  o.method.omega = omega_deg * std::numbers::pi / 180.0;
  o.max_iterations = options.max_iterations;
  o.search = options.search;
  o.accuracy = options.accuracy;
  o.best_effort = options.best_effort;
  fit_min_energy(input, o, level, out, report);
}

namespace {

// The framework's node kinds; examples with sharp turns, where the pieces are far from cubics.
Capabilities elastic_capabilities() {
  Capabilities caps{
      .kinds = {PointKind::kSmooth, PointKind::kClamped, PointKind::kCorner},
      .continuity = Continuity::kG2,
      .node_states = true,
      .data_balls = true,
      .examples = {R"({"points": [[1,90],[3,105],[6,120],[10,100],[12,85],[15,104],[17,80]]})",
                   R"({"points": [[0,0],[3,0],[1,1],[3,2],[0,2]], "closed": true})",
                   R"({"points": [[0,0],[2,1],[4,0],[6,1]], "kinds": ["clamped","smooth",
              "corner","smooth"], "tangents": [[0,1],null,null,null]})"}};
  return caps;
}

MethodInfo make(bool restricted) {
  const double max_omega = restricted ? 90.0 : 180.0;
  return MethodInfo{
      .name = restricted ? "restricted-elastic" : "elastic",
      .description =
          restricted
              ? "Restricted elastic spline (Curve Ensemble's default): the curve of least "
                "bending energy whose pieces are s-curves turning at most 90 degrees from "
                "their chords; exact elastica pieces output as cubic Beziers within the "
                "accuracy; G2 wherever no bound is active."
              : "Elastic spline: the curve of least bending energy whose pieces are s-curves "
                "(end angles below 180 degrees, |alpha - beta| <= 180 degrees); pieces may "
                "make U-turns; a local minimum reached from the restricted elastic spline.",
      .paper =
          "A. Borbely, M. J. Johnson, Elastic Splines I: Existence, Constr. Approx. 40 "
          "(2014); M. J. Johnson, H. S. Johnson, A constructive framework for minimal "
          "energy planar curves, Section 1, Remark 4.5",
      .options = {{.name = "omega_deg",
                   .type = OptionType::kNumber,
                   .default_value = max_omega,
                   .min = 0.0,
                   .max = max_omega,
                   .doc = restricted ? "feasibility bound: |angle of each end direction to its "
                                       "chord| <= omega_deg, at most 90"
                                     : "feasibility bound: |angle of each end direction to its "
                                       "chord| <= omega_deg, at most 180"},
                  {.name = "max_iterations",
                   .type = OptionType::kInteger,
                   .default_value = nullptr,
                   .min = 1.0,
                   .max = 100000.0,
                   .doc = detail::kMaxIterationsDoc},
                  detail::min_energy_search_option()},
      .fit =
          [restricted](const FitInput& in, const nlohmann::json& o, const FitOptions& f,
                       FitResult& out) {
            ElasticOptions opt;
            opt.restricted = restricted;
            opt.omega_deg = o.at("omega_deg").get<double>();
            if (o.contains("max_iterations"))
              opt.max_iterations = o.at("max_iterations").get<int>();
            opt.search = detail::parse_min_energy_search(o);
            opt.accuracy = f.curve_accuracy();
            opt.best_effort = f.best_effort;
            fit_elastic(in, opt, f.method_report_level(), out);
          },
      .capabilities = elastic_capabilities(),
      .report_units = detail::min_energy_report_units(),
  };
}

}  // namespace

namespace detail {

std::vector<MethodInfo> elastic_methods() {
  return {make(true), make(false)};
}

}  // namespace detail

}  // namespace fairspline
