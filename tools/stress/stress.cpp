// fairspline_stress: fits generated curves with every iterative method of the registry and
// certifies each returned optimum (issue 18, part 2). See docs/hardening.md, "Stress suite".
//
// Every method with an integer option whose name says it limits iterations is iterative; an
// option "basis" (the min-energy framework's basic curve) makes one variant per value, the
// boolean that switches a solver on (`g2` for `g2_max_iterations`) is set, and every bounded
// number option that changes the result is spread over its accepted range. Inputs come from
// (seed, case index) alone, so any case can be replayed (--start K --count 1 --save-all).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"
#include "fairspline/vec2.hpp"
#include "kkt.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace fairspline::stress {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// ---------------------------------------------------------------- command line

struct Args {
  std::uint64_t seed = 1;
  std::uint64_t count = 1000;        ///< cases; every variant fits each
  std::uint64_t start = 0;           ///< first case index
  std::vector<std::string> methods;  ///< variant labels (empty: all)
  unsigned threads = 1;
  std::string out = "stress-out";
  std::size_t max_points = 2000;
  json set = json::object();  ///< --set KEY=VALUE overrides for every variant
  bool save_all = false;
  bool check = false;  ///< exit 1 on any not_converged, internal error or KKT failure
  int max_saved = 50;  ///< inputs saved per variant and outcome
  double hang_seconds = 60.0;
  std::string summary_json;
  double balls = 0.0;  ///< share of cases with data balls (methods that fit them)
  /// Which minimum (issue 18): every returned fit of a variant with a `search` option is fitted
  /// again with search=`minima_search` and both energies compared (and written here as JSON
  /// lines).
  std::string minima;
  std::string minima_search = "global";
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "fairspline_stress: %s\n"
               "usage: fairspline_stress [--seed S] [--count N] [--start K] [--methods a,b,...]\n"
               "         [--threads T] [--out DIR] [--max-points N] [--set KEY=VALUE]...\n"
               "         [--save-all] [--check] [--max-saved N] [--hang-seconds S]\n"
               "         [--summary-json FILE] [--balls P] [--minima FILE]\n"
               "         [--minima-search newton|coordinate|global] [--list]\n",
               why.c_str());
  std::exit(2);
}

