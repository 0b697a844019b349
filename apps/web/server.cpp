#include "server.hpp"

#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"
#include "live.hpp"

namespace fairspline::web {

namespace {

// Messages quote the request (a bad field, a bad option value), which need not be valid UTF-8:
// bodies are written with invalid bytes replaced, so that writing an answer never throws.
std::string dump(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

ApiResponse error_response(int status, const Error& e) {
  return {status, dump(io::error_to_json(e))};
}

/// The error shape of the library's errors, for the codes that exist only at the HTTP layer
/// ("timeout", "busy", "too_large", "internal"): they are no fairspline::Error.
std::string http_error_body(std::string_view code, const std::string& message) {
  return dump(nlohmann::json{
      {"error", {{"code", std::string(code)}, {"message", message}, {"index", nullptr}}}});
}

/// Pending connections the kernel keeps for the server (capped by net.core.somaxconn).
constexpr int kListenBacklog = 1024;
/// The Retry-After of a "busy" answer, in seconds.
constexpr int kBusyRetryAfterSeconds = 1;

ApiResponse handle_fit_untimed(std::string_view body, const ServerOptions& options,
                               const std::atomic<bool>* stop) {
  try {
    // The same parser as `fairspline fit` (line/column of a syntax error, 1e999 named, typos
    // in field names refused).
    const io::ParsedInput parsed = io::parse_json_input(body);
    if (parsed.input.points.size() > options.max_points) {
      return error_response(
          400,
          Error(ErrorCode::kInvalidArgument,
                "too many points: " + std::to_string(parsed.input.points.size()) +
                    " (this server accepts at most " + std::to_string(options.max_points) + ")"));
    }
    const std::string method = parsed.method ? *parsed.method : std::string(default_method_name());
    FitOptions fit_options = parsed.fit_options(ReportLevel::kFull);
    if (stop) {
      fit_options.progress_interval = 0.01;
      fit_options.progress = [stop](const FitProgress&) { return !stop->load(); };
    }
    const FitResult result = fit(method, parsed.input, parsed.options, fit_options);
    return {200, io::write_json(result)};
  } catch (const Error& e) {
    return error_response(400, e);
  } catch (const std::exception& e) {
    // Not a user error: report it without bringing the server down.
    return {500, http_error_body("internal", e.what())};
  }
}

}  // namespace

ApiResponse handle_methods() {
  return {
      200,
      nlohmann::json{{"default", default_method_name()}, {"methods", registry_schema()}}.dump()};
}

ApiResponse handle_fit(std::string_view body, const ServerOptions& options,
                       const std::atomic<bool>* stop) {
  const auto start = std::chrono::steady_clock::now();
  ApiResponse response = handle_fit_untimed(body, options, stop);
  response.elapsed_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return response;
}

// ---------------------------------------------------------------- FitRunner
//
// A slot is a worker thread: at most max_concurrent_fits of them, started when first needed and
// kept until the runner dies (no thread per request; each thread keeps its malloc arena, which
// keeps the server's memory flat under load). A timed-out fit, "abandoned", is stopped at its
// next step (its progress callback reads `stop`; a closed-form fit or a report runs to its end)
// and keeps its slot until then: that is what keeps a flood of slow fits from piling up work
// and memory. A request waits for
// a free slot, since a slot held by a fit whose request is still waiting frees within the time
// limit; but when every slot is held by an abandoned fit, which has already run past the limit,
// it is answered "busy" at once. One mutex guards the counts, the queue and the jobs; `changed`
// announces a fit done or abandoned, `work` a job queued or the end.

struct FitRunner::Impl {
  struct Job {
    std::string body;  // the worker's own copy: the request may be gone when it reads it
    ApiResponse response;
    bool done = false;       // guarded by mutex
    bool abandoned = false;  // guarded by mutex: the request timed out, nobody reads response
    std::atomic<bool> stop{false};  // set with abandoned (when options.stop_abandoned_fits)
  };

  ServerOptions options;
  std::size_t slots = 1;
  mutable std::mutex mutex;
  std::condition_variable changed;
  std::condition_variable work;
  std::size_t running = 0;    // fits admitted and not done: queued, or computing on a worker
  std::size_t abandoned = 0;  // of which their request has timed out
  bool stopping = false;
  std::deque<std::shared_ptr<Job>> queue;
  std::vector<std::thread> workers;

  void worker() {
    std::unique_lock lock(mutex);
    for (;;) {
      work.wait(lock, [this] { return stopping || !queue.empty(); });
      if (queue.empty()) return;  // stopping, and nothing left to do
      const std::shared_ptr<Job> job = std::move(queue.front());
      queue.pop_front();
      lock.unlock();
      ApiResponse r =
          handle_fit(job->body, options, options.stop_abandoned_fits ? &job->stop : nullptr);
      std::string().swap(job->body);  // only this thread reads it
      lock.lock();
      if (job->abandoned) {
        --abandoned;
      } else {
        job->response = std::move(r);
      }
      job->done = true;
      --running;
      changed.notify_all();
      lock.unlock();
      r = ApiResponse{};  // an abandoned answer is freed here, outside the lock
      lock.lock();
    }
  }
};

FitRunner::FitRunner(ServerOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->slots = std::max<std::size_t>(1, impl_->options.max_concurrent_fits);
}

FitRunner::~FitRunner() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->work.notify_all();
  // Each worker finishes its fit (and whatever is queued) first: at most the length of a fit.
  for (std::thread& t : impl_->workers) t.join();
}

std::size_t FitRunner::running() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->running;
}

