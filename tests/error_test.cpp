// The error catalog: every entry of tests/data/errors.json raises its code, index and message in
// the C++ library, the CLI (exit status and stderr) and the web API (HTTP 400 body); the Python
// module is checked on the same file by tests/python/test_error_catalog.py. docs/errors.md must
// document every code and quote every entry's message.
#include "fairspline/error.hpp"

#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "fairspline/io/csv.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

#if __has_include("server.hpp")
#include "server.hpp"
#define FAIRSPLINE_HAVE_WEB 1
#endif

namespace fairspline {
namespace {

using nlohmann::json;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const json& catalog() {
  static const json entries =
      json::parse(read_text(std::string(FAIRSPLINE_TEST_DATA_DIR) + "/errors.json")).at("entries");
  return entries;
}

std::string describe(const json& entry) {
  return entry.at("code").get<std::string>() + ": " + entry.dump();
}

std::optional<std::size_t> expected_index(const json& entry) {
  if (entry.at("index").is_null()) return std::nullopt;
  return entry.at("index").get<std::size_t>();
}

/// Every code has a stable, distinct name; the catalog covers every one of them.
TEST(ErrorCatalog, CoversEveryCode) {
  std::set<std::string> names;
  for (int c = 0; c <= static_cast<int>(ErrorCode::kCancelled); ++c) {
    names.insert(std::string(error_code_name(static_cast<ErrorCode>(c))));
  }
  EXPECT_EQ(names.size(), static_cast<std::size_t>(ErrorCode::kCancelled) + 1);
  EXPECT_EQ(names.count("unknown"), 0u);
  std::set<std::string> covered;
  for (const json& e : catalog()) covered.insert(e.at("code").get<std::string>());
  EXPECT_EQ(covered, names);
}

/// docs/errors.md has a section per code, and quotes each entry's message in it.
TEST(ErrorCatalog, DocsMatchTheCatalog) {
  const std::string doc = read_text(std::string(FAIRSPLINE_SOURCE_DIR) + "/docs/errors.md");
  ASSERT_FALSE(doc.empty());
  for (const json& e : catalog()) {
    const std::string code = e.at("code");
    const std::string heading = "## `" + code + "`";
    const auto at = doc.find(heading);
    ASSERT_NE(at, std::string::npos) << heading;
    const auto next = doc.find("\n## ", at + heading.size());
    const std::string section = doc.substr(at, next == std::string::npos ? next : next - at);
    for (const char* key : {"message", "python_message"}) {
      if (!e.contains(key)) continue;
      EXPECT_NE(section.find(e.at(key).get<std::string>()), std::string::npos)
          << "docs/errors.md, section " << code << " should quote: " << e.at(key);
    }
  }
}

/// The library: parse the request (or the CSV / the file) and fit it.
TEST(ErrorCatalog, Cpp) {
  for (const json& e : catalog()) {
    SCOPED_TRACE(describe(e));
    const Error err = testing::expect_error([&] {
      if (e.contains("path")) {
        io::read_csv_points(e.at("path").get<std::string>());
      } else if (e.contains("csv")) {
        FitInput in;
        in.points = io::parse_csv_points(e.at("csv").get<std::string>());
        fit(default_method_name(), in);
      } else {
        const io::ParsedInput p = io::parse_json_input(e.at("body").get<std::string>());
        // "report": a level other than the default (the curvature variation's overflow needs
        // the full report).
        const FitOptions level = p.fit_options(io::parse_report_level(e.value("report", "basic")));
        fit(p.method ? *p.method : std::string(default_method_name()), p.input, p.options, level);
      }
    });
    EXPECT_EQ(error_code_name(err.code()), e.at("code").get<std::string>());
    EXPECT_EQ(err.index(), expected_index(e));
    EXPECT_NE(std::string(err.what()).find(e.at("message").get<std::string>()), std::string::npos)
        << err.what();
    // Front-end neutral: no command-line flag in a library message (each front end adds its
    // own hint).
    EXPECT_EQ(std::string(err.what()).find(" --"), std::string::npos) << err.what();
  }
}

TEST(ErrorCatalog, LiSingularSystemSpeaksNoFrontEndsSyntax) {
  // The one library message that named command-line flags (issue 20, bug 4).
  FitInput in;
  in.points = {{0, 0}, {1, 1}, {2, 0}, {3, 1}};
  const Error open =
      testing::expect_error(ErrorCode::kSingularSystem, [&] { fit("li-curvature-variation", in); },
                            {"Give a start tangent (or clamp a point)"});
  in.closed = true;
  const Error closed =
      testing::expect_error(ErrorCode::kSingularSystem, [&] { fit("li-curvature-variation", in); },
                            {"a clamped point or a start tangent"});
  for (const Error* e : {&open, &closed}) {
    EXPECT_EQ(std::string(e->what()).find("--"), std::string::npos) << e->what();
  }
}

/// No string literal of the library quotes a command-line flag ("--set", "-m NAME"): messages
/// are front-end neutral, and an option that gets past an error travels as Error::hint, which
/// each front end words in its own syntax (issue 20, bug 4).
TEST(ErrorCatalog, LibrarySourcesQuoteNoCommandLineFlags) {
  const std::regex literal(R"re("(?:[^"\\\n]|\\.)*")re");
  const std::regex flag(R"re(--[a-z]|(^|[^a-z0-9_-])-[a-zA-Z] [a-z])re");
  std::size_t files = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(std::string(FAIRSPLINE_SOURCE_DIR) + "/src")) {
    if (entry.path().extension() != ".cpp" && entry.path().extension() != ".hpp") continue;
    ++files;
    std::istringstream lines(read_text(entry.path().string()));
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
      const auto code = line.find_first_not_of(' ');
      if (code != std::string::npos && line.compare(code, 2, "//") == 0) continue;
      for (std::sregex_iterator m(line.begin(), line.end(), literal), end; m != end; ++m) {
        EXPECT_FALSE(std::regex_search(m->str(), flag))
            << entry.path().string() << ":" << number << ": " << m->str();
      }
    }
  }
  EXPECT_GT(files, 20u);
}

/// The hints: the option and value that get past an error, never in a flag's syntax.
TEST(ErrorCatalog, HintsNameTheOption) {
  FitInput five;
  five.points = {{0, 0}, {1, 1}, {2, 0}, {3, 1}, {4, 0}};
  const Error kk =
      testing::expect_error(ErrorCode::kWrongPointCount, [&] { fit("kozak-krajnc", five); });
  ASSERT_TRUE(kk.hint());
  EXPECT_EQ(kk.hint()->name, "remainder");
  EXPECT_EQ(kk.hint()->value, "hermite");
  FitInput back;
  back.points = {{0, 0}, {2, 0}, {1, 0}, {3, 0}};
  const Error jz = testing::expect_error(ErrorCode::kReversal, [&] { fit("jaklic-zagar", back); },
                                         {"set the option reversal to insert"});
  ASSERT_TRUE(jz.hint());
  EXPECT_EQ(jz.hint()->name, "reversal");
  EXPECT_EQ(jz.hint()->value, "insert");
  EXPECT_EQ(jz.index(), 1u);
}

#ifdef FAIRSPLINE_HAVE_WEB
/// The web API: HTTP 400 with {"error": {"code", "message", "index"}}.
TEST(ErrorCatalog, Http) {
  for (const json& e : catalog()) {
    if (!e.contains("body")) continue;  // files and CSV text are not requests
    SCOPED_TRACE(describe(e));
    const web::ApiResponse r = web::handle_fit(e.at("body").get<std::string>(), {});
    EXPECT_EQ(r.status, 400);
    const json body = json::parse(r.body);
    const json& err = body.at("error");
    EXPECT_EQ(err.at("code"), e.at("code"));
    EXPECT_EQ(err.at("index"), e.at("index"));
    EXPECT_NE(err.at("message").get<std::string>().find(e.at("message").get<std::string>()),
              std::string::npos)
        << err.at("message");
  }
  // A hint travels as data, for the editor to offer as a button.
  const web::ApiResponse kk = web::handle_fit(
      R"({"points": [[0,0],[1,1],[2,0],[3,1],[4,0]], "method": "kozak-krajnc"})", {});
  EXPECT_EQ(json::parse(kk.body).at("error").at("hint"),
            (json{{"option", "remainder"}, {"value", "hermite"}}));
}
#endif

#ifdef FAIRSPLINE_CLI
class ErrorCatalogCli : public testing::CommandTest {};

/// The command: exit status, then "fairspline: error [code] at point N: message" on stderr.
TEST_F(ErrorCatalogCli, ExitStatusAndMessage) {
  for (const json& e : catalog()) {
    SCOPED_TRACE(describe(e));
    testing::CliRun r;
    if (e.contains("path")) {
      r = run_program(FAIRSPLINE_CLI, "fit " + testing::shell_quote(e.at("path")));
    } else if (e.contains("csv")) {
      r = run_program(FAIRSPLINE_CLI, "fit -", e.at("csv").get<std::string>());
    } else {
      r = run_program(FAIRSPLINE_CLI, "fit - --report " + e.value("report", "basic"),
                      e.at("body").get<std::string>());
    }
    EXPECT_EQ(r.exit_code, e.at("exit").get<int>()) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    const std::string code = e.at("code");
    EXPECT_EQ(r.err.rfind("fairspline: error [" + code + "]", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(e.at("message").get<std::string>()), std::string::npos) << r.err;
    // A point index is named as such; a parse error's index is a line, named in the message.
    const bool names_point = r.err.find("] at point ") != std::string::npos;
    EXPECT_EQ(names_point, e.at("index").is_number() && code != "parse_error") << r.err;
    if (names_point) {
      EXPECT_NE(r.err.find("at point " + std::to_string(e.at("index").get<int>()) + ":"),
                std::string::npos)
          << r.err;
    }
  }
}
#endif

}  // namespace
}  // namespace fairspline
