// Writing a fit's JSON into a new string (the web server's responses, Python's to_json and
// pickle) against writing it to a stream in 1 MiB pieces (`fairspline fit`), measured in the
// same run on a 2·10^5-point random walk fitted with the default method.
//   json-write/string/200000    io::write_json(result) into a new std::string each time
//   json-write/stream/200000    io::write_json(result, stream) to a stream that drops the bytes
//   json-write/ratio/200000     both alternated; counter string_over_stream, the best of each
//                               (goal <= 1.25: a string's growth once cost 8 times the writing)
//   json-read/fit-result/<n>    io::read_fit_result of that text for n-point walks (Python's
//                               from_json and unpickling); linear in n (BigO): nlohmann's parser
//                               with a callback made it quadratic in the segments (4·10^4
//                               points: 1.17 s; by the DOM alone 0.22 s; the fast reader 26-33 ms)
#include <algorithm>
#include <chrono>
#include <limits>
#include <ostream>
#include <streambuf>
#include <string>

#include <benchmark/benchmark.h>

#include "bench_data.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"

namespace {

constexpr std::size_t kPoints = 200'000;

const fairspline::FitResult& fitted() {
  static const fairspline::FitResult r =
      fairspline::fit(fairspline::default_method_name(), fairspline::bench::walk_input(kPoints), {},
                      fairspline::ReportLevel::kNone);
  return r;
}

/// A stream whose bytes go nowhere (counted, so the writing cannot be optimized away).
class NullBuffer : public std::streambuf {
 public:
  std::size_t bytes = 0;

 protected:
  std::streamsize xsputn(const char*, std::streamsize n) override {
    bytes += static_cast<std::size_t>(n);
    return n;
  }
  int_type overflow(int_type c) override {
    ++bytes;
    return c;
  }
};

std::size_t write_string() {
  const std::string text = fairspline::io::write_json(fitted());
  benchmark::DoNotOptimize(text.data());
  return text.size();
}

std::size_t write_stream() {
  NullBuffer buffer;
  std::ostream out(&buffer);
  fairspline::io::write_json(fitted(), out);
  return buffer.bytes;
}

void bm_read(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const std::string text = fairspline::io::write_json(
      fairspline::fit(fairspline::default_method_name(), fairspline::bench::walk_input(n), {},
                      fairspline::ReportLevel::kNone));
  for (auto _ : state) {
    const fairspline::FitResult r = fairspline::io::read_fit_result(text);
    benchmark::DoNotOptimize(r.spline.segments.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(text.size()));
  state.SetComplexityN(static_cast<std::int64_t>(n));
}

template <std::size_t (*Write)()>
void bm_write(benchmark::State& state) {
  std::size_t bytes = 0;
  for (auto _ : state) bytes += Write();
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
}

void bm_ratio(benchmark::State& state) {
  using clock = std::chrono::steady_clock;
  double best_string = std::numeric_limits<double>::infinity(), best_stream = best_string;
  for (auto _ : state) {
    const auto t0 = clock::now();
    write_string();
    const auto t1 = clock::now();
    write_stream();
    const auto t2 = clock::now();
    best_string = std::min(best_string, std::chrono::duration<double>(t1 - t0).count());
    best_stream = std::min(best_stream, std::chrono::duration<double>(t2 - t1).count());
  }
  state.counters["string_ms"] = 1e3 * best_string;
  state.counters["stream_ms"] = 1e3 * best_stream;
  state.counters["string_over_stream"] = best_string / best_stream;
}

[[maybe_unused]] const bool kRegistered = [] {
  const auto name = [](const char* what) {
    return std::string("json-write/").append(what).append("/").append(std::to_string(kPoints));
  };
  benchmark::RegisterBenchmark(name("string").c_str(), bm_write<write_string>)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(name("stream").c_str(), bm_write<write_stream>)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(name("ratio").c_str(), bm_ratio)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("json-read/fit-result", bm_read)
      ->Arg(10'000)
      ->Arg(20'000)
      ->Arg(40'000)
      ->Complexity()
      ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
