#include "shaderfit/core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace shaderfit {
namespace {

TEST(ParallelFor, CoversEveryIndexOnce) {
  ThreadPool pool(4);
  for (std::size_t n : {1u, 2u, 7u, 100u, 1000u, 12345u}) {
    for (std::size_t grain : {0u, 1u, 3u, 64u, 5000u}) {
      std::vector<std::atomic<int>> hits(n);
      std::atomic<std::size_t> short_ranges{0};
      pool.parallel_for(n, grain, [&](std::size_t begin, std::size_t end) {
        ASSERT_LT(begin, end);
        if (end - begin < std::max<std::size_t>(grain, 1) && end != n) ++short_ranges;
        for (std::size_t i = begin; i < end; ++i) ++hits[i];
      });
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(hits[i].load(), 1) << n << " " << grain << " " << i;
      EXPECT_EQ(short_ranges.load(), 0u);  // only the last range may be short
    }
  }
}

TEST(ParallelFor, ZeroIndicesCallsNothing) {
  bool called = false;
  parallel_for(0, 1, [&](std::size_t, std::size_t) { called = true; });
  EXPECT_FALSE(called);
}

TEST(ParallelFor, OneThreadRunsOnCaller) {
  ThreadPool pool(4);
  const auto me = std::this_thread::get_id();
  pool.parallel_for(
      100, 1, [&](std::size_t, std::size_t) { EXPECT_EQ(std::this_thread::get_id(), me); }, 1);
}

TEST(ParallelFor, UsesAtMostMaxThreadsAndCanGrow) {
  ThreadPool pool(1);
  EXPECT_EQ(pool.threads(), 1);
  for (int max_threads : {2, 3, 6}) {
    std::mutex m;
    std::set<std::thread::id> ids;
    std::atomic<int> running{0}, peak{0};
    pool.parallel_for(
        600, 1,
        [&](std::size_t, std::size_t) {
          const int now = ++running;
          int p = peak.load();
          while (now > p && !peak.compare_exchange_weak(p, now)) {
          }
          {
            std::lock_guard lock(m);
            ids.insert(std::this_thread::get_id());
          }
          std::this_thread::sleep_for(std::chrono::microseconds(50));
          --running;
        },
        max_threads);
    EXPECT_LE(peak.load(), max_threads);
    EXPECT_LE(static_cast<int>(ids.size()), max_threads);
  }
}

TEST(ParallelFor, RethrowsFirstExceptionAndSkipsTheRest) {
  ThreadPool pool(3);
  std::atomic<int> ran{0};
  // The caller always runs the first range; the others are slow, so that only the few already
  // started when it throws can run.
  EXPECT_THROW(pool.parallel_for(1000, 1,
                                 [&](std::size_t begin, std::size_t) {
                                   ++ran;
                                   if (begin == 0) throw std::runtime_error("boom");
                                   std::this_thread::sleep_for(std::chrono::milliseconds(1));
                                 }),
               std::runtime_error);
  EXPECT_LT(ran.load(), 1000);
  // The pool still works afterwards.
  std::atomic<int> sum{0};
  pool.parallel_for(100, 1, [&](std::size_t b, std::size_t e) { sum += static_cast<int>(e - b); });
  EXPECT_EQ(sum.load(), 100);
}

TEST(ParallelFor, NestedLoopsFinish) {
  ThreadPool pool(2);
  std::atomic<int> total{0};
  pool.parallel_for(8, 1, [&](std::size_t, std::size_t) {
    pool.parallel_for(50, 1,
                      [&](std::size_t b, std::size_t e) { total += static_cast<int>(e - b); });
  });
  EXPECT_EQ(total.load(), 400);
}

TEST(ParallelFor, ConcurrentCallers) {
  ThreadPool pool(3);
  std::atomic<long> total{0};
  std::vector<std::thread> callers;
  callers.reserve(4);
  for (int t = 0; t < 4; ++t)
    callers.emplace_back([&] {
      for (int rep = 0; rep < 20; ++rep)
        pool.parallel_for(1000, 7,
                          [&](std::size_t b, std::size_t e) { total += static_cast<long>(e - b); });
    });
  for (auto& c : callers) c.join();
  EXPECT_EQ(total.load(), 4L * 20 * 1000);
}

TEST(ParallelFor, DefaultPoolHasAThread) { EXPECT_GE(default_thread_pool().threads(), 1); }

}  // namespace
}  // namespace shaderfit