ApiResponse FitRunner::fit(std::string_view body) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  // 0: no limit (and at most a year, so that start + limit cannot overflow the clock).
  const std::int64_t limit_ms = impl_->options.fit_time_limit_ms <= 0
                                    ? std::int64_t{365} * 24 * 3600'000
                                    : std::min<std::int64_t>(impl_->options.fit_time_limit_ms,
                                                             std::int64_t{365} * 24 * 3600'000);
  const auto deadline = start + std::chrono::milliseconds(limit_ms);
  const auto elapsed_ms = [&start] {
    return std::chrono::duration<double, std::milli>(clock::now() - start).count();
  };
  const auto busy = [&](const std::string& why) {
    ApiResponse r{503, http_error_body("busy", "the server is busy: " + why + "; retry in " +
                                                   std::to_string(kBusyRetryAfterSeconds) +
                                                   " s, or fit with the command line "
                                                   "(fairspline fit)")};
    r.elapsed_ms = elapsed_ms();
    r.retry_after_s = kBusyRetryAfterSeconds;
    return r;
  };
  try {
    auto job = std::make_shared<Impl::Job>();
    job->body.assign(body);
    Impl& impl = *impl_;
    std::unique_lock lock(impl.mutex);
    const bool got_slot = impl.changed.wait_until(lock, deadline, [&impl] {
      return impl.running < impl.slots || impl.abandoned >= impl.slots;
    });
    if (!got_slot || impl.running >= impl.slots) {
      const std::string n = std::to_string(impl.slots);
      return busy(got_slot ? "every fit slot (" + n +
                                 ") is taken by a fit that went past the time limit and has "
                                 "not stopped yet"
                           : "no fit slot (of " + n + ") came free within the time limit of " +
                                 std::to_string(limit_ms) + " ms");
    }
    // Admitted. The workers not computing take the queued jobs; start one more when they are
    // too few (never more than the slots: computing + queued = running <= slots).
    impl.queue.push_back(job);
    ++impl.running;
    const std::size_t computing = impl.running - impl.queue.size();
    if (impl.workers.size() - computing < impl.queue.size()) {
      try {
        impl.workers.emplace_back([&impl] { impl.worker(); });
      } catch (...) {
        if (impl.workers.empty()) {
          impl.queue.pop_back();
          --impl.running;
          return busy("it cannot start a thread to fit on");
        }
        // Else the job waits for a worker to be done with its fit.
      }
    }
    impl.work.notify_one();
    impl.changed.wait_until(lock, deadline, [&job] { return job->done; });
    if (job->done) return std::move(job->response);  // elapsed_ms: the fit's own time
    job->abandoned = true;
    job->stop = true;
    ++impl.abandoned;
    impl.changed.notify_all();  // requests waiting for a slot may now be answered "busy"
    lock.unlock();
    ApiResponse r{
        503,
        http_error_body("timeout", "the fit took longer than this server's time limit of " +
                                       std::to_string(limit_ms) +
                                       " ms (it is stopped, and its answer dropped): fit fewer "
                                       "points or a faster method, start the server with "
                                       "a larger --fit-time-limit-ms, or fit with the command line "
                                       "(fairspline fit), which has no time limit")};
    r.elapsed_ms = elapsed_ms();
    return r;
  } catch (const std::system_error&) {
    return busy("it cannot take a lock");
  } catch (const std::bad_alloc&) {
    return busy("it is out of memory");
  }
}

// ---------------------------------------------------------------- Server

struct Server::Impl {
  explicit Impl(ServerOptions opt)
      : options(std::move(opt)), runner(options), live(runner, options.max_body_bytes) {}
  ServerOptions options;
  FitRunner runner;  // destroyed after http and live, which call it
  LiveChannel live;
  int live_port = -1;  // −1: no live channel (the page fits over HTTP)
  httplib::Server http;
  bool binding = false;                  // inside bind(): sockets made are listeners
  ::socket_t listener = INVALID_SOCKET;  // the listening socket, once bound
};

