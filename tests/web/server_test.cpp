// Tests of the web server (apps/web/server.cpp): the JSON API's handlers on every error path,
// the time and concurrency limits of FitRunner, HTTP round trips on a free loopback port, and
// the live channel (apps/web/live.cpp) through a WebSocket client written here from RFC 6455.
// (Under load, with the real `fairspline serve`: tests/web/server_load.cpp, CTest web.load.)
#include "server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>

#include <nlohmann/json.hpp>

#include "fairspline/registry.hpp"
#include "live.hpp"
#include "test_util.hpp"

namespace fairspline::web {
namespace {

using nlohmann::json;

json error_of(const ApiResponse& r) {
  const json j = json::parse(r.body);
  return j.at("error");
}

/// A request that takes far longer than a millisecond anywhere: 20000 points with the full
/// report (0.4-1 s in a Release build on the 2-core build VM, 4 s under ASan; 500 kB in).
std::string slow_request() {
  json points = json::array();
  for (const Point& p : testing::random_walk(20000, 7)) points.push_back({p.x, p.y});
  return json{{"points", points}, {"method", "min-energy"}}.dump();
}

/// A Server on a free loopback port, serving on its own thread until the end of the scope (also
/// when an ASSERT returns early), and a client of it.
class LiveServer {
 public:
  explicit LiveServer(ServerOptions opt) : server_(on_free_port(std::move(opt))) {
    port_ = server_.bind();
    if (port_ > 0) thread_ = std::thread([this] { server_.run(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    client_->set_connection_timeout(5);
  }
  ~LiveServer() {
    server_.stop();  // (waits for fits still running in the background)
    if (thread_.joinable()) thread_.join();
  }
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;
  int port() const { return port_; }
  int live_port() const { return server_.live_port(); }
  httplib::Client& client() { return *client_; }
  void stop() { server_.stop(); }

 private:
  static ServerOptions on_free_port(ServerOptions opt) {
    opt.port = 0;
    return opt;
  }
  Server server_;
  int port_ = -1;
  std::thread thread_;
  std::unique_ptr<httplib::Client> client_;
};

/// Waits (up to a minute) until the runner has no fit left in the background.
void wait_until_idle(const FitRunner& runner) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::minutes(1);
  while (runner.running() > 0 && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
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

TEST(WebApi, RequestCarriesAccuracyAndBestEffort) {
  const ServerOptions opt;
  // Kozak-Krajnc G2 on points with no G2 spline for the tangent rule's ends (the scan at T3
  // proves it even when the iteration cap stops Newton first) is a 400 infeasible, or with
  // "best_effort" the curve and the solver's status.
  const std::string points = R"("points": [[0,0],[1,1],[2,1.2],[3,0],[4,-1],[5,-0.5],[6,2]])";
  const std::string g2 =
      R"("method": "kozak-krajnc", "options": {"g2": true, "g2_max_iterations": 1})";
  const ApiResponse strict = handle_fit("{" + points + ", " + g2 + "}", opt);
  ASSERT_EQ(strict.status, 400) << strict.body;
  EXPECT_EQ(json::parse(strict.body).at("error").at("code"), "infeasible");
  const ApiResponse best = handle_fit("{" + points + ", " + g2 + R"(, "best_effort": true})", opt);
  ASSERT_EQ(best.status, 200) << best.body;
  EXPECT_EQ(json::parse(best.body).at("method_report").at("solver").at("status"),
            "iteration_limit");
  const ApiResponse bad = handle_fit("{" + points + R"(, "accuracy": 2})", opt);
  ASSERT_EQ(bad.status, 400) << bad.body;
  EXPECT_EQ(json::parse(bad.body).at("error").at("code"), "bad_option");
  const ApiResponse typed = handle_fit("{" + points + R"(, "best_effort": "yes"})", opt);
  ASSERT_EQ(typed.status, 400) << typed.body;
  EXPECT_EQ(json::parse(typed.body).at("error").at("code"), "parse_error");
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

TEST(FitRunner, AnswersLikeHandleFitWithinTheLimits) {
  ServerOptions opt;
  opt.max_points = 10;
  FitRunner runner(opt);
  for (const char* body : {R"({"points": [[0,0],[1,0.5],[2,0],[3,0.5]], "method": "li-strain"})",
                           R"({"points": [[0,0],[1,1],[1,1]]})", "{"}) {
    const ApiResponse expected = handle_fit(body, opt);
    const ApiResponse r = runner.fit(body);
    EXPECT_EQ(r.status, expected.status) << body;
    EXPECT_EQ(r.body, expected.body) << body;
    EXPECT_EQ(r.retry_after_s, 0);
    EXPECT_GE(r.elapsed_ms, 0.0);
  }
  EXPECT_EQ(runner.running(), 0u);  // the worker is done once its answer is back
  // 0: no time limit.
  opt.fit_time_limit_ms = 0;
  FitRunner unlimited(opt);
  EXPECT_EQ(unlimited.fit(R"({"points": [[0,0],[1,1],[2,0]]})").status, 200);
}

/// A request whose fit takes about ten seconds (the elastic spline's grid search over 1000
/// sharp points), in steps of a few milliseconds.
std::string very_slow_request() {
  json points = json::array();
  for (const Point& p : testing::random_walk(1000, 5, 150)) points.push_back({p.x, p.y});
  return json{{"points", points}, {"method", "elastic"}, {"options", {{"search", "global"}}}}
      .dump();
}

TEST(FitRunner, ATimedOutFitIsStoppedAndFreesItsSlot) {
  ServerOptions opt;
  opt.fit_time_limit_ms = 1;
  FitRunner runner(opt);
  const auto t0 = std::chrono::steady_clock::now();
  const ApiResponse r = runner.fit(very_slow_request());
  ASSERT_EQ(r.status, 503) << r.body.substr(0, 300);
  EXPECT_EQ(error_of(r).at("code"), "timeout");
  wait_until_idle(runner);
  EXPECT_EQ(runner.running(), 0u);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(ms, 3000.0);  // stopped within a step, not after the fit's ten seconds
  // The request's own time limit stops it the same way, as the library's error.
  opt.fit_time_limit_ms = 0;
  FitRunner unlimited(opt);
  json body = json::parse(very_slow_request());
  body["time_limit"] = 0.05;
  const ApiResponse own = unlimited.fit(body.dump());
  ASSERT_EQ(own.status, 400) << own.body.substr(0, 300);
  EXPECT_EQ(error_of(own).at("code"), "cancelled");
  EXPECT_LT(own.elapsed_ms, 3000.0);
}

TEST(FitRunner, ASlowFitGets503TimeoutAndFinishesInTheBackground) {
  ServerOptions opt;
  opt.fit_time_limit_ms = 1;
  opt.stop_abandoned_fits = false;
  FitRunner runner(opt);
  const std::string body = slow_request();
  const auto t0 = std::chrono::steady_clock::now();
  const ApiResponse r = runner.fit(body);
  const double waited_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(r.status, 503) << r.body.substr(0, 300);
  const json e = error_of(r);
  EXPECT_EQ(e.at("code"), "timeout");
  EXPECT_TRUE(e.at("index").is_null());
  const std::string message = e.at("message");
  EXPECT_NE(message.find("the fit took longer than this server's time limit of 1 ms"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("--fit-time-limit-ms"), std::string::npos) << message;
  EXPECT_NE(message.find("fairspline fit"), std::string::npos) << message;
  EXPECT_EQ(r.retry_after_s, 0);
  EXPECT_LT(waited_ms, 5000.0);     // answered at the limit, not when the fit ends
  EXPECT_EQ(runner.running(), 1u);  // still computing, holding its slot
  wait_until_idle(runner);
  EXPECT_EQ(runner.running(), 0u);
}

TEST(FitRunner, AllSlotsTakenGives503BusyWithRetryAfter) {
  ServerOptions opt;
  opt.fit_time_limit_ms = 1;  // a request waits at most 1 ms for a slot, too
  opt.max_concurrent_fits = 1;
  opt.stop_abandoned_fits = false;  // so that the slot stays taken
  FitRunner runner(opt);
  ASSERT_EQ(runner.fit(slow_request()).status, 503);  // times out; its fit keeps the slot
  const ApiResponse r = runner.fit(R"({"points": [[0,0],[1,1],[2,0]]})");
  ASSERT_EQ(r.status, 503) << r.body;
  const json e = error_of(r);
  EXPECT_EQ(e.at("code"), "busy");
  EXPECT_TRUE(e.at("index").is_null());
  const std::string message = e.at("message");
  EXPECT_NE(message.find("the server is busy: every fit slot (1) is taken by a fit that went "
                         "past the time limit"),
            std::string::npos)
      << message;
  EXPECT_LT(r.elapsed_ms, 5000.0);  // at once, not when a slot frees
  EXPECT_EQ(r.retry_after_s, 1);
  wait_until_idle(runner);
  EXPECT_EQ(runner.running(), 0u);  // the slot is free again
}

TEST(FitRunner, ManyThreadsAtOnceAllGetTheirOwnAnswer) {
  ServerOptions opt;
  opt.max_concurrent_fits = 2;
  FitRunner runner(opt);
  std::vector<std::thread> threads;
  std::vector<int> ok(8, 0);
  for (std::size_t t = 0; t < ok.size(); ++t) {
    threads.emplace_back([&runner, &ok, t] {
      for (int i = 0; i < 10; ++i) {
        // Each thread's own curve: its answer must carry its own points.
        const double y = static_cast<double>(t) + 0.5;
        const std::string body =
            json{{"points", {{0.0, 0.0}, {1.0, y}, {2.0, 0.0}}}, {"method", "jaklic-zagar"}}.dump();
        const ApiResponse r = runner.fit(body);
        if (r.status == 200 && json::parse(r.body).at("points").at(1).at(1) == y) ++ok[t];
      }
    });
  }
  for (std::thread& t : threads) t.join();
  for (std::size_t t = 0; t < ok.size(); ++t) EXPECT_EQ(ok[t], 10) << "thread " << t;
  EXPECT_EQ(runner.running(), 0u);
}

TEST(WebApi, HttpRoundTripOnAFreeLoopbackPort) {
  ServerOptions opt;
  opt.max_body_bytes = 4096;
  opt.max_points = 5;
  LiveServer live(opt);
  ASSERT_GT(live.port(), 0);
  httplib::Client& client = live.client();
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
  // More points than the server takes: 400 with the library's error shape.
  auto many = client.Post("/api/fit", R"({"points": [[0,0],[1,1],[2,0],[3,1],[4,0],[5,1]]})",
                          "application/json");
  ASSERT_TRUE(many);
  EXPECT_EQ(many->status, 400);
  const json many_error = error_of({many->status, many->body});
  EXPECT_EQ(many_error.at("code"), "invalid_argument");
  EXPECT_NE(many_error.at("message").get<std::string>().find(
                "too many points: 6 (this server accepts at most 5)"),
            std::string::npos)
      << many->body;
  // A body above the limit is refused before parsing: 413, in the API's error shape.
  auto big = client.Post("/api/fit", std::string(10000, ' '), "application/json");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  EXPECT_EQ(big->get_header_value("Content-Type"), "application/json");
  const json big_error = error_of({big->status, big->body});
  EXPECT_EQ(big_error.at("code"), "too_large");
  EXPECT_TRUE(big_error.at("index").is_null());
  EXPECT_NE(big_error.at("message").get<std::string>().find(
                "the request body is larger than this server accepts (at most 4096 bytes)"),
            std::string::npos)
      << big->body;
  // httplib caps form-encoded bodies (curl's default type) at 8 kB, whatever our limit: the
  // message says what to do instead of quoting a limit the body did not exceed.
  opt.max_body_bytes = 1 << 20;
  LiveServer roomy(opt);
  ASSERT_GT(roomy.port(), 0);
  auto form =
      roomy.client().Post("/api/fit", std::string(10000, ' '), "application/x-www-form-urlencoded");
  ASSERT_TRUE(form);
  EXPECT_EQ(form->status, 413);
  const std::string form_message = error_of({form->status, form->body}).at("message");
  EXPECT_NE(form_message.find("a request body sent as application/x-www-form-urlencoded may "
                              "have at most 8192 bytes: send it as application/json"),
            std::string::npos)
      << form_message;
  auto missing = client.Get("/api/nothing");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
}

TEST(WebApi, HttpTimeoutAndBusyAre503WithRetryAfter) {
  ServerOptions opt;
  opt.fit_time_limit_ms = 1;
  opt.max_concurrent_fits = 1;
  opt.stop_abandoned_fits = false;
  LiveServer live(opt);
  ASSERT_GT(live.port(), 0);
  httplib::Client& client = live.client();
  auto slow = client.Post("/api/fit", slow_request(), "application/json");
  ASSERT_TRUE(slow);
  EXPECT_EQ(slow->status, 503);
  EXPECT_EQ(slow->get_header_value("Content-Type"), "application/json");
  EXPECT_EQ(error_of({slow->status, slow->body}).at("code"), "timeout");
  EXPECT_FALSE(slow->has_header("Retry-After"));
  auto busy = client.Post("/api/fit", R"({"points": [[0,0],[1,1],[2,0]]})", "application/json");
  ASSERT_TRUE(busy);
  EXPECT_EQ(busy->status, 503);
  EXPECT_EQ(error_of({busy->status, busy->body}).at("code"), "busy");
  EXPECT_EQ(busy->get_header_value("Retry-After"), "1");
}

/// The codes that exist only at the HTTP layer are documented with the others (they have no
/// entry in tests/data/errors.json, which holds the library's codes), quoting the messages
/// that the tests above check.
TEST(WebApi, HttpOnlyCodesAreInTheErrorDocs) {
  std::ifstream in(std::string(FAIRSPLINE_SOURCE_DIR) + "/docs/errors.md");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string doc = ss.str();
  const auto at = doc.find("## Codes of the HTTP layer only");
  ASSERT_NE(at, std::string::npos);
  const std::string section = doc.substr(at);
  for (const char* text :
       {"`too_large`", "`timeout`", "`busy`", "`internal`", "Retry-After: 1",
        "the request body is larger than this server accepts",
        "a request body sent as application/x-www-form-urlencoded may have at most 8192 bytes",
        "the fit took longer than this server's time limit of",
        "the server is busy: every fit slot (N) is taken by a fit that went past the time limit",
        "the server is busy: no fit slot (of N) came free within the time limit of"}) {
    EXPECT_NE(section.find(text), std::string::npos) << "docs/errors.md should say: " << text;
  }
}

// ---------------------------------------------------------------- the live channel

TEST(LiveChannel, AnswerWrapsTheHttpBodyWithStatusAndTime) {
  EXPECT_EQ(live_answer(200, 0.4567, R"({"a":1})"),
            R"({"status":200,"ms":0.457,"answer":{"a":1}})");
  const json j = json::parse(live_answer(400, 12.0, R"({"error":{"code":"x"}})"));
  EXPECT_EQ(j.at("status"), 400);
  EXPECT_EQ(j.at("answer").at("error").at("code"), "x");
  EXPECT_TRUE(json::parse(live_answer(503, 0, "")).at("answer").is_null());
}

TEST(LiveChannel, OnlyTheEditorsOwnPageMayConnect) {
  EXPECT_TRUE(live_origin_allowed("", "127.0.0.1:5000", 8080));  // not a browser
  EXPECT_TRUE(live_origin_allowed("http://127.0.0.1:8080", "127.0.0.1:5000", 8080));
  EXPECT_TRUE(live_origin_allowed("http://LocalHost:8080", "localhost:5000", 8080));
  EXPECT_TRUE(live_origin_allowed("http://[::1]:8080", "[::1]:5000", 8080));
  EXPECT_TRUE(live_origin_allowed("http://example.org", "example.org:5000", 80));
  EXPECT_FALSE(live_origin_allowed("http://127.0.0.1:8081", "127.0.0.1:5000", 8080));
  EXPECT_FALSE(live_origin_allowed("http://evil.example:8080", "127.0.0.1:5000", 8080));
  EXPECT_FALSE(live_origin_allowed("http://127.0.0.1.evil:8080", "127.0.0.1:5000", 8080));
  EXPECT_FALSE(live_origin_allowed("null", "127.0.0.1:5000", 8080));
  EXPECT_FALSE(live_origin_allowed("https://127.0.0.1:8080", "127.0.0.1:5000", 8080));
  EXPECT_FALSE(live_origin_allowed("http://127.0.0.1:8080/x", "127.0.0.1:5000", 8080));
  EXPECT_FALSE(live_origin_allowed("http://127.0.0.1:80x80", "127.0.0.1:5000", 8080));
  EXPECT_FALSE(live_origin_allowed("http://:8080", ":5000", 8080));
}

/// A WebSocket client of the live channel, from RFC 6455 alone (not Boost.Beast, which the
/// server uses): the handshake with the RFC's own key, masked frames out, frames in. Reads time
/// out after 20 s, so that a silent server fails the test instead of hanging it.
class WsClient {
 public:
  struct Frame {
    int opcode = -1;
    std::string payload;
  };

  /// Connects and sends the upgrade request (extra headers end in "\r\n"); returns the
  /// server's answer head, up to its blank line.
  std::string open(int port, const std::string& path = "/api/live", const std::string& extra = "",
                   bool upgrade = true) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    timeval tv{20, 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) return {};
    std::string req =
        "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n";
    if (upgrade) {
      req +=
          "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
          "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n";
    }
    send_all(req + extra + "\r\n");
    std::string head;
    char c = 0;
    while (!head.ends_with("\r\n\r\n") && ::recv(fd_, &c, 1, 0) == 1) head.push_back(c);
    return head;
  }
  ~WsClient() {
    if (fd_ >= 0) ::close(fd_);
  }
  WsClient() = default;
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  void send(int opcode, std::string_view payload) {
    std::string frame(1, static_cast<char>(0x80 | opcode));
    const std::size_t n = payload.size();
    if (n < 126) {
      frame.push_back(static_cast<char>(0x80 | n));
    } else if (n < 65536) {
      frame.push_back(static_cast<char>(0x80 | 126));
      for (int s = 8; s >= 0; s -= 8) frame.push_back(static_cast<char>((n >> s) & 0xff));
    } else {
      frame.push_back(static_cast<char>(0x80 | 127));
      for (int s = 56; s >= 0; s -= 8) frame.push_back(static_cast<char>((n >> s) & 0xff));
    }
    const unsigned char mask[4] = {0x37, 0xfa, 0x21, 0x3d};
    frame.append(reinterpret_cast<const char*>(mask), 4);
    for (std::size_t i = 0; i < n; ++i)
      frame.push_back(static_cast<char>(payload[i] ^ mask[i % 4]));
    send_all(frame);
  }

  /// The next message (its frames joined), or none when the connection ends first.
  std::optional<Frame> read() {
    std::optional<Frame> message;
    for (;;) {
      bool fin = false;
      auto frame = read_frame(fin);
      if (!frame) return std::nullopt;
      if (!message) {
        message = std::move(frame);
      } else {
        message->payload += frame->payload;  // a continuation (opcode 0)
      }
      if (fin) return message;
    }
  }

 private:
  std::optional<Frame> read_frame(bool& fin) {
    unsigned char h[2];
    if (!recv_all(h, 2)) return std::nullopt;
    std::uint64_t n = h[1] & 0x7f;
    if (n >= 126) {
      unsigned char ext[8];
      const std::size_t k = n == 126 ? 2 : 8;
      if (!recv_all(ext, k)) return std::nullopt;
      n = 0;
      for (std::size_t i = 0; i < k; ++i) n = (n << 8) | ext[i];
    }
    Frame f;
    fin = (h[0] & 0x80) != 0;
    f.opcode = h[0] & 0x0f;
    f.payload.resize(n);
    if (n > 0 && !recv_all(f.payload.data(), n)) return std::nullopt;
    return f;
  }

  void send_all(const std::string& s) {
    for (std::size_t done = 0; done < s.size();) {
      const ssize_t k = ::send(fd_, s.data() + done, s.size() - done, MSG_NOSIGNAL);
      if (k <= 0) return;
      done += static_cast<std::size_t>(k);
    }
  }
  bool recv_all(void* p, std::size_t n) {
    auto* c = static_cast<char*>(p);
    for (std::size_t done = 0; done < n;) {
      const ssize_t k = ::recv(fd_, c + done, n - done, 0);
      if (k <= 0) return false;
      done += static_cast<std::size_t>(k);
    }
    return true;
  }
  int fd_ = -1;
};

/// The close code of a close frame.
int close_code(const WsClient::Frame& f) {
  if (f.opcode != 8 || f.payload.size() < 2) return -1;
  return (static_cast<unsigned char>(f.payload[0]) << 8) | static_cast<unsigned char>(f.payload[1]);
}

TEST(LiveChannel, AnswersLikePostApiFitOverAWebSocket) {
  ServerOptions opt;
  opt.max_body_bytes = 100000;
  LiveServer server(opt);
  ASSERT_GT(server.port(), 0);
  // The page learns the channel's port from GET /api/live.
  auto where = server.client().Get("/api/live");
  ASSERT_TRUE(where);
  EXPECT_EQ(where->status, 200);
  const json info = json::parse(where->body);
  ASSERT_GT(server.live_port(), 0);
  EXPECT_EQ(info.at("port"), server.live_port());
  EXPECT_EQ(info.at("path"), "/api/live");
  EXPECT_NE(server.live_port(), server.port());

  WsClient ws;
  const std::string head =
      ws.open(server.live_port(), "/api/live",
              "Origin: http://127.0.0.1:" + std::to_string(server.port()) + "\r\n");
  ASSERT_TRUE(head.starts_with("HTTP/1.1 101")) << head;
  // RFC 6455 section 1.3: the accept value of this key.
  EXPECT_NE(head.find("Sec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo="), std::string::npos)
      << head;
  // Several fits on one connection, answered in order, each exactly the HTTP answer's body.
  const std::string bodies[] = {
      R"({"points": [[0,0],[1,1],[2,0],[3,1]]})",
      R"({"points": [[0,0],[1,2],[3,0]], "method": "li-strain"})",
      json{{"points",
            [] {
              json p = json::array();
              for (const Point& q : testing::random_walk(300, 3)) p.push_back({q.x, q.y});
              return p;
            }()}}
          .dump(),  // an answer of more than 64 kB: a frame with a 64-bit length
      "{",
  };
  for (const std::string& body : bodies) ws.send(1, body);
  for (const std::string& body : bodies) {
    const auto frame = ws.read();
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->opcode, 1);  // text
    const json reply = json::parse(frame->payload);
    const ApiResponse expected = handle_fit(body, opt);
    EXPECT_EQ(reply.at("status"), expected.status) << body.substr(0, 80);
    EXPECT_GE(reply.at("ms").get<double>(), 0.0);
    EXPECT_EQ(reply.at("answer"), json::parse(expected.body)) << body.substr(0, 80);
  }
  // A message above the server's body limit closes the connection with 1009 (too big).
  ws.send(1, std::string(opt.max_body_bytes + 1, ' '));
  const auto too_big = ws.read();
  ASSERT_TRUE(too_big);
  EXPECT_EQ(close_code(*too_big), 1009);

  // A binary message closes it with 1003 (data it cannot accept).
  WsClient binary;
  ASSERT_TRUE(binary.open(server.live_port()).starts_with("HTTP/1.1 101"));
  binary.send(2, R"({"points": [[0,0],[1,1],[2,0]]})");
  const auto refused = binary.read();
  ASSERT_TRUE(refused);
  EXPECT_EQ(close_code(*refused), 1003);
}

TEST(LiveChannel, RefusesOtherPagesPathsAndPlainRequests) {
  LiveServer server{ServerOptions{}};
  ASSERT_GT(server.live_port(), 0);
  WsClient other_site;
  const std::string forbidden =
      other_site.open(server.live_port(), "/api/live", "Origin: http://evil.example\r\n");
  EXPECT_TRUE(forbidden.starts_with("HTTP/1.1 403")) << forbidden;
  WsClient wrong_path;
  EXPECT_TRUE(wrong_path.open(server.live_port(), "/api/fit").starts_with("HTTP/1.1 404"));
  WsClient plain;
  EXPECT_TRUE(plain.open(server.live_port(), "/api/live", "", false).starts_with("HTTP/1.1 426"));
}

TEST(LiveChannel, StopClosesOpenConnectionsAndAFitInFlightIsAnswered) {
  ServerOptions opt;
  opt.fit_time_limit_ms = 60000;
  LiveServer server(opt);
  ASSERT_GT(server.live_port(), 0);
  WsClient idle;  // connected and silent: its thread waits in a read
  ASSERT_TRUE(idle.open(server.live_port()).starts_with("HTTP/1.1 101"));
  WsClient busy;
  ASSERT_TRUE(busy.open(server.live_port()).starts_with("HTTP/1.1 101"));
  busy.send(1, slow_request());
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the fit has started
  const auto start = std::chrono::steady_clock::now();
  server.stop();
  // stop() returned after the threads were joined: the silent connection is closed, and the fit
  // that was running was answered or its connection closed (never a hang).
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
  EXPECT_FALSE(idle.read());
  for (auto frame = busy.read(); frame; frame = busy.read()) {
    if (frame->opcode == 1) {
      EXPECT_EQ(json::parse(frame->payload).at("status"), 200);
    }
  }
}

}  // namespace
}  // namespace fairspline::web
