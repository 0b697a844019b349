// `fairspline serve` as a module the command opens only when it serves: the server's libraries
// (cpp-httplib and, through it, OpenSSL, zlib and brotli: 4 MiB resident) are then not loaded
// by every other command (docs/architecture.md, "The command and the server").
#pragma once

#include <cstddef>

#include "server.hpp"

namespace fairspline::web {

/// The module's file name; the command looks for it next to itself, then where it is installed.
inline constexpr const char* kServeModuleName = "fairspline-serve.so";
/// The name of its entry point (extern "C", so that dlsym finds it unmangled).
inline constexpr const char* kServeEntryName = "fairspline_serve";

/// What the entry point returns.
enum ServeOutcome : int {
  kServeStopped = 0,       ///< the server ran and stopped
  kServeFailed = 1,        ///< the server stopped on an error of its own
  kServeCannotListen = 2,  ///< the address could not be bound
  kServeError = 3,         ///< an exception; its text is in the message buffer
};

/// Binds, prints the machine-readable first line "fairspline: serving http://HOST:PORT/" on
/// standard output, and serves until stopped. Never throws.
using ServeEntry = int (*)(const ServerOptions* options, char* message, std::size_t size);

}  // namespace fairspline::web
