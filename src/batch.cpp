#include "fairspline/batch.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

#include "fairspline/registry.hpp"

namespace fairspline {

namespace {

/// Indices handed to a thread at a time: small enough to balance uneven items, large enough
/// that the shared counter is not contended.
std::size_t chunk_size(std::size_t count, unsigned threads) {
  return std::clamp<std::size_t>(count / (std::size_t{threads} * 64), 1, 256);
}

}  // namespace

unsigned resolve_threads(unsigned requested, std::size_t work_items) {
  unsigned threads = requested != 0 ? requested : std::thread::hardware_concurrency();
  threads = std::max(threads, 1u);
  if (work_items < threads) threads = static_cast<unsigned>(std::max<std::size_t>(work_items, 1));
  return threads;
}

void parallel_for(std::size_t count, unsigned threads,
                  const std::function<void(std::size_t)>& work) {
  threads = resolve_threads(threads, count);
  if (threads == 1) {
    for (std::size_t i = 0; i < count; ++i) work(i);
    return;
  }
  const std::size_t chunk = chunk_size(count, threads);
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&] {
    try {
      for (;;) {
        const std::size_t begin = next.fetch_add(chunk, std::memory_order_relaxed);
        if (begin >= count) return;
        const std::size_t end = std::min(count, begin + chunk);
        for (std::size_t i = begin; i < end; ++i) work(i);
      }
    } catch (...) {
      const std::lock_guard lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next.store(count, std::memory_order_relaxed);  // the others stop at their next chunk
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

std::vector<BatchOutcome> fit_many(std::span<const BatchJob> jobs, const BatchOptions& options) {
  std::vector<BatchOutcome> outcomes(jobs.size());
  std::mutex progress_mutex;
  std::size_t done = 0;
  const std::size_t report_every = std::max<std::size_t>(
      1, chunk_size(jobs.size(), resolve_threads(options.threads, jobs.size())));
  std::atomic<std::size_t> finished{0};
  parallel_for(jobs.size(), options.threads, [&](std::size_t i) {
    const BatchJob& job = jobs[i];
    BatchOutcome& out = outcomes[i];
    if (options.stop && options.stop->load(std::memory_order_relaxed)) return;
    try {
      const std::string_view method =
          job.method.empty() ? default_method_name() : std::string_view(job.method);
      out.result = fit(method, job.input, job.options, options.fit);
    } catch (const Error& e) {
      out.error = e;
    } catch (const std::exception& e) {
      // Not a user error (e.g. out of memory): still reported per job, never lost.
      out.error =
          Error(ErrorCode::kInvalidArgument, std::string("unexpected failure: ") + e.what());
    }
    if (!options.progress) return;
    const std::size_t n = finished.fetch_add(1, std::memory_order_relaxed) + 1;
    if (n % report_every != 0 && n != jobs.size()) return;
    const std::lock_guard lock(progress_mutex);
    if (n > done) {
      done = n;
      options.progress(done, jobs.size());
    }
  });
  // An empty batch is finished at once: report it, as the contract says (done == total).
  if (jobs.empty() && options.progress) options.progress(0, 0);
  return outcomes;
}

}  // namespace fairspline
