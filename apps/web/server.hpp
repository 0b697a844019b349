// The server behind `fairspline serve`: a JSON API over the method registry and the static
// files of the editor page. The request handlers are plain functions (tested without sockets);
// Server binds and runs them over HTTP with cpp-httplib.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

namespace fairspline::web {

/// Default of ServerOptions::max_concurrent_fits: twice the hardware threads, at least 2.
/// (Inline: the command reads it for its help without linking the server.)
inline std::size_t default_max_concurrent_fits() {
  return std::max<std::size_t>(2,
                               2 * static_cast<std::size_t>(std::thread::hardware_concurrency()));
}

struct ServerOptions {
  std::string host = "127.0.0.1";         ///< loopback only unless asked otherwise
  int port = 8080;                        ///< 0: any free port (see Server::bind)
  std::string root;                       ///< directory of the page and its assets; empty: none
  std::size_t max_body_bytes = 8u << 20;  ///< larger requests get HTTP 413 (code "too_large")
  std::size_t max_points = 200000;        ///< larger fits get HTTP 400
  /// A fit not answered within this many milliseconds of its arrival gets HTTP 503 (code
  /// "timeout"); its computation is stopped at its next step (FitOptions::progress), holding
  /// its slot until then (a closed-form method's fit or a report runs to its end). 0: no limit.
  std::int64_t fit_time_limit_ms = 10000;
  /// false: a timed-out fit runs to its end in the background instead (the server before fits
  /// could be stopped; the tests of the "busy" answer use it).
  bool stop_abandoned_fits = true;
  /// Fits computed at once, each on a thread of its own, counting those whose request timed
  /// out. A request waits for a free slot within its time limit; it gets HTTP 503 (code
  /// "busy") with Retry-After when none comes free, and at once when every slot is held by a
  /// fit that went past the time limit. 0 is taken as 1.
  std::size_t max_concurrent_fits = default_max_concurrent_fits();
};

/// An HTTP status and a JSON body.
struct ApiResponse {
  int status = 200;
  std::string body;
  /// Wall time of parsing, fitting and serializing, in milliseconds (sent to the page as
  /// `Server-Timing: fit;dur=...`); 0 when not measured.
  double elapsed_ms = 0.0;
  /// Seconds of a `Retry-After` header (0: none); set on the 503 "busy" answer.
  int retry_after_s = 0;
};

/// GET /api/methods: {"default": name, "methods": [method_schema...]}.
ApiResponse handle_methods();

/// POST /api/fit: the body is the request JSON of `fairspline fit` (points, closed, tangents,
/// kinds, method, options, ...); the answer is the output JSON of `fairspline fit` with the full
/// report. Bad requests (malformed JSON, bad fields, NaN, too many points, any
/// fairspline::Error) → 400 with {"error": {"code", "message", "index"}}; never throws.
/// `stop`, when given and set, stops the fit at its next step (its answer is then the
/// "cancelled" error).
ApiResponse handle_fit(std::string_view body, const ServerOptions& options,
                       const std::atomic<bool>* stop = nullptr);

/// POST /api/fit under the server's time and concurrency limits (Server owns one; socket-free
/// for tests). Each fit runs handle_fit on a thread of its own, with its own copy of the body,
/// at most max_concurrent_fits at once; the caller waits at most fit_time_limit_ms from its
/// call, for a slot and for the fit. Past the limit: 503 {"error": {"code": "timeout", ...}}
/// while the fit is stopped at its next step (or, with stop_abandoned_fits false, finishes in
/// the background), keeping its slot until then. No slot within the limit, or
/// every slot held by such a timed-out fit: 503 "busy" with retry_after_s = 1 (the latter at
/// once). Thread-safe; never throws.
class FitRunner {
 public:
  explicit FitRunner(ServerOptions options);
  /// Waits for the fits still running in the background (at most the length of one fit).
  ~FitRunner();
  FitRunner(const FitRunner&) = delete;
  FitRunner& operator=(const FitRunner&) = delete;

  ApiResponse fit(std::string_view body);
  /// Fits being computed now, including those whose request has timed out.
  std::size_t running() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The HTTP server: GET /api/methods, POST /api/fit through a FitRunner, GET /api/live (the port
/// of the live channel, a WebSocket for the same fits: live.hpp), the static files.
/// Not copyable; stop() may be called from another thread. The destructor waits for fits
/// still running in the background.
class Server {
 public:
  explicit Server(ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds to host:port (port 0: a free port); returns the port, or −1 on failure.
  int bind();
  /// Serves until stop(); call after bind(). Returns false if the listener failed.
  bool run();
  void stop();
  /// The port of the live channel (live.hpp) bound by bind(), or −1 without one.
  int live_port() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fairspline::web
