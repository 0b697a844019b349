// `fairspline batch`: fits a JSON Lines file of curves in parallel, streaming, in input order.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "fairspline/fit.hpp"

namespace fairspline::cli {

/// The command line of `fairspline batch`.
struct BatchArgs {
  std::string input;                 ///< JSON Lines file; empty or "-": standard input
  std::string output;                ///< empty or "-": standard output
  unsigned threads = 0;              ///< 0: all cores
  std::vector<std::string> methods;  ///< -m, in order; empty: each line's "method" or the default
  std::string report = "basic";      ///< none | basic | full
  bool quiet = false;                ///< no progress line even on a terminal
  std::optional<double> accuracy;    ///< --accuracy, else each line's, else the default
  bool best_effort = false;          ///< --best-effort, or each line's
  bool no_diagnostics = false;       ///< --no-diagnostics, or each line's "diagnostics": false
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
