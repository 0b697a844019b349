// End-to-end tests of the `fairspline` command.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "fairspline/io/curve_ensemble.hpp"

#ifdef FAIRSPLINE_CLI

namespace {

namespace fs = std::filesystem;
using fairspline::testing::CliRun;
using fairspline::testing::slurp;
using nlohmann::json;

std::string quote(const std::string& s) {
  return fairspline::testing::shell_quote(s);
}

const std::string kExample = std::string(FAIRSPLINE_SOURCE_DIR) + "/examples/li-example1.csv";
const std::string kData = FAIRSPLINE_TEST_DATA_DIR;

class Cli : public fairspline::testing::CommandTest {
 protected:
  /// Runs the CLI with `args` (already shell-quoted where needed), optional stdin text.
  CliRun run(const std::string& args, const std::optional<std::string>& stdin_text = std::nullopt) {
    return run_program(FAIRSPLINE_CLI, args, stdin_text);
  }
  /// Writes `text` to a file of this test's scratch directory; returns its path.
  std::string write_file(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
};

void expect_fit_schema(const json& j, const std::string& method, std::size_t points) {
  for (const char* key : {"method", "closed", "options", "points", "knots", "tangents", "segments",
                          "report", "method_report"}) {
    ASSERT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["method"], method);
  EXPECT_TRUE(j["closed"].is_boolean());
  EXPECT_TRUE(j["options"].is_object());
  EXPECT_EQ(j["points"].size(), points);
  EXPECT_EQ(j["tangents"].size(), points);
  EXPECT_EQ(j["knots"].size(), points);
  ASSERT_EQ(j["segments"].size(), points - 1);
  for (const auto& s : j["segments"]) {
    ASSERT_EQ(s["bezier"].size(), 4u);
    EXPECT_TRUE(s["t0"].is_number());
    EXPECT_TRUE(s["t1"].is_number());
    EXPECT_TRUE(s["span"].is_number_integer());
  }
  // The default (basic) report: the curvature variation is the full report's.
  const json& rep = j["report"];
  for (const char* key :
       {"bending_energy", "linearized_energy", "length", "max_tangent_angle_jump_deg",
        "max_curvature_jump", "min_relative_speed"}) {
    EXPECT_TRUE(rep[key].is_number()) << key;
  }
  EXPECT_TRUE(rep["curvature_variation_energy"].is_null());
  EXPECT_FALSE(rep.contains("intersections"));  // not searched: not an empty list
  EXPECT_TRUE(rep["regular"].is_boolean());
}

TEST_F(Cli, FitEachLiMethodAsJson) {
  for (const std::string method : {"li-strain", "li-combined", "li-curvature-variation"}) {
    const std::string extra = method == "li-curvature-variation" ? " --start-tangent 1,0" : "";
    const CliRun r = run("fit " + quote(kExample) + " -m " + method + extra);
    ASSERT_EQ(r.exit_code, 0) << method << ": " << r.err;
    const json j = json::parse(r.out);
    expect_fit_schema(j, method, 7);
  }
}

TEST_F(Cli, YongChengHermiteExampleAndMissingTangents) {
  const std::string hermite =
      std::string(FAIRSPLINE_SOURCE_DIR) + "/examples/yong-cheng-hermite.json";
  const CliRun r = run("fit " + quote(hermite) + " --report basic");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["method"], "yong-cheng");
  EXPECT_TRUE(j["report"]["regular"].get<bool>());
  EXPECT_TRUE(j["method_report"]["all_preserved"].get<bool>());
  EXPECT_EQ(j["method_report"]["spans"].size(), 4u);
  // The segments of a span carry its index; composite spans have several.
  EXPECT_GT(j["segments"].size(), 4u);
  // Points alone: a clear error naming the point, exit 1; tangents_from fixes it.
  const CliRun bad = run("fit " + quote(kExample) + " -m yong-cheng");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("point 0 has none"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("tangents_from"), std::string::npos) << bad.err;
  const CliRun ok =
      run("fit " + quote(kExample) + " -m yong-cheng --set tangents_from=jaklic-zagar");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

TEST_F(Cli, KozakKrajncExampleAndPointCountError) {
  const std::string example = std::string(FAIRSPLINE_SOURCE_DIR) + "/examples/kozak-krajnc.csv";
  // g2=true: this example has no G2 spline for the tangent rule's end directions (Newton stalls,
  // the chain scan proves it): an error, or with --best-effort the G1 spline and the solver's
  // status.
  const CliRun stalled = run("fit " + quote(example) + " -m kozak-krajnc --set g2=true");
  EXPECT_EQ(stalled.exit_code, 1) << stalled.err;
  EXPECT_NE(stalled.err.find("infeasible"), std::string::npos) << stalled.err;
  for (const std::string extra : {"", " --set gamma=auto", " --set g2=true --best-effort"}) {
    const CliRun r = run("fit " + quote(example) + " -m kozak-krajnc" + extra);
    ASSERT_EQ(r.exit_code, 0) << extra << ": " << r.err;
    const json j = json::parse(r.out);
    expect_fit_schema(j, "kozak-krajnc", 10);
    EXPECT_TRUE(j["report"]["regular"].get<bool>());
    EXPECT_EQ(j["method_report"]["segments"].size(), 3u);
    EXPECT_EQ(j["method_report"]["breakpoints"].size(), 4u);
  }
  // 10 points minus one: the error names the count and the way out, exit 1.
  std::string csv = slurp(example);
  csv.erase(csv.rfind('\n', csv.size() - 2) + 1);
  const CliRun bad = run("fit - -m kozak-krajnc", csv);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("3m+1"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("remainder=hermite"), std::string::npos) << bad.err;
  const CliRun ok = run("fit - -m kozak-krajnc --set remainder=hermite", csv);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

TEST_F(Cli, NoDiagnosticsKeepsTheMethodReportsSummary) {
  // --no-diagnostics (or the request's "diagnostics": false) drops the per-piece entries of
  // method_report and keeps its summary and the report; "diagnostics" must be a boolean.
  const std::string example = std::string(FAIRSPLINE_SOURCE_DIR) + "/examples/kozak-krajnc.csv";
  const json full = json::parse(run("fit " + quote(example) + " -m kozak-krajnc").out);
  ASSERT_EQ(full["method_report"]["segments"].size(), 3u);
  const CliRun flag = run("fit " + quote(example) + " -m kozak-krajnc --no-diagnostics");
  ASSERT_EQ(flag.exit_code, 0) << flag.err;
  const json quiet = json::parse(flag.out);
  EXPECT_FALSE(quiet["method_report"].contains("segments"));
  EXPECT_FALSE(quiet["method_report"].contains("breakpoints"));
  EXPECT_EQ(quiet["method_report"]["gamma"], full["method_report"]["gamma"]);
  EXPECT_EQ(quiet["report"], full["report"]);
  EXPECT_EQ(quiet["segments"], full["segments"]);
  json request = {{"points", full["points"]}, {"method", "kozak-krajnc"}, {"diagnostics", false}};
  const CliRun asked = run("fit -", request.dump());
  ASSERT_EQ(asked.exit_code, 0) << asked.err;
  EXPECT_EQ(json::parse(asked.out)["method_report"], quiet["method_report"]);
  request["diagnostics"] = "no";
  const CliRun bad = run("fit -", request.dump());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("diagnostics: expected true or false"), std::string::npos) << bad.err;
}

TEST_F(Cli, FieldsWriteOnlyTheNamedMembers) {
  // As batch --fields, for one curve: the members named (whole, or some of an object's), always
  // "method", each byte for byte as in the whole output; the others are not written at all.
  const std::string in = write_file("walk.json", R"({"points": [[0,0],[1,2],[3,1],[4,3],[6,2]]})");
  const CliRun whole = run("fit " + quote(in));
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const json all = json::parse(whole.out);
  const CliRun some = run("fit " + quote(in) + " --fields 'segments, tangents'");
  ASSERT_EQ(some.exit_code, 0) << some.err;
  const json some_expected = {
      {"method", all["method"]}, {"segments", all["segments"]}, {"tangents", all["tangents"]}};
  EXPECT_EQ(some.out, some_expected.dump() + "\n");
  const CliRun part = run("fit " + quote(in) + " --fields report.length,method_report.energy");
  ASSERT_EQ(part.exit_code, 0) << part.err;
  const json part_expected = {{"method", all["method"]},
                              {"method_report", {{"energy", all["method_report"]["energy"]}}},
                              {"report", {{"length", all["report"]["length"]}}}};
  EXPECT_EQ(json::parse(part.out), part_expected);
  const CliRun indented = run("fit " + quote(in) + " --fields knots --indent 2");
  ASSERT_EQ(indented.exit_code, 0) << indented.err;
  const json knots_expected = {{"knots", all["knots"]}, {"method", all["method"]}};
  EXPECT_EQ(indented.out, knots_expected.dump(2) + "\n");
  // Usage errors: a field fit does not write ("line" is a batch record's), another format,
  // the report when none is written.
  for (const std::string bad : {"--fields line", "--fields nope", "--fields segments -f csv",
                                "--fields report.length "
                                "--report none"}) {
    const CliRun r = run("fit " + quote(in) + " " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("[invalid_argument]"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << bad;
  }
  EXPECT_NE(run("fit " + quote(in) + " --fields line").err.find("unknown field 'line'"),
            std::string::npos);
}

TEST_F(Cli, MinEnergyKindsFromJson) {
  // A closed square with a corner at point 0: one open piece from the corner around to it.
  const CliRun a = run("fit -",
                       R"({"points": [[0,0],[2,0],[2,2],[0,2],[1,1]], "closed": true,
          "kinds": ["corner","smooth","smooth","smooth","smooth"]})");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const json j = json::parse(a.out);
  EXPECT_EQ(j["method"], "quasi-elastic");
  EXPECT_EQ(j["method_report"]["pieces"], 1);
  EXPECT_EQ(j["method_report"]["status"], "converged");
  EXPECT_GT(j["report"]["max_tangent_angle_jump_deg"].get<double>(), 10.0);  // the corner
  // A clamped tangent at 124° to its chord: infeasible, exit 1, the point named.
  const CliRun b = run("fit -",
                       R"({"points": [[0,0],[2,0],[2,2],[0,2],[1,1]], "closed": true,
          "kinds": ["clamped","smooth","smooth","smooth","smooth"],
          "tangents": [[1,-0.2],null,null,null,null]})");
  EXPECT_EQ(b.exit_code, 1);
  EXPECT_NE(b.err.find("[infeasible] at point 0"), std::string::npos) << b.err;
  EXPECT_NE(b.err.find("given tangent"), std::string::npos) << b.err;
}

TEST_F(Cli, GlobalSearchIsOneOptionAway) {
  // Issue 18: the grid search from the command line; method_report says which search ran, and
  // the output, a request itself, fits the same curve again.
  const std::string req = quote(kData + "/cond-g2-two-minima.json");
  const CliRun a = run("fit " + req + " --report none");
  const CliRun b = run("fit " + req + " --report none --set search=global");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const json ja = json::parse(a.out), jb = json::parse(b.out);
  EXPECT_EQ(ja["method_report"]["search"], "newton");
  EXPECT_EQ(jb["method_report"]["search"], "global");
  EXPECT_EQ(jb["options"]["search"], "global");
  EXPECT_EQ(ja["method_report"]["minimum"], "newton");
  EXPECT_EQ(jb["method_report"]["minimum"], "global");  // lower than newton's
  EXPECT_LT(jb["method_report"]["energy"].get<double>(),
            0.95 * ja["method_report"]["energy"].get<double>());
  const CliRun c = run("fit " + quote(write_file("global.json", b.out)) + " --report none");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_EQ(json::parse(c.out)["segments"], jb["segments"]);
}

/// A sharp 300-point walk: the elastic spline's grid search takes about two seconds on it.
std::string slow_walk_request(double turn_deg = 150) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> turn(-turn_deg * std::numbers::pi / 180,
                                              turn_deg * std::numbers::pi / 180);
  std::uniform_real_distribution<double> step(0.5, 2.0);
  json points = json::array();
  double x = 0, y = 0, h = 0;
  for (int i = 0; i < 300; ++i) {
    points.push_back({x, y});
    h += turn(rng);
    const double s = step(rng);
    x += s * std::cos(h), y += s * std::sin(h);
  }
  return json{{"points", points}, {"method", "elastic"}, {"options", {{"search", "global"}}}}
      .dump();
}

TEST_F(Cli, ATimeLimitStopsTheFitAndProgressShowsItsStages) {
  const std::string req = quote(write_file("slow.json", slow_walk_request()));
  const CliRun a = run("fit " + req + " --time-limit 0.2 --report none");
  EXPECT_EQ(a.exit_code, 1);
  EXPECT_TRUE(a.out.empty());
  EXPECT_NE(a.err.find("fairspline: error [cancelled]: the fit was stopped at its time limit of "
                       "0.2 s ("),
            std::string::npos)
      << a.err;
  // The request's own limit, and the flag over it.
  json body = json::parse(slow_walk_request());
  body["time_limit"] = 0.1;
  EXPECT_EQ(run("fit -", body.dump()).exit_code, 1);
  body["time_limit"] = "soon";
  const CliRun bad = run("fit -", body.dump());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("time_limit: expected a number of seconds"), std::string::npos) << bad.err;
  EXPECT_EQ(run("fit " + req + " --time-limit 0").exit_code, 2);
  // --progress: a line per half second on stderr (no terminal here), then the curve.
  const CliRun p = run("fit " + req + " --progress --report none");
  EXPECT_EQ(p.exit_code, 0) << p.err;
  EXPECT_EQ(p.err.find("fairspline: "), 0u) << p.err;
  EXPECT_NE(p.err.find(", 0.5 s\n"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("fairspline: global search: "), std::string::npos) << p.err;
  EXPECT_NE(p.err.find(" of 300, "), std::string::npos) << p.err;
  EXPECT_EQ(json::parse(p.out)["method_report"]["search"], "global");
  // Batch: the limit is per record, and the run goes on.
  json quick = {{"points", {{0, 0}, {1, 1}, {2, 0}}}};
  const std::string lines = quick.dump() + "\n" + slow_walk_request() + "\n" + quick.dump() + "\n";
  const CliRun b = run("batch --time-limit 0.2 --report none --threads 1", lines);
  EXPECT_EQ(b.exit_code, 1);
  std::vector<json> records;
  std::istringstream out(b.out);
  for (std::string line; std::getline(out, line);) records.push_back(json::parse(line));
  ASSERT_EQ(records.size(), 3u) << b.out;
  EXPECT_TRUE(records[0].contains("segments"));
  EXPECT_EQ(records[1]["error"]["code"], "cancelled");
  EXPECT_TRUE(records[2].contains("segments"));
}

TEST_F(Cli, DefaultMethodAndStdin) {
  const std::string csv = slurp(kExample);
  const CliRun a = run("fit", csv);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const CliRun b = run("fit -", csv);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_EQ(json::parse(a.out)["method"], "quasi-elastic");
  // JSON on stdin is detected by its first character.
  const CliRun c = run("fit --report none", R"({"points": [[0,0],[1,1],[2,0]], "closed": true})");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const json j = json::parse(c.out);
  EXPECT_EQ(j["closed"], true);
  EXPECT_EQ(j["segments"].size(), 3u);
  EXPECT_FALSE(j.contains("report"));
}

TEST_F(Cli, JsonRequestFileAndCommandLineOverrides) {
  const std::string req = quote(kData + "/cli-request.json");
  const CliRun a = run("fit " + req);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const json ja = json::parse(a.out);
  EXPECT_EQ(ja["method"], "li-combined");
  EXPECT_EQ(ja["options"]["weights"], json({1, 0.5}));
  const CliRun b = run("fit " + req + " -m li-strain --set weights=[1,0]");
  EXPECT_EQ(b.exit_code, 1);  // li-strain has no options
  EXPECT_NE(b.err.find("unknown_option"), std::string::npos) << b.err;
  const CliRun c = run("fit " + req + " --set weights=[2,0] --closed --alpha 0 --indent 2");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const json jc = json::parse(c.out);
  EXPECT_EQ(jc["options"]["weights"], json({2, 0}));
  EXPECT_EQ(jc["closed"], true);
  EXPECT_EQ(jc["knots"], json({0, 1, 2, 3, 4, 5}));    // uniform knots from --alpha 0
  EXPECT_NE(c.out.find("\n  \""), std::string::npos);  // indented
}

TEST_F(Cli, BadOptionExitsOneWithMessage) {
  const CliRun r = run("fit " + quote(kExample) + " --set wieghts=[1,0]");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("fairspline: error [unknown_option]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("wieghts"), std::string::npos) << r.err;
  const CliRun v = run("fit " + quote(kExample) + " -m cond-g2 --set lambda=heavy");
  EXPECT_EQ(v.exit_code, 1);
  EXPECT_NE(v.err.find("[bad_option]"), std::string::npos) << v.err;
  const CliRun s = run("fit " + quote(kExample) + " -f svg --set svg.comb=maybe");
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_NE(s.err.find("svg.comb"), std::string::npos) << s.err;
  const CliRun m = run("fit " + quote(kExample) + " -m li-nope");
  EXPECT_EQ(m.exit_code, 1);
  EXPECT_NE(m.err.find("[unknown_method]"), std::string::npos) << m.err;
}

TEST_F(Cli, FitErrorsExitOneNamingThePoint) {
  const CliRun r = run("fit " + quote(file("rep.csv", "0,0\n1,1\n1,1\n2,0\n").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("fairspline: error [repeated_point] at point 2: "), std::string::npos)
      << r.err;
  const CliRun s = run("fit " + quote(kExample) + " -m li-curvature-variation");
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_NE(s.err.find("fairspline: error [singular_system]: "), std::string::npos) << s.err;
  const CliRun t = run("fit", "0,0\n");
  EXPECT_EQ(t.exit_code, 1);
  EXPECT_NE(t.err.find("[too_few_points]"), std::string::npos) << t.err;
}

TEST_F(Cli, MalformedInputExitsTwoNamingTheLine) {
  const CliRun r = run("fit " + quote(kData + "/cli-malformed.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("fairspline: error [parse_error]: line 8: expected two numbers"),
            std::string::npos)
      << r.err;
  const CliRun nan = run("fit", "0,0\n1,nan\n");
  EXPECT_EQ(nan.exit_code, 2);
  EXPECT_NE(nan.err.find("[non_finite]"), std::string::npos) << nan.err;
  EXPECT_NE(nan.err.find("line 2"), std::string::npos) << nan.err;
  const CliRun js = run("fit", "{\"points\": [[0,0],[1]]}");
  EXPECT_EQ(js.exit_code, 2);
  EXPECT_NE(js.err.find("points[1]: expected [x, y]"), std::string::npos) << js.err;
  const CliRun syntax =
      run("fit " + quote(file("bad.json", "{\"points\": [[0,0],\n[1,2]").string()));
  EXPECT_EQ(syntax.exit_code, 2);
  EXPECT_NE(syntax.err.find("invalid JSON at line 2"), std::string::npos) << syntax.err;
  const CliRun missing = run("fit " + quote((dir_ / "missing.csv").string()));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("[io_error]"), std::string::npos) << missing.err;
  const CliRun directory = run("fit " + quote(dir_.string()));
  EXPECT_EQ(directory.exit_code, 2);
  const CliRun binary = run("fit", std::string("\0\x01\xff\xfe", 4));
  EXPECT_EQ(binary.exit_code, 2);
}

TEST_F(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(run("").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
  EXPECT_EQ(run("fit " + quote(kExample) + " --bogus").exit_code, 2);
  EXPECT_EQ(run("fit " + quote(kExample) + " -f pdf").exit_code, 2);
  EXPECT_EQ(run("fit " + quote(kExample) + " --report most").exit_code, 2);
  EXPECT_EQ(run("fit " + quote(kExample) + " --alpha abc").exit_code, 2);
  const CliRun t = run("fit " + quote(kExample) + " --start-tangent 1");
  EXPECT_EQ(t.exit_code, 2);
  EXPECT_NE(t.err.find("--start-tangent expects X,Y"), std::string::npos) << t.err;
  const CliRun s = run("fit " + quote(kExample) + " --set novalue");
  EXPECT_EQ(s.exit_code, 2);
  EXPECT_NE(s.err.find("KEY=VALUE"), std::string::npos) << s.err;
  EXPECT_EQ(run("bench").exit_code, 2);  // -n required
  EXPECT_EQ(run("bench -n 10 --shape square").exit_code, 2);
  EXPECT_EQ(run("bench -n 10 --repeat 0").exit_code, 2);
  const CliRun unwritable =
      run("fit " + quote(kExample) + " -o " + quote((dir_ / "no/such/dir/x.json").string()));
  EXPECT_EQ(unwritable.exit_code, 2);
  const CliRun help = run("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("fit"), std::string::npos);
  EXPECT_EQ(run("fit --help").exit_code, 0);
}

TEST_F(Cli, OutputFormatsFilesAndSummary) {
  const fs::path svg = dir_ / "fit.svg";
  const CliRun r = run("fit " + quote(kExample) + " -o " + quote(svg.string()) + " --summary");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = slurp(svg);
  EXPECT_NE(text.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  EXPECT_NE(r.out.find("bending energy"), std::string::npos);  // summary to stdout with -o
  EXPECT_TRUE(r.err.empty()) << r.err;
  const CliRun comb = run("fit " + quote(kExample) + " -f svg --set svg.comb=1");
  ASSERT_EQ(comb.exit_code, 0) << comb.err;
  EXPECT_NE(comb.out.find("class=\"comb-teeth\""), std::string::npos);
  const CliRun csv = run("fit " + quote(kExample) + " -f csv --summary");
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(csv.out.rfind("x0,y0,x1,y1,x2,y2,x3,y3\n1,90,", 0), 0u) << csv.out;
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 7);
  EXPECT_NE(csv.err.find("linearized energy"), std::string::npos);  // summary to stderr
  // -o extension chooses the format.
  const fs::path out_csv = dir_ / "fit.csv";
  ASSERT_EQ(run("fit " + quote(kExample) + " -o " + quote(out_csv.string())).exit_code, 0);
  EXPECT_EQ(slurp(out_csv).rfind("x0,y0", 0), 0u);
}

/// The numbers of SVG path data in order (command letters dropped), read with std::from_chars;
/// `commands` gets the letters.
std::vector<double> path_numbers(std::string_view d, std::string& commands) {
  std::vector<double> out;
  std::size_t i = 0;
  while (i < d.size()) {
    const char c = d[i];
    if (c == ' ') {
      ++i;
    } else if (std::isalpha(static_cast<unsigned char>(c))) {
      commands += c;
      ++i;
    } else {
      double v = 0;
      const auto [end, ec] = std::from_chars(d.data() + i, d.data() + d.size(), v);
      EXPECT_TRUE(ec == std::errc()) << d.substr(i);
      if (ec != std::errc()) break;
      out.push_back(v);
      i = static_cast<std::size_t>(end - d.data());
    }
  }
  return out;
}

TEST_F(Cli, SvgPathOutputIsTheControlPointsOfTheJsonOutput) {
  for (const std::string closed : {"", " --closed"}) {
    SCOPED_TRACE(closed);
    const CliRun js = run("fit " + quote(kExample) + closed);
    const CliRun path = run("fit " + quote(kExample) + closed + " -f svg-path");
    ASSERT_EQ(js.exit_code, 0) << js.err;
    ASSERT_EQ(path.exit_code, 0) << path.err;
    // One line: the d attribute and a newline.
    ASSERT_FALSE(path.out.empty());
    EXPECT_EQ(path.out.find('\n'), path.out.size() - 1);
    std::string commands;
    const std::vector<double> numbers =
        path_numbers(std::string_view(path.out).substr(0, path.out.size() - 1), commands);
    const json segments = json::parse(js.out)["segments"];
    EXPECT_EQ(commands, "M" + std::string(segments.size(), 'C') + (closed.empty() ? "" : "Z"));
    std::vector<double> expected;
    for (std::size_t k = 0; k < segments.size(); ++k) {
      for (std::size_t j = k == 0 ? 0 : 1; j < 4; ++j) {
        expected.push_back(segments[k]["bezier"][j][0].get<double>());
        expected.push_back(segments[k]["bezier"][j][1].get<double>());
      }
    }
    EXPECT_EQ(numbers, expected);  // exactly: both are shortest round-trip digits
  }
}

TEST_F(Cli, GeoJsonOutputAndItsTolerance) {
  for (const bool closed : {false, true}) {
    SCOPED_TRACE(closed ? "closed" : "open");
    const std::string args = "fit " + quote(kExample) + (closed ? " --closed" : "");
    const json fit = json::parse(run(args).out);
    const json& points = fit["points"];
    std::size_t previous = 0;
    for (const std::string tolerance :
         {"", " --tolerance 1", " --tolerance 0.1", " --tolerance 0.01", " --tolerance 0.001"}) {
      SCOPED_TRACE(tolerance);
      const CliRun r = run(args + " -f geojson" + tolerance);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const json f = json::parse(r.out);
      EXPECT_EQ(f["type"], "Feature");
      EXPECT_EQ(f["geometry"]["type"], "LineString");
      EXPECT_EQ(f["properties"]["method"], "quasi-elastic");
      EXPECT_EQ(f["properties"]["closed"], closed);
      const json& c = f["geometry"]["coordinates"];
      ASSERT_GE(c.size(), 2u);
      EXPECT_EQ(c.front(), points.front());
      EXPECT_EQ(c.back(), closed ? points.front() : points.back());
      if (tolerance.empty()) {
        // The default: 1e-4 of the diagonal of the curve's bounds (~42 for this example).
        const double t = f["properties"]["tolerance"].get<double>();
        EXPECT_GT(t, 1e-4 * 35);
        EXPECT_LT(t, 1e-4 * 60);
        continue;
      }
      EXPECT_EQ(f["properties"]["tolerance"].get<double>(), std::stod(tolerance.substr(13)));
      EXPECT_GT(c.size(), previous);  // a smaller tolerance, more vertices
      previous = c.size();
    }
  }
  // With -o NAME.geojson the format follows the extension and --tolerance applies.
  const fs::path out = dir_ / "fit.geojson";
  const CliRun file_out =
      run("fit " + quote(kExample) + " --tolerance 0.5 -o " + quote(out.string()));
  ASSERT_EQ(file_out.exit_code, 0) << file_out.err;
  EXPECT_EQ(json::parse(slurp(out))["properties"]["tolerance"], 0.5);
}

TEST_F(Cli, ToleranceOnlyForGeoJsonAndOnlyPositive) {
  const std::string svg_file = " -o " + quote((dir_ / "fit.svg").string());
  for (const std::string& other :
       std::vector<std::string>{" -f svg", " -f json", " -f svg-path", " -f csv", "", svg_file}) {
    const CliRun r = run("fit " + quote(kExample) + other + " --tolerance 0.1");
    EXPECT_EQ(r.exit_code, 2) << other;
    EXPECT_TRUE(r.out.empty()) << other;
    EXPECT_NE(r.err.find("--tolerance applies only to -f geojson"), std::string::npos)
        << other << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "fit.svg"));
  for (const std::string bad : {"0", "-1", "nan", "inf"}) {
    const CliRun r = run("fit " + quote(kExample) + " -f geojson --tolerance " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--tolerance must be a positive number"), std::string::npos)
        << bad << ": " << r.err;
  }
  EXPECT_EQ(run("fit " + quote(kExample) + " -f geojson --tolerance abc").exit_code, 2);
}

TEST_F(Cli, OutputFormatFromTheExtension) {
  const auto fit_to = [&](const std::string& name, const std::string& extra = "") {
    const fs::path out = dir_ / name;
    const CliRun r = run("fit " + quote(kExample) + extra + " -o " + quote(out.string()));
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    return slurp(out);
  };
  EXPECT_TRUE(json::parse(fit_to("fit.json")).contains("segments"));
  EXPECT_TRUE(json::parse(fit_to("FIT.JSON")).contains("segments"));  // any case
  EXPECT_EQ(fit_to("fit.csv").rfind("x0,y0,x1,y1,x2,y2,x3,y3\n", 0), 0u);
  EXPECT_NE(fit_to("fit.svg").find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  EXPECT_EQ(json::parse(fit_to("fit.geojson"))["type"], "Feature");
  // A name without an extension (/dev/stdout, a fifo) keeps JSON, the default; -f wins over
  // the extension.
  EXPECT_TRUE(json::parse(fit_to("fit")).contains("segments"));
  EXPECT_EQ(fit_to("fit.xyz", " -f svg-path").rfind("M1 90 C", 0), 0u);
  EXPECT_EQ(fit_to("fit.txt", " -f ce").rfind("#Curve Ensemble Text File", 0), 0u);
  // Any other extension is refused before fitting, naming the known ones and -f (it used to
  // write JSON whatever the name said).
  for (const std::string name : {"fit.xyz", "fit.txt", "fit.jsonl", "fit.path"}) {
    const fs::path out = dir_ / ("refused-" + name);
    const CliRun r = run("fit " + quote(kExample) + " -o " + quote(out.string()));
    EXPECT_EQ(r.exit_code, 2) << name;
    EXPECT_FALSE(fs::exists(out)) << name;
    const std::string ext = name.substr(name.find('.'));
    EXPECT_NE(r.err.find("fairspline: error [invalid_argument]: cannot tell the output format "
                         "from the extension '" +
                         ext + "'"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("(known: .json, .csv, .svg, .geojson)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("give it with -f"), std::string::npos) << r.err;
  }
}

TEST_F(Cli, SvgOutputRendersWithRsvg) {
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "rsvg-convert not installed";
  }
  const fs::path svg = dir_ / "fit.svg", png = dir_ / "fit.png";
  ASSERT_EQ(run("fit " + quote(kExample) + " -o " + quote(svg.string()) +
                " --set svg.comb=1 --set svg.control_polygon=true")
                .exit_code,
            0);
  const std::string cmd = "rsvg-convert " + quote(svg.string()) + " -o " + quote(png.string());
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 1000u);
}

TEST_F(Cli, MethodsListAndJson) {
  const CliRun text = run("methods");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  for (const char* m : {"li-strain", "li-combined", "li-curvature-variation", "weights"}) {
    EXPECT_NE(text.out.find(m), std::string::npos) << m;
  }
  const CliRun js = run("methods --json");
  ASSERT_EQ(js.exit_code, 0) << js.err;
  const json j = json::parse(js.out);
  ASSERT_TRUE(j.is_array());
  std::vector<std::string> names;
  for (const auto& m : j) {
    for (const char* key : {"name", "description", "paper", "options", "default"}) {
      EXPECT_TRUE(m.contains(key)) << key;
    }
    names.push_back(m["name"]);
  }
  for (const char* m : {"li-strain", "li-combined", "li-curvature-variation"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), m), names.end()) << m;
  }
}

TEST_F(Cli, BenchPrintsTimingJson) {
  for (const std::string args : {"bench -m li-strain -n 200 --repeat 2",
                                 "bench -m li-combined -n 100 --closed --shape circle --seed 3"}) {
    const CliRun r = run(args);
    ASSERT_EQ(r.exit_code, 0) << args << ": " << r.err;
    const json j = json::parse(r.out);
    for (const char* key :
         {"method", "n", "closed", "shape", "seconds", "points_per_second", "repeat"}) {
      EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_GT(j["seconds"].get<double>(), 0.0);
    EXPECT_GT(j["points_per_second"].get<double>(), 0.0);
  }
  const json j = json::parse(run("bench -m li-strain -n 200 --repeat 2").out);
  EXPECT_EQ(j["method"], "li-strain");
  EXPECT_EQ(j["n"], 200);
  EXPECT_EQ(j["repeat"], 2);
  EXPECT_EQ(j["shape"], "random");
  EXPECT_EQ(j["closed"], false);
  const CliRun fail = run("bench -m li-curvature-variation -n 10");
  EXPECT_EQ(fail.exit_code, 1);
  EXPECT_NE(fail.err.find("[singular_system]"), std::string::npos);
}

TEST_F(Cli, CurveEnsembleFilesInAndOut) {
  // The bundled Curve Ensemble file is recognized by its header line, fits, and writes back
  // with -f ce: the same nodes and states, the fitted directions.
  const std::string ce = std::string(FAIRSPLINE_SOURCE_DIR) + "/examples/curve-ensemble.txt";
  const CliRun r = run("fit " + quote(ce) + " -m restricted-elastic -f ce");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fairspline::FitInput back = fairspline::io::parse_curve_ensemble(r.out);
  const fairspline::FitInput given = fairspline::io::read_curve_ensemble(ce);
  EXPECT_EQ(back.points, given.points);
  EXPECT_EQ(back.states, given.states);
  EXPECT_EQ(back.corners_deg, given.corners_deg);
  EXPECT_FALSE(back.closed);
  // --input-format ce reads a file whose header was stripped; the JSON output refits exactly.
  const std::string body = r.out.substr(r.out.find('\n') + 1);
  const std::string file = write_file("nodes.dat", body);
  const CliRun json_out = run("fit " + quote(file) + " --input-format ce -m restricted-elastic");
  ASSERT_EQ(json_out.exit_code, 0) << json_out.err;
  const std::string saved = write_file("fit.json", json_out.out);
  const CliRun refit = run("fit " + quote(saved));
  ASSERT_EQ(refit.exit_code, 0) << refit.err;
  EXPECT_EQ(refit.out, json_out.out) << "a result file is a request for the same curve";
  // A data-ball file ("x y r" lines) fits through its discs, and -f ce writes the balls back
  // (state −r); a negative radius is refused as malformed input (exit 2), naming the node.
  const std::string balls = write_file("balls.txt", "0 0 0\n3 1.5 0.5\n6 -0.5 0.5\n9 1 0\n");
  const CliRun fitted = run("fit " + quote(balls) + " --input-format ce -f ce");
  ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  EXPECT_NE(fitted.out.find(" -0.5 "), std::string::npos) << fitted.out;
  const std::string negative = write_file("negative.txt", "0 0 1\n5 5 -2\n9 0 0\n");
  const CliRun bad = run("fit " + quote(negative) + " --input-format ce");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("node 1"), std::string::npos) << bad.err;
}

// Issue 22's memory goal for a whole `fit` process: at most 300 bytes a point with --report
// none. At 2·10^5 points: 290 with transparent huge pages on `madvise` or `always`, 271 with
// them off (312 while the command loaded the server's libraries; the library's per-thread cache
// of blocks for a next fit had once raised it to 418).
TEST_F(Cli, AFitProcessPeaksAt300BytesAPointOrLess) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's shadow memory and redzones triple the resident memory";
#endif
  constexpr int kPoints = 200000;
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> turn(-2.0 * std::numbers::pi / 3.0,
                                              2.0 * std::numbers::pi / 3.0),
      step(0.5, 2.0);
  std::string text = "{\"points\": [";
  double x = 0.0, y = 0.0, heading = 0.0;
  for (int i = 0; i < kPoints; ++i) {
    char buf[80];
    std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", i ? ", " : "", x, y);
    text += buf;
    heading += turn(rng);
    const double d = step(rng);
    x += d * std::cos(heading);
    y += d * std::sin(heading);
  }
  text += "]}";
  const std::string input = write_file("walk.json", text);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl(FAIRSPLINE_CLI, FAIRSPLINE_CLI, "fit", input.c_str(), "--report", "none", "-o",
          "/dev/null", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  ASSERT_EQ(wait4(pid, &status, 0, &usage), pid);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0);
  const double bytes_per_point = usage.ru_maxrss * 1024.0 / kPoints;  // ru_maxrss: KiB
  EXPECT_LE(bytes_per_point, 300.0);
  RecordProperty("bytes_per_point", std::to_string(bytes_per_point));
}

// `serve` opens the server as a module (apps/web/serve_module.hpp): the command itself does not
// load cpp-httplib or what it links (OpenSSL, zlib, brotli), which every command paid for at
// start-up. The dynamic loader lists what it would load without running the program.
TEST_F(Cli, OnlyServeLoadsTheServersLibraries) {
  const CliRun r = run_program("env", "LD_TRACE_LOADED_OBJECTS=1 " + quote(FAIRSPLINE_CLI));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("libstdc++"), std::string::npos) << r.out;  // the listing is real
  for (const char* lib : {"httplib", "libssl", "libcrypto", "libbrotli", "libz."}) {
    EXPECT_EQ(r.out.find(lib), std::string::npos) << lib << " in\n" << r.out;
  }
  const fs::path module = fs::path(FAIRSPLINE_CLI).parent_path() / "fairspline-serve.so";
  ASSERT_TRUE(fs::is_regular_file(module)) << module;
  const CliRun m = run_program("ldd", quote(module.string()));
  EXPECT_NE(m.out.find("httplib"), std::string::npos) << m.out << m.err;
}

TEST_F(Cli, ServeWithoutItsModuleSaysWhereItLooked) {
  // A copy of the command without the module beside it (and none installed: else skip, since
  // the copy would find that one and serve).
  if (fs::exists(fs::path(FAIRSPLINE_SERVE_MODULE_INSTALL_DIR) / "fairspline-serve.so")) {
    GTEST_SKIP() << "a module is installed in " << FAIRSPLINE_SERVE_MODULE_INSTALL_DIR;
  }
  const fs::path copy = dir_ / "fairspline";
  fs::copy_file(FAIRSPLINE_CLI, copy);
  const CliRun r = run_program(copy.string(), "serve --port 0");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("[io_error]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fairspline-serve.so is not installed (looked for " +
                       (dir_ / "fairspline-serve.so").lexically_normal().string()),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.out, "");
}

}  // namespace

#endif  // FAIRSPLINE_CLI
