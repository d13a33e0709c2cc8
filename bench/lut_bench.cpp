// Time to bake seed 002's FV lookup tables (fits, texels and per-cell error tables).
//
//   build/<dir>/bench/lut_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
//
// Names: four_tables/size:N/threads:T bakes all four variants at once (tables and cells in
// parallel on T threads); one_table/<variant>/size:N bakes one variant on every core. Wall time.
#include <benchmark/benchmark.h>

#include <array>

#include "shaderfit/lut/fv_lut.hpp"

namespace {

using shaderfit::lut::FvLutOptions;
using shaderfit::lut::FvVariant;

void four_tables(benchmark::State& state) {
  FvLutOptions o;
  o.size = static_cast<std::size_t>(state.range(0));
  o.threads = static_cast<int>(state.range(1));
  for (auto _ : state) {
    const auto bake = shaderfit::lut::bake_fv_luts(o, shaderfit::lut::kAllFvVariants);
    benchmark::DoNotOptimize(bake.tables.data());
  }
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(4 * o.size * o.size),
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void one_table(benchmark::State& state) {
  FvLutOptions o;
  o.size = 128;
  const std::array<FvVariant, 1> v = {static_cast<FvVariant>(state.range(0))};
  for (auto _ : state) benchmark::DoNotOptimize(shaderfit::lut::bake_fv_luts(o, v).tables.data());
}

BENCHMARK(four_tables)
    ->ArgNames({"size", "threads"})
    ->Args({128, 1})
    ->Args({128, 2})
    ->Args({128, 0})
    ->Args({64, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(one_table)
    ->ArgName("variant")
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
