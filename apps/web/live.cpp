#include "live.hpp"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <list>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "server.hpp"

namespace fairspline::web {

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

/// Open connections at most; more are closed at once (the page then fits over HTTP).
constexpr std::size_t kMaxConnections = 64;
/// The upgrade request's header at most (browsers send ~500 bytes).
constexpr std::size_t kMaxUpgradeHeaderBytes = 16384;
/// A connection that sends no upgrade request within this time is closed: each holds a thread.
constexpr int kUpgradeWaitMs = 10000;

/// The host name of an authority "name[:port]" or "[v6][:port]", and its port (0 if none).
std::pair<std::string_view, int> split_authority(std::string_view authority) {
  std::size_t colon = authority.rfind(':');
  if (authority.starts_with('[')) {
    const std::size_t close = authority.find(']');
    if (close == std::string_view::npos) return {authority, 0};
    colon = close + 1 < authority.size() && authority[close + 1] == ':' ? close + 1
                                                                        : std::string_view::npos;
  }
  if (colon == std::string_view::npos) return {authority, 0};
  int port = 0;
  for (const char c : authority.substr(colon + 1)) {
    if (c < '0' || c > '9' || port > 65535) return {authority.substr(0, colon), -1};
    port = port * 10 + (c - '0');
  }
  return {authority.substr(0, colon), port};
}

/// Beast's string_view (Boost's in 1.74) as the standard one.
std::string_view view(beast::string_view s) {
  return {s.data(), s.size()};
}

bool same_host(std::string_view a, std::string_view b) {
  return std::ranges::equal(a, b, [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) ==
           std::tolower(static_cast<unsigned char>(y));
  });
}

/// A plain HTTP refusal of a request that is no upgrade to the channel.
void refuse(tcp::socket& socket, http::status status, const std::string& message) {
  http::response<http::string_body> res{status, 11};
  res.set(http::field::content_type, "application/json");
  res.set(http::field::connection, "close");
  res.body() =
      nlohmann::json{
          {"error", {{"code", "invalid_argument"}, {"message", message}, {"index", nullptr}}}}
          .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  res.prepare_payload();
  beast::error_code ec;
  http::write(socket, res, ec);
}

}  // namespace

std::string live_answer(int status, double elapsed_ms, std::string_view body) {
  char head[64];
  const int n = std::snprintf(head, sizeof head, "{\"status\":%d,\"ms\":%.3f,\"answer\":", status,
                              elapsed_ms);
  std::string out;
  out.reserve(static_cast<std::size_t>(n) + body.size() + 5);
  out.append(head, static_cast<std::size_t>(n));
  out.append(body.empty() ? std::string_view("null") : body);
  out.push_back('}');
  return out;
}

bool live_origin_allowed(std::string_view origin, std::string_view host, int http_port) {
  if (origin.empty()) return true;
  constexpr std::string_view kScheme = "http://";
  if (!origin.starts_with(kScheme)) return false;  // also "null" (a file:// page)
  const std::string_view authority = origin.substr(kScheme.size());
  if (authority.find('/') != std::string_view::npos) return false;
  auto [origin_host, origin_port] = split_authority(authority);
  if (origin_port == 0) origin_port = 80;
  return origin_port == http_port && !origin_host.empty() &&
         same_host(origin_host, split_authority(host).first);
}

// One thread accepts, one thread per connection reads, fits and answers (the fits themselves
// run on the runner's workers, under its limits). stop() wakes every blocking call by shutting
// its socket down (an OS call, safe beside another thread's blocking read), then joins.

struct LiveChannel::Impl {
  struct Session {
    int fd = -1;  // guarded by mutex; −1 once the socket is about to close
    std::thread thread;
    std::atomic<bool> done{false};
  };

  Impl(FitRunner& r, std::size_t max_bytes) : runner(r), max_message_bytes(max_bytes) {}

  FitRunner& runner;
  std::size_t max_message_bytes;
  int http_port = 0;
  net::io_context io;
  tcp::acceptor acceptor{io};
  std::thread accepting;
  std::mutex join_mutex;  // one stop() joins at a time
  mutable std::mutex mutex;
  bool stopping = false;
  std::list<Session> sessions;  // guarded by mutex; nodes stay put while their threads run

  void reap_locked() {
    for (auto it = sessions.begin(); it != sessions.end();) {
      if (it->done) {
        it->thread.join();  // its last step was setting done: this returns at once
        it = sessions.erase(it);
      } else {
        ++it;
      }
    }
  }

