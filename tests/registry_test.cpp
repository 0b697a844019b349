#include "fairspline/registry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>

#include "capability_inputs.hpp"
#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

TEST(Registry, ListsLiMethodsAndDefault) {
  std::vector<std::string> names;
  for (const auto& m : methods()) names.push_back(m.name);
  for (const char* expected : {"li-strain", "li-combined", "li-curvature-variation"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }
  EXPECT_NO_THROW(find_method(default_method_name()));
}

TEST(Registry, UnknownMethodListsAlternatives) {
  try {
    find_method("li-strian");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnknownMethod);
    EXPECT_NE(std::string(e.what()).find("li-strain"), std::string::npos);
  }
}

TEST(Registry, ResolveOptionsFillsDefaultsAndValidates) {
  const MethodInfo& m = find_method("li-combined");
  const auto resolved = resolve_options(m, nlohmann::json::object());
  EXPECT_EQ(resolved.at("weights"), nlohmann::json({1.0, 1.0}));
  EXPECT_EQ(resolve_options(m, {{"weights", {2, 3}}}).at("weights"), nlohmann::json({2, 3}));
  EXPECT_THROW(resolve_options(m, {{"weights", "heavy"}}), Error);
  EXPECT_THROW(resolve_options(m, {{"weights", {1, -2}}}), Error);
  EXPECT_THROW(resolve_options(m, {{"nope", 1}}), Error);
  EXPECT_THROW(resolve_options(m, nlohmann::json::array()), Error);
  EXPECT_THROW(resolve_options(find_method("li-strain"), {{"weights", {1, 1}}}), Error);
}

TEST(Registry, OptionTypeChecks) {
  MethodInfo m;
  m.name = "demo";
  m.options = {{"n", OptionType::kInteger, 3, 1.0, 10.0, {}, ""},
               {"flag", OptionType::kBoolean, false, std::nullopt, std::nullopt, {}, ""},
               {"mode", OptionType::kChoice, "a", std::nullopt, std::nullopt, {"a", "b"}, ""},
               {"lam", OptionType::kChoiceOrNumber, "optimal", 0.0, 1.0, {"optimal"}, ""}};
  EXPECT_EQ(resolve_options(m, {{"n", 4}}).at("n"), 4);
  EXPECT_THROW(resolve_options(m, {{"n", 4.5}}), Error);
  EXPECT_THROW(resolve_options(m, {{"n", 11}}), Error);
  EXPECT_EQ(resolve_options(m, {{"flag", 1}}).at("flag"), true);
  EXPECT_EQ(resolve_options(m, {{"flag", "false"}}).at("flag"), false);
  EXPECT_THROW(resolve_options(m, {{"flag", "maybe"}}), Error);
  EXPECT_THROW(resolve_options(m, {{"mode", "c"}}), Error);
  EXPECT_EQ(resolve_options(m, {{"lam", 0.25}}).at("lam"), 0.25);
  EXPECT_EQ(resolve_options(m, {}).at("lam"), "optimal");
  EXPECT_THROW(resolve_options(m, {{"lam", 1.5}}), Error);
}

// A string option from the command line (--set key=VALUE) may be invalid UTF-8: the message
// quoting it used json::dump, which threw a type_error instead of the promised Error.
TEST(Registry, BadOptionWithInvalidUtf8GivesAnError) {
  try {
    resolve_options(find_method("jaklic-zagar"), {{"reversal", "\xff"}});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kBadOption);
  }
}

TEST(Registry, SchemaJson) {
  const auto s = method_schema(find_method("li-combined"));
  EXPECT_EQ(s.at("name"), "li-combined");
  ASSERT_EQ(s.at("options").size(), 1u);
  EXPECT_EQ(s.at("options")[0].at("type"), "number_list");
  EXPECT_EQ(s.at("options")[0].at("min"), 0.0);
}

TEST(Registry, FitFillsMethodOptionsAndReport) {
  FitInput in;
  in.points = {{0, 0}, {1, 1}, {2, 0}, {3, 1}};
  const FitResult r = fit("li-combined", in, {}, ReportLevel::kBasic);
  EXPECT_EQ(r.method, "li-combined");
  EXPECT_EQ(r.options.at("weights"), nlohmann::json({1.0, 1.0}));
  ASSERT_TRUE(r.report.has_value());
  EXPECT_TRUE(r.report->regular);
  EXPECT_LT(r.report->max_interpolation_residual, 1e-15);
  EXPECT_FALSE(fit("li-combined", in, {}, ReportLevel::kNone).report.has_value());
}

}  // namespace
}  // namespace fairspline

