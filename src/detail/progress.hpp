// Progress reports and stops of a running fit (FitOptions::progress, FitOptions::time_limit).
// fit_into installs a FitWatch for the method's run on the calling thread; the solvers call
// checkpoint() between their steps. A thread-local rather than a parameter: the steps sit
// deep inside every iterative solver, and threading the options through each signature would
// touch them all for what is a no-op in nearly every fit.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string_view>

#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"

namespace fairspline::detail {

class FitWatch {
 public:
  /// Watches the calling thread's fit if `options` has a time limit or a progress callback.
  explicit FitWatch(const FitOptions& options);
  ~FitWatch();
  FitWatch(const FitWatch&) = delete;
  FitWatch& operator=(const FitWatch&) = delete;

  /// The error the fit was stopped with, if it was (kept: solvers that catch an Error and go
  /// on must not turn a stop into another outcome).
  const std::optional<Error>& stopped() const { return stopped_; }
  void check(std::string_view stage, std::size_t done, std::size_t total);

 private:
  using Clock = std::chrono::steady_clock;
  const FitOptions* options_ = nullptr;
  FitWatch* outer_ = nullptr;
  Clock::time_point start_, next_call_, deadline_;
  std::optional<Error> stopped_;
};

/// The watch of the calling thread's fit, or null.
FitWatch*& current_watch();

/// Between two steps of long work: calls the progress callback when it is due and throws
/// Error(kCancelled) once the fit is past its time limit or the callback stopped it. Free
/// when the fit has neither (a thread-local load and a test).
inline void checkpoint(std::string_view stage, std::size_t done, std::size_t total = 0) {
  if (FitWatch* w = current_watch()) w->check(stage, done, total);
}

}  // namespace fairspline::detail
