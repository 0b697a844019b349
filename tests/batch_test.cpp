#include "fairspline/batch.hpp"

#include <atomic>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

TEST(Batch, ResolveThreads) {
  EXPECT_EQ(resolve_threads(3, 100), 3u);
  EXPECT_EQ(resolve_threads(8, 2), 2u);
  EXPECT_EQ(resolve_threads(4, 0), 1u);
  EXPECT_GE(resolve_threads(0, 1000), 1u);
}

TEST(Batch, StopSkipsTheJobsNotYetStarted) {
  std::vector<BatchJob> jobs(200);
  for (BatchJob& j : jobs) j.input.points = {{0, 0}, {1, 2}, {3, 3}, {5, 2}};
  std::atomic<bool> stop{true};
  BatchOptions o;
  o.threads = 1;
  o.stop = &stop;
  for (const BatchOutcome& out : fit_many(jobs, o)) {
    EXPECT_FALSE(out.result || out.error) << "stopped before it began";
  }
  // Stopped from the progress callback after the first chunk: those jobs are done, the rest
  // skipped, and every outcome is one or the other.
  stop = false;
  std::size_t stopped_at = 0;
  o.progress = [&](std::size_t done, std::size_t) {
    if (stopped_at == 0) stopped_at = done;
    stop = true;
  };
  const std::vector<BatchOutcome> outs = fit_many(jobs, o);
  std::size_t fitted = 0;
  for (std::size_t i = 0; i < outs.size(); ++i) {
    EXPECT_FALSE(outs[i].error) << i;
    if (outs[i].result) ++fitted;
  }
  EXPECT_GT(stopped_at, 0u);
  EXPECT_EQ(fitted, stopped_at);
  EXPECT_LT(fitted, jobs.size());
}

TEST(Batch, ParallelForVisitsEveryIndexOnce) {
  for (unsigned threads : {1u, 2u, 5u}) {
    std::vector<std::atomic<int>> seen(10007);
    parallel_for(seen.size(), threads, [&](std::size_t i) { seen[i].fetch_add(1); });
    for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << i;
  }
}

TEST(Batch, ParallelForWithNoItemsOrMoreThreadsThanItems) {
  int calls = 0;
  parallel_for(0, 4, [&](std::size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
  std::vector<std::atomic<int>> seen(3);
  parallel_for(seen.size(), 8, [&](std::size_t i) { seen[i].fetch_add(1); });
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i].load(), 1) << i;
  EXPECT_TRUE(fit_many({}, {}).empty());
}

TEST(Batch, ParallelForRethrowsTheFirstFailure) {
  EXPECT_THROW(parallel_for(1000, 2,
                            [](std::size_t i) {
                              if (i == 500) throw std::runtime_error("boom");
                            }),
               std::runtime_error);
}

// Counts the threads that ever ran work of the pool tests below (one per thread's first item).
std::atomic<int> pool_threads_started{0};
struct CountThread {
  CountThread() { pool_threads_started.fetch_add(1); }
};

TEST(Batch, WorkerPoolKeepsItsThreadsFromRoundToRound) {
  WorkerPool pool(2);
  ASSERT_EQ(pool.threads(), 2u);
  const int before = pool_threads_started.load();
  std::atomic<int> items_on_workers{0};
  const std::thread::id caller = std::this_thread::get_id();
  for (int round = 0; round < 50; ++round) {
    std::vector<std::atomic<int>> seen(1000 + static_cast<std::size_t>(round));
    pool.run(seen.size(), [&](std::size_t i) {
      thread_local CountThread counted;
      if (std::this_thread::get_id() != caller) {
        items_on_workers.fetch_add(1);
      } else if (round == 0) {  // the caller waits (at most 10 s) until the worker has an item
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (items_on_workers.load() == 0 && std::chrono::steady_clock::now() < until) {
          std::this_thread::yield();
        }
      }
      seen[i].fetch_add(1);
    });
    for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << round << " " << i;
  }
  // parallel_for would have started a thread per round: 51 thread_local objects, not 2.
  EXPECT_LE(pool_threads_started.load() - before, 2);
  EXPECT_GT(items_on_workers.load(), 0);  // the worker did take part
}

TEST(Batch, WorkerPoolRethrowsAndStaysUsable) {
  WorkerPool pool(3);
  EXPECT_EQ(pool.threads(), 3u);
  EXPECT_GE(WorkerPool(0).threads(), 1u);
  EXPECT_THROW(pool.run(1000,
                        [](std::size_t i) {
                          if (i % 100 == 7) throw std::runtime_error("boom");
                        }),
               std::runtime_error);
  std::vector<std::atomic<int>> seen(777);
  pool.run(seen.size(), [&](std::size_t i) { seen[i].fetch_add(1); });
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << i;
  int calls = 0;
  pool.run(0, [&](std::size_t) { ++calls; });
  pool.run(1, [&](std::size_t) { ++calls; });
  EXPECT_EQ(calls, 1);
}

