// FitOptions::time_limit and FitOptions::progress (src/detail/progress.cpp): a long fit reports
// where it is, stops at its time limit or when the callback says so, and is otherwise the same
// fit bit for bit.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "detail/progress.hpp"
#include "fairspline/batch.hpp"
#include "fairspline/error.hpp"
#include "fairspline/registry.hpp"
#include "test_util.hpp"

namespace fairspline {
namespace {

FitInput walk(std::size_t n, std::uint64_t seed, double turn_deg = 150) {
  FitInput in;
  in.points = testing::random_walk(n, seed, turn_deg);
  return in;
}

struct Call {
  std::string stage;
  std::size_t done, total;
  double seconds;
};

/// FitOptions whose progress records every call (interval 0: at every checkpoint) and returns
/// false from call `stop_at` on (0: never).
FitOptions recording(std::vector<Call>& calls, std::size_t stop_at = 0) {
  FitOptions o;
  o.progress_interval = 0.0;
  o.progress = [&calls, stop_at](const FitProgress& p) {
    calls.push_back({std::string(p.stage), p.done, p.total, p.seconds});
    return stop_at == 0 || calls.size() < stop_at;
  };
  return o;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(FitProgress, ATimeLimitStopsALongFitWithCancelled) {
  // The elastic spline's grid search over 1000 sharp points takes about ten seconds.
  const FitInput in = walk(1000, 5);
  FitOptions o;
  o.time_limit = 0.2;
  const auto t0 = std::chrono::steady_clock::now();
  const Error e = testing::expect_error(ErrorCode::kCancelled,
                                        [&] {
                                          fit("elastic", in, {{"search", "global"}}, o);
                                        },
                                        {"the fit was stopped at its time limit of 0.2 s ("});
  EXPECT_LT(seconds_since(t0), 5.0);  // within a step of the limit, not at the fit's end
  EXPECT_FALSE(e.index());
  EXPECT_EQ(detail::current_watch(), nullptr);
}

TEST(FitProgress, TheCallbackSeesEveryStageAndFalseCancels) {
  const FitInput in = walk(60, 3);
  std::vector<Call> calls;
  const Error e = testing::expect_error(
      ErrorCode::kCancelled,
      [&] {
        fit("quasi-elastic", in, {{"search", "coordinate"}}, recording(calls, 40));
      },
      {"the fit was cancelled by its progress callback (coordinate search)"});
  // Not called again once it said stop, though the solvers go on to their next steps.
  ASSERT_EQ(calls.size(), 40u);
  for (std::size_t i = 0; i < calls.size(); ++i) {
    if (calls[i].total > 0) {
      EXPECT_LT(calls[i].done, calls[i].total);
    }
    if (i > 0) {
      EXPECT_GE(calls[i].seconds, calls[i - 1].seconds);
    }
  }
  EXPECT_EQ(calls.back().stage, "coordinate search");
}

TEST(FitProgress, EachIterativeFamilyReportsItsStages) {
  const auto stages = [](const char* method, const FitInput& in, const nlohmann::json& options) {
    std::vector<Call> calls;
    fit(method, in, options, recording(calls));
    std::set<std::string> out;
    for (const Call& c : calls) out.insert(c.stage);
    return out;
  };
  const FitInput in = walk(30, 2, 120);
  EXPECT_EQ(stages("quasi-elastic", in, {}), (std::set<std::string>{"newton", "report"}));
  EXPECT_EQ(stages("elastic", in, {{"search", "global"}}),
            (std::set<std::string>{"global search", "newton", "report"}));
  FitInput balls = in;
  balls.radii.assign(in.points.size(), 0.2);
  EXPECT_TRUE(stages("quasi-elastic", balls, {}).contains("data balls"));
  FitInput ellipse;
  const auto E = testing::ellipse(12, 3, 1);
  ellipse.points.assign(E.begin(), E.begin() + 10);
  EXPECT_TRUE(
      stages("kozak-krajnc", ellipse, {{"tangents", "local-quadratic-uniform"}, {"g2", true}})
          .contains("g2"));
  // A closed-form method has no steps: only the report's checkpoint.
  EXPECT_EQ(stages("jaklic-zagar", in, {}), (std::set<std::string>{"report"}));
}

TEST(FitProgress, AStopInsideSolversThatCatchErrorsStillEndsCancelled) {
  // Kozak–Krajnc's G2 stage tries further starts when one throws; the stop must not turn into
  // "no G2 spline" or into the G1 curve.
  FitInput ellipse;
  const auto E = testing::ellipse(12, 3, 1);
  ellipse.points.assign(E.begin(), E.begin() + 10);
  std::vector<Call> calls;
  FitOptions o = recording(calls, 1);
  o.best_effort = true;
  testing::expect_error(ErrorCode::kCancelled, [&] {
    fit("kozak-krajnc", ellipse, {{"tangents", "local-quadratic-uniform"}, {"g2", true}}, o);
  });
  EXPECT_EQ(calls.size(), 1u);
}

TEST(FitProgress, AWatchedFitIsTheSameFit) {
  for (const char* method : {"quasi-elastic", "elastic", "cond-g2"}) {
    SCOPED_TRACE(method);
    const FitInput in = walk(40, 11, 120);
    const FitResult plain = fit(method, in);
    std::vector<Call> calls;
    FitOptions o = recording(calls);
    o.time_limit = 1e6;
    const FitResult watched = fit(method, in, {}, o);
    EXPECT_FALSE(calls.empty());
    ASSERT_EQ(plain.spline.segments.size(), watched.spline.segments.size());
    for (std::size_t i = 0; i < plain.spline.segments.size(); ++i) {
      for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(plain.spline.segments[i].bezier.p[k], watched.spline.segments[i].bezier.p[k]);
      }
    }
    EXPECT_EQ(plain.method_report, watched.method_report);
  }
}

TEST(FitProgress, BadLimitsAreBadOptions) {
  const FitInput in = walk(5, 1);
  for (double limit : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    testing::expect_error(ErrorCode::kBadOption,
                          [&] { fit("quasi-elastic", in, {}, {.time_limit = limit}); },
                          {"the time limit must be a positive number of seconds"});
  }
  FitOptions o;
  o.progress_interval = -1.0;
  testing::expect_error(ErrorCode::kBadOption, [&] { fit("quasi-elastic", in, {}, o); },
                        {"the progress interval must be a number of seconds"});
}

TEST(FitProgress, AnInfiniteIntervalOrLimitMeansNever) {
  // Durations past the clock's range are "never", not an overflow.
  const FitInput in = walk(60, 3);
  std::vector<Call> calls;
  FitOptions o = recording(calls);
  o.progress_interval = std::numeric_limits<double>::infinity();
  o.time_limit = std::numeric_limits<double>::infinity();
  const FitResult r = fit("quasi-elastic", in, {{"search", "coordinate"}}, o);
  EXPECT_TRUE(calls.empty());
  EXPECT_EQ(r.spline.segments.size(), 59u);
  o.progress_interval = 1e300;
  o.time_limit = 1e300;
  EXPECT_NO_THROW(fit("quasi-elastic", in, {}, o));
}

TEST(FitProgress, AnExceptionFromTheCallbackReachesTheCallerAndNothingStaysInstalled) {
  const FitInput in = walk(60, 3);
  FitOptions o;
  o.progress_interval = 0.0;
  o.progress = [](const FitProgress&) -> bool { throw std::runtime_error("from the callback"); };
  EXPECT_THROW(fit("quasi-elastic", in, {}, o), std::runtime_error);
  EXPECT_EQ(detail::current_watch(), nullptr);
  // The next fit on this thread runs unwatched.
  EXPECT_NO_THROW(fit("quasi-elastic", in));
  detail::checkpoint("nothing", 0);  // no watch: no effect
}

TEST(FitProgress, ABatchStopsOnlyTheJobsPastTheirLimit) {
  std::vector<BatchJob> jobs(3);
  jobs[0].input = walk(10, 1, 90);
  jobs[1].input = walk(1000, 5);
  jobs[1].method = "elastic";
  jobs[1].options = {{"search", "global"}};
  jobs[2].input = walk(12, 2, 90);
  BatchOptions b;
  b.threads = 2;
  b.fit.time_limit = 0.3;
  const std::vector<BatchOutcome> out = fit_many(jobs, b);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_TRUE(out[0].result);
  ASSERT_TRUE(out[1].error);
  EXPECT_EQ(out[1].error->code(), ErrorCode::kCancelled);
  EXPECT_TRUE(out[2].result);
}

}  // namespace
}  // namespace fairspline
