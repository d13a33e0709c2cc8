// GPU against CPU, in one run (docs/gpu.md quotes the results). Built when the CUDA target is;
// without a usable GPU the GPU benchmarks stop with "skipped: no CUDA device" and the CPU ones
// still run.
//
//   build/release/bench/gpu_bench --benchmark_counters_tabular=true
//
// Population/<device>/rows:R: a population of 10,000 random formulas of 10 to 30 nodes (every
//   operator) over R rows (4,096 and 1,000,000), each formula's MSE against a target.
//   gpu: GpuEvaluator::evaluate_population, one call for the whole population (packing,
//   program upload, kernels and the download of the sums included; the data is uploaded once,
//   before). cpu: evaluate() (Highway) per formula, float32, formulas spread over all cores,
//   then the float64 MSE; at 1,000,000 rows on the first 400 formulas only (the rate is per
//   node, so it does not depend on how many). Counter node_evals_per_s = nodes x rows / s.
// EnumerationStep/<device>: the enumeration's column step (operator, key, screen loss) on 64
//   screen rows, candidates per second: GpuScreen::screen on 1,000,000 candidates per launch;
//   cpu: search_detail::compute_column + analyze_column on one core (the enumerator's kernels).
// TimeToTarget/device:D: the seed task as in bench/search_bench.cpp (search seeds 1..10, all
//   cores): when the front first holds MSE <= that of r0 + (x - r0) * x^4 at cost <= 4, with
//   --device cpu and cuda.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gpu/pack.hpp"
#include "gpu/population_test_util.hpp"
#include "gpu/screen.hpp"
#include "search/enumeration/enum_kernels.hpp"
#include "seed_task.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/gpu/device.hpp"
#include "shaderfit/gpu/evaluator.hpp"
#include "shaderfit/search/search.hpp"

namespace {

using namespace shaderfit;

constexpr std::size_t kPopulation = 10'000;
constexpr std::size_t kCpuRowBudget = 400'000'000;  // formulas x rows per CPU iteration

bool skip_without_gpu(benchmark::State& state) {
  if (cuda_available()) return false;
  state.SkipWithError(("skipped: " + cuda_unavailable_reason()).c_str());
  return true;
}

struct PopulationData {
  gpu_test::RandomColumns inputs;
  std::vector<double> target;
  std::vector<Expression> population;
  std::vector<const Expression*> pointers;
  std::size_t nodes = 0;  // of the whole population

