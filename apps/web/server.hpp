// The server behind `fairspline serve`: a JSON API over the method registry and the static
// files of the editor page. The request handlers are plain functions (tested without sockets);
// Server binds and runs them over HTTP with cpp-httplib.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace fairspline::web {

struct ServerOptions {
  std::string host = "127.0.0.1";         ///< loopback only unless asked otherwise
  int port = 8080;                        ///< 0: any free port (see Server::bind)
  std::string root;                       ///< directory of the page and its assets; empty: none
  std::size_t max_body_bytes = 8u << 20;  ///< larger requests get HTTP 413
  std::size_t max_points = 200000;        ///< larger fits get HTTP 400
};

/// An HTTP status and a JSON body.
struct ApiResponse {
  int status = 200;
  std::string body;
  /// Wall time of parsing, fitting and serializing, in milliseconds (sent to the page as
  /// `Server-Timing: fit;dur=...`); 0 when not measured.
  double elapsed_ms = 0.0;
};

/// GET /api/methods: {"default": name, "methods": [method_schema...]}.
ApiResponse handle_methods();

/// POST /api/fit: the body is the request JSON of `fairspline fit` (points, closed, tangents,
/// kinds, method, options, ...); the answer is the output JSON of `fairspline fit` with the full
/// report. Bad requests (malformed JSON, bad fields, NaN, too many points, any
/// fairspline::Error) → 400 with {"error": {"code", "message", "index"}}; never throws.
ApiResponse handle_fit(std::string_view body, const ServerOptions& options);

/// The HTTP server. Not copyable; stop() may be called from another thread.
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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fairspline::web
