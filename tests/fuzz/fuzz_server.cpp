// Fuzz target: the web server's request handlers (apps/web/server.hpp) without sockets. The body
// of POST /api/fit is the fuzzer's bytes; the answer must be 200 with a finite fit, or 400/413
// with {"error": {"code", "message", "index"}} -- a 500 or an escaping exception is a bug.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fuzz_util.hpp"
#include "server.hpp"

namespace {

using fairspline::fuzz::fail;
using nlohmann::json;

/// Every number of a fit answer is a number (nlohmann writes NaN/Inf as null).
void check_numbers(const json& j, const char* what) {
  if (j.is_null()) fail(std::string("null where a number belongs: ") + what);
  if (j.is_array()) {
    for (const json& v : j) check_numbers(v, what);
  } else if (!j.is_number()) {
    fail(std::string("not a number: ") + what);
  }
}

void check_fit_answer(const json& j) {
  for (const char* k : {"method", "closed", "options", "points", "knots", "tangents", "segments",
                        "report", "method_report"}) {
    if (!j.contains(k)) fail(std::string("answer without '") + k + "'");
  }
  check_numbers(j.at("points"), "points");
  check_numbers(j.at("knots"), "knots");
  check_numbers(j.at("tangents"), "tangents");
  if (j.at("segments").empty()) fail("answer without segments");
  for (const json& s : j.at("segments")) {
    check_numbers(s.at("bezier"), "bezier");
    check_numbers(s.at("t0"), "t0");
    check_numbers(s.at("t1"), "t1");
  }
  const json& r = j.at("report");
  for (const char* k : {"bending_energy", "linearized_energy", "curvature_variation_energy",
                        "length", "max_tangent_angle_jump_deg", "max_curvature_jump",
                        "min_relative_speed", "max_interpolation_residual"}) {
    check_numbers(r.at(k), k);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool methods_ok = [] {
    const fairspline::web::ApiResponse m = fairspline::web::handle_methods();
    if (m.status != 200) fail("GET /api/methods is not 200");
    const json j = json::parse(m.body);
    if (!j.at("methods").is_array() || j.at("methods").empty()) fail("no methods listed");
    return true;
  }();
  (void)methods_ok;

  fairspline::web::ServerOptions options;
  options.max_points = 64;           // keep each fit small
  options.max_body_bytes = 1 << 16;  // (the 413 limit lives in httplib, before handle_fit)
  const std::string_view body(reinterpret_cast<const char*>(data), size);
  fairspline::web::ApiResponse r;
  try {
    r = fairspline::web::handle_fit(body, options);
  } catch (const std::exception& e) {
    fail(std::string("handle_fit threw: ") + e.what());
  }
  json j;
  try {
    j = json::parse(r.body);
  } catch (const std::exception& e) {
    fail("status " + std::to_string(r.status) + " with a body that is not JSON: " + e.what());
  }
  if (r.status == 200) {
    check_fit_answer(j);
  } else if (r.status == 400 || r.status == 413) {
    const json& e = j.at("error");
    if (!e.at("code").is_string() || !e.at("message").is_string()) fail("malformed error body");
    if (!e.at("index").is_null() && !e.at("index").is_number_unsigned()) fail("bad error index");
    if (e.at("code") == "internal") fail("an internal error answered as a bad request");
  } else {
    fail("status " + std::to_string(r.status) + ": " + r.body.substr(0, 300));
  }
  return 0;
}
