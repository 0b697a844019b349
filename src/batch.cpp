#include "fairspline/batch.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

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

struct WorkerPool::State {
  unsigned threads = 1;
  std::mutex mutex;
  std::condition_variable start, done;
  std::uint64_t round = 0;  ///< bumped by run(): the workers' signal to start
  bool stop = false;
  unsigned running = 0;  ///< workers not yet finished with this round
  const std::function<void(std::size_t)>* work = nullptr;
  std::size_t count = 0, chunk = 1;
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::vector<std::thread> pool;

  /// Takes chunks of the round until none is left; the first failure stops every thread at
  /// its next chunk.
  void drain() {
    try {
      for (;;) {
        const std::size_t begin = next.fetch_add(chunk, std::memory_order_relaxed);
        if (begin >= count) return;
        const std::size_t end = std::min(count, begin + chunk);
        for (std::size_t i = begin; i < end; ++i) (*work)(i);
      }
    } catch (...) {
      const std::lock_guard lock(mutex);
      if (!failure) failure = std::current_exception();
      next.store(count, std::memory_order_relaxed);
    }
  }

  void serve() {
    std::uint64_t seen = 0;
    std::unique_lock lock(mutex);
    for (;;) {
      start.wait(lock, [&] { return stop || round != seen; });
      if (stop) return;
      seen = round;
      lock.unlock();
      drain();
      lock.lock();
      if (--running == 0) done.notify_one();
    }
  }
};

WorkerPool::WorkerPool(unsigned threads) : state_(std::make_unique<State>()) {
  state_->threads = resolve_threads(threads, std::numeric_limits<std::size_t>::max());
  state_->pool.reserve(state_->threads - 1);
  for (unsigned t = 1; t < state_->threads; ++t) {
    state_->pool.emplace_back([s = state_.get()] { s->serve(); });
  }
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard lock(state_->mutex);
    state_->stop = true;
  }
  state_->start.notify_all();
  for (std::thread& t : state_->pool) t.join();
}

unsigned WorkerPool::threads() const {
  return state_->threads;
}

void WorkerPool::run(std::size_t count, const std::function<void(std::size_t)>& work) {
  State& s = *state_;
  if (s.threads == 1 || count <= 1) {
    for (std::size_t i = 0; i < count; ++i) work(i);
    return;
  }
  {
    const std::lock_guard lock(s.mutex);
    s.work = &work;
    s.count = count;
    s.chunk = chunk_size(count, s.threads);
    s.next.store(0, std::memory_order_relaxed);
    s.failure = nullptr;
    s.running = s.threads - 1;
    ++s.round;
  }
  s.start.notify_all();
  s.drain();
  std::unique_lock lock(s.mutex);
  s.done.wait(lock, [&] { return s.running == 0; });
  if (s.failure) std::rethrow_exception(std::exchange(s.failure, nullptr));
}

void parallel_for(std::size_t count, unsigned threads,
                  const std::function<void(std::size_t)>& work) {
  threads = resolve_threads(threads, count);
  if (threads == 1) {
    for (std::size_t i = 0; i < count; ++i) work(i);
    return;
  }
  WorkerPool(threads).run(count, work);
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
