// Tests of the web server (apps/web/server.cpp): the JSON API's handlers on every error path,
// and one HTTP round trip on a free loopback port.
#include "server.hpp"

#include <gtest/gtest.h>
#include <httplib.h>

#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "fairspline/registry.hpp"

namespace fairspline::web {
namespace {

using nlohmann::json;

json error_of(const ApiResponse& r) {
  const json j = json::parse(r.body);
  return j.at("error");
}

TEST(WebApi, MethodsListsTheRegistryWithTheDefault) {
  const ApiResponse r = handle_methods();
  ASSERT_EQ(r.status, 200);
  const json j = json::parse(r.body);
  EXPECT_EQ(j.at("default"), default_method_name());
  EXPECT_EQ(j.at("methods").size(), methods().size());
  bool found = false;
  for (const json& m : j.at("methods")) {
    if (m.at("name") == "min-energy") {
      found = true;
      bool has_omega = false;
      for (const json& o : m.at("options")) has_omega = has_omega || o.at("name") == "omega_deg";
      EXPECT_TRUE(has_omega);
    }
  }
  EXPECT_TRUE(found);
}

TEST(WebApi, FitAnswersLikeTheCommandLine) {
  const ServerOptions opt;
  const ApiResponse r =
      handle_fit(R"({"points": [[0,0],[1,0.5],[2,0],[3,0.5]], "method": "jaklic-zagar"})", opt);
  ASSERT_EQ(r.status, 200) << r.body;
  const json j = json::parse(r.body);
  EXPECT_EQ(j.at("method"), "jaklic-zagar");
  EXPECT_EQ(j.at("segments").size(), 3u);
  EXPECT_TRUE(j.at("report").at("regular").get<bool>());
  // Default method and options.
  const ApiResponse d = handle_fit(
      R"({"points": [[0,0],[1,1],[2,0]], "closed": true, "options": {"omega_deg": 80}})", opt);
  ASSERT_EQ(d.status, 200) << d.body;
  EXPECT_EQ(json::parse(d.body).at("method"), default_method_name());
}

TEST(WebApi, BadRequestsAre400WithTheLibrarysMessage) {
  ServerOptions opt;
  opt.max_points = 10;
  struct Case {
    const char* body;
    const char* code;
    json index;
  };
  const Case cases[] = {
      {R"({"points": [[0,0],)", "parse_error", nullptr},            // truncated
      {"", "parse_error", nullptr},                                 // empty
      {"[1, 2", "parse_error", nullptr},                            // not closed
      {R"({"points": [[0,0],[1,1e999]]})", "non_finite", nullptr},  // overflows
      {R"({"points": [[0,0],[1,"x"]]})", "parse_error", 1},         // wrong type
      {R"({"points": [[0,0],[1,1],[1,1]]})", "repeated_point", 2},  // duplicate
      {R"({"points": [[0,0]]})", "too_few_points", nullptr},        // too few
      {R"({"points": [[0,0],[1,1]], "method": "nope"})", "unknown_method", nullptr},
      {R"({"points": [[0,0],[1,1]], "options": {"wieghts": 1}})", "unknown_option", nullptr},
      {R"({"points": [[0,0],[1,1]], "pionts": 1})", "parse_error", nullptr},  // typo'd key
      {R"({"points": [[0,0],[1,0],[2,0],[3,0],[4,0],[5,0],[6,0],[7,0],[8,0],[9,0],[10,0]]})",
       "invalid_argument", nullptr},  // more than max_points
      {R"({"points": [[0,0],[1,0],[0.2,0.3],[0,1]], "method": "min-energy",
          "options": {"basis": "yong-cheng"}})",
       "infeasible", 1},                         // a stencil angle beyond 2Ω = 120°
      {"{\"points\": \xff}", "parse_error", 1},  // invalid UTF-8 quoted in the message (fuzz)
  };
  for (const Case& c : cases) {
    const ApiResponse r = handle_fit(c.body, opt);
    ASSERT_EQ(r.status, 400) << c.body << " -> " << r.body.substr(0, 200);
    const json e = error_of(r);
    EXPECT_EQ(e.at("code"), c.code) << c.body << " -> " << r.body;
    EXPECT_FALSE(e.at("message").get<std::string>().empty());
    if (!c.index.is_null()) {
      EXPECT_EQ(e.at("index"), c.index) << r.body;
    }
  }
}

TEST(WebApi, HttpRoundTripOnAFreeLoopbackPort) {
  ServerOptions opt;
  opt.port = 0;
  opt.max_body_bytes = 4096;
  Server server(opt);
  const int port = server.bind();
  ASSERT_GT(port, 0);
  std::thread thread([&server] { server.run(); });
  httplib::Client client("127.0.0.1", port);
  client.set_connection_timeout(5);
  auto methods = client.Get("/api/methods");
  ASSERT_TRUE(methods);
  EXPECT_EQ(methods->status, 200);
  EXPECT_EQ(methods->get_header_value("Content-Type"), "application/json");
  auto ok = client.Post("/api/fit", R"({"points": [[0,0],[1,1],[2,0]]})", "application/json");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200);
  EXPECT_EQ(json::parse(ok->body).at("segments").size(), 2u);
  // The page shows the server's fit time from the Server-Timing header.
  const std::string timing = ok->get_header_value("Server-Timing");
  ASSERT_EQ(timing.rfind("fit;dur=", 0), 0u) << timing;
  const double ms = std::stod(timing.substr(8));
  EXPECT_GE(ms, 0.0);
  EXPECT_LT(ms, 60000.0);
  // Never compressed, even when the client accepts it (brotli costs 100x the fit).
  auto plain = client.Post("/api/fit", {{"Accept-Encoding", "gzip, deflate, br"}},
                           R"({"points": [[0,0],[1,1],[2,0]]})", "application/json");
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->status, 200);
  EXPECT_FALSE(plain->has_header("Content-Encoding"))
      << plain->get_header_value("Content-Encoding");
  EXPECT_EQ(json::parse(plain->body).at("segments").size(), 2u);
  auto bad = client.Post("/api/fit", "{", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(error_of({bad->status, bad->body}).at("code"), "parse_error");
  // A body above the limit is refused before parsing.
  auto big = client.Post("/api/fit", std::string(10000, ' '), "application/json");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  auto missing = client.Get("/api/nothing");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  server.stop();
  thread.join();
}

}  // namespace
}  // namespace fairspline::web
