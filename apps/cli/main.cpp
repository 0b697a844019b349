// The `fairspline` command: fit points from CSV/JSON, fit a JSON Lines file of curves in
// parallel (batch.cpp), list methods, time a method, serve the editor.
//
// Exit codes: 0 success; 1 the fit failed with a fairspline::Error; 2 usage errors and
// malformed or unreadable input (and unwritable output).

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <dlfcn.h>
#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "batch.hpp"
#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/io/csv.hpp"
#include "fairspline/io/curve_ensemble.hpp"
#include "fairspline/io/file.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/io/paths.hpp"
#include "fairspline/io/svg.hpp"
#include "fairspline/registry.hpp"
#include "fields.hpp"
#include "serve_module.hpp"

namespace fs = std::filesystem;
using fairspline::Error;
using fairspline::ErrorCode;
using nlohmann::json;

namespace {

constexpr int kExitOk = 0;
constexpr int kExitFitError = 1;
constexpr int kExitUsage = 2;

/// An error that maps to exit code 2 (usage, malformed input, I/O).
struct UsageError {
  Error error;
};

void print_error(const Error& e) {
  std::string where;
  if (e.index() && e.code() != ErrorCode::kParseError) {
    where = " at point " + std::to_string(*e.index());
  }
  std::cerr << "fairspline: error [" << fairspline::error_code_name(e.code()) << "]" << where
            << ": " << e.what() << "\n";
  if (e.hint()) {
    const std::string value = e.hint()->value.empty() ? "VALUE" : e.hint()->value;
    std::cerr << "fairspline: hint: --set " << e.hint()->name << "=" << value << "\n";
  }
}

[[noreturn]] void usage_fail(const std::string& message) {
  throw UsageError{Error(ErrorCode::kInvalidArgument, message)};
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

fairspline::io::FileText read_all(const std::string& path) {
  if (path.empty() || path == "-") return fairspline::io::read_stream(stdin, "standard input");
  return fairspline::io::read_file(path);
}

bool looks_like_json(const std::string& path, std::string_view text) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".json") return true;
  if (ext == ".csv" || ext == ".txt" || ext == ".tsv" || ext == ".dat") return false;
  const auto first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  return first != std::string::npos && (text[first] == '{' || text[first] == '[');
}

fairspline::Vec2 parse_vector_arg(const std::string& text, const char* flag) {
  const auto comma = text.find(',');
  double x = 0, y = 0;
  bool ok = comma != std::string::npos;
  try {
    ok = ok && fairspline::io::parse_number(std::string_view(text).substr(0, comma), x, flag) &&
         fairspline::io::parse_number(std::string_view(text).substr(comma + 1), y, flag);
  } catch (const Error& e) {
    throw UsageError{e};
  }
  if (!ok) usage_fail(std::string(flag) + " expects X,Y (two numbers), got '" + text + "'");
  return {x, y};
}

