// SPDX-License-Identifier: MIT
// parallelFor (common/parallel.h): every iteration once, on workers below the thread count; the
// caller's tick alone, stopping the loop; an exception rethrown after the threads stopped.
#include "common/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace omnislice {
namespace {

TEST(ParallelFor, EveryIterationOnceOnItsWorkers) {
  for (size_t threads : {1u, 2u, 4u}) {
    std::vector<std::atomic<int>> runs(1000);
    std::vector<size_t> worker(1000);
    const std::thread::id caller = std::this_thread::get_id();
    std::atomic<bool> callerTicksOnly{true};
    const bool ok = parallelFor(
        runs.size(), threads,
        [&](size_t i, size_t w) {
          ++runs[i];
          worker[i] = w;
        },
        [&](size_t done) {
          if (std::this_thread::get_id() != caller) callerTicksOnly = false;
          return done <= runs.size();
        });
    EXPECT_TRUE(ok);
    EXPECT_TRUE(callerTicksOnly);
    for (size_t i = 0; i < runs.size(); ++i) {
      EXPECT_EQ(runs[i].load(), 1) << i;
      EXPECT_LT(worker[i], threads);
    }
  }
  parallelFor(0, 4, [](size_t, size_t) { ADD_FAILURE() << "no iteration"; });
}

TEST(ParallelFor, TickStopsTheLoop) {
  std::atomic<size_t> ran{0};
  // Each iteration takes 1 ms: with instant iterations the other thread could run all of them
  // before the caller's thread takes its first (a loaded CI machine did), and the caller's tick,
  // which runs only after the caller's own iterations, would then never run.
  const bool ok = parallelFor(
      2000, 2,
      [&](size_t, size_t) {
        ++ran;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      },
      [](size_t done) { return done < 10; });
  EXPECT_FALSE(ok);
  EXPECT_LT(ran.load(), size_t(2000));
}

TEST(ParallelFor, ExceptionsReachTheCaller) {
  std::atomic<size_t> ran{0};
  // Every other iteration takes 1 ms, so the loop stops long before its end even when the thread
  // that throws is descheduled for a while (a loaded machine; without the sleep the other threads
  // could finish all 10000 first).
  EXPECT_THROW(parallelFor(2000, 3,
                           [&](size_t i, size_t) {
                             ++ran;
                             if (i == 17) throw std::runtime_error("iteration 17");
                             std::this_thread::sleep_for(std::chrono::milliseconds(1));
                           }),
               std::runtime_error);
  EXPECT_LT(ran.load(), size_t(2000));
}

TEST(ParallelFor, ThreadCount) {
  EXPECT_EQ(threadCount(3), 3u);
  EXPECT_GE(threadCount(0), 1u);
}

}  // namespace
}  // namespace omnislice
