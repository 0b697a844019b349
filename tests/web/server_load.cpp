// Load test of `fairspline serve` (CTest web.load): the real command on a free loopback port,
// 50 client threads posting valid and invalid fits for 30 s, then a flood of slow fits against
// a second server with a short time limit.
//
//   fairspline_load_test PATH/TO/fairspline
//   environment: FAIRSPLINE_LOAD_SECONDS (default 30), FAIRSPLINE_LOAD_CLIENTS (default 50),
//   FAIRSPLINE_LOAD_RSS_FILE (writes the RSS samples of phase 1 there: seconds and kB per line)
//
// Phase 1 (`serve --max-points 5000 --max-body-bytes 1000000`, default time and concurrency
// limits): every client cycles through a mix of requests -- a valid fit of every method
// listed by GET /api/methods at 5, 200 and 1000 points (3m+1 for kozak-krajnc), a closed
// curve, GET /api/methods, and invalid requests (malformed JSON, NaN, 1e999, a repeated point,
// an unknown method, too many points, an oversize body, a form-encoded body); half of the
// clients keep their connection alive. Checked: every valid request answered 200
// with its curve, every invalid one with its 4xx status and error code, no connection failure,
// the server alive at the end, and its resident memory (VmRSS, sampled every 50 ms) over the
// last 10 s within 10% of the 10 s after the warm-up (the first sixth of the run, at most 5 s),
// comparing medians (shorter windows in shorter runs).
// Phase 2 (`serve --fit-time-limit-ms 100 --max-concurrent-fits 2`, a tenth of the run, at
// least 2 s): every client posts a 20000-point fit (1 s in Release). Checked: every answer is
// 503 "timeout" or 503 "busy" with Retry-After (or 200, should a fit be fast enough), both
// occur, no connection failure, and the server answers a small fit with 200 once the
// abandoned fits are done.
// Prints requests/s, latency percentiles, memory, and the count of each kind of answer.
// The loops are bounded by the clock; the servers are killed at the end (and if this program
// dies first: PR_SET_PDEATHSIG).
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#if defined(__SANITIZE_ADDRESS__)
#define FAIRSPLINE_LOAD_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FAIRSPLINE_LOAD_ASAN 1
#endif
#endif

namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

std::atomic<int> g_failures{0};
std::mutex g_print;

void fail(const std::string& what) {
  const int n = ++g_failures;
  if (n <= 20) {
    std::lock_guard lock(g_print);
    std::fprintf(stderr, "FAIL %s\n", what.c_str());
  } else if (n == 21) {
    std::lock_guard lock(g_print);
    std::fprintf(stderr, "FAIL ... (further failures counted, not printed)\n");
  }
}

void check(bool ok, const std::string& what) {
  if (!ok) fail(what);
}

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  if (v == nullptr || *v == '\0') return fallback;
  const int n = std::atoi(v);
  return n > 0 ? n : fallback;
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// ---------------------------------------------------------------- the server process

/// `fairspline serve --port 0 ARGS...` as a child process; the port is read from its first
/// line ("fairspline: serving http://127.0.0.1:PORT/"), as apps/web/e2e/harness.mjs does.
class ServerProcess {
 public:
  ServerProcess(const std::string& cli, const std::vector<std::string>& args) {
    int fds[2];
    if (pipe(fds) != 0) return;
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ == 0) {
      // The child: dies with this program (the forking thread is the main thread).
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (getppid() != parent) _exit(127);
      dup2(fds[1], STDOUT_FILENO);
      close(fds[0]);
      close(fds[1]);
      std::vector<std::string> all = {cli, "serve", "--port", "0"};
      all.insert(all.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (std::string& a : all) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(cli.c_str(), argv.data());
      _exit(127);
    }
    close(fds[1]);
    out_ = fds[0];
    if (pid_ < 0) return;
    std::string line;
    const auto until = Clock::now() + std::chrono::seconds(30);
    while (line.find('\n') == std::string::npos && Clock::now() < until) {
      pollfd p{out_, POLLIN, 0};
      if (poll(&p, 1, 200) <= 0) continue;
      char buf[256];
      const ssize_t n = read(out_, buf, sizeof buf);
      if (n <= 0) break;
      line.append(buf, static_cast<std::size_t>(n));
    }
    const auto at = line.find("http://127.0.0.1:");
    if (at != std::string::npos) port_ = std::atoi(line.c_str() + at + 17);
    if (port_ <= 0) std::fprintf(stderr, "server did not start; it said: %s\n", line.c_str());
  }
  ~ServerProcess() { stop(); }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  int port() const { return port_; }
  pid_t pid() const { return pid_; }