/// Gives `write` the output (standard output for "" or "-"); a failed write is a usage error.
template <class Write>
void write_output_with(const std::string& path, Write write) {
  try {
    if (path.empty() || path == "-") {
      write(std::cout);
      std::cout.flush();
      if (!std::cout) {
        throw UsageError{Error(ErrorCode::kIoError, "cannot write to standard output")};
      }
      return;
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw UsageError{Error(ErrorCode::kIoError, "cannot write '" + path + "'")};
    write(out);
    out.close();
    if (!out) throw UsageError{Error(ErrorCode::kIoError, "error while writing '" + path + "'")};
  } catch (const Error& e) {  // from a writer that writes as it goes
    throw UsageError{Error(
        ErrorCode::kIoError,
        "error while writing '" + (path.empty() ? std::string("-") : path) + "': " + e.what())};
  }
}

void write_output(const std::string& path, const std::string& text) {
  write_output_with(path, [&](std::ostream& os) { os << text; });
}

// ---------------------------------------------------------------- fit

/// "global search: 120 of 400, 3.5 s" (steps of unknown number: "newton: step 12, 3.5 s").
std::string progress_text(const fairspline::FitProgress& p) {
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f s", p.seconds);
  const std::string step = p.total > 0 ? std::to_string(p.done) + " of " + std::to_string(p.total)
                                       : "step " + std::to_string(p.done);
  return std::string(p.stage) + ": " + step + ", " + seconds;
}

struct FitArgs {
  std::string input;
  std::string input_format = "auto";
  std::string method;
  bool closed = false;
  double alpha = fairspline::FitInput::kDefaultAlpha;
  std::string start_tangent;
  std::string end_tangent;
  std::vector<std::string> sets;
  std::string format;
  std::string output;
  std::string report = "basic";
  bool summary = false;
  bool progress = false;  ///< progress lines on stderr also when it is no terminal
  int indent = -1;
  fairspline::cli::FitFlags flags;
  std::optional<double> tolerance;    ///< GeoJSON's flattening tolerance, else its default
  std::optional<std::string> fields;  ///< JSON only: the members kept (as batch's --fields)
  CLI::Option* alpha_opt = nullptr;
};

/// The output formats an -o extension implies (compared in lower case). Only the extensions
/// whose meaning is unambiguous: .txt could be CSV or Curve Ensemble, so `ce` needs -f.
constexpr std::pair<std::string_view, std::string_view> kFormatOfExtension[] = {
    {".json", "json"}, {".csv", "csv"}, {".svg", "svg"}, {".geojson", "geojson"}};

/// The output format: -f, else the -o file's extension; JSON for standard output and for a
/// name without an extension (/dev/stdout, a fifo). An extension we do not know is refused
/// rather than answered with JSON: `-o fit.geojson` used to write fairspline JSON silently.
std::string output_format(const std::string& format, const std::string& output) {
  if (!format.empty()) return format;
  if (output.empty() || output == "-") return "json";
  const std::string ext = lower(fs::path(output).extension().string());
  if (ext.empty()) return "json";
  std::string known;
  for (const auto& [e, f] : kFormatOfExtension) {
    if (ext == e) return std::string(f);
    known += (known.empty() ? "" : ", ") + std::string(e);
  }
  usage_fail("cannot tell the output format from the extension '" + ext + "' of '" + output +
             "' (known: " + known + "); give it with -f json|csv|svg|svg-path|geojson|ce");
}

/// One fit per process: large blocks go straight to mmap and back to the system when freed.
/// glibc otherwise raises its mmap threshold to the largest block freed so far (the input
/// text, ~40 bytes a point), after which the solver's freed work arrays stayed resident beside
/// the result's (2·10^5 points: 74 MB peak instead of 55, docs/methods/min-energy.md); and
/// the library's per-thread cache of blocks for a next fit, which never comes, did the same
/// (84 MB).
void return_large_blocks() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
  fairspline::keep_fit_memory(false);
}