namespace fairspline {
namespace {

// ---- capabilities ----

TEST(RegistryCapabilities, EveryExampleRequestFits) {
  for (const MethodInfo& m : methods()) {
    ASSERT_FALSE(m.capabilities.examples.empty()) << m.name << " has no example request";
    for (const std::string& e : m.capabilities.examples) {
      SCOPED_TRACE(m.name + " " + e);
      const io::ParsedInput req = io::parse_json_input(e);
      EXPECT_FALSE(req.method.has_value()) << "examples name no method: they belong to one";
      const FitResult r = fit(m.name, req.input, req.options);
      EXPECT_FALSE(r.spline.segments.empty());
      EXPECT_EQ(req.input.closed, r.closed);
      if (m.capabilities.regular) {
        EXPECT_TRUE(r.report->regular);
      }
    }
  }
}

TEST(RegistryCapabilities, WithoutDiagnosticsTheMethodReportIsOfConstantSize) {
  // FitOptions::diagnostics = false: at any report level the method_report is the one of level
  // none, whose size does not grow with the points, while the Report is still computed.
  auto dump = [](const MethodInfo& m, std::size_t n, FitOptions f) {
    FitInput in;
    for (std::size_t i = 0; i < n; ++i) in.points.push_back({0.5 * i, std::sin(0.9 * i)});
    testing::clamp_if_needed(m, in);
    const FitResult r = fit(m.name, in, testing::options_for_any_points(m), f);
    EXPECT_EQ(r.report.has_value(), f.level != ReportLevel::kNone);
    return r.method_report.dump();
  };
  int with_entries = 0;
  for (const MethodInfo& m : methods()) {
    SCOPED_TRACE(m.name);
    for (const ReportLevel level : {ReportLevel::kBasic, ReportLevel::kFull}) {
      const std::string quiet = dump(m, 301, {.level = level, .diagnostics = false});
      EXPECT_EQ(quiet, dump(m, 301, {.level = ReportLevel::kNone}));
      const std::size_t small = dump(m, 31, {.level = level, .diagnostics = false}).size();
      EXPECT_LT(quiet.size(), small + 64);  // (the numbers' digits differ)
      with_entries += dump(m, 301, {.level = level}).size() > 4 * quiet.size();
    }
  }
  EXPECT_GE(with_entries, 10);  // the methods with per-point entries lose them
}

TEST(RegistryCapabilities, SchemaShowsThem) {
  const nlohmann::json all = registry_schema();
  ASSERT_EQ(all.size(), methods().size());
  for (const nlohmann::json& s : all) {
    const Capabilities& c = find_method(s.at("name").get<std::string>()).capabilities;
    const nlohmann::json& j = s.at("capabilities");
    EXPECT_EQ(j.at("closed"), c.closed);
    EXPECT_EQ(j.at("continuity"), continuity_name(c.continuity));
    EXPECT_EQ(j.at("tangents"), tangent_use_name(c.tangents));
    EXPECT_EQ(j.at("points").at("min_open"), c.points.min_open);
    EXPECT_EQ(s.at("examples").size(), c.examples.size());
    EXPECT_EQ(j.at("kinds").at(0), "smooth");
  }
  const nlohmann::json kk = method_schema(find_method("kozak-krajnc")).at("capabilities");
  EXPECT_EQ(kk.at("points").at("step"), 3);
  EXPECT_EQ(kk.at("points").at("relaxed_by"), nlohmann::json({{"remainder", "hermite"}}));
  EXPECT_EQ(kk.at("closed"), false);
}

/// Each rule, for every method that declares it, gives the same code, index and sentence.
TEST(RegistryCapabilities, PrepareInputEnforcesThemForEveryMethod) {
  for (const MethodInfo& m : methods()) {
    SCOPED_TRACE(m.name);
    const Capabilities& c = m.capabilities;
    if (!c.honours(PointKind::kCorner)) {
      io::ParsedInput req = io::parse_json_input(c.examples.front());
      req.input.kinds.assign(req.input.points.size(), PointKind::kSmooth);
      req.input.kinds[1] = PointKind::kCorner;
      testing::expect_error(ErrorCode::kInvalidArgument,
                            [&] { fit(m.name, req.input, req.options); },
                            {"point 1 is a corner, but "});
    }
    if (!c.closed) {
      io::ParsedInput req = io::parse_json_input(c.examples.front());
      req.input.closed = true;
      testing::expect_error(ErrorCode::kInvalidArgument,
                            [&] { fit(m.name, req.input, req.options); },
                            {"interpolates open curves only"});
    }
    if (c.tangents == TangentUse::kRequired) {
      FitInput in;
      in.points = {{0, 0}, {1, 1}, {2, 0}};
      in.tangents = {Vec2{1, 0}, std::nullopt, Vec2{1, 0}};
      const Error e = testing::expect_error(ErrorCode::kInvalidArgument, [&] { fit(m.name, in); },
                                            {"point 1 has none"});
      EXPECT_EQ(e.index(), std::optional<std::size_t>(1));
      const FitResult r = fit(m.name, in, {{std::string(kTangentsFromOption), "jaklic-zagar"}});
      EXPECT_EQ(r.tangents.size(), 3u);
    }
    if (c.points.step > 1) {
      FitInput in;
      for (std::size_t i = 0; i < c.points.step + 2; ++i) {  // on an arc: no parallel chords
        in.points.push_back(
            {std::cos(0.3 * static_cast<double>(i)), std::sin(0.3 * static_cast<double>(i))});
      }
      const Error e = testing::expect_error(ErrorCode::kWrongPointCount, [&] { fit(m.name, in); },
                                            {"m+1 points"});
      EXPECT_EQ(e.index(), std::optional<std::size_t>(in.points.size() - 1));
      const FitResult r =
          fit(m.name, in, {{std::string(c.points.relaxed_by), c.points.relaxed_value}});
      EXPECT_EQ(r.points.size(), in.points.size());
    }
  }
}

/// README's method table names every registered method (the one doc edit a method needs
/// besides its own page).
TEST(RegistryCapabilities, ReadmeTableListsEveryMethod) {
  std::ifstream f(std::string(FAIRSPLINE_SOURCE_DIR) + "/README.md");
  const std::string readme((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::size_t begin = readme.find("## Methods\n");
  ASSERT_NE(begin, std::string::npos);
  const std::string table = readme.substr(begin, readme.find("\n## ", begin + 1) - begin);
  for (const MethodInfo& m : methods()) {
    EXPECT_NE(table.find("`" + m.name + "`"), std::string::npos) << m.name;
  }
}

}  // namespace
}  // namespace fairspline
