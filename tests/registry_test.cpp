#include "fairspline/registry.hpp"

#include <gtest/gtest.h>

#include "fairspline/error.hpp"

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