int run_fit(const FitArgs& a) {
  return_large_blocks();
  // 1. Input (errors here are malformed/unreadable input: exit 2).
  fairspline::io::ParsedInput parsed;
  try {
    const fairspline::io::FileText file = read_all(a.input);
    const std::string_view text = file.view();
    const bool ce = a.input_format == "ce" ||
                    (a.input_format == "auto" && text.starts_with("#Curve Ensemble Text File"));
    if (ce) {
      parsed.input = fairspline::io::parse_curve_ensemble(text);
    } else if (a.input_format == "json" ||
               (a.input_format == "auto" && looks_like_json(a.input, text))) {
      parsed = fairspline::io::parse_json_input(text);
    } else {
      parsed.input.points = fairspline::io::parse_csv_points(text);
    }
  } catch (const Error& e) {
    throw UsageError{e};
  }

  // 2. Command-line overrides.
  fairspline::FitInput& in = parsed.input;
  if (a.closed) in.closed = true;
  if (a.alpha_opt && a.alpha_opt->count() > 0) {
    if (!std::isfinite(a.alpha)) usage_fail("--alpha must be a finite number");
    in.alpha = a.alpha;
  }
  if (!a.start_tangent.empty())
    in.start_tangent = parse_vector_arg(a.start_tangent, "--start-tangent");
  if (!a.end_tangent.empty()) in.end_tangent = parse_vector_arg(a.end_tangent, "--end-tangent");
  const std::string method = !a.method.empty() ? a.method
                             : parsed.method.has_value()
                                 ? *parsed.method
                                 : std::string(fairspline::default_method_name());
  json options = parsed.options;
  json svg_keys = json::object();
  for (const std::string& s : a.sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0) {
      usage_fail("--set expects KEY=VALUE, got '" + s + "'");
    }
    const std::string key = s.substr(0, eq), text = s.substr(eq + 1);
    json value = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (value.is_discarded()) value = text;
    if (key.rfind("svg.", 0) == 0) {
      svg_keys[key] = value;
    } else {
      options[key] = value;
    }
  }
  const fairspline::ReportLevel level = fairspline::io::parse_report_level(a.report);

  // Checked before the fit, which may take long: a wrong output request fails at once.
  const std::string format = output_format(a.format, a.output);
  if (a.tolerance) {
    // Only GeoJSON flattens the curve; a tolerance given to another format would be ignored.
    if (format != "geojson") {
      usage_fail("--tolerance applies only to -f geojson (the output format here is " + format +
                 ")");
    }
    if (!(*a.tolerance > 0.0) || !std::isfinite(*a.tolerance)) {
      usage_fail(
          "--tolerance must be a positive number (in the data's units); leave it out for "
          "the default, 1e-4 of the diagonal of the curve's bounds");
    }
  }

  fairspline::cli::FieldSelection fields;
  if (a.fields) {
    if (format != "json") {
      usage_fail("--fields applies only to JSON output (the output format here is " + format + ")");
    }
    try {
      fields = fairspline::cli::parse_fields(a.fields, level, /*line=*/false);
    } catch (const Error& e) {
      throw UsageError{e};
    }
  }

  // 3. Fit (errors here: exit 1).
  const fairspline::io::SvgOptions svg = fairspline::io::svg_options_from_json(svg_keys);
  fairspline::FitOptions fit_options = parsed.fit_options(level);
  a.flags.apply(fit_options);
  const bool terminal = ::isatty(STDERR_FILENO) == 1;
  bool drawn = false;  // a terminal's progress line waits to be cleared
  if (a.progress || terminal) {
    fit_options.progress = [terminal, &drawn](const fairspline::FitProgress& p) {
      std::cerr << (terminal ? "\r\033[K" : "") << "fairspline: " << progress_text(p)
                << (terminal ? "" : "\n") << std::flush;
      drawn = terminal;
      return true;
    };
  }
  const auto clear_line = [&drawn] {
    if (drawn) std::cerr << "\r\033[K" << std::flush;
  };
  const fairspline::FitResult result = [&] {
    try {
      return fairspline::fit(method, in, options, fit_options);
    } catch (...) {
      clear_line();
      throw;
    }
  }();
  clear_line();

  // 4. Output.
  std::string text;
  if (format == "svg") {
    text = fairspline::io::write_svg(result, svg);
  } else if (format == "csv") {
    text = fairspline::io::write_csv(result);
  } else if (format == "ce") {
    text = fairspline::io::write_curve_ensemble(result);
  } else if (format == "svg-path") {
    text = fairspline::io::svg_path_data(result.spline) + "\n";
  } else if (format == "geojson") {
    text = fairspline::io::write_geojson(result, a.tolerance.value_or(0.0));
  } else if (!fields.whole_members()) {  // some objects in part: cut from their text
    fairspline::cli::append_fit_text(text, result, fields);
    if (a.indent >= 0) text = json::parse(text).dump(a.indent);
    text += '\n';
  } else {  // JSON, the long output: written as it is made (with --fields, only those members)
    write_output_with(a.output, [&](std::ostream& os) {
      fairspline::io::write_json(result, os, a.indent, fairspline::cli::member_filter(fields));
      os << '\n';
    });
  }
  if (format != "json" || !fields.whole_members()) write_output(a.output, text);
  if (a.summary) {
    const std::string table = fairspline::io::summary_table(result);
    if (a.output.empty() || a.output == "-") {
      std::cerr << table << std::flush;
    } else {
      std::cout << table << std::flush;
    }
  }
  return kExitOk;
}

