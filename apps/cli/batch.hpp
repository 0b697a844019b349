// `fairspline batch`: fits a JSON Lines file of curves in parallel, streaming, in input order.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fairspline/fit.hpp"

namespace fairspline::cli {

/// --accuracy, --best-effort and --no-diagnostics of `fit` and `batch`: each overrides the
/// request's (a line's) own.
struct FitFlags {
  std::optional<double> accuracy;    ///< else the request's, else the default
  bool best_effort = false;          ///< or the request's "best_effort": true
  bool no_diagnostics = false;       ///< or the request's "diagnostics": false
  std::optional<double> time_limit;  ///< seconds per fit; else the request's, else none
  void apply(FitOptions& f) const {
    if (accuracy) f.accuracy = *accuracy;
    if (time_limit) f.time_limit = *time_limit;
    f.best_effort = f.best_effort || best_effort;
    f.diagnostics = f.diagnostics && !no_diagnostics;
  }
};

/// The command line of `fairspline batch`.
struct BatchArgs {
  std::string input;                 ///< JSON Lines file; empty or "-": standard input
  std::string output;                ///< empty or "-": standard output
  unsigned threads = 0;              ///< 0: all cores
  std::vector<std::string> methods;  ///< -m, in order; empty: each line's "method" or the default
  std::string report = "basic";      ///< none | basic | full
  bool quiet = false;                ///< no progress line even on a terminal
  FitFlags flags;
  /// --fields: comma-separated members a fit record keeps ("segments", "report.length"); none:
  /// the whole record.
  std::optional<std::string> fields;
};

/// Runs the batch and returns the exit status: 0 every record succeeded, 1 some record failed
/// (stderr then ends with "fairspline batch: F of N records failed"). Throws fairspline::Error
/// for what the caller reports as a usage error (exit 2): an unknown method or field, unreadable
/// input, unwritable output.
int run_batch(const BatchArgs& args);

}  // namespace fairspline::cli
