#include "detail/progress.hpp"

#include <algorithm>
#include <string>

#include "detail/format.hpp"

namespace fairspline::detail {

FitWatch*& current_watch() {
  thread_local FitWatch* watch = nullptr;
  return watch;
}

namespace {

using Clock = std::chrono::steady_clock;

/// `seconds` after `from`; past ~300 years (or infinite) a duration would overflow the clock's
/// count: never, then.
Clock::time_point after(Clock::time_point from, double seconds) {
  if (!(seconds < 1e10)) return Clock::time_point::max();
  return from + std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double>(std::max(seconds, 0.0)));
}

}  // namespace

FitWatch::FitWatch(const FitOptions& options) {
  if (!options.time_limit && !options.progress) return;
  options_ = &options;
  outer_ = current_watch();
  start_ = Clock::now();
  next_call_ = after(start_, options.progress_interval);
  deadline_ = options.time_limit ? after(start_, *options.time_limit) : Clock::time_point::max();
  current_watch() = this;
}

FitWatch::~FitWatch() {
  if (options_) current_watch() = outer_;
}

void FitWatch::check(std::string_view stage, std::size_t done, std::size_t total) {
  if (stopped_) throw *stopped_;
  const Clock::time_point now = Clock::now();
  const auto during = [&] {
    return stage.empty() ? std::string() : " (" + std::string(stage) + ")";
  };
  if (now >= deadline_) {
    stopped_ =
        Error(ErrorCode::kCancelled, "the fit was stopped at its time limit of " +
                                         format_number(*options_->time_limit) + " s" + during());
    throw *stopped_;
  }
  if (!options_->progress || now < next_call_) return;
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (!options_->progress(FitProgress{stage, done, total, seconds})) {
    stopped_ =
        Error(ErrorCode::kCancelled, "the fit was cancelled by its progress callback" + during());
    throw *stopped_;
  }
  next_call_ = after(Clock::now(), options_->progress_interval);
}

}  // namespace fairspline::detail