// ---------------------------------------------------------------- methods

int run_methods(bool as_json) {
  if (as_json) {
    std::cout << fairspline::registry_schema().dump(2) << "\n";
    return kExitOk;
  }
  for (const auto& m : fairspline::methods()) {
    std::cout << m.name << (m.name == fairspline::default_method_name() ? "  (default)" : "")
              << "\n    " << m.description << "\n    paper: " << m.paper << "\n";
    if (m.options.empty()) {
      std::cout << "    options: none\n";
    } else {
      std::cout << "    options:\n";
      for (const auto& o : m.options) {
        std::cout << "      " << o.name << " (" << fairspline::option_type_name(o.type);
        if (!o.default_value.is_null()) std::cout << ", default " << o.default_value.dump();
        if (!o.choices.empty()) {
          std::string c;
          for (const auto& s : o.choices) c += (c.empty() ? "" : "|") + s;
          std::cout << ", one of " << c;
        }
        std::cout << ")\n        " << o.doc << "\n";
      }
    }
    std::cout << "\n";
  }
  return kExitOk;
}

// ---------------------------------------------------------------- bench

struct BenchArgs {
  std::string method;
  std::int64_t n = 0;
  bool closed = false;
  std::string shape = "random";
  int repeat = 5;
  std::uint64_t seed = 1;
};

std::vector<fairspline::Point> bench_points(const BenchArgs& a) {
  const auto n = static_cast<std::size_t>(a.n);
  std::vector<fairspline::Point> pts;
  pts.reserve(n);
  if (a.shape == "circle") {
    for (std::size_t i = 0; i < n; ++i) {
      const double t = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
      pts.push_back({std::cos(t), std::sin(t)});
    }
    return pts;
  }
  // Random walk: turns uniform within ±120°, steps uniform in [0.5, 2].
  std::mt19937_64 rng(a.seed);
  std::uniform_real_distribution<double> turn(-120.0 * std::numbers::pi / 180.0,
                                              120.0 * std::numbers::pi / 180.0);
  std::uniform_real_distribution<double> step(0.5, 2.0);
  fairspline::Point p{0.0, 0.0};
  double heading = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    pts.push_back(p);
    heading += turn(rng);
    p += step(rng) * fairspline::from_angle(heading);
  }
  return pts;
}

