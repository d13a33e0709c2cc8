// The search's device selection and a whole search on the GPU (GpuDevice.*: skipped with
// "skipped: no CUDA device" where there is none). Beside the search, which may include the GPU
// code; the GPU's own tests are in src/gpu/device_test.cpp.
#include <gtest/gtest.h>

#include <vector>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/gpu/device.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

#define SF_REQUIRE_GPU() \
  if (!cuda_available()) GTEST_SKIP() << "skipped: " << cuda_unavailable_reason()

TEST(GpuSelection, WithoutAGpuTheSearchNeedsAuto) {
  if (cuda_available()) GTEST_SKIP() << "a CUDA device is present";
  const std::vector<double> x = {1, 2, 3}, y = {1, 2, 3};
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs = {x};
  p.target = y;
  SearchOptions o = test::seed_task_options();
  o.device = ComputeDevice::Cuda;
  o.time_limit_s = 0.1;
  SearchSummary s;
  EXPECT_THROW(run_search(o, p, &s), Error);
  o.device = ComputeDevice::Auto;  // falls back to the CPU
  EXPECT_NO_THROW(run_search(o, p, &s));
}

TEST(GpuDevice, SearchOnTheGpu) {
  SF_REQUIRE_GPU();
  const SearchProblem p = test::fresnel_seed_problem();
  // The evolution alone, with a candidate budget (a count): reproducible, GPU scoring included.
  SearchOptions o = test::seed_task_options();
  o.device = ComputeDevice::Cuda;
  o.enumerate = false;
  o.threads = 2;
  o.time_limit_s = 120;
  o.max_candidates = 4000;
  SearchSummary a, b;
  run_search(o, p, &a);
  run_search(o, p, &b);
  ASSERT_FALSE(a.front.empty());
  EXPECT_GT(a.generations, 0u);
  EXPECT_EQ(a.termination, Termination::CandidateLimit);
  ASSERT_EQ(a.front.size(), b.front.size());
  for (std::size_t i = 0; i < a.front.size(); ++i)
    EXPECT_EQ(a.front[i].formula, b.front[i].formula);
  // The whole search on the seed task reaches the seed formula's error at cost 4.
  SearchOptions full = test::seed_task_options();
  full.device = ComputeDevice::Cuda;
  full.time_limit_s = 60;
  full.stop_at = SearchTarget{0.00035236, 4};
  SearchSummary s;
  run_search(full, p, &s);
  EXPECT_EQ(s.termination, Termination::TargetReached);
}

}  // namespace
}  // namespace shaderfit
