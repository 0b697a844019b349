// Fuzz target: io::parse_json_input and io::read_fit_result on arbitrary text. The promise: a
// request whose every number is finite, or a fairspline::Error whose JSON form (the web API's
// error body) can be written; never another exception. And the fit-result reader's fast path
// reads what its DOM reader reads: the same result, or the same error.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "detail/json_input.hpp"
#include "fairspline/error.hpp"
#include "fairspline/io/json.hpp"
#include "fuzz_util.hpp"

namespace {

/// A result reader's outcome: the result's text, or the error's code and message.
std::string result_outcome(const std::function<fairspline::FitResult()>& read) {
  try {
    return fairspline::io::write_json(read());
  } catch (const fairspline::Error& e) {
    return std::string("error ") + std::string(fairspline::error_code_name(e.code())) + " " +
           e.what() + " index " + (e.index() ? std::to_string(*e.index()) : "-");
  } catch (const std::exception& e) {
    fairspline::fuzz::fail(std::string("a fit result's text: exception other than "
                                       "fairspline::Error: ") +
                           e.what());
  }
  return {};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using fairspline::fuzz::check_finite;
  using fairspline::fuzz::fail;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const fairspline::io::ParsedInput parsed = fairspline::io::parse_json_input(text);
    const fairspline::FitInput& in = parsed.input;
    for (const auto& p : in.points) check_finite(p, "point");
    for (const auto& t : in.tangents) {
      if (t) check_finite(*t, "tangent");
    }
    for (double t : in.knots) check_finite(t, "knot");
    check_finite(in.alpha, "alpha");
    if (in.start_tangent) check_finite(*in.start_tangent, "start tangent");
    if (in.end_tangent) check_finite(*in.end_tangent, "end tangent");
    fairspline::fuzz::check_finite_json(parsed.options, "option");
    if (!parsed.options.is_object()) fail("options is not an object");
  } catch (const fairspline::Error& e) {
    // Front ends send this error as JSON: it must serialize (messages quote the input).
    try {
      const std::string body = fairspline::io::error_to_json(e).dump();
      if (!nlohmann::json::parse(body).contains("error")) fail("an error body without 'error'");
    } catch (const std::exception& x) {
      fail(std::string("the error of a bad request cannot be written as JSON: ") + x.what());
    }
  } catch (const std::exception& e) {
    fail(std::string("exception other than fairspline::Error: ") + e.what());
  }
  if (result_outcome([&] { return fairspline::io::read_fit_result(text); }) !=
      result_outcome([&] { return fairspline::detail::read_fit_result_dom(text); })) {
    fail("read_fit_result and the DOM reader disagree");
  }
  return 0;
}