TEST(Batch, FitManyEqualsFitOneByOneInInputOrder) {
  std::vector<BatchJob> jobs;
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    BatchJob job;
    job.input.points = testing::random_walk(5 + seed % 7, seed, 60);
    job.method = seed % 3 == 0 ? "jaklic-zagar" : (seed % 3 == 1 ? "" : "li-strain");
    jobs.push_back(job);
  }
  // One bad job in the middle: a NaN coordinate.
  jobs[17].input.points[2].x = std::numeric_limits<double>::quiet_NaN();
  std::size_t last_done = 0, calls = 0;
  BatchOptions options;
  options.threads = 2;
  options.fit.level = ReportLevel::kBasic;
  options.progress = [&](std::size_t done, std::size_t total) {
    EXPECT_GT(done, last_done);
    EXPECT_EQ(total, jobs.size());
    last_done = done;
    ++calls;
  };
  const std::vector<BatchOutcome> out = fit_many(jobs, options);
  ASSERT_EQ(out.size(), jobs.size());
  EXPECT_EQ(last_done, jobs.size());
  EXPECT_GE(calls, 1u);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    if (i == 17) {
      ASSERT_TRUE(out[i].error);
      EXPECT_FALSE(out[i].result);
      EXPECT_EQ(out[i].error->code(), ErrorCode::kNonFinite);
      EXPECT_EQ(out[i].error->index(), 2u);
      continue;
    }
    ASSERT_TRUE(out[i].result) << i;
    const std::string method =
        jobs[i].method.empty() ? std::string(default_method_name()) : jobs[i].method;
    const FitResult one = fit(method, jobs[i].input, jobs[i].options, ReportLevel::kBasic);
    EXPECT_EQ(out[i].result->method, one.method);
    // Every field, doubles bit for bit: the JSON text of the two is the same.
    EXPECT_EQ(io::write_json(*out[i].result), io::write_json(one)) << i;
    ASSERT_EQ(out[i].result->spline.segments.size(), one.spline.segments.size());
    for (std::size_t s = 0; s < one.spline.segments.size(); ++s) {
      for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(out[i].result->spline.segments[s].bezier.p[k].x,
                  one.spline.segments[s].bezier.p[k].x);
        EXPECT_EQ(out[i].result->spline.segments[s].bezier.p[k].y,
                  one.spline.segments[s].bezier.p[k].y);
      }
    }
  }
}

TEST(Batch, FitManyGivesTheSameResultsForAnyThreadCount) {
  std::vector<BatchJob> jobs;
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    BatchJob job;
    job.input.points = testing::random_walk(3 + seed % 40, seed + 1000, 100);
    job.input.closed = seed % 5 == 0;
    job.method = seed % 2 == 0 ? "jaklic-zagar" : "quasi-elastic";
    if (seed % 50 == 7) job.input.points[1] = job.input.points[0];  // repeated point
    jobs.push_back(job);
  }
  BatchOptions options;
  options.fit.level = ReportLevel::kBasic;
  options.threads = 1;
  const std::vector<BatchOutcome> one = fit_many(jobs, options);
  for (unsigned threads : {2u, 3u, 0u}) {
    options.threads = threads;
    const std::vector<BatchOutcome> other = fit_many(jobs, options);
    ASSERT_EQ(other.size(), one.size());
    for (std::size_t i = 0; i < one.size(); ++i) {
      ASSERT_EQ(other[i].error.has_value(), one[i].error.has_value()) << threads << " " << i;
      if (one[i].error) {
        EXPECT_EQ(other[i].error->code(), ErrorCode::kRepeatedPoint);
        EXPECT_EQ(other[i].error->index(), one[i].error->index());
        continue;
      }
      const FitResult& a = *one[i].result;
      const FitResult& b = *other[i].result;
      ASSERT_EQ(b.spline.segments.size(), a.spline.segments.size()) << i;
      for (std::size_t s = 0; s < a.spline.segments.size(); ++s) {
        for (int k = 0; k < 4; ++k) {
          EXPECT_EQ(b.spline.segments[s].bezier.p[k].x, a.spline.segments[s].bezier.p[k].x);
          EXPECT_EQ(b.spline.segments[s].bezier.p[k].y, a.spline.segments[s].bezier.p[k].y);
        }
      }
      ASSERT_TRUE(a.report && b.report);
      EXPECT_EQ(b.report->linearized_energy, a.report->linearized_energy) << i;
      EXPECT_EQ(b.method_report, a.method_report) << i;
      EXPECT_EQ(io::write_json(b), io::write_json(a)) << i;  // every field, bit for bit
    }
  }
  std::size_t failed = 0;
  for (const BatchOutcome& o : one) failed += o.error.has_value();
  EXPECT_EQ(failed, 6u);
}

TEST(Batch, AnEmptyBatchReportsItsProgressOnce) {
  std::vector<std::pair<std::size_t, std::size_t>> calls;
  BatchOptions options;
  options.progress = [&](std::size_t done, std::size_t total) { calls.emplace_back(done, total); };
  EXPECT_TRUE(fit_many({}, options).empty());
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_EQ(calls[0], std::make_pair(std::size_t{0}, std::size_t{0}));
}

}  // namespace
}  // namespace fairspline