  bool alive() {
    if (pid_ <= 0 || exited_) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      std::fprintf(stderr, "server %d ended: %s %d\n", pid_,
                   WIFSIGNALED(status) ? "signal" : "exit status",
                   WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
      return false;
    }
    return true;
  }

  /// Resident memory in kB (VmRSS of /proc/PID/status), 0 if unknown.
  long rss_kb() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
    std::string key;
    while (in >> key) {
      if (key == "VmRSS:") {
        long kb = 0;
        in >> kb;
        return kb;
      }
      in.ignore(1 << 20, '\n');
    }
    return 0;
  }

  /// CPU time used so far (user + system, /proc/PID/stat), in seconds.
  double cpu_seconds() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto paren = text.rfind(')');
    if (paren == std::string::npos) return 0.0;
    std::istringstream fields(text.substr(paren + 2));
    std::string f;
    double ticks = 0;
    for (int i = 3; i <= 15 && fields >> f; ++i) {
      if (i == 14 || i == 15) ticks += std::atof(f.c_str());  // utime, stime
    }
    return ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
  }

  void stop() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGTERM);
      int status = 0;
      const auto until = Clock::now() + std::chrono::seconds(10);
      while (waitpid(pid_, &status, WNOHANG) == 0) {
        if (Clock::now() > until) {
          kill(pid_, SIGKILL);
          waitpid(pid_, &status, 0);
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      exited_ = true;
    }
    if (out_ >= 0) close(out_);
    out_ = -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  int port_ = -1;
  bool exited_ = false;
};

// ---------------------------------------------------------------- requests

struct Case {
  std::string label;
  bool valid = false;
  bool get = false;  // GET /api/methods instead of POST /api/fit
  std::string body;
  std::string content_type = "application/json";
  int status = 200;
  std::string code;    // expected error code of an invalid request
  std::string method;  // expected "method" of a valid fit
  std::size_t points = 0;
  int weight = 1;
};

json wave(std::size_t n) {
  // What a user draws in the editor (the curve of bench/web_api_bench.cpp).
  json points = json::array();
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    points.push_back({50.0 + 900.0 * t / static_cast<double>(n - 1),
                      350.0 + 200.0 * std::sin(t / 12.0) + 40.0 * std::sin(t / 3.7)});
  }
  return points;
}

/// A valid request for `method` at about n points (3m+1 for kozak-krajnc).
Case valid_fit(const std::string& method, std::size_t n, int weight) {
  if (method == "kozak-krajnc") n = 3 * ((n - 1) / 3) + 1;
  json body = {{"points", wave(n)}, {"method", method}};
  if (method == "yong-cheng") body["options"] = {{"tangents_from", "jaklic-zagar"}};
  if (method == "li-curvature-variation") body["start_tangent"] = {1.0, 0.0};
  Case c;
  c.label = method + "/" + std::to_string(n);
  c.valid = true;
  c.body = body.dump();
  c.method = method;
  c.points = n;
  c.weight = weight;
  return c;
}

Case invalid(std::string label, std::string body, int status, std::string code) {
  Case c;
  c.label = std::move(label);
  c.body = std::move(body);
  c.status = status;
  c.code = std::move(code);
  return c;
}

constexpr std::size_t kMaxPoints = 5000;
constexpr std::size_t kMaxBodyBytes = 1000000;