std::uint64_t to_u64(const std::string& s, const char* what) {
  try {
    std::size_t used = 0;
    const unsigned long long v = std::stoull(s, &used, 0);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  usage(std::string("bad ") + what + ": " + s);
}

// ---------------------------------------------------------------- variants

struct Spread {
  std::string name;
  double lo = 0.0, hi = 0.0;
  std::vector<std::string> choices;  ///< choice_or_number: also these
};

struct Variant {
  std::string label;
  const MethodInfo* method = nullptr;
  json base = json::object();  ///< options of every fit
  std::vector<Spread> spreads;
};

const OptionSpec* find_option(const MethodInfo& m, const std::string& name) {
  for (const OptionSpec& o : m.options) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

/// The integer option that caps the method's solver, if any.
const OptionSpec* iteration_option(const MethodInfo& m) {
  for (const OptionSpec& o : m.options) {
    if (o.type == OptionType::kInteger && o.name.find("iterations") != std::string::npos) return &o;
  }
  return nullptr;
}

/// Gentle 7-point data with sharp turns too (so that bounds such as Ω bind).
FitInput probe_input() {
  FitInput in;
  in.points = {{0, 0}, {1, 0.2}, {2, 1.3}, {2.4, 2.5}, {1.8, 3.1}, {1.0, 3.0}, {0.2, 3.6}};
  return in;
}

/// Fit of the probe with `options` (a basic report: the method report names the options in
/// effect), or nullopt on any error.
std::optional<FitResult> probe(const Variant& v, const json& options) {
  try {
    return fit(v.method->name, probe_input(), options, ReportLevel::kBasic);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

bool accepted(const Variant& v, const std::string& name, double value) {
  json o = v.base;
  o[name] = value;
  try {
    (void)resolve_options(*v.method, o);
    (void)fit(v.method->name, probe_input(), o, ReportLevel::kNone);
    return true;
  } catch (const Error& e) {
    return e.code() != ErrorCode::kBadOption;
  }
}

/// The accepted range of a bounded number option for this variant (a basis may accept less
/// than the schema: Jaklič–Žagar Ω < 90°, Yong–Cheng Ω < 70.53°): bisection on bad_option.
std::optional<Spread> spread_of(const Variant& v, const OptionSpec& o) {
  if (!o.min || !o.max || !(*o.max > *o.min)) return std::nullopt;
  Spread s{o.name, *o.min, *o.max, o.choices};
  auto narrow = [&](double good, double bad) {
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (good + bad);
      (accepted(v, o.name, mid) ? good : bad) = mid;
    }
    return good;
  };
  // An accepted value inside the range (Jaklič–Žagar refuses Ω = 90°, the middle of 0…180).
  double mid = s.lo;
  for (double f : {0.5, 0.25, 0.375, 0.125, 0.75, 0.0625}) {
    if (accepted(v, o.name, s.lo + f * (s.hi - s.lo))) {
      mid = s.lo + f * (s.hi - s.lo);
      break;
    }
  }
  if (mid == s.lo) return std::nullopt;
  if (!accepted(v, o.name, s.hi)) s.hi = narrow(mid, s.hi);
  if (!accepted(v, o.name, s.lo)) s.lo = narrow(mid, s.lo);
  // Inert for this variant (e.g. lambda with another basis): the same curve and report.
  const auto a = probe(v, v.base);
  json changed = v.base;
  changed[o.name] = s.lo + 0.63 * (s.hi - s.lo);
  const auto b = probe(v, changed);
  if (a && b && a->tangents == b->tangents && a->method_report == b->method_report) {
    return std::nullopt;
  }
  return s;
}

std::vector<Variant> discover(const Args& args) {
  std::vector<Variant> out;
  std::set<std::string> labels;
  // A method named like the label hosts it if it can; otherwise the first that offers it.
  std::map<std::string, const MethodInfo*> host;
  std::vector<std::string> order;
  for (const MethodInfo& m : methods()) {
    if (!iteration_option(m)) continue;
    std::vector<std::string> ls{m.name};
    const OptionSpec* basis = find_option(m, "basis");
    if (basis && basis->type == OptionType::kChoice) ls = basis->choices;
    for (const std::string& l : ls) {
      if (!host.count(l)) {
        host[l] = &m;
        order.push_back(l);
      } else if (m.name == l) {
        host[l] = &m;
      }
    }
  }
  for (const std::string& l : order) {
    if (!args.methods.empty() &&
        std::find(args.methods.begin(), args.methods.end(), l) == args.methods.end()) {
      continue;
    }
    const MethodInfo& m = *host[l];
    Variant v;
    v.label = l;
    v.method = &m;
    // Options that let the method take any point set (a Hermite method's directions from
    // another method, a point-count rule relaxed by its option).
    const Capabilities& k = m.capabilities;
    if (k.tangents == TangentUse::kRequired)
      v.base[std::string(kTangentsFromOption)] = "jaklic-zagar";
    if (k.points.step > 1 && !k.points.relaxed_by.empty()) {
      v.base[std::string(k.points.relaxed_by)] = std::string(k.points.relaxed_value);
    }
    if (const OptionSpec* b = find_option(m, "basis"); b && m.name != l) v.base["basis"] = l;
    // The solver's switch: option `p` for `p_max_iterations`.
    const std::string it = iteration_option(m)->name;
    const std::string suffix = "_max_iterations";
    if (it.size() > suffix.size() && it.ends_with(suffix)) {
      const OptionSpec* sw = find_option(m, it.substr(0, it.size() - suffix.size()));
      if (sw && sw->type == OptionType::kBoolean) v.base[sw->name] = true;
    }
    for (const auto& [key, value] : args.set.items()) {
      if (find_option(m, key)) v.base[key] = value;
    }
    for (const OptionSpec& o : m.options) {
      if (args.set.contains(o.name) || v.base.contains(o.name)) continue;
      if (o.type != OptionType::kNumber && o.type != OptionType::kChoiceOrNumber) continue;
      if (auto s = spread_of(v, o)) v.spreads.push_back(*s);
    }
    out.push_back(std::move(v));
  }
  return out;
}

// ---------------------------------------------------------------- inputs

std::uint64_t mix(std::uint64_t x) {  // splitmix64
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

std::uint64_t hash_text(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
  return h;
}

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t s) : g(s) {}
  double u(double a = 0.0, double b = 1.0) {
    return std::uniform_real_distribution<double>(a, b)(g);
  }
  bool p(double prob) { return u() < prob; }
  std::size_t i(std::size_t a, std::size_t b) {  // [a, b]
    return std::uniform_int_distribution<std::size_t>(a, b)(g);
  }
  double log_u(double a, double b) { return std::exp(u(std::log(a), std::log(b))); }
};

struct Case {
  FitInput in;
  std::string shape;  ///< a few words for the saved file
};

/// Point count: mostly small (so that 10^6 fits per method fit in an hour), up to max.
std::size_t draw_count(Rng& r, std::size_t max_points) {
  const double u = r.u();
  double lo = 3, hi = 40;
  if (u >= 0.89 && u < 0.99) lo = 40, hi = 400;
  if (u >= 0.99) lo = 400, hi = 2000;
  hi = std::min<double>(hi, static_cast<double>(max_points));
  lo = std::min(lo, hi);
  return std::max<std::size_t>(3, static_cast<std::size_t>(std::lround(r.log_u(lo, hi + 0.49))));
}

/// The case's input: a random walk (turn limit 5°…179°, steps spread over up to 4 decades,
/// near-collinear runs, near-repeated points) or a perturbed circle; open or closed; clamped
/// ends, clamped and corner nodes.
Case make_case(std::uint64_t seed, std::uint64_t k, std::size_t max_points) {
  Rng r(mix(seed ^ mix(k + 0x51ed27)));
  Case c;
  const std::size_t n = draw_count(r, max_points);
  std::vector<Point>& p = c.in.points;
  char buf[160];
  if (r.p(0.8)) {
    const double turn = r.u(5.0, 179.0) * kDeg;
    const double decades = r.u(0.0, 4.0);
    c.in.closed = r.p(0.25);
    std::vector<double> turns(n), steps(n);
    for (std::size_t i = 0; i < n; ++i) {
      turns[i] = r.u(-turn, turn);
      steps[i] = std::pow(10.0, r.u(0.0, decades));
    }
    std::size_t runs = 0, repeats = 0;
    if (r.p(0.3)) {  // near-collinear runs: turns of 0 or 1e-12 … 1e-4 rad
      runs = r.i(1, 3);
      for (std::size_t q = 0; q < runs; ++q) {
        const std::size_t len = r.i(3, std::max<std::size_t>(3, std::min<std::size_t>(n, 30)));
        const std::size_t at = r.i(0, n - 1);
        const bool exact = r.p(0.2);
        for (std::size_t i = at; i < std::min(n, at + len); ++i) {
          turns[i] = exact ? 0.0 : (r.p(0.5) ? 1 : -1) * std::pow(10.0, r.u(-12.0, -4.0));
        }
      }
    }
    if (r.p(0.2)) {  // near-repeated points: a step 1e-4 … 1e-9 of a typical one
      repeats = r.i(1, 2);
      for (std::size_t q = 0; q < repeats; ++q)
        steps[r.i(0, n - 1)] = std::pow(10.0, -r.u(4.0, 9.0));
    }
    double heading = r.u(0.0, 2 * kPi);
    Point at{0, 0};
    for (std::size_t i = 0; i < n; ++i) {
      p.push_back(at);
      heading += turns[i];
      at += steps[i] * from_angle(heading);
    }
    std::snprintf(buf, sizeof buf, "walk turn<=%.1fdeg steps 1..1e%.2f runs=%zu repeats=%zu",
                  turn / kDeg, decades, runs, repeats);
  } else {
    const double wobble = r.u(0.0, 0.6);
    c.in.closed = r.p(0.8);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = 2 * kPi * (static_cast<double>(i) + r.u(-0.4, 0.4)) / static_cast<double>(n);
      p.push_back((1.0 + wobble * r.u(-1.0, 1.0)) * from_angle(t));
    }
    std::snprintf(buf, sizeof buf, "perturbed circle wobble=%.2f", wobble);
  }
  c.shape = buf;
  const double scale = std::pow(10.0, r.u(-2.0, 2.0));
  for (Point& q : p) q = scale * q;

  // Node kinds and clamped directions.
  auto chord = [&](std::size_t i) {  // unit chord from i to i+1 (cyclic)
    return normalized(p[(i + 1) % n] - p[i]);
  };
  const bool corners = r.p(0.15), clamps = r.p(0.15);
  if (corners || clamps) {
    c.in.kinds.assign(n, PointKind::kSmooth);
    c.in.tangents.assign(n, std::nullopt);
    for (std::size_t i = 0; i < n; ++i) {
      if (!c.in.closed && (i == 0 || i + 1 == n)) continue;
      if (corners && r.p(0.15)) {
        c.in.kinds[i] = PointKind::kCorner;
      } else if (clamps && r.p(0.1)) {
        // (At a reversal the bisector is undefined: the next chord, an infeasible clamp.)
        const Vec2 sum = chord((i + n - 1) % n) + chord(i);
        const Vec2 bis = norm(sum) > 1e-3 ? normalized(sum) : chord(i);
        c.in.kinds[i] = PointKind::kClamped;
        c.in.tangents[i] = rotate(bis, r.u(-20.0, 20.0) * kDeg);
      }
    }
  }
  auto end_direction = [&](Vec2 along) {
    return rotate(along, (r.p(0.85) ? r.u(-60.0, 60.0) : r.u(-120.0, 120.0)) * kDeg);
  };
  if (!c.in.closed) {
    if (r.p(0.25)) c.in.start_tangent = end_direction(chord(0));
    if (r.p(0.25)) c.in.end_tangent = end_direction(chord(n - 2));
  } else if (r.p(0.1)) {
    c.in.start_tangent = end_direction(chord(0));
  }
  return c;
}

/// With probability `share`, data balls on 80% of the case's points: radius up to 0.45 of the
/// shorter gap to a neighbour (neighbouring discs apart). Drawn from a stream of their own, so
/// that the cases themselves do not depend on --balls.
void add_balls(Case& c, std::uint64_t seed, std::uint64_t k, double share) {
  Rng r(mix(seed ^ mix(k + 0xba11)));
  if (!(share > 0.0) || !r.p(share)) return;
  const std::vector<Point>& p = c.in.points;
  const std::size_t n = p.size();
  c.in.radii.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double gap = HUGE_VAL;
    if (c.in.closed || i > 0) gap = std::min(gap, distance(p[i], p[(i + n - 1) % n]));
    if (c.in.closed || i + 1 < n) gap = std::min(gap, distance(p[i], p[(i + 1) % n]));
    if (r.p(0.8)) c.in.radii[i] = r.u(0.0, 0.45) * gap;
  }
  c.shape += " balls";
}

