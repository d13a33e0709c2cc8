// Throughput of the batched CPU evaluator, in node evaluations per second (rows x nodes / s).
//
//   build/<dir>/bench/eval_bench --benchmark_min_time=0.2 --benchmark_repetitions=5 \
//       --benchmark_report_aggregates_only=true
//
// Names: <backend>/<formula>/<type>/rows:R/threads:T, where backend is
//   simd        evaluate(): Highway kernels, best target for this CPU
//   scalar_ops  the same interpreter with plain per-op loops (the SIMD gain is simd / scalar_ops)
//   inlined     a hand-written loop computing the formula directly (what a compiler does with
//               the formula inlined): the ceiling an interpreter can approach
//   half        evaluate_in(Precision::Half): row by row, every operation rounded to binary16
//               (the search's --precision half and every front member's half check)
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "eval/interpreter.hpp"
#include "eval/sample_formulas_test_util.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/expression.hpp"

namespace {

using shaderfit::Expression;
using shaderfit::eval_detail::Backend;

template <typename T>
struct Columns {
  std::vector<std::vector<T>> values;
  std::vector<const T*> pointers;
  std::vector<T> out;

  Columns(std::size_t num_vars, std::size_t rows) : out(rows) {
    shaderfit::Rng rng(1);
    values.resize(num_vars);
    for (auto& c : values) {
      for (std::size_t i = 0; i < rows; ++i)
        c.push_back(static_cast<T>(shaderfit::uniform(rng, 0.05, 1.0)));
      pointers.push_back(c.data());
    }
  }
};

void set_rate(benchmark::State& state, std::size_t rows, std::size_t nodes) {
  state.counters["node_evals/s"] = benchmark::Counter(
      static_cast<double>(rows * nodes), benchmark::Counter::kIsIterationInvariantRate);
}

template <typename T>
void interpreter(benchmark::State& state, const Expression& e, Backend backend) {
  const auto rows = static_cast<std::size_t>(state.range(0));
  Columns<T> data(e.variables.size(), rows);
  const shaderfit::EvalOptions options{.threads = static_cast<int>(state.range(1))};
  for (auto _ : state) {
    shaderfit::eval_detail::evaluate_with_backend(e, data.pointers, data.out, options, backend);
    benchmark::DoNotOptimize(data.out.data());
    benchmark::ClobberMemory();
  }
  set_rate(state, rows, e.size());
}

// r0 + (x - r0) * x^4 written out, counted as the same 8 nodes.
template <typename T>
void inlined_fresnel(benchmark::State& state) {
  const auto rows = static_cast<std::size_t>(state.range(0));
  Columns<T> data(2, rows);
  for (auto _ : state) {
    const T* r0 = data.pointers[0];
    const T* x = data.pointers[1];
    T* out = data.out.data();
    for (std::size_t i = 0; i < rows; ++i) {
      const T x2 = x[i] * x[i];
      out[i] = r0[i] + (x[i] - r0[i]) * (x2 * x2);
    }
    benchmark::DoNotOptimize(out);
    benchmark::ClobberMemory();
  }
  set_rate(state, rows, 8);
}

void half(benchmark::State& state, const Expression& e) {
  const auto rows = static_cast<std::size_t>(state.range(0));
  Columns<double> data(e.variables.size(), rows);
  for (auto _ : state) {
    shaderfit::evaluate_in(shaderfit::Precision::Half, e, data.pointers, data.out);
    benchmark::DoNotOptimize(data.out.data());
    benchmark::ClobberMemory();
  }
  set_rate(state, rows, e.size());
}

template <typename T>
void register_type(const char* type) {
  const std::vector<std::int64_t> rows = {4096, 1000000};
  for (const auto& f : shaderfit::eval_detail::sample_formulas()) {
    const Expression e = f.expression;
    benchmark::RegisterBenchmark(("simd/" + f.name + "/" + type).c_str(),
                                 [e](benchmark::State& s) { interpreter<T>(s, e, Backend::Simd); })
        ->ArgsProduct({rows, {1, 2}})
        ->ArgNames({"rows", "threads"})
        ->UseRealTime();
    benchmark::RegisterBenchmark(
        ("scalar_ops/" + f.name + "/" + type).c_str(),
        [e](benchmark::State& s) { interpreter<T>(s, e, Backend::Scalar); })
        ->ArgsProduct({rows, {1}})
        ->ArgNames({"rows", "threads"})
        ->UseRealTime();
  }
  benchmark::RegisterBenchmark((std::string("inlined/fresnel/") + type).c_str(), inlined_fresnel<T>)
      ->ArgsProduct({rows, {1}})
      ->ArgNames({"rows", "threads"})
      ->UseRealTime();
}

const bool registered = [] {
  register_type<float>("f32");
  register_type<double>("f64");
  for (const auto& f : shaderfit::eval_detail::sample_formulas()) {
    const Expression e = f.expression;
    benchmark::RegisterBenchmark(("half/" + f.name + "/f16").c_str(),
                                 [e](benchmark::State& s) { half(s, e); })
        ->ArgsProduct({{4096}, {1}})
        ->ArgNames({"rows", "threads"})
        ->UseRealTime();
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
