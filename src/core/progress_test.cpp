#include "shaderfit/core/progress.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "shaderfit/core/parallel.hpp"

namespace shaderfit {
namespace {

TEST(ProgressCounter, ReportsEachCountInOrderOnOneThread) {
  std::vector<std::size_t> seen;
  const ProgressCallback cb = [&](const Progress& p) {
    EXPECT_EQ(p.total, 5u);
    EXPECT_EQ(p.unit, "cells");
    seen.push_back(p.done);
  };
  ProgressCounter c(cb, 5, "cells");
  c.add();
  c.add(3);
  c.add();
  c.add();  // past the total: reported as the total
  EXPECT_EQ(seen, (std::vector<std::size_t>{1, 4, 5, 5}));
}

TEST(ProgressCounter, FromManyThreadsOneCallAtATime) {
  std::size_t calls = 0, largest = 0;
  bool inside = false;
  const ProgressCallback cb = [&](const Progress& p) {
    EXPECT_FALSE(inside);  // never two calls at once
    inside = true;
    ++calls;
    largest = std::max(largest, p.done);
    EXPECT_LE(p.done, p.total);
    inside = false;
  };
  ProgressCounter c(cb, 10000, "blocks");
  parallel_for(10000, 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) c.add();
  });
  EXPECT_GT(calls, 0u);
  EXPECT_LE(largest, 10000u);
  // Without a callback it only counts.
  const ProgressCallback none;
  ProgressCounter quiet(none, 3, "cells");
  quiet.add(3);
}

}  // namespace
}  // namespace shaderfit
