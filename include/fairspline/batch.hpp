// Fitting many independent curves in parallel: the engine behind `fairspline batch` and the
// Python module's fit_many. One curve never depends on another, so the work is split by curve
// over a small pool of threads; results come back in input order.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"

namespace fairspline {

/// One curve of a batch: what to fit and with which method and options.
struct BatchJob {
  FitInput input;
  std::string method;  ///< empty: the default method
  nlohmann::json options = nlohmann::json::object();
};

/// The outcome of one job: exactly one of `result` and `error` is set (neither for a job that
/// BatchOptions::stop skipped).
struct BatchOutcome {
  std::optional<FitResult> result;
  std::optional<Error> error;
};

/// How a batch runs.
struct BatchOptions {
  unsigned threads = 0;  ///< worker threads; 0: std::thread::hardware_concurrency()
  /// Report level, accuracy, best effort: the same for every job.
  FitOptions fit{};
  /// Called with (done, total) as jobs finish (after each small chunk of jobs, and once with
  /// done == total), never concurrently with itself; may be empty. Runs on a worker thread:
  /// keep it short.
  std::function<void(std::size_t done, std::size_t total)> progress;
  /// When set and true, jobs not yet started are skipped (their outcomes stay empty: neither
  /// result nor error) and fit_many returns once the running ones finish: how a caller
  /// interrupts a long batch (Python's Ctrl-C). May be set from any thread.
  const std::atomic<bool>* stop = nullptr;
};

/// The number of threads `requested` resolves to (0: hardware concurrency, at least 1), never
/// more than `work_items` (and at least 1).
unsigned resolve_threads(unsigned requested, std::size_t work_items);

/// Runs work(i) for every i in [0, count) on `threads` threads (resolved as above), handing
/// out indices in small chunks so that uneven items balance. work must not throw; if it does,
/// the first exception is rethrown after all threads have stopped.
void parallel_for(std::size_t count, unsigned threads,
                  const std::function<void(std::size_t)>& work);

/// Threads kept for many rounds of parallel_for-like work: a caller that runs short rounds one
/// after another (`fairspline batch`'s blocks of lines) starts its threads once instead of per
/// round, and their thread_local state (reused results, the JSON writer's memo) stays warm.
/// The thread that calls run() works too; one run() at a time.
class WorkerPool {
 public:
  /// `threads` resolved as resolve_threads(threads, any number of items): 0 is every core.
  explicit WorkerPool(unsigned threads = 0);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// The threads that share a run, the caller's included.
  unsigned threads() const;

  /// parallel_for's contract on this pool's threads: work(i) for every i in [0, count), in small
  /// chunks; the first exception work throws is rethrown once every thread has stopped, and the
  /// pool stays usable.
  void run(std::size_t count, const std::function<void(std::size_t)>& work);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Fits every job (fit() with the job's method and options and options.fit). A job that fails
/// with fairspline::Error gets it in its outcome; the others are unaffected.
std::vector<BatchOutcome> fit_many(std::span<const BatchJob> jobs,
                                   const BatchOptions& options = {});

}  // namespace fairspline
