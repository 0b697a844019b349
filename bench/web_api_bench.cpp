// Latency of one live fit of the web editor: POST /api/fit handled end to end (parse the
// request JSON, fit with the full report, serialize the answer) for every method at 200
// points, the editor's budget being <= 16 ms per fit (issue 7). Run with
//   build/bench/fairspline_bench --benchmark_filter=api_fit
// The data is what a user draws: 200 points along a wave across the editor's 1000x700 frame
// (fewer where a method's point-count rule asks: 199 for 3m+1).
#include <cmath>
#include <cstddef>
#include <string>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "capability_inputs.hpp"
#include "fairspline/registry.hpp"
#include "server.hpp"

namespace {

std::string editor_request(const std::string& method, std::size_t n) {
  nlohmann::json points = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    points.push_back({50.0 + 900.0 * t / static_cast<double>(n - 1),
                      350.0 + 200.0 * std::sin(t / 12.0) + 40.0 * std::sin(t / 3.7)});
  }
  const fairspline::MethodInfo& m = fairspline::find_method(method);
  nlohmann::json body = {{"points", points},
                         {"method", method},
                         {"options", fairspline::testing::options_for_any_points(m)}};
  if (m.capabilities.needs_clamped_tangent) body["start_tangent"] = {1.0, 0.0};
  return body.dump();
}

void bm_api_fit(benchmark::State& state, const std::string& method) {
  const std::size_t n = fairspline::testing::accepted_count(fairspline::find_method(method), 200);
  const std::string body = editor_request(method, n);
  const fairspline::web::ServerOptions options;
  const fairspline::web::ApiResponse check = fairspline::web::handle_fit(body, options);
  if (check.status != 200) {
    state.SkipWithError(("the request fails: " + check.body).c_str());
    return;
  }
  for (auto _ : state) {
    fairspline::web::ApiResponse r = fairspline::web::handle_fit(body, options);
    benchmark::DoNotOptimize(r.body.data());
  }
  state.counters["points"] = static_cast<double>(n);
}

const bool kRegistered = [] {
  for (const fairspline::MethodInfo& m : fairspline::methods()) {
    benchmark::RegisterBenchmark(("api_fit/" + m.name + "/200").c_str(), bm_api_fit, m.name)
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