  void accept_loop() {
    for (;;) {
      tcp::socket socket(io);
      beast::error_code ec;
      acceptor.accept(socket, ec);
      std::unique_lock lock(mutex);
      if (stopping) return;
      if (ec) {
        // Out of file descriptors and the like: wait rather than spin.
        lock.unlock();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        continue;
      }
      reap_locked();
      if (sessions.size() >= kMaxConnections) {
        socket.close(ec);
        continue;
      }
      Session& s = sessions.emplace_back();
      s.fd = socket.native_handle();
      try {
        s.thread = std::thread([this, &s, sock = std::move(socket)]() mutable {
          serve(sock);
          {
            std::lock_guard g(mutex);
            s.fd = -1;
          }
          beast::error_code ignored;
          sock.close(ignored);
          s.done = true;
        });
      } catch (const std::system_error&) {
        sessions.pop_back();  // its socket, moved into the lambda or not, closes here
      }
    }
  }

  void serve(tcp::socket& socket) {
    beast::error_code ec;
    socket.set_option(tcp::no_delay(true), ec);
    pollfd wait{socket.native_handle(), POLLIN, 0};
    if (::poll(&wait, 1, kUpgradeWaitMs) <= 0) return;
    beast::flat_buffer buffer;
    http::request_parser<http::empty_body> parser;
    parser.header_limit(kMaxUpgradeHeaderBytes);
    http::read(socket, buffer, parser, ec);
    if (ec) return;
    const http::request<http::empty_body>& req = parser.get();
    if (view(req.target()) != kLivePath) {
      refuse(socket, http::status::not_found, "the live channel is at " + std::string(kLivePath));
      return;
    }
    if (!websocket::is_upgrade(req)) {
      refuse(socket, http::status::upgrade_required,
             "the live channel speaks WebSocket only; fit with POST /api/fit");
      return;
    }
    if (!live_origin_allowed(view(req[http::field::origin]), view(req[http::field::host]),
                             http_port)) {
      refuse(socket, http::status::forbidden,
             "only the editor's own page may open the live channel");
      return;
    }
    websocket::stream<tcp::socket&> ws(socket);
    ws.read_message_max(max_message_bytes);
    ws.auto_fragment(false);  // an answer is one frame, not frames of 4 kB
    ws.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& res) { res.set(http::field::server, "fairspline"); }));
    ws.accept(req, ec);
    if (ec) return;
    beast::flat_buffer message;
    for (;;) {
      message.clear();
      ws.read(message, ec);
      if (ec) return;  // closed by the client or by stop(), or too big (Beast sent 1009)
      if (!ws.got_text()) {
        ws.close(websocket::close_code::unknown_data, ec);
        return;
      }
      const auto data = message.cdata();
      const ApiResponse r =
          runner.fit(std::string_view(static_cast<const char*>(data.data()), data.size()));
      ws.text(true);
      ws.write(net::buffer(live_answer(r.status, r.elapsed_ms, r.body)), ec);
      if (ec) return;
    }
  }
};

LiveChannel::LiveChannel(FitRunner& runner, std::size_t max_message_bytes)
    : impl_(std::make_unique<Impl>(runner, max_message_bytes)) {}

LiveChannel::~LiveChannel() {
  stop();
}

int LiveChannel::bind(const std::string& host, int http_port) {
  Impl& impl = *impl_;
  impl.http_port = http_port;
  beast::error_code ec;
  const net::ip::address address =
      net::ip::make_address(host == "localhost" ? "127.0.0.1" : host, ec);
  if (ec) return -1;
  const tcp::endpoint endpoint(address, 0);
  impl.acceptor.open(endpoint.protocol(), ec);
  if (!ec) impl.acceptor.bind(endpoint, ec);
  if (!ec) impl.acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    impl.acceptor.close(ec);
    return -1;
  }
  return impl.acceptor.local_endpoint().port();
}

void LiveChannel::start() {
  Impl& impl = *impl_;
  if (!impl.acceptor.is_open() || impl.accepting.joinable()) return;
  impl.accepting = std::thread([&impl] { impl.accept_loop(); });
}

void LiveChannel::stop() {
  Impl& impl = *impl_;
  std::lock_guard join_lock(impl.join_mutex);
  std::list<Impl::Session> sessions;
  {
    std::lock_guard lock(impl.mutex);
    impl.stopping = true;
    if (impl.acceptor.is_open()) ::shutdown(impl.acceptor.native_handle(), SHUT_RDWR);
    for (const Impl::Session& s : impl.sessions) {
      if (s.fd >= 0) ::shutdown(s.fd, SHUT_RDWR);
    }
  }
  if (impl.accepting.joinable()) impl.accepting.join();
  {
    std::lock_guard lock(impl.mutex);
    sessions.splice(sessions.end(), impl.sessions);  // no new ones: the acceptor is done
  }
  for (Impl::Session& s : sessions) s.thread.join();
  beast::error_code ignored;
  impl.acceptor.close(ignored);
}

std::size_t LiveChannel::connections() const {
  std::lock_guard lock(impl_->mutex);
  return static_cast<std::size_t>(std::ranges::count_if(
      impl_->sessions, [](const Impl::Session& s) { return !s.done.load(); }));
}

}  // namespace fairspline::web