  explicit PopulationData(std::size_t rows, Rng rng = Rng(7))
      : inputs(rng, 3, rows, 0.05, 2.0), target(rows) {
    for (double& t : target) t = uniform(rng, 0.0, 1.0);
    population = gpu_test::random_population(rng, kPopulation, {"a", "b", "c"}, 10, 30,
                                             gpu_test::OpSet::All);
    for (const Expression& e : population) {
      pointers.push_back(&e);
      nodes += e.size();
    }
  }
};

const PopulationData& population_data(std::size_t rows) {
  static std::map<std::size_t, std::unique_ptr<PopulationData>> cache;
  auto& p = cache[rows];
  if (!p) p = std::make_unique<PopulationData>(rows);
  return *p;
}

void set_rate(benchmark::State& state, double node_evals) {
  state.counters["node_evals_per_s"] =
      benchmark::Counter(node_evals, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_PopulationGpu(benchmark::State& state) {
  if (skip_without_gpu(state)) return;
  const auto rows = static_cast<std::size_t>(state.range(0));
  const PopulationData& d = population_data(rows);
  const GpuEvaluator gpu(d.inputs.pointers, d.target);
  (void)gpu.evaluate_population(std::span(d.pointers).first(16), Loss::Mse);  // warm-up
  double checksum = 0;
  for (auto _ : state) {
    const std::vector<PopulationScore> s = gpu.evaluate_population(d.pointers, Loss::Mse);
    checksum += s[0].loss;
  }
  benchmark::DoNotOptimize(checksum);
  // Packing alone, for scale: the host's share of each call.
  const auto t0 = std::chrono::steady_clock::now();
  benchmark::DoNotOptimize(gpu_detail::pack_programs(d.pointers, 3));
  state.counters["host_pack_ms"] =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  state.counters["formulas"] = static_cast<double>(d.pointers.size());
  set_rate(state, static_cast<double>(d.nodes) * static_cast<double>(rows));
  state.SetLabel(cuda_device_name());
}

void BM_PopulationCpu(benchmark::State& state) {
  const auto rows = static_cast<std::size_t>(state.range(0));
  const PopulationData& d = population_data(rows);
  const std::size_t count = std::min(kPopulation, std::max<std::size_t>(1, kCpuRowBudget / rows));
  std::vector<std::vector<float>> columns;
  std::vector<const float*> pointers;
  for (const auto& c : d.inputs.values) columns.emplace_back(c.begin(), c.end());
  for (const auto& c : columns) pointers.push_back(c.data());
  std::size_t nodes = 0;
  for (std::size_t i = 0; i < count; ++i) nodes += d.population[i].size();
  std::vector<double> loss(count);
  for (auto _ : state) {
    parallel_for(count, 1, [&](std::size_t begin, std::size_t end) {
      thread_local std::vector<float> out;
      out.resize(rows);
      for (std::size_t i = begin; i < end; ++i) {
        evaluate(d.population[i], pointers, out, {.threads = 1});
        double se = 0;
        for (std::size_t r = 0; r < rows; ++r) {
          const double e = static_cast<double>(out[r]) - d.target[r];
          se += e * e;
        }
        loss[i] = se / static_cast<double>(rows);
      }
    });
    benchmark::DoNotOptimize(loss.data());
  }
  state.counters["formulas"] = static_cast<double>(count);
  state.counters["threads"] = default_thread_pool().threads();
  set_rate(state, static_cast<double>(nodes) * static_cast<double>(rows));
}

// The enumeration step on 64 screen rows: a store of columns and random operand pairs.
struct ScreenData {
  static constexpr std::size_t kRows = 64, kColumns = 2000, kCandidates = 1'000'000;
  std::vector<float> store, y, w;
  std::vector<gpu_detail::ColumnCandidate> candidates;
  double wyy = 0;
  ScreenData() : y(kRows), w(kRows, 1.0f / kRows) {
    Rng rng(9);
    for (std::size_t i = 0; i < kColumns * kRows; ++i)
      store.push_back(static_cast<float>(uniform(rng, 0.05, 1.0)));
    for (std::size_t i = 0; i < kRows; ++i) {
      y[i] = static_cast<float>(uniform(rng, 0.0, 1.0));
      wyy += static_cast<double>(w[i]) * y[i] * y[i];
    }
    const gpu_detail::ColumnOp kinds[] = {gpu_detail::ColumnOp::AddSub, gpu_detail::ColumnOp::Mul,
                                          gpu_detail::ColumnOp::Div, gpu_detail::ColumnOp::IPow};
    for (std::size_t i = 0; i < kCandidates; ++i) {
      gpu_detail::ColumnCandidate c;
      c.a = static_cast<std::uint32_t>(uniform_index(rng, kColumns));
      c.b = static_cast<std::uint32_t>(uniform_index(rng, kColumns));
      c.kind = kinds[uniform_index(rng, 4)];
      c.k = static_cast<std::int8_t>(2 + uniform_index(rng, 4));
      c.flags = static_cast<std::uint8_t>(uniform_index(rng, 4));
      candidates.push_back(c);
    }
  }
};

const ScreenData& screen_data() {
  static const ScreenData d;
  return d;
}

void BM_EnumerationStepGpu(benchmark::State& state) {
  if (skip_without_gpu(state)) return;
  const ScreenData& d = screen_data();
  gpu_detail::GpuScreen gpu(d.y, d.w, {}, d.wyy, Loss::Mse);
  gpu.add_columns(d.store);
  for (auto _ : state) benchmark::DoNotOptimize(gpu.screen(d.candidates));
  state.counters["candidates_per_s"] = benchmark::Counter(
      static_cast<double>(d.candidates.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(cuda_device_name());
}

void BM_EnumerationStepCpu(benchmark::State& state) {
  using namespace search_detail;
  const ScreenData& d = screen_data();
  const std::size_t n = ScreenData::kRows, count = 100'000;
  const ScreenTarget target{d.y.data(), d.w.data(), nullptr, d.wyy, Loss::Mse, n};
  std::vector<float> column(n);
  for (auto _ : state) {
    for (std::size_t i = 0; i < count; ++i) {
      const gpu_detail::ColumnCandidate& c = d.candidates[i];
      const EKind kind = c.kind == gpu_detail::ColumnOp::AddSub ? EKind::AddSub
                         : c.kind == gpu_detail::ColumnOp::Mul  ? EKind::Mul
                         : c.kind == gpu_detail::ColumnOp::Div  ? EKind::Div
                                                                : EKind::IPow;
      compute_column(kind, Op::Neg, c.k, d.store.data() + c.a * n, d.store.data() + c.b * n, false,
                     (c.flags & 2) != 0, column.data(), n);
      benchmark::DoNotOptimize(analyze_column(column.data(), target));
    }
  }
  state.counters["candidates_per_s"] =
      benchmark::Counter(static_cast<double>(count), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_TimeToTarget(benchmark::State& state) {
  const bool gpu = state.range(0) != 0;
  if (gpu && skip_without_gpu(state)) return;
  static const SearchProblem p = bench::seed_problem(1);
  static std::map<bool, int> repetition;
  for (auto _ : state) {
    SearchOptions o = test::seed_task_options();
    o.seed = static_cast<std::uint64_t>(repetition[gpu]++ % 10) + 1;
    o.device = gpu ? ComputeDevice::Cuda : ComputeDevice::Cpu;
    o.time_limit_s = 30;
    SearchSummary s;
    const double found = bench::time_to_target(o, p, &s);
    if (found < 0) {
      state.SkipWithError("target not reached");
      break;
    }
    state.SetIterationTime(found);
    state.counters["generations"] = static_cast<double>(s.generations);
  }
}

double stat_min(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
double stat_max(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

BENCHMARK(BM_PopulationGpu)
    ->ArgName("rows")
    ->Arg(4096)
    ->Arg(1'000'000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PopulationCpu)
    ->ArgName("rows")
    ->Arg(4096)
    ->Arg(1'000'000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_EnumerationStepGpu)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EnumerationStepCpu)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_TimeToTarget)
    ->ArgName("device_cuda")
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1)
    ->Repetitions(10)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", stat_min)
    ->ComputeStatistics("max", stat_max);

}  // namespace

int main(int argc, char** argv) {
  benchmark::AddCustomContext("cuda_device",
                              cuda_available() ? cuda_device_name() : cuda_unavailable_reason());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
