#include "server.hpp"

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"

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

ApiResponse handle_fit_untimed(std::string_view body, const ServerOptions& options) {
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
    const FitResult result = fit(method, parsed.input, parsed.options, ReportLevel::kFull);
    return {200, io::write_json(result)};
  } catch (const Error& e) {
    return error_response(400, e);
  } catch (const std::exception& e) {
    // Not a user error: report it without bringing the server down.
    return {500,
            dump(nlohmann::json{
                {"error", {{"code", "internal"}, {"message", e.what()}, {"index", nullptr}}}})};
  }
}

}  // namespace

ApiResponse handle_methods() {
  nlohmann::json all = nlohmann::json::array();
  for (const MethodInfo& m : methods()) all.push_back(method_schema(m));
  return {200, nlohmann::json{{"default", default_method_name()}, {"methods", all}}.dump()};
}

ApiResponse handle_fit(std::string_view body, const ServerOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ApiResponse response = handle_fit_untimed(body, options);
  response.elapsed_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return response;
}

struct Server::Impl {
  ServerOptions options;
  httplib::Server http;
};

Server::Server(ServerOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  httplib::Server& http = impl_->http;
  const ServerOptions& opt = impl_->options;
  http.set_payload_max_length(opt.max_body_bytes);
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
  http.Post("/api/fit", [&opt](const httplib::Request& req, httplib::Response& res) {
    const ApiResponse r = handle_fit(req.body, opt);
    res.status = r.status;
    char timing[48];
    std::snprintf(timing, sizeof timing, "fit;dur=%.3f", r.elapsed_ms);
    res.set_header("Server-Timing", timing);
    res.set_content(r.body, "application/json");
  });
  http.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        res.status = 500;
        res.set_content(R"({"error": {"code": "internal", "message": "unexpected error"}})",
                        "application/json");
      });
  if (!opt.root.empty() && std::filesystem::is_directory(opt.root)) {
    http.set_mount_point("/", opt.root);
  }
}

Server::~Server() {
  stop();
}

int Server::bind() {
  if (impl_->options.port == 0) return impl_->http.bind_to_any_port(impl_->options.host);
  return impl_->http.bind_to_port(impl_->options.host, impl_->options.port) ? impl_->options.port
                                                                            : -1;
}

bool Server::run() {
  return impl_->http.listen_after_bind();
}

void Server::stop() {
  if (impl_) impl_->http.stop();
}

}  // namespace fairspline::web