/// The case as the method can take it: no closed curve, point kind or data ball it does not
/// offer.
FitInput adapt(const Case& c, const MethodInfo& m) {
  FitInput in = c.in;
  const Capabilities& k = m.capabilities;
  if (!k.data_balls) in.radii.clear();
  if (in.closed && !k.closed) in.closed = false;
  for (std::size_t i = 0; i < in.kinds.size(); ++i) {
    if (!k.honours(in.kinds[i])) {
      in.kinds[i] = PointKind::kSmooth;
      in.tangents[i] = std::nullopt;
    }
  }
  return in;
}

json draw_options(const Variant& v, std::uint64_t seed, std::uint64_t k) {
  Rng r(mix(seed ^ mix(k ^ hash_text(v.label))));
  json o = v.base;
  for (const Spread& s : v.spreads) {
    const double u = r.u();
    if (u < 0.4) continue;  // the default
    if (!s.choices.empty() && u < 0.55) {
      o[s.name] = s.choices[r.i(0, s.choices.size() - 1)];
    } else {
      double x = r.u(s.lo, s.hi);
      if (x <= s.lo) x = std::nextafter(s.lo, s.hi);  // open ends: (0, 3) for lambda
      o[s.name] = x;
    }
  }
  return o;
}

json request_json(const FitInput& in, const std::string& method, const json& options) {
  json j = io::input_to_json(in);
  j["method"] = method;
  j["options"] = options;
  return j;
}