std::vector<Case> phase1_cases(const json& methods) {
  std::vector<Case> cases;
  for (const json& m : methods.at("methods")) {
    const std::string name = m.at("name");
    cases.push_back(valid_fit(name, 5, 3));
    cases.push_back(valid_fit(name, 200, 3));
    cases.push_back(valid_fit(name, 1000, 1));
  }
  {
    json circle = json::array();
    for (int i = 0; i < 50; ++i) {
      const double a = 2 * std::numbers::pi * i / 50;
      circle.push_back({std::cos(a), std::sin(a)});
    }
    Case c;
    c.label = "closed/50";
    c.valid = true;
    c.body = json{{"points", circle}, {"closed", true}}.dump();
    c.method = methods.at("default");
    c.points = 50;
    cases.push_back(c);
  }
  {
    Case c;
    c.label = "GET /api/methods";
    c.valid = true;
    c.get = true;
    cases.push_back(c);
  }
  cases.push_back(invalid("malformed", R"({"points": [[0,0],[1,1],)", 400, "parse_error"));
  cases.push_back(invalid("NaN", R"({"points": [[0,0],[1,NaN],[2,0]]})", 400, "parse_error"));
  cases.push_back(invalid("1e999", R"({"points": [[0,0],[1,1e999],[2,0]]})", 400, "non_finite"));
  cases.push_back(
      invalid("repeated", R"({"points": [[0,0],[1,1],[1,1],[2,0]]})", 400, "repeated_point"));
  cases.push_back(invalid("unknown method", R"({"points": [[0,0],[1,1],[2,0]], "method": "nope"})",
                          400, "unknown_method"));
  cases.push_back(invalid("too many points", json{{"points", wave(kMaxPoints + 1)}}.dump(), 400,
                          "invalid_argument"));
  {
    // Valid JSON, one byte over the limit.
    std::string big = json{{"points", wave(3)}}.dump();
    big.insert(1, kMaxBodyBytes + 1 - big.size(), ' ');
    cases.push_back(invalid("oversize body", big, 413, "too_large"));
  }
  {
    Case c = invalid("form-encoded 10 kB", json{{"points", wave(400)}}.dump(), 413, "too_large");
    c.content_type = "application/x-www-form-urlencoded";
    cases.push_back(c);
  }
  return cases;
}

// ---------------------------------------------------------------- clients

struct Tally {
  std::vector<long> count;  // per case
  std::vector<double> valid_ms, invalid_ms;
  std::map<std::string, long> answers;     // "200", "400 parse_error", "503 busy", ...
  std::map<std::string, long> per_method;  // valid fits answered 200, by method
  long transport_errors = 0;
  double slowest_ms = 0;
  std::string slowest;

  void merge(const Tally& o) {
    if (count.size() < o.count.size()) count.resize(o.count.size());
    for (std::size_t i = 0; i < o.count.size(); ++i) count[i] += o.count[i];
    valid_ms.insert(valid_ms.end(), o.valid_ms.begin(), o.valid_ms.end());
    invalid_ms.insert(invalid_ms.end(), o.invalid_ms.begin(), o.invalid_ms.end());
    for (const auto& [k, v] : o.answers) answers[k] += v;
    for (const auto& [k, v] : o.per_method) per_method[k] += v;
    transport_errors += o.transport_errors;
    if (o.slowest_ms > slowest_ms) {
      slowest_ms = o.slowest_ms;
      slowest = o.slowest;
    }
  }
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

std::string error_code(const std::string& body) {
  const json j = json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("error")) return "(no error body)";
  const json& e = j.at("error");
  if (!e.contains("code") || !e.contains("message") || !e.contains("index")) {
    return "(malformed error body)";
  }
  return e.at("code").is_string() ? e.at("code").get<std::string>() : "(bad code)";
}

std::unique_ptr<httplib::Client> make_client(int port, bool keep_alive) {
  auto client = std::make_unique<httplib::Client>("127.0.0.1", port);
  client->set_keep_alive(keep_alive);
  client->set_tcp_nodelay(true);  // as browsers do
  client->set_connection_timeout(30);
  client->set_read_timeout(60);
  client->set_write_timeout(60);
  return client;
}