Server::Server(ServerOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  httplib::Server& http = impl_->http;
  // httplib's own options (SO_REUSEADDR...), and the listening socket kept for bind().
  http.set_socket_options([impl = impl_.get()](::socket_t sock) {
    httplib::default_socket_options(sock);
    if (impl->binding) impl->listener = sock;
  });
  const ServerOptions& opt = impl_->options;
  http.set_payload_max_length(opt.max_body_bytes);
  // Answers go out as a header write and a body write; with Nagle's algorithm the second waited
  // for the client's delayed ACK (40 ms on Linux) whenever the first was small.
  http.set_tcp_nodelay(true);
  // No compression: Debian's cpp-httplib is built with brotli and compresses whatever a client
  // accepts, with no switch to turn it off; at brotli's default quality a 200-point fit answer
  // (110 kB) took 380 ms against 3 ms of work, app.js 100 ms. On loopback that is all loss, so
  // Accept-Encoding is dropped before routing. The Request is a non-const local of the library
  // handed out as const&, so removing a header from it is well defined.
  http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
    const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");
    return httplib::Server::HandlerResponse::Unhandled;
  });
  http.Get("/api/methods", [](const httplib::Request&, httplib::Response& res) {
    const ApiResponse r = handle_methods();
    res.status = r.status;
    res.set_content(r.body, "application/json");
  });
  // The live channel is on a port of its own: the page asks for it.
  http.Get("/api/live", [impl = impl_.get()](const httplib::Request&, httplib::Response& res) {
    const nlohmann::json port =
        impl->live_port > 0 ? nlohmann::json(impl->live_port) : nlohmann::json(nullptr);
    res.set_content(nlohmann::json{{"port", port}, {"path", kLivePath}}.dump(), "application/json");
  });
  http.Post("/api/fit",
            [&runner = impl_->runner](const httplib::Request& req, httplib::Response& res) {
              const ApiResponse r = runner.fit(req.body);
              res.status = r.status;
              char timing[48];
              std::snprintf(timing, sizeof timing, "fit;dur=%.3f", r.elapsed_ms);
              res.set_header("Server-Timing", timing);
              if (r.retry_after_s > 0)
                res.set_header("Retry-After", std::to_string(r.retry_after_s));
              res.set_content(r.body, "application/json");
            });
  // httplib answers an oversize body itself (413, after discarding the body), with no content:
  // give it the API's error shape, so that the page can show why. Other errors keep theirs.
  // httplib also caps form-encoded bodies (curl's default Content-Type) at 8 kB
  // (CPPHTTPLIB_FORM_URL_ENCODED_PAYLOAD_MAX_LENGTH): say so, rather than quote our own limit.
  const httplib::Server::HandlerWithResponse too_large =
      [max = opt.max_body_bytes](const httplib::Request& req, httplib::Response& res) {
        if (res.status != 413 || !res.body.empty()) {
          return httplib::Server::HandlerResponse::Unhandled;
        }
        const bool form =
            req.get_header_value("Content-Type").starts_with("application/x-www-form-urlencoded");
        const std::string message =
            form ? "a request body sent as application/x-www-form-urlencoded may have at most " +
                       std::to_string(CPPHTTPLIB_FORM_URL_ENCODED_PAYLOAD_MAX_LENGTH) +
                       " bytes: send it as application/json (curl: -H 'Content-Type: "
                       "application/json')"
                 : "the request body is larger than this server accepts (at most " +
                       std::to_string(max) +
                       " bytes): send fewer points, or start the server with a larger "
                       "--max-body-bytes";
        res.set_content(http_error_body("too_large", message), "application/json");
        return httplib::Server::HandlerResponse::Handled;
      };
  http.set_error_handler(too_large);
  http.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        res.status = 500;
        res.set_content(http_error_body("internal", "unexpected error"), "application/json");
      });
  if (!opt.root.empty() && std::filesystem::is_directory(opt.root)) {
    http.set_mount_point("/", opt.root);
  }
}

Server::~Server() {
  stop();
}

int Server::bind() {
  impl_->binding = true;
  int port = -1;
  if (impl_->options.port == 0) {
    port = impl_->http.bind_to_any_port(impl_->options.host);
  } else if (impl_->http.bind_to_port(impl_->options.host, impl_->options.port)) {
    port = impl_->options.port;
  }
  impl_->binding = false;
  // Debian's libcpp-httplib is compiled with a listen backlog of 5 (CPPHTTPLIB_LISTEN_BACKLOG).
  // With 50 clients connecting at once, the kernel dropped connections beyond it and the
  // clients resent them a second later (TcpExtListenOverflows; p99 latency 1.1 s in the load
  // test). Calling listen() again on a listening socket sets its backlog (Linux, POSIX).
  if (port > 0 && impl_->listener != INVALID_SOCKET) ::listen(impl_->listener, kListenBacklog);
  if (port > 0) impl_->live_port = impl_->live.bind(impl_->options.host, port);
  return port;
}

bool Server::run() {
  impl_->live.start();
  const bool ok = impl_->http.listen_after_bind();
  impl_->live.stop();
  return ok;
}

void Server::stop() {
  if (!impl_) return;
  impl_->http.stop();
  impl_->live.stop();
}

int Server::live_port() const {
  return impl_->live_port;
}

}  // namespace fairspline::web
