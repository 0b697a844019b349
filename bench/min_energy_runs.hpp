// The two benchmarks every basis of the minimal-energy framework gets (private to bench/):
//   reference/<name>/N   min_energy_reference, the Curve-Ensemble-like coordinate search
//   newton/<name>/N      fit_min_energy on the same walk
// with counters "energy" (both; equal or lower for Newton is the goal), "iterations" and
// "beziers_per_span" (Newton).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "bench_data.hpp"
#include "fairspline/methods/min_energy.hpp"

namespace fairspline::bench {

inline void register_min_energy_runs(const std::string& name, const MinEnergyOptions& opt,
                                     std::int64_t n,
                                     std::optional<std::int64_t> reference_iterations = {}) {
  auto* ref =
      benchmark::RegisterBenchmark(("reference/" + name).c_str(), [opt](benchmark::State& state) {
        const auto size = static_cast<std::size_t>(state.range(0));
        const FitInput& in = walk_input(size);
        double energy = 0.0;
        for (auto _ : state) {
          const MinEnergyReference r = min_energy_reference(in, opt);
          benchmark::DoNotOptimize(r.angles.data());
          energy = r.energy;
        }
        state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                                static_cast<std::int64_t>(size));
        state.counters["energy"] = energy;
      });
  ref->Arg(n)->Unit(benchmark::kMillisecond);
  if (reference_iterations) ref->Iterations(*reference_iterations);
  benchmark::RegisterBenchmark(
      ("newton/" + name).c_str(),
      [opt](benchmark::State& state) {
        const auto size = static_cast<std::size_t>(state.range(0));
        const FitInput& in = walk_input(size);
        FitResult out;
        MinEnergyReport rep;
        for (auto _ : state) {
          fit_min_energy(in, opt, ReportLevel::kNone, out, &rep);
          benchmark::DoNotOptimize(out.spline.segments.data());
        }
        state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                                static_cast<std::int64_t>(size));
        state.counters["energy"] = rep.energy;
        state.counters["iterations"] = rep.iterations;
        state.counters["beziers_per_span"] =
            static_cast<double>(out.spline.segments.size()) / static_cast<double>(size - 1);
      })
      ->Arg(n)
      ->Unit(benchmark::kMillisecond);
}

}  // namespace fairspline::bench