// ---------------------------------------------------------------- outcomes

enum class Outcome { kOk, kRejected, kNotConverged, kInternal };

/// Legitimate answers to inputs the method cannot take (by its capabilities or its theory).
bool rejection(ErrorCode c) {
  switch (c) {
    case ErrorCode::kInfeasible:
    case ErrorCode::kRepeatedPoint:
    case ErrorCode::kReversal:
    case ErrorCode::kTooFewPoints:
    case ErrorCode::kWrongPointCount:
    case ErrorCode::kInvalidArgument:
      return true;
    default:
      return false;
  }
}

struct Stats {
  std::uint64_t fits = 0, ok = 0, conditioning = 0, not_converged = 0, internal = 0,
                kkt_checked = 0, kkt_failed = 0;
  std::map<std::string, std::uint64_t> rejected;        ///< legitimate errors by code
  std::map<std::string, std::uint64_t> internal_codes;  ///< by code, "exception", "nan"
  std::vector<int> iterations;
  std::vector<float> ms;
  double total_ms = 0.0;
  double worst_kkt = 0.0, worst_allowance = 0.0;  ///< residual, rounding allowance there
  std::uint64_t worst_case = 0;
  int max_iterations = 0;  ///< and the cases where the maxima were reached
  double max_ms = 0.0;
  std::uint64_t max_iterations_case = 0, max_ms_case = 0;
  /// --minima: fits compared, those where the reference search (--minima-search) is lower
  /// (relative excess above 1e-9; above 1e-4), the worst relative excess of the variant's own
  /// search and its case, reference fits that failed, and the two searches' times over the
  /// compared fits.
  std::uint64_t compared = 0, reference_lower = 0, reference_lower_1e4 = 0, reference_failed = 0,
                worst_excess_case = 0;
  double worst_excess = 0.0, compared_ms = 0.0, reference_ms = 0.0;

  void merge(const Stats& o) {
    fits += o.fits, ok += o.ok, conditioning += o.conditioning;
    not_converged += o.not_converged, internal += o.internal;
    kkt_checked += o.kkt_checked, kkt_failed += o.kkt_failed;
    for (const auto& [c, n] : o.rejected) rejected[c] += n;
    for (const auto& [c, n] : o.internal_codes) internal_codes[c] += n;
    iterations.insert(iterations.end(), o.iterations.begin(), o.iterations.end());
    ms.insert(ms.end(), o.ms.begin(), o.ms.end());
    total_ms += o.total_ms;
    if (o.max_iterations > max_iterations) {
      max_iterations = o.max_iterations, max_iterations_case = o.max_iterations_case;
    }
    if (o.max_ms > max_ms) max_ms = o.max_ms, max_ms_case = o.max_ms_case;
    compared += o.compared, reference_lower += o.reference_lower;
    reference_lower_1e4 += o.reference_lower_1e4;
    reference_failed += o.reference_failed;
    compared_ms += o.compared_ms, reference_ms += o.reference_ms;
    if (o.worst_excess > worst_excess) {
      worst_excess = o.worst_excess, worst_excess_case = o.worst_excess_case;
    }
    if (o.worst_kkt > worst_kkt) {
      worst_kkt = o.worst_kkt, worst_allowance = o.worst_allowance, worst_case = o.worst_case;
    }
  }
};

/// Iterations of the result's solver: FitResult::solver, else "iterations" in the method
/// report; nullopt when the result says neither (a closed-form fit).
std::optional<int> iterations_of(const FitResult& r) {
  if (r.solver) return r.solver->iterations;
  if (r.method_report.contains("iterations") && r.method_report.at("iterations").is_number()) {
    return r.method_report.at("iterations").get<int>();
  }
  return std::nullopt;
}

bool finite_output(const FitResult& r) {
  for (const Segment& s : r.spline.segments) {
    for (const Point& q : s.bezier.p) {
      if (!std::isfinite(q.x) || !std::isfinite(q.y)) return false;
    }
  }
  return true;
}

// ---------------------------------------------------------------- crash and hang reports

struct Slot {
  std::atomic<int> variant{-1};
  std::atomic<std::uint64_t> k{0};
  std::atomic<std::int64_t> since_ms{0};
};
Slot g_slots[256];
unsigned g_threads = 1;
std::uint64_t g_seed = 0;
std::size_t g_max_points = 0;  ///< 0: the default (not in replay commands)
const std::vector<Variant>* g_variants = nullptr;

void write_number(int fd, std::uint64_t v) {
  char b[24];
  int i = 24;
  do b[--i] = static_cast<char>('0' + v % 10), v /= 10;
  while (v);
  (void)!write(fd, b + i, 24 - i);
}
void write_text(int fd, const char* s) {
  (void)!write(fd, s, std::strlen(s));
}