int run_bench(const BenchArgs& a) {
  const std::string method =
      a.method.empty() ? std::string(fairspline::default_method_name()) : a.method;
  fairspline::FitInput in;
  in.closed = a.closed;
  in.points = bench_points(a);
  // Two timings, best of R each: `seconds` fits into one reused FitResult (the steady state of
  // a pipeline: output memory already mapped); `fresh_result_seconds` allocates a new result
  // per fit and so includes the kernel zeroing ~150 bytes of fresh pages per point.
  using clock = std::chrono::steady_clock;
  double best = std::numeric_limits<double>::infinity();
  double best_fresh = std::numeric_limits<double>::infinity();
  fairspline::FitResult reused;
  fairspline::fit_into(method, in, json::object(), fairspline::ReportLevel::kNone, reused);
  for (int r = 0; r < a.repeat; ++r) {
    const auto t0 = clock::now();
    fairspline::fit_into(method, in, json::object(), fairspline::ReportLevel::kNone, reused);
    const auto t1 = clock::now();
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
  }
  for (int r = 0; r < a.repeat; ++r) {
    const auto t0 = clock::now();
    const fairspline::FitResult result =
        fairspline::fit(method, in, json::object(), fairspline::ReportLevel::kNone);
    const auto t1 = clock::now();
    best_fresh = std::min(best_fresh, std::chrono::duration<double>(t1 - t0).count());
  }
  const std::size_t segments = reused.spline.segments.size();
  const json out = {{"method", std::string(fairspline::find_method(method).name)},
                    {"n", a.n},
                    {"closed", a.closed},
                    {"shape", a.shape},
                    {"seconds", best},
                    {"points_per_second", best > 0.0 ? static_cast<double>(a.n) / best : 0.0},
                    {"fresh_result_seconds", best_fresh},
                    {"repeat", a.repeat},
                    {"seed", a.seed},
                    {"segments", segments}};
  std::cout << out.dump() << "\n";
  return kExitOk;
}

// The directory of this executable (Linux: /proc/self/exe), where an installed command finds
// the files installed with it.
std::optional<fs::path> executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  return exe.parent_path();
}

// The default --root: the page installed next to this executable (<bindir>/
// FAIRSPLINE_WEB_ROOT_FROM_BINDIR, i.e. <prefix>/share/fairspline/web), so that an installed
// fairspline serves the page installed with it even where the source tree still exists; else
// the source tree's apps/web/static (the build tree's executable); else the configured install
// location (an executable copied elsewhere). Linux finds this executable via /proc/self/exe.
std::string default_web_root() {
  const std::optional<fs::path> bindir = executable_dir();
  std::vector<fs::path> candidates;
  if (bindir) candidates.push_back(*bindir / FAIRSPLINE_WEB_ROOT_FROM_BINDIR);
  candidates.emplace_back(FAIRSPLINE_WEB_ROOT);
  candidates.emplace_back(FAIRSPLINE_WEB_INSTALL_ROOT);
  std::error_code ec;
  for (const fs::path& dir : candidates) {
    if (fs::is_regular_file(dir / "index.html", ec)) return dir.lexically_normal().string();
  }
  return FAIRSPLINE_WEB_ROOT;
}

// The server's module (serve_module.hpp): next to this executable (the build tree), else where
// it is installed relative to it (<prefix>/lib/fairspline), else the configured install path.
// Opened only here, so that no other command loads the server's libraries.
fairspline::web::ServeEntry open_serve_module() {
  using fairspline::web::kServeModuleName;
  std::vector<fs::path> candidates;
  if (const std::optional<fs::path> bindir = executable_dir()) {
    candidates.push_back(*bindir / kServeModuleName);
    candidates.push_back(*bindir / FAIRSPLINE_SERVE_MODULE_FROM_BINDIR / kServeModuleName);
  }
  candidates.push_back(fs::path(FAIRSPLINE_SERVE_MODULE_INSTALL_DIR) / kServeModuleName);
  std::string looked;
  std::error_code ec;
  for (const fs::path& candidate : candidates) {
    const fs::path path = candidate.lexically_normal();
    if (!fs::is_regular_file(path, ec)) {
      looked += (looked.empty() ? "" : ", ") + path.string();
      continue;
    }
    void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr) {
      const char* why = dlerror();
      throw Error(ErrorCode::kIoError, "cannot load the web server module " + path.string() + ": " +
                                           (why ? why : "unknown reason"));
    }
    // (Kept loaded until the process ends: the server runs in it.)
    if (void* entry = dlsym(module, fairspline::web::kServeEntryName)) {
      return reinterpret_cast<fairspline::web::ServeEntry>(entry);
    }
    throw Error(ErrorCode::kIoError, "the web server module " + path.string() + " has no entry " +
                                         fairspline::web::kServeEntryName);
  }
  throw Error(ErrorCode::kIoError, std::string("the web server module ") + kServeModuleName +
                                       " is not installed (looked for " + looked + ")");
}

