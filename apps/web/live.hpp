// The editor's live channel: POST /api/fit over a WebSocket. In headless chromium on the 2-core
// build machine a fetch round trip on loopback costs 5–17 ms, a WebSocket message 1–1.5 ms, and
// a drag needs one fit per pointer move. Messages and answers are those of POST /api/fit.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace fairspline::web {

class FitRunner;

/// The path a client opens (`ws://host:port/api/live`).
inline constexpr std::string_view kLivePath = "/api/live";

/// The text sent for an answer of the runner: {"status": S, "ms": T, "answer": BODY}, BODY being
/// the JSON that POST /api/fit sends with status S, T its Server-Timing duration.
std::string live_answer(int status, double elapsed_ms, std::string_view body);

/// Whether a browser page of `origin` may open the channel reached as `host` (the Host header):
/// no Origin (not a browser) or the editor's own page, whose origin has the same host name and
/// the HTTP port. Other sites' pages may not make the server fit for them.
bool live_origin_allowed(std::string_view origin, std::string_view host, int http_port);

/// A WebSocket listener on its own port, beside the HTTP server (cpp-httplib has no WebSocket).
/// Each connection has a thread; each text message it receives is fitted through the runner
/// and answered with live_answer, in the order received. Binary messages close the connection
/// (code 1003); a message above max_message_bytes closes it too (code 1009, by Boost.Beast).
class LiveChannel {
 public:
  LiveChannel(FitRunner& runner, std::size_t max_message_bytes);
  /// stop()s and waits for the connections' threads (each at most the length of a fit).
  ~LiveChannel();
  LiveChannel(const LiveChannel&) = delete;
  LiveChannel& operator=(const LiveChannel&) = delete;

  /// Binds to a free port of host; returns it, or −1 on failure. `http_port` is the port of the
  /// page allowed to connect (live_origin_allowed).
  int bind(const std::string& host, int http_port);
  /// Starts accepting on a thread of its own; call after bind().
  void start();
  /// Closes the listener and every connection; may be called from any thread, more than once.
  void stop();
  /// Connections open now.
  std::size_t connections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fairspline::web