/// On a crash: which fit it was and how to replay it (async-signal-safe writes only).
extern "C" void on_crash(int sig) {
  for (unsigned t = 0; t < g_threads; ++t) {
    const int v = g_slots[t].variant.load();
    if (v < 0) continue;
    write_text(2, "\nfairspline_stress: CRASH (signal ");
    write_number(2, static_cast<std::uint64_t>(sig));
    write_text(2, ") possibly in ");
    write_text(2, (*g_variants)[static_cast<std::size_t>(v)].label.c_str());
    write_text(2, "; replay: fairspline_stress --seed ");
    write_number(2, g_seed);
    write_text(2, " --start ");
    write_number(2, g_slots[t].k.load());
    if (g_max_points != 0) {
      write_text(2, " --max-points ");
      write_number(2, g_max_points);
    }
    write_text(2, " --count 1 --save-all --methods ");
    write_text(2, (*g_variants)[static_cast<std::size_t>(v)].label.c_str());
    write_text(2, "\n");
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// ---------------------------------------------------------------- the run

struct Shared {
  const Args* args = nullptr;
  const std::vector<Variant>* variants = nullptr;
  std::mutex save_mutex;
  /// Saved inputs per "label/outcome", by (points, case).
  std::map<std::string, std::map<std::pair<std::size_t, std::uint64_t>, fs::path>> saved;
  std::atomic<std::uint64_t> done{0};
  std::atomic<std::uint64_t> bad{0};  ///< not_converged + internal + KKT failures so far
  std::mutex minima_mutex;
  std::ofstream minima;  ///< --minima's lines
  std::string minima_search;
};

/// --minima: fits `in` again with the reference search (--minima-search) and compares its energy
/// with that of `r`, the variant's own (default) search, which took `ms`.
void compare_minima(Shared& sh, const Variant& v, std::uint64_t k, const FitInput& in,
                    const json& options, const FitResult& r, double ms, Stats& st) {
  if (!find_option(*v.method, "search") || options.value("search", "") == sh.minima_search ||
      !r.method_report.contains("energy")) {
    return;
  }
  json reference = options;
  reference["search"] = sh.minima_search;
  const double e = r.method_report.at("energy").get<double>();
  double ec = std::numeric_limits<double>::quiet_NaN();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    FitResult rc;
    fit_into(v.method->name, in, reference, FitOptions{.level = ReportLevel::kNone}, rc);
    ec = rc.method_report.at("energy").get<double>();
  } catch (const Error&) {
    ++st.reference_failed;
  }
  const double cms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ++st.compared;
  st.compared_ms += ms;
  st.reference_ms += cms;
  // Relative to the reference search's energy, but at least 1e-6 of the energy of turning every
  // piece by a radian (Σ 1/L): nearly collinear data have energies of rounding errors.
  double unit_turns = 0.0;
  const std::size_t n = r.points.size(), spans = r.closed ? n : n - 1;
  for (std::size_t i = 0; i < spans; ++i) {
    unit_turns += 1.0 / norm(r.points[i + 1 == n ? 0 : i + 1] - r.points[i]);
  }
  const double excess = std::isfinite(ec) ? (e - ec) / std::max(ec, 1e-6 * unit_turns) : 0.0;
  if (excess > 1e-9) ++st.reference_lower;
  if (excess > 1e-4) ++st.reference_lower_1e4;
  if (excess > st.worst_excess) st.worst_excess = excess, st.worst_excess_case = k;
  std::lock_guard<std::mutex> lock(sh.minima_mutex);
  sh.minima << json{{"case", k},   {"variant", v.label},  {"points", in.points.size()},
                    {"energy", e}, {"reference", ec},     {"excess", excess},
                    {"ms", ms},    {"reference_ms", cms}, {"search", sh.minima_search}}
                   .dump()
            << "\n";
}

/// Saves the request of a failing (or, with --save-all, any) fit. Per variant and outcome the
/// --max-saved smallest inputs are kept (fewest points, then lowest case): the best
/// regression tests, and the same set whatever the thread count.
void save(Shared& sh, const Variant& v, std::uint64_t k, const FitInput& in, const json& options,
          const std::string& outcome, const std::string& message, double kkt, const Case& c) {
  const std::string key = v.label + "/" + outcome;
  const fs::path path =
      fs::path(sh.args->out) / (v.label + "-" + outcome + "-s" + std::to_string(sh.args->seed) +
                                "-c" + std::to_string(k) + ".json");
  const std::pair<std::size_t, std::uint64_t> rank{in.points.size(), k};
  std::lock_guard<std::mutex> lock(sh.save_mutex);
  auto& kept = sh.saved[key];
  if (!sh.args->save_all && kept.size() >= static_cast<std::size_t>(sh.args->max_saved)) {
    if (kept.empty() || !(rank < kept.rbegin()->first)) return;
    fs::remove(kept.rbegin()->second);
    kept.erase(std::prev(kept.end()));
  }
  kept.emplace(rank, path);
  json j = request_json(in, v.method->name, options);
  // The point counts depend on --max-points: a replay needs it.
  const std::string max_points = sh.args->max_points == Args{}.max_points
                                     ? std::string()
                                     : " --max-points " + std::to_string(sh.args->max_points);
  const std::string balls =
      sh.args->balls > 0.0 ? " --balls " + nlohmann::json(sh.args->balls).dump() : std::string();
  j["_stress"] = {{"seed", sh.args->seed},
                  {"case", k},
                  {"variant", v.label},
                  {"outcome", outcome},
                  {"message", message},
                  {"kkt_residual", kkt},
                  {"shape", c.shape},
                  {"replay", "fairspline_stress --seed " + std::to_string(sh.args->seed) +
                                 " --start " + std::to_string(k) + " --count 1 --methods " +
                                 v.label + max_points + balls + " --save-all"}};
  std::ofstream f(path);
  f << j.dump(1) << "\n";
}

void run_case(Shared& sh, unsigned t, std::uint64_t k, std::vector<Stats>& stats, FitResult& r) {
  const Args& a = *sh.args;
  Case c = make_case(a.seed, k, a.max_points);
  add_balls(c, a.seed, k, a.balls);
  bool any_bad = false;
  for (std::size_t vi = 0; vi < sh.variants->size(); ++vi) {
    const Variant& v = (*sh.variants)[vi];
    Stats& st = stats[vi];
    const FitInput in = adapt(c, *v.method);
    const json options = draw_options(v, a.seed, k);
    g_slots[t].k = k;
    g_slots[t].since_ms = now_ms();
    g_slots[t].variant = static_cast<int>(vi);
    Outcome outcome = Outcome::kOk;
    std::string code, message;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      fit_into(v.method->name, in, options, FitOptions{.level = ReportLevel::kNone}, r);
      if (!finite_output(r)) outcome = Outcome::kInternal, code = "nan", message = "NaN output";
    } catch (const Error& e) {
      code = std::string(error_code_name(e.code()));
      message = e.what();
      outcome = e.code() == ErrorCode::kNotConverged ? Outcome::kNotConverged
                : rejection(e.code())                ? Outcome::kRejected
                                                     : Outcome::kInternal;
    } catch (const std::exception& e) {
      outcome = Outcome::kInternal, code = "exception", message = e.what();
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    g_slots[t].variant = -1;
    ++st.fits;
    st.total_ms += ms;
    if (outcome == Outcome::kRejected) ++st.rejected[code];
    if (outcome == Outcome::kNotConverged) ++st.not_converged;
    if (outcome == Outcome::kInternal) ++st.internal, ++st.internal_codes[code];
    double kkt_residual = 0.0;
    std::string kind;
    if (outcome == Outcome::kOk) {
      ++st.ok;
      st.iterations.push_back(iterations_of(r).value_or(0));
      st.ms.push_back(static_cast<float>(ms));
      if (st.iterations.back() > st.max_iterations) {
        st.max_iterations = st.iterations.back(), st.max_iterations_case = k;
      }
      if (ms > st.max_ms) st.max_ms = ms, st.max_ms_case = k;
      if (r.solver && r.solver->status == SolverStatus::kConditioningLimit) ++st.conditioning;
      if (!a.minima.empty()) compare_minima(sh, v, k, in, options, r, ms, st);
      const KktResult kkt = check_optimum(in, r);
      if (kkt.checked) {
        ++st.kkt_checked;
        kkt_residual = kkt.residual;
        if (kkt.residual > st.worst_kkt || !std::isfinite(kkt.residual)) {
          st.worst_kkt = std::isfinite(kkt.residual) ? kkt.residual : 1e300;
          st.worst_allowance = kkt.allowance;
          st.worst_case = k;
        }
        if (!kkt.pass) ++st.kkt_failed, kind = "kkt", message = kkt.what;
      }
    } else if (outcome == Outcome::kNotConverged) {
      kind = "not_converged";
    } else if (outcome == Outcome::kInternal) {
      kind = "internal-" + code;
    }
    if (!kind.empty()) any_bad = true;
    if (!kind.empty() || a.save_all) {
      save(sh, v, k, in, options, kind.empty() ? (code.empty() ? "ok" : code) : kind, message,
           kkt_residual, c);
    }
  }
  if (any_bad) ++sh.bad;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

template <class T>
T percentile(std::vector<T> v, double q) {
  if (v.empty()) return T{};
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(i), v.end());
  return v[i];
}

}  // namespace
}  // namespace fairspline::stress