int run_serve(const fairspline::web::ServerOptions& options) {
  fairspline::web::ServeEntry serve;
  try {
    serve = open_serve_module();
  } catch (const Error& e) {
    throw UsageError{e};
  }
  char message[1024] = {};
  switch (serve(&options, message, sizeof message)) {
    case fairspline::web::kServeStopped:
      return kExitOk;
    case fairspline::web::kServeCannotListen:
      throw UsageError{Error(ErrorCode::kIoError, "cannot listen on " + options.host + ":" +
                                                      std::to_string(options.port) +
                                                      " (in use, or not a local address?)")};
    case fairspline::web::kServeError:
      throw Error(ErrorCode::kIoError, std::string("the web server stopped: ") + message);
    default:
      return kExitFitError;
  }
}

/// --accuracy, --best-effort and --no-diagnostics, shared by fit and batch.
void add_fit_options(CLI::App& cmd, fairspline::cli::FitFlags& flags) {
  cmd.add_option("--accuracy", flags.accuracy,
                 "Relative accuracy of every approximation, in (0, 1): the report's quadratures "
                 "and searches (default 1e-9), the Beziers of elastic splines (relative to the "
                 "data's size, default 1e-6); a request's \"accuracy\" unless given");
  cmd.add_flag("--best-effort", flags.best_effort,
               "When an iterative method stops short of its tolerance, write its curve with the "
               "solver's status instead of failing (also a request's \"best_effort\": true)");
  cmd.add_flag("--no-diagnostics", flags.no_diagnostics,
               "Leave the per-point and per-piece entries out of method_report, keeping its "
               "summary: at a million points they cost several times the fit (also a request's "
               "\"diagnostics\": false)");
  cmd.add_option("--time-limit", flags.time_limit,
                 "Stop a fit that runs longer than this many seconds, with error [cancelled] "
                 "(exit 1; in batch an error record, and the run goes on); a request's "
                 "\"time_limit\" unless given")
      ->type_name("SECONDS")
      ->check(CLI::Validator(
          [](const std::string& text) {
            double v = 0.0;
            return CLI::detail::lexical_cast(text, v) && v > 0.0 && std::isfinite(v)
                       ? std::string()
                       : "must be a positive number of seconds, got " + text;
          },
          "SECONDS > 0"));
}