/// One client of phase 1: cycles through `schedule` (case indices) from `offset` until `stop`.
void phase1_client(int port, bool keep_alive, const std::vector<Case>& cases,
                   const std::vector<std::size_t>& schedule, std::size_t offset,
                   const std::atomic<bool>& stop, Tally& tally) {
  auto client = make_client(port, keep_alive);
  tally.count.assign(cases.size(), 0);
  for (std::size_t k = offset; !stop.load(std::memory_order_relaxed); ++k) {
    const std::size_t ci = schedule[k % schedule.size()];
    const Case& c = cases[ci];
    const auto t0 = Clock::now();
    httplib::Result res = c.get ? client->Get("/api/methods")
                                : client->Post("/api/fit", c.body, c.content_type.c_str());
    const double ms = ms_since(t0);
    ++tally.count[ci];
    if (ms > tally.slowest_ms) {
      tally.slowest_ms = ms;
      tally.slowest = c.label + (keep_alive ? " (keep-alive)" : "");
    }
    if (!res) {
      ++tally.transport_errors;
      fail(c.label + ": no answer (" + httplib::to_string(res.error()) + ")");
      client = make_client(port, keep_alive);
      continue;
    }
    const int status = res->status;
    const std::string code = status == 200 ? std::string() : error_code(res->body);
    ++tally.answers[std::to_string(status) + (code.empty() ? "" : " " + code)];
    if (c.valid) {
      tally.valid_ms.push_back(ms);
      if (status != 200) {
        fail(c.label + ": " + std::to_string(status) + " " + res->body.substr(0, 300));
        continue;
      }
      check(res->get_header_value("Content-Type") == "application/json",
            c.label + ": Content-Type " + res->get_header_value("Content-Type"));
      const json j = json::parse(res->body, nullptr, false);
      if (j.is_discarded()) {
        fail(c.label + ": the answer is not JSON");
        continue;
      }
      if (c.get) {
        check(j.contains("methods") && !j.at("methods").empty(), c.label + ": no methods");
        continue;
      }
      const bool ok = j.value("method", "") == c.method && j.contains("segments") &&
                      !j.at("segments").empty() && j.contains("report") && j.contains("points") &&
                      j.at("points").size() == c.points;
      check(ok, c.label + ": not the curve asked for: " + res->body.substr(0, 200));
      if (ok) ++tally.per_method[c.method];
    } else {
      tally.invalid_ms.push_back(ms);
      check(status == c.status && code == c.code,
            c.label + ": expected " + std::to_string(c.status) + " " + c.code + ", got " +
                std::to_string(status) + " " + code + " " + res->body.substr(0, 200));
    }
  }
}

/// One client of phase 2: posts `body` (a slow fit) until `stop`.
void flood_client(int port, const std::string& body, const std::atomic<bool>& stop, Tally& tally) {
  auto client = make_client(port, false);
  while (!stop.load(std::memory_order_relaxed)) {
    const auto t0 = Clock::now();
    httplib::Result res = client->Post("/api/fit", body, "application/json");
    const double ms = ms_since(t0);
    if (!res) {
      ++tally.transport_errors;
      fail("flood: no answer (" + httplib::to_string(res.error()) + ")");
      client = make_client(port, false);
      continue;
    }
    const std::string code = res->status == 200 ? std::string() : error_code(res->body);
    ++tally.answers[std::to_string(res->status) + (code.empty() ? "" : " " + code)];
    (res->status == 200 ? tally.valid_ms : tally.invalid_ms).push_back(ms);
    if (res->status == 200) continue;
    check(res->status == 503 && (code == "timeout" || code == "busy"),
          "flood: expected 503 timeout or busy, got " + std::to_string(res->status) + " " +
              res->body.substr(0, 200));
    if (code == "busy") {
      check(res->get_header_value("Retry-After") == "1",
            "flood: busy without Retry-After: 1 (" + res->get_header_value("Retry-After") + ")");
    }
  }
}

template <typename Client>
void run_clients(int clients, double seconds, Client client, std::vector<Tally>& tallies,
                 const std::function<void(double)>& each_tick) {
  std::atomic<bool> stop{false};
  tallies.assign(static_cast<std::size_t>(clients), Tally{});
  std::vector<std::thread> threads;
  for (int i = 0; i < clients; ++i) {
    threads.emplace_back([&, i] { client(i, stop, tallies[static_cast<std::size_t>(i)]); });
  }
  const auto t0 = Clock::now();
  for (double t = 0; t < seconds; t = ms_since(t0) / 1000.0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    each_tick(ms_since(t0) / 1000.0);
  }
  stop = true;
  for (std::thread& t : threads) t.join();
}

/// Length of the two windows whose RSS medians are compared.
double rss_window(int seconds, double warmup) {
  return std::min(10.0, (seconds - warmup) / 2.0);
}

long sum(const std::map<std::string, long>& m) {
  long s = 0;
  for (const auto& [k, v] : m) s += v;
  return s;
}

