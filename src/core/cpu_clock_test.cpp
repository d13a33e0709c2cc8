// process_cpu_seconds counts work, not waiting: what lets the enumeration's share of the time
// budget hold when other processes take the cores.
#include "core/cpu_clock.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace shaderfit {
namespace {

TEST(CpuClock, SleepingDoesNotCount) {
  const double before = process_cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_LT(process_cpu_seconds() - before, 0.05);
}

TEST(CpuClock, WorkCounts) {
  const double before = process_cpu_seconds();
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  volatile double sink = 0;
  while (process_cpu_seconds() - before < 0.03 && std::chrono::steady_clock::now() < give_up)
    for (int i = 0; i < 10000; ++i) sink = sink + 1e-9 * i;
  EXPECT_GE(process_cpu_seconds() - before, 0.03);
}

}  // namespace
}  // namespace shaderfit