int run(int argc, char** argv) {
  CLI::App app{"fairspline: fair planar cubic Bézier splines through points.", "fairspline"};
  app.set_version_flag("--version", "fairspline 0.1.0");
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 success, 1 the fit failed (fairspline error), 2 usage error or malformed "
      "input.\nRun 'fairspline COMMAND --help' for the options of a command.");

  FitArgs fa;
  CLI::App* fit =
      app.add_subcommand("fit", "Fit a spline through the points of a CSV or JSON file.");
  fit->add_option("INPUT", fa.input,
                  "CSV (x,y per line) or JSON ({\"points\": [[x,y],...], ...}) file; '-' or none "
                  "reads standard input");
  fit->add_option("-m,--method", fa.method,
                  "Method name (default: " + std::string(fairspline::default_method_name()) +
                      "; see 'fairspline methods')");
  fit->add_flag("--closed", fa.closed, "Closed curve (overrides the file)");
  fa.alpha_opt = fit->add_option("--alpha", fa.alpha,
                                 "Knot parameterization exponent: 0 uniform, 0.5 centripetal "
                                 "(default), 1 chordal");
  fit->add_option("--start-tangent", fa.start_tangent, "Clamped start tangent X,Y")
      ->type_name("X,Y");
  fit->add_option("--end-tangent", fa.end_tangent, "Clamped end tangent X,Y")->type_name("X,Y");
  fit->add_option("--set", fa.sets,
                  "Method option KEY=VALUE (VALUE as JSON if it parses, else a string); keys "
                  "starting with 'svg.' set SVG options (svg.width, svg.height, svg.margin, "
                  "svg.points, svg.control_polygon, svg.comb, svg.comb_scale, "
                  "svg.comb_samples_per_segment, svg.caption). Repeatable.")
      ->type_name("KEY=VALUE")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  fit->add_option("-f,--format", fa.format,
                  "Output format (default: from the -o extension: .json, .csv, .svg, .geojson; "
                  "json for standard output or a name without extension; any other extension "
                  "needs -f). svg-path: the d attribute of an SVG path in data coordinates "
                  "(one line); geojson: a GeoJSON Feature, the curve flattened to a LineString; "
                  "ce: Curve Ensemble's text file (x y direction corner state energy per node)")
      ->check(CLI::IsMember({"json", "csv", "svg", "svg-path", "geojson", "ce"}));
  fit->add_option("--input-format", fa.input_format,
                  "Input format (default auto: a Curve Ensemble file by its header line "
                  "'#Curve Ensemble Text File', JSON by extension or a leading { or [, else "
                  "CSV); ce reads Curve Ensemble's node states, directions and corners")
      ->check(CLI::IsMember({"auto", "csv", "json", "ce"}));
  fit->add_option("-o,--output", fa.output, "Output file (default: standard output)");
  fit->add_option("--tolerance", fa.tolerance,
                  "-f geojson only: the largest distance of the LineString from the curve, in "
                  "the data's units (default: 1e-4 of the diagonal of the curve's bounds)");
  fit->add_option("--report", fa.report,
                  "Report level (default: basic; full adds per-piece reports, curvature variation "
                  "and self-intersections)")
      ->check(CLI::IsMember({"none", "basic", "full"}));
  add_fit_options(*fit, fa.flags);
  fit->add_option("--fields", fa.fields,
                  "-f json only: comma-separated members to write, e.g. segments,report.length "
                  "(as batch --fields; \"method\" is always kept); the others are not computed "
                  "into text at all (default: the whole result)")
      ->type_name("LIST");
  fit->add_flag("--summary", fa.summary,
                "Print a summary table (to stdout with -o, else to stderr)");
  fit->add_flag("--progress", fa.progress,
                "Report a long fit's progress on stderr every 0.5 s (stage, step, seconds); by "
                "default only when stderr is a terminal");
  fit->add_option("--indent", fa.indent, "JSON indentation (default: compact, one line)")
      ->check(CLI::Range(-1, 16));

  fairspline::cli::BatchArgs bta;
  CLI::App* batch = app.add_subcommand(
      "batch",
      "Fit one JSON request per line (JSON Lines) in parallel; one JSON record per line and "
      "method out, in input order.");
  batch->add_option("INPUT", bta.input,
                    "JSON Lines file, one request as accepted by 'fit' per line (blank lines and "
                    "lines starting with '#' are skipped); '-' or none reads standard input");
  batch->add_option("-o,--output", bta.output, "Output file (default: standard output)");
  batch->add_option("--threads", bta.threads, "Worker threads (default 0: all cores)")
      ->check(CLI::Range(0u, 1024u));
  batch
      ->add_option("-m,--method", bta.methods,
                   "Method, overriding each line's \"method\"; repeat to fit every line with "
                   "each method in turn (one record per line and method)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  batch->add_option("--report", bta.report, "Report level (default: basic)")
      ->check(CLI::IsMember({"none", "basic", "full"}));
  add_fit_options(*batch, bta.flags);
  batch
      ->add_option("--fields", bta.fields,
                   "Comma-separated members a fit record keeps, e.g. segments,report.length: "
                   "top-level keys of the record, or NAME.KEY for one member of the report, "
                   "method_report, options or request object. \"line\" and \"method\" are always "
                   "kept; error records are written whole (default: the whole record)")
      ->type_name("LIST");
  batch->add_flag("--quiet", bta.quiet, "No progress line (shown only when stderr is a terminal)");
  batch->footer(
      "Exit codes: 0 every record succeeded, 1 some record failed (its error record is in the "
      "output), 2 usage error, unreadable input or unwritable output.");

  bool methods_json = false;
  CLI::App* methods = app.add_subcommand("methods", "List the methods and their options.");
  methods->add_flag("--json", methods_json, "Print the method schemas as a JSON array");

  BenchArgs ba;
  CLI::App* bench = app.add_subcommand(
      "bench", "Time one method on generated data (best of R runs, no report); prints JSON.");
  bench->add_option(
      "-m,--method", ba.method,
      "Method name (default: " + std::string(fairspline::default_method_name()) + ")");
  bench->add_option("-n,--points", ba.n, "Number of points")
      ->required()
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{100'000'000}));
  bench->add_flag("--closed", ba.closed, "Closed curve");
  bench
      ->add_option("--shape", ba.shape,
                   "Generated data: random walk or unit circle (default: random)")
      ->check(CLI::IsMember({"random", "circle"}));
  bench->add_option("--repeat", ba.repeat, "Runs; the best time is reported (default: 5)")
      ->check(CLI::Range(1, 1'000'000));
  bench->add_option("--seed", ba.seed, "Seed of the random walk (default: 1)");

  fairspline::web::ServerOptions sa;
  sa.root = default_web_root();
  CLI::App* serve = app.add_subcommand(
      "serve", "Serve the JSON API (GET /api/methods, POST /api/fit) and the editor page.");
  serve->add_option("--host", sa.host, "Address to bind (default: 127.0.0.1, loopback only)");
  serve->add_option("--port", sa.port, "Port (default: 8080; 0 picks a free one)")
      ->check(CLI::Range(0, 65535));
  serve->add_option("--root", sa.root,
                    "Directory of the page and its assets (default: " + sa.root + ")");
  serve->add_option("--max-points", sa.max_points, "Largest fit accepted (default: 200000)")
      ->check(CLI::Range(std::size_t{2}, std::size_t{100'000'000}));
  serve
      ->add_option("--max-body-bytes", sa.max_body_bytes,
                   "Largest request body accepted; larger ones get HTTP 413 (default: 8388608)")
      ->check(CLI::Range(std::size_t{1024}, std::size_t{1} << 40));
  serve
      ->add_option("--fit-time-limit-ms", sa.fit_time_limit_ms,
                   "A fit not answered within this time gets HTTP 503 \"timeout\" and finishes "
                   "in the background (default: 10000; 0: no limit)")
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{86'400'000}));
  serve
      ->add_option("--max-concurrent-fits", sa.max_concurrent_fits,
                   "Fits computed at once, timed-out ones included; a request that gets no slot "
                   "within the time limit, or finds every slot held by a timed-out fit, gets "
                   "HTTP 503 \"busy\" with Retry-After (default: 2 x hardware threads, at "
                   "least 2: " +
                       std::to_string(fairspline::web::default_max_concurrent_fits()) + ")")
      ->check(CLI::Range(std::size_t{1}, std::size_t{4096}));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }

  try {
    if (*fit) return run_fit(fa);
    if (*batch) {
      try {
        return fairspline::cli::run_batch(bta);
      } catch (const Error& e) {
        throw UsageError{e};  // per-record failures are records; what escapes stops the batch
      }
    }
    if (*methods) return run_methods(methods_json);
    if (*bench) return run_bench(ba);
    if (*serve) return run_serve(sa);
  } catch (const UsageError& u) {
    print_error(u.error);
    return kExitUsage;
  } catch (const Error& e) {
    print_error(e);
    return kExitFitError;
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc&) {
    std::cerr << "fairspline: error: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << "fairspline: internal error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "fairspline: internal error\n";
  }
  return kExitFitError;
}