void print_answers(const char* what, const std::map<std::string, long>& answers) {
  std::printf("  %s:", what);
  for (const auto& [k, v] : answers) std::printf("  [%s] %ld", k.c_str(), v);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s PATH/TO/fairspline\n", argv[0]);
    return 2;
  }
  signal(SIGPIPE, SIG_IGN);
  const std::string cli = argv[1];
  const int seconds = env_int("FAIRSPLINE_LOAD_SECONDS", 30);
  const int clients = env_int("FAIRSPLINE_LOAD_CLIENTS", 50);
  const double warmup = std::clamp(seconds / 6.0, 1.0, 5.0);
  std::printf("load test: %d clients, %d s (warm-up %.1f s), then a flood of slow fits\n", clients,
              seconds, warmup);

  // ---- phase 1
  long rss_warm = 0, rss_end = 0, rss_peak = 0;
  std::vector<std::pair<double, long>> rss_samples;  // (seconds, kB), every 50 ms
  std::vector<long> rss_series;                      // one sample a second, for the log
  double server_cpu = 0, client_cpu = 0;
  Tally total;
  double elapsed_s = 0;
  std::size_t method_count = 0;
  {
    ServerProcess server(cli, {"--max-points", std::to_string(kMaxPoints), "--max-body-bytes",
                               std::to_string(kMaxBodyBytes)});
    if (server.port() <= 0) return 1;
    httplib::Client probe("127.0.0.1", server.port());
    auto listed = probe.Get("/api/methods");
    if (!listed || listed->status != 200) {
      std::fprintf(stderr, "GET /api/methods failed\n");
      return 1;
    }
    const json methods = json::parse(listed->body);
    method_count = methods.at("methods").size();
    const std::vector<Case> cases = phase1_cases(methods);
    std::vector<std::size_t> schedule;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      for (int w = 0; w < cases[i].weight; ++w) schedule.push_back(i);
    }
    // Spread the kinds of request over the schedule (a fixed shuffle).
    std::mt19937 rng(12345);
    std::shuffle(schedule.begin(), schedule.end(), rng);
    std::printf(
        "server pid %d on port %d; %zu kinds of request (%zu methods), RSS at start %ld kB\n",
        server.pid(), server.port(), cases.size(), method_count, server.rss_kb());

    std::vector<Tally> tallies;
    const auto t0 = Clock::now();
    run_clients(
        clients, seconds,
        [&](int i, const std::atomic<bool>& stop, Tally& tally) {
          phase1_client(
              server.port(), i % 2 == 0, cases, schedule,
              static_cast<std::size_t>(i) * schedule.size() / static_cast<std::size_t>(clients),
              stop, tally);
        },
        tallies,
        [&](double t) {
          const long rss = server.rss_kb();
          rss_peak = std::max(rss_peak, rss);
          rss_samples.emplace_back(t, rss);
          if (t >= static_cast<double>(rss_series.size() + 1)) rss_series.push_back(rss);
        });
    // The resident size swings by +-20% from one sample to the next with the requests in
    // flight (a 1000-point answer is 650 kB, an oversize body 1 MB): compare the medians of the
    // samples over a window after the warm-up and over the last window of the run (10 s each
    // in a 30 s run, both under load). A leak shows as a rise of one against the other; with
    // 5 s windows the medians of a flat run still differed by up to 6%.
    const double window = rss_window(seconds, warmup);
    std::vector<double> early, late;
    for (const auto& [t, kb] : rss_samples) {
      if (t >= warmup && t < warmup + window) early.push_back(static_cast<double>(kb));
      if (t >= seconds - window) late.push_back(static_cast<double>(kb));
    }
    rss_warm = static_cast<long>(percentile(early, 50));
    rss_end = static_cast<long>(percentile(late, 50));
    elapsed_s = ms_since(t0) / 1000.0;
    if (const char* path = std::getenv("FAIRSPLINE_LOAD_RSS_FILE")) {
      std::ofstream out(path);
      for (const auto& [t, kb] : rss_samples) out << t << " " << kb << "\n";
    }
    server_cpu = server.cpu_seconds();
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    client_cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                 1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    for (const Tally& t : tallies) total.merge(t);
    check(server.alive(), "phase 1: the server is not alive at the end");
    for (std::size_t i = 0; i < cases.size(); ++i) {
      check(i < total.count.size() && total.count[i] > 0, "never sent: " + cases[i].label);
    }
    for (const json& m : methods.at("methods")) {
      check(total.per_method[m.at("name").get<std::string>()] > 0,
            "no successful fit of " + m.at("name").get<std::string>());
    }
    server.stop();
  }
  check(total.transport_errors == 0, "phase 1: connection failures");
  const long requests = sum(total.answers);
  const double growth = rss_warm > 0 ? 100.0 * (static_cast<double>(rss_end) / rss_warm - 1) : 0;
  std::printf(
      "phase 1: %ld requests in %.1f s = %.0f requests/s; %zu valid, %zu invalid, %ld "
      "connection failures\n",
      requests, elapsed_s, static_cast<double>(requests) / elapsed_s, total.valid_ms.size(),
      total.invalid_ms.size(), total.transport_errors);
  std::printf("  latency valid:   p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
              percentile(total.valid_ms, 50), percentile(total.valid_ms, 99),
              percentile(total.valid_ms, 100));
  std::printf("  latency invalid: p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
              percentile(total.invalid_ms, 50), percentile(total.invalid_ms, 99),
              percentile(total.invalid_ms, 100));
  std::printf("  slowest: %s, %.0f ms\n", total.slowest.c_str(), total.slowest_ms);
  print_answers("answers", total.answers);
  print_answers("200 by method", total.per_method);
  std::printf("  CPU: server %.1f s, clients %.1f s (%.1f cores in all)\n", server_cpu, client_cpu,
              (server_cpu + client_cpu) / elapsed_s);
  std::printf("  RSS each second (MB):");
  for (long kb : rss_series) std::printf(" %.1f", static_cast<double>(kb) / 1024.0);
  std::printf("\n");
  std::printf(
      "  RSS (median over %.1f s) after warm-up %ld kB, at the end %ld kB (%+.1f%%); "
      "peak %ld kB\n",
      rss_window(seconds, warmup), rss_warm, rss_end, growth, rss_peak);
