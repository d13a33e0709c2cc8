// Benchmarks of the search (docs/search.md quotes their results).
//
//   build/bench/search_bench --benchmark_counters_tabular=true
//
// TimeToTarget: the seed task (fresnel-seed data, inputs r0 and x, target R, default options):
//   the search's own clock when the front first holds a formula with MSE <= that of
//   r0 + (x - r0) * x^4 and cost <= 4. Ten repetitions, each with the next search seed (1..10);
//   the /vary_data variant also draws the data with that seed. Median, mean, min, max and
//   standard deviation over the ten.
// Throughput: candidates and node evaluations per second during a search, for each strategy.
// ProcessStart and DataLoading: what the search's clock leaves out, measured on their own.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "seed_task.hpp"
#include "shaderfit/data/csv.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/search/search.hpp"

namespace {

using namespace shaderfit;

std::string g_cli;  // the shaderfit executable, next to bench/

using bench::seed_problem;

const SearchProblem& cached_problem(std::uint64_t data_seed) {
  static std::map<std::uint64_t, SearchProblem> cache;
  auto it = cache.find(data_seed);
  if (it == cache.end()) it = cache.emplace(data_seed, seed_problem(data_seed)).first;
  return it->second;
}

void BM_TimeToTarget(benchmark::State& state) {
  const bool vary_data = state.range(0) != 0;
  const int threads = static_cast<int>(state.range(1));
  static std::map<std::pair<bool, int>, int> repetition;
  for (auto _ : state) {
    const int rep = repetition[{vary_data, threads}]++;
    const std::uint64_t seed = static_cast<std::uint64_t>(rep % 10) + 1;
    const SearchProblem& p = cached_problem(vary_data ? seed : 1);
    SearchOptions o = test::seed_task_options();
    o.seed = seed;
    o.threads = threads;
    SearchSummary s;
    const double found = bench::time_to_target(o, p, &s);
    if (found < 0) {
      state.SkipWithError("target not reached");
      break;
    }
    state.SetIterationTime(found);
    state.counters["candidates"] = static_cast<double>(s.candidates);
    state.counters["classes"] = static_cast<double>(s.distinct_candidates);
  }
}

void BM_Throughput(benchmark::State& state) {
  const bool enumerate = state.range(0) == 0;
  const int threads = static_cast<int>(state.range(1));
  const SearchProblem& p = cached_problem(1);
  for (auto _ : state) {
    SearchOptions o = test::seed_task_options();
    o.threads = threads;
    o.enumerate = enumerate;
    o.evolve = !enumerate;
    o.time_limit_s = enumerate ? 1.0 : 3.0;
    SearchSummary s;
    run_search(o, p, &s);
    state.SetIterationTime(s.total_time_s);
    state.counters["candidates_per_s"] = static_cast<double>(s.candidates) / s.total_time_s;
    state.counters["node_evals_per_s"] = static_cast<double>(s.node_evaluations) / s.total_time_s;
  }
}

void BM_DataLoading(benchmark::State& state) {
  const std::string csv =
      (std::filesystem::temp_directory_path() / "shaderfit_bench_seed.csv").string();
  {
    Rng rng(1);
    write_csv(make_fresnel_seed_dataset(rng), csv);
  }
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    if (state.range(0) == 0) {
      Rng rng(1);
      benchmark::DoNotOptimize(make_fresnel_seed_dataset(rng));
    } else {
      benchmark::DoNotOptimize(read_csv(csv));
    }
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
}

void BM_ProcessStart(benchmark::State& state) {
  if (g_cli.empty() || !std::filesystem::exists(g_cli)) {
    state.SkipWithError("shaderfit executable not found next to bench/");
    return;
  }
  const std::string cmd = g_cli + " --version > /dev/null";
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    if (std::system(cmd.c_str()) != 0) {
      state.SkipWithError("shaderfit --version failed");
      break;
    }
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
}

double stat_min(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
double stat_max(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

BENCHMARK(BM_TimeToTarget)
    ->ArgNames({"vary_data", "threads"})
    ->Args({0, 2})
    ->Args({0, 1})
    ->Args({1, 2})
    ->Iterations(1)
    ->Repetitions(10)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", stat_min)
    ->ComputeStatistics("max", stat_max);
BENCHMARK(BM_Throughput)
    ->ArgNames({"evolve", "threads"})
    ->Args({0, 2})
    ->Args({0, 1})
    ->Args({1, 2})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DataLoading)
    ->ArgName("csv")
    ->Arg(0)
    ->Arg(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ProcessStart)->Iterations(10)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  g_cli = (std::filesystem::path(argv[0]).parent_path().parent_path() / "shaderfit").string();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