int main(int argc, char** argv) {
  using namespace fairspline;
  using namespace fairspline::stress;
  Args a;
  bool list = false;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage("missing value after " + s);
      return argv[++i];
    };
    if (s == "--seed") {
      a.seed = to_u64(value(), "seed");
    } else if (s == "--count") {
      a.count = to_u64(value(), "count");
    } else if (s == "--start") {
      a.start = to_u64(value(), "start");
    } else if (s == "--methods") {
      std::stringstream ss(value());
      for (std::string m; std::getline(ss, m, ',');) {
        if (!m.empty()) a.methods.push_back(m);
      }
    } else if (s == "--threads") {
      a.threads =
          static_cast<unsigned>(std::clamp<std::uint64_t>(to_u64(value(), "threads"), 1, 256));
    } else if (s == "--out") {
      a.out = value();
    } else if (s == "--max-points") {
      a.max_points = std::max<std::size_t>(3, to_u64(value(), "max-points"));
    } else if (s == "--set") {
      const std::string kv = value();
      const auto eq = kv.find('=');
      if (eq == std::string::npos) usage("--set needs KEY=VALUE");
      const std::string text = kv.substr(eq + 1);
      a.set[kv.substr(0, eq)] = json::accept(text) ? json::parse(text) : json(text);
    } else if (s == "--save-all") {
      a.save_all = true;
    } else if (s == "--check") {
      a.check = true;
    } else if (s == "--max-saved") {
      a.max_saved = static_cast<int>(to_u64(value(), "max-saved"));
    } else if (s == "--hang-seconds") {
      a.hang_seconds = std::stod(value());
    } else if (s == "--balls") {
      a.balls = std::stod(value());
      if (!(a.balls >= 0.0 && a.balls <= 1.0)) usage("--balls needs a share in [0, 1]");
    } else if (s == "--summary-json") {
      a.summary_json = value();
    } else if (s == "--minima") {
      a.minima = value();
    } else if (s == "--minima-search") {
      a.minima_search = value();
      if (a.minima_search != "newton" && a.minima_search != "coordinate" &&
          a.minima_search != "global") {
        usage("--minima-search needs newton, coordinate or global");
      }
    } else if (s == "--list") {
      list = true;
    } else {
      usage("unknown argument " + s);
    }
  }
  const std::vector<Variant> variants = discover(a);
  if (variants.empty()) usage("no iterative method matches --methods");
  for (const std::string& m : a.methods) {
    if (std::none_of(variants.begin(), variants.end(),
                     [&](const Variant& v) { return v.label == m; })) {
      usage("no iterative method or basis called " + m);
    }
  }
  std::fprintf(stderr, "fairspline_stress: seed %llu, cases %llu..%llu, %zu variants:\n",
               static_cast<unsigned long long>(a.seed), static_cast<unsigned long long>(a.start),
               static_cast<unsigned long long>(a.start + a.count - 1), variants.size());
  for (const Variant& v : variants) {
    std::string spreads;
    for (const Spread& s : v.spreads) {
      spreads += " " + s.name + " in (" + fmt("%.6g", s.lo) + ", " + fmt("%.10g", s.hi) + ")";
    }
    std::fprintf(stderr, "  %-20s method %s options %s%s%s\n", v.label.c_str(),
                 v.method->name.c_str(), v.base.dump().c_str(), spreads.empty() ? "" : " spread",
                 spreads.c_str());
  }
  if (list) return 0;
  fs::create_directories(a.out);

  g_threads = a.threads;
  g_seed = a.seed;
  g_max_points = a.max_points == Args{}.max_points ? 0 : a.max_points;
  g_variants = &variants;
  for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL}) std::signal(sig, on_crash);

  Shared sh;
  sh.args = &a;
  sh.variants = &variants;
  if (!a.minima.empty()) {
    sh.minima.open(a.minima);
    if (!sh.minima) usage("cannot write " + a.minima);
    sh.minima_search = a.minima_search;
  }
  std::vector<std::vector<Stats>> per_thread(a.threads, std::vector<Stats>(variants.size()));
  std::atomic<bool> finished{false};
  std::vector<std::thread> pool;
  const auto started = std::chrono::steady_clock::now();
  for (unsigned t = 0; t < a.threads; ++t) {
    pool.emplace_back([&, t] {
      FitResult r;
      for (std::uint64_t k = a.start + t; k < a.start + a.count; k += a.threads) {
        run_case(sh, t, k, per_thread[t], r);
        ++sh.done;
      }
    });
  }
  // Progress on stderr; a fit that runs for longer than --hang-seconds is reported (and its
  // input saved) while it runs.
  std::thread monitor([&] {
    const bool tty = isatty(2) != 0;
    std::int64_t last_print = 0;
    std::set<std::pair<int, std::uint64_t>> hung;
    while (!finished) {
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
      const std::int64_t now = now_ms();
      for (unsigned t = 0; t < a.threads; ++t) {
        const int v = g_slots[t].variant.load();
        const std::uint64_t k = g_slots[t].k.load();
        if (v < 0 || now - g_slots[t].since_ms.load() < a.hang_seconds * 1000.0) continue;
        if (!hung.insert({v, k}).second) continue;
        const Variant& var = variants[static_cast<std::size_t>(v)];
        std::fprintf(stderr, "\nfairspline_stress: %s case %llu runs for over %.0f s\n",
                     var.label.c_str(), static_cast<unsigned long long>(k), a.hang_seconds);
        Case c = make_case(a.seed, k, a.max_points);
        add_balls(c, a.seed, k, a.balls);
        save(sh, var, k, adapt(c, *var.method), draw_options(var, a.seed, k), "hang",
             "runs for over " + std::to_string(a.hang_seconds) + " s", 0.0, c);
      }
      if (now - last_print >= (tty ? 1000 : 30000)) {
        last_print = now;
        const double secs =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        const double done = static_cast<double>(sh.done.load());
        const double eta = done > 0 ? secs * (static_cast<double>(a.count) - done) / done : 0.0;
        std::fprintf(stderr, "%scases %llu/%llu  %.0f s  eta %.0f s  cases with failures %llu%s",
                     tty ? "\r" : "", static_cast<unsigned long long>(sh.done.load()),
                     static_cast<unsigned long long>(a.count), secs, eta,
                     static_cast<unsigned long long>(sh.bad.load()), tty ? "   " : "\n");
      }
    }
  });
  for (std::thread& th : pool) th.join();
  finished = true;
  monitor.join();
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::fprintf(stderr, "\nfairspline_stress: %llu cases in %.1f s\n",
               static_cast<unsigned long long>(a.count), secs);

  // The table (markdown) and the exit status.
  std::printf(
      "| variant | fits | ok | rejected (by code) | not_converged | internal (by code) | "
      "conditioning_limit | KKT checked | KKT failed | worst KKT (allowance) | "
      "iterations max / p99 | "
      "time ms max / p99 (returned) / mean (all fits) "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  json summary = json::array();
  bool failed = false;
  for (std::size_t vi = 0; vi < variants.size(); ++vi) {
    Stats st;
    for (const auto& ts : per_thread) st.merge(ts[vi]);
    auto by_code = [](const std::map<std::string, std::uint64_t>& m, std::uint64_t& total) {
      std::string text;
      total = 0;
      for (const auto& [code, n] : m) {
        text += (text.empty() ? "" : ", ") + code + " " + std::to_string(n);
        total += n;
      }
      return text.empty() ? std::string("-") : text;
    };
    std::uint64_t rejected_total = 0, internal_total = 0;
    const std::string rejected = by_code(st.rejected, rejected_total);
    const std::string internal = by_code(st.internal_codes, internal_total);
    const int it_max =
        st.iterations.empty() ? 0 : *std::max_element(st.iterations.begin(), st.iterations.end());
    const float ms_max = st.ms.empty() ? 0.0f : *std::max_element(st.ms.begin(), st.ms.end());
    std::printf(
        "| %s | %llu | %llu | %llu (%s) | %llu | %llu (%s) | %llu | %llu | %llu | %s | "
        "%d / %d | "
        "%s / %s / %s |\n",
        variants[vi].label.c_str(), static_cast<unsigned long long>(st.fits),
        static_cast<unsigned long long>(st.ok), static_cast<unsigned long long>(rejected_total),
        rejected.c_str(), static_cast<unsigned long long>(st.not_converged),
        static_cast<unsigned long long>(st.internal), internal.c_str(),
        static_cast<unsigned long long>(st.conditioning),
        static_cast<unsigned long long>(st.kkt_checked),
        static_cast<unsigned long long>(st.kkt_failed),
        (fmt("%.2g", st.worst_kkt) + " (" + fmt("%.1g", st.worst_allowance) + ")").c_str(), it_max,
        percentile(st.iterations, 0.99), fmt("%.3g", ms_max).c_str(),
        fmt("%.3g", percentile(st.ms, 0.99)).c_str(),
        fmt("%.3g", st.fits ? st.total_ms / static_cast<double>(st.fits) : 0.0).c_str());
    failed = failed || st.not_converged > 0 || st.internal > 0 || st.kkt_failed > 0;
    summary.push_back({{"variant", variants[vi].label},
                       {"method", variants[vi].method->name},
                       {"fits", st.fits},
                       {"ok", st.ok},
                       {"rejected", st.rejected},
                       {"internal_codes", st.internal_codes},
                       {"not_converged", st.not_converged},
                       {"internal", st.internal},
                       {"conditioning_limit", st.conditioning},
                       {"kkt_checked", st.kkt_checked},
                       {"kkt_failed", st.kkt_failed},
                       {"worst_kkt", st.worst_kkt},
                       {"worst_kkt_allowance", st.worst_allowance},
                       {"worst_kkt_case", st.worst_case},
                       {"iterations_max", it_max},
                       {"iterations_p99", percentile(st.iterations, 0.99)},
                       {"iterations_max_case", st.max_iterations_case},
                       {"ms_max", ms_max},
                       {"ms_max_case", st.max_ms_case},
                       {"ms_p99", percentile(st.ms, 0.99)},
                       {"ms_total", st.total_ms}});
    if (st.compared) {
      summary.back()["minima"] = {{"compared", st.compared},
                                  {"reference_lower", st.reference_lower},
                                  {"reference_lower_1e4", st.reference_lower_1e4},
                                  {"reference_failed", st.reference_failed},
                                  {"worst_excess", st.worst_excess},
                                  {"worst_excess_case", st.worst_excess_case},
                                  {"ms", st.compared_ms},
                                  {"reference_ms", st.reference_ms}};
    }
  }
  // --minima: how often the variant's own search misses a lower minimum.
  bool header = false;
  for (std::size_t vi = 0; vi < variants.size(); ++vi) {
    const json& m = summary[vi].value("minima", json());
    if (m.is_null()) continue;
    if (!header) {
      std::printf(
          "\n| variant | compared | search=%s lower (by > 1e-4) | worst excess (case) | "
          "%s failed | time %s / own |\n|---|---|---|---|---|---|\n",
          a.minima_search.c_str(), a.minima_search.c_str(), a.minima_search.c_str());
      header = true;
    }
    std::printf("| %s | %llu | %llu (%llu) | %s (%llu) | %llu | %s |\n", variants[vi].label.c_str(),
                m.at("compared").get<unsigned long long>(),
                m.at("reference_lower").get<unsigned long long>(),
                m.at("reference_lower_1e4").get<unsigned long long>(),
                fmt("%.2g", m.at("worst_excess").get<double>()).c_str(),
                m.at("worst_excess_case").get<unsigned long long>(),
                m.at("reference_failed").get<unsigned long long>(),
                fmt("%.3g", m.at("reference_ms").get<double>() / m.at("ms").get<double>()).c_str());
  }
  if (!a.summary_json.empty()) {
    std::ofstream f(a.summary_json);
    f << json{{"seed", a.seed},
              {"start", a.start},
              {"count", a.count},
              {"seconds", secs},
              {"variants", summary}}
             .dump(1)
      << "\n";
  }
  if (failed) {
    std::fprintf(stderr, "fairspline_stress: failing inputs saved in %s\n", a.out.c_str());
  }
  return a.check && failed ? 1 : 0;
}