#ifdef FAIRSPLINE_LOAD_ASAN
  std::printf("  (AddressSanitizer build: its quarantine holds freed memory, RSS not judged)\n");
#else
  check(rss_warm > 0 && rss_end > 0, "RSS not measured");
  check(growth < 10.0, "RSS grew by " + std::to_string(growth) + "% (limit 10%)");
#endif

  // ---- phase 2: a flood of slow fits against a short time limit
  const double flood_seconds = std::max(2.0, seconds / 10.0);
  Tally flood;
  {
    ServerProcess server(cli, {"--fit-time-limit-ms", "100", "--max-concurrent-fits", "2"});
    if (server.port() <= 0) return 1;
    json points = json::array();
    {
      std::mt19937_64 rng(7);
      std::uniform_real_distribution<double> turn(-2.0, 2.0), step(0.5, 2.0);
      double x = 0, y = 0, h = 0;
      for (int i = 0; i < 20000; ++i) {
        points.push_back({x, y});
        h += turn(rng);
        const double s = step(rng);
        x += s * std::cos(h);
        y += s * std::sin(h);
      }
    }
    const std::string slow = json{{"points", points}, {"method", "min-energy"}}.dump();
    std::vector<Tally> tallies;
    long peak = 0;
    run_clients(
        clients, flood_seconds,
        [&](int, const std::atomic<bool>& stop, Tally& tally) {
          flood_client(server.port(), slow, stop, tally);
        },
        tallies, [&](double) { peak = std::max(peak, server.rss_kb()); });
    for (const Tally& t : tallies) flood.merge(t);
    check(server.alive(), "phase 2: the server is not alive after the flood");
    // Once the abandoned fits are done, a small fit is answered again.
    const auto t0 = Clock::now();
    bool recovered = false;
    httplib::Client probe("127.0.0.1", server.port());
    probe.set_read_timeout(30);
    while (!recovered && ms_since(t0) < 60000) {
      auto r = probe.Post("/api/fit", R"({"points": [[0,0],[1,1],[2,0]]})", "application/json");
      recovered = r && r->status == 200;
      if (!recovered) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    check(recovered, "phase 2: no 200 for a small fit within 60 s after the flood");
    std::printf(
        "phase 2 (limit 100 ms, 2 fit slots, 20000-point fits): %ld answers in %.1f s, "
        "%ld connection failures; recovered after %.1f s; RSS peak %ld kB\n",
        sum(flood.answers), flood_seconds, flood.transport_errors, ms_since(t0) / 1000.0, peak);
    std::printf("  latency 503: p50 %.1f ms, p99 %.1f ms\n", percentile(flood.invalid_ms, 50),
                percentile(flood.invalid_ms, 99));
    print_answers("answers", flood.answers);
    server.stop();
  }
  check(flood.transport_errors == 0, "phase 2: connection failures");
  check(flood.answers["503 timeout"] > 0, "phase 2: no 503 timeout");
  check(flood.answers["503 busy"] > 0, "phase 2: no 503 busy");

  if (g_failures > 0) {
    std::printf("FAILED: %d check(s)\n", g_failures.load());
    return 1;
  }
  std::printf("all load checks passed\n");
  return 0;
}
