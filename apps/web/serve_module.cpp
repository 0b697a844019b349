// The entry point of fairspline-serve.so (serve_module.hpp).
#include "serve_module.hpp"

#include <cstdio>
#include <exception>
#include <iostream>
#include <type_traits>

extern "C" __attribute__((visibility("default"))) int fairspline_serve(
    const fairspline::web::ServerOptions* options, char* message, std::size_t size) {
  using namespace fairspline::web;
  // (The command's exceptions would cross a library boundary: their text comes back instead.)
  try {
    Server server(*options);
    const int port = server.bind();
    if (port < 0) return kServeCannotListen;
    // The first line is machine-readable: tests and scripts read the port from it.
    std::cout << "fairspline: serving http://" << options->host << ":" << port << "/" << std::endl;
    return server.run() ? kServeStopped : kServeFailed;
  } catch (const std::exception& e) {
    std::snprintf(message, size, "%s", e.what());
  } catch (...) {
    std::snprintf(message, size, "unknown error in the web server");
  }
  return kServeError;
}

// Checked here, where both are seen: the command calls through ServeEntry.
static_assert(std::is_same_v<decltype(&fairspline_serve), fairspline::web::ServeEntry>);
