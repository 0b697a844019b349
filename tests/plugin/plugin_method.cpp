// A throw-away method registered by this test program alone, to prove that adding a method is
// its own file plus one registration: the registry's schema (what the CLI, the web API and
// Python list), the fuzzer's method table, the report and the extremes suite (compiled into this
// program from tests/extremes_test.cpp and run on this method alone) all pick it up with no
// other edit. The method: Catmull–Rom-like C1 cubic Hermite interpolation on the knots,
// derivatives by central differences (one-sided at open ends).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "detail/input.hpp"
#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace fairspline {
namespace {

constexpr const char* kName = "test-catmull-rom";

const Capabilities& catmull_rom_capabilities() {
  static const Capabilities caps{
      .continuity = Continuity::kC1,
      .regular = false,  // a central difference vanishes at an exact reversal
      .examples = {R"({"points": [[0,0],[1,2],[3,3],[5,2],[6,0]]})",
                   R"({"points": [[0,0],[4,0],[4,4],[0,4]], "closed": true})"}};
  return caps;
}

void fit_catmull_rom(const FitInput& input, const nlohmann::json& /*options*/,
                     const FitOptions& /*fit*/, FitResult& out) {
  const std::size_t spans = detail::prepare_input(input, catmull_rom_capabilities(), kName, out);
  const std::vector<Point>& p = out.points;
  const std::vector<double>& t = out.knots;
  const std::size_t n = p.size();
  std::vector<Vec2> m(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!out.closed && i == 0) {
      m[i] = (p[1] - p[0]) / (t[1] - t[0]);
    } else if (!out.closed && i + 1 == n) {
      m[i] = (p[i] - p[i - 1]) / (t[i] - t[i - 1]);
    } else {
      const std::size_t prev = i == 0 ? n - 1 : i - 1, next = i + 1 == n ? 0 : i + 1;
      const double dt = (t[i + 1] - t[i]) + (i == 0 ? t[n] - t[n - 1] : t[i] - t[i - 1]);
      m[i] = (p[next] - p[prev]) / dt;
    }
  }
  out.spline.closed = out.closed;
  out.spline.segments.resize(spans);
  out.tangents.resize(n);
  for (std::size_t i = 0; i < n; ++i) out.tangents[i] = normalized(m[i]);
  for (std::size_t s = 0; s < spans; ++s) {
    const std::size_t e = s + 1 == n ? 0 : s + 1;
    const double h = (t[s + 1] - t[s]) / 3.0;
    out.spline.segments[s] = {{{p[s], p[s] + h * m[s], p[e] - h * m[e], p[e]}}, t[s], t[s + 1], s};
  }
}

// The one registration line (a built-in method has it in src/methods/builtin.cpp).
const bool kRegistered = (register_method({.name = kName,
                                           .description = "Test-only Catmull-Rom C1 spline.",
                                           .paper = "none (a throw-away method of the tests)",
                                           .fit = fit_catmull_rom,
                                           .capabilities = catmull_rom_capabilities()}),
                          true);

TEST(Plugin, RegistrySchemaListsIt) {
  ASSERT_TRUE(kRegistered);
  const nlohmann::json all = registry_schema();
  const auto it = std::find_if(all.begin(), all.end(),
                               [](const nlohmann::json& m) { return m.at("name") == kName; });
  ASSERT_NE(it, all.end());
  EXPECT_EQ(it->at("capabilities").at("continuity"), "C1");
  EXPECT_EQ(it->at("capabilities").at("regular"), false);
  EXPECT_EQ(it->at("examples").size(), 2u);
  EXPECT_EQ(it->at("default"), false);
}

TEST(Plugin, ExamplesFitWithAReport) {
  for (const std::string& e : catmull_rom_capabilities().examples) {
    const io::ParsedInput req = io::parse_json_input(e);
    const FitResult r = fit(kName, req.input, req.options);
    ASSERT_TRUE(r.report.has_value());
    EXPECT_TRUE(r.report->bending_energy.has_value());
    EXPECT_LT(r.report->max_interpolation_residual, 1e-12);
    EXPECT_LT(r.report->max_tangent_angle_jump_deg, 1e-9);  // C1 with non-zero derivatives
    EXPECT_EQ(r.spline.segments.size(), req.input.points.size() - (req.input.closed ? 0 : 1));
  }
}

TEST(Plugin, CapabilitiesAreEnforcedForIt) {
  FitInput in;
  in.points = {{0, 0}, {1, 1}, {2, 0}};
  in.kinds = {PointKind::kSmooth, PointKind::kCorner, PointKind::kSmooth};
  try {
    (void)fit(kName, in);
    FAIL() << "a corner was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(e.index(), std::optional<std::size_t>(1));
    EXPECT_NE(std::string(e.what()).find(kName), std::string::npos) << e.what();
  }
}

TEST(Plugin, TheFuzzerFindsItByName) {
  // fuzz_fit (compiled into this program) names its method as a string: the new method is in
  // its table with no edit, and no committed input changes method.
  std::string bytes = std::string(kName) + '\0';
  bytes += std::string("\x01\x00\x05", 3);  // no reuse; flags 0; five points
  for (int i = 0; i < 5; ++i) bytes += std::string("\x08\x00\x01\x00\x00\x02\x00", 7);
  setenv("FUZZ_FIT_PRINT", "1", 1);
  ::testing::internal::CaptureStderr();
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  const std::string printed = ::testing::internal::GetCapturedStderr();
  unsetenv("FUZZ_FIT_PRINT");
  EXPECT_NE(printed.find(std::string("\"method\":\"") + kName + "\""), std::string::npos)
      << printed;
  EXPECT_EQ(printed.find("\"registered\":false"), std::string::npos) << printed;
}

TEST(Plugin, RegisteringANameTwiceIsAnError) {
  EXPECT_THROW(register_method({.name = kName, .fit = fit_catmull_rom}), Error);
}

}  // namespace
}  // namespace fairspline
