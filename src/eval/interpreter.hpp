// Internal: the compiled form of an expression and the batch loop shared by the CPU backends.
//
// A Plan is the postfix array turned into instructions over a table of "sources", each a
// pointer to a column of `kBatchRows<T>` values:
//   [0, num_vars)                 input variables, pointing straight into the caller's columns
//   [const_base, stack_base)      Const/Param nodes, filled once per task
//   [stack_base, out_index)       intermediate results; the k-th slot holds the value at postfix
//                                 stack depth k, so the buffer is (stack depth) columns, not
//                                 (nodes) columns, and stays in L1
//   out_index                     the caller's output rows (written by the root instruction)
// Instructions are elementwise, so an output slot may be the same as its first operand's.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/op.hpp"

namespace shaderfit::eval_detail {

// Rows per batch: 2 KiB per column (512 floats, 256 doubles).
template <typename T>
inline constexpr std::size_t kBatchRows = 2048 / sizeof(T);
// Every kernel processes a multiple of this many rows (64 bytes: the widest vector).
template <typename T>
inline constexpr std::size_t kRowAlign = 64 / sizeof(T);

struct Instr {
  Op op = Op::Add;
  std::int16_t k = 0;  // exponent (IPow)
  std::uint32_t out = 0;
  std::uint32_t arg[3] = {0, 0, 0};
};

template <typename T>
struct Plan {
  std::vector<Instr> code;               // empty when the root is a leaf
  std::vector<T> constants;              // values of sources [const_base, stack_base)
  std::vector<std::uint32_t> used_vars;  // variables some node reads
  std::uint32_t num_vars = 0;
  std::uint32_t const_base = 0;
  std::uint32_t stack_base = 0;
  std::uint32_t out_index = 0;
  std::uint32_t root = 0;  // source holding the result when `code` is empty
  [[nodiscard]] std::size_t num_sources() const { return out_index + 1; }
};

// Checks the expression and compiles it; throws shaderfit::Error if it is malformed or if
// `num_columns` differs from the number of variables.
template <typename T>
Plan<T> compile_plan(const Expression& e, std::size_t num_columns);

// Evaluates rows [begin, end) of a plan (a task); columns and out as in evaluate().
template <typename T>
using TaskFn = void (*)(const Plan<T>& plan, const T* const* columns, T* out, std::size_t begin,
                        std::size_t end);

enum class Backend {
  Simd,    // Highway kernels, best target for this CPU chosen at run time
  Scalar,  // plain per-op loops over a batch (what the compiler makes of them)
};

TaskFn<float> task_function_f32(Backend backend);
TaskFn<double> task_function_f64(Backend backend);

// evaluate() with an explicit backend (benchmarks and tests).
void evaluate_with_backend(const Expression& e, std::span<const float* const> columns,
                           std::span<float> out, const EvalOptions& options, Backend backend);
void evaluate_with_backend(const Expression& e, std::span<const double* const> columns,
                           std::span<double> out, const EvalOptions& options, Backend backend);

// The SIMD targets compiled in and supported by this CPU (Highway target bits), best first,
// and their names. force_simd_target(t) makes the Simd backend use target t from now on;
// force_simd_target(0) goes back to the best one. Tests use these to check every target.
std::vector<std::int64_t> simd_targets();
std::string simd_target_name(std::int64_t target);
void force_simd_target(std::int64_t target);

// The batch loop of one task. `kernels(instr, sources, count)` computes one instruction for
// `count` rows (a multiple of kRowAlign<T>), reading and writing through `sources`.
// Full batches read the caller's columns in place; the last, partial batch of a task goes
// through zero-padded copies so that kernels never read or write past the caller's rows.
template <typename T, typename Kernels>
void run_task(const Plan<T>& plan, const T* const* columns, T* out, std::size_t begin,
              std::size_t end, const Kernels& kernels) {
  constexpr std::size_t B = kBatchRows<T>;
  const std::size_t nvars = plan.used_vars.size();
  const std::size_t slots = plan.out_index - plan.const_base;
  // Slots, then one padded column per used variable, then the padded output; 64-byte aligned.
  // Reused by later tasks on this thread (a task never starts another on the same thread).
  thread_local std::vector<T> scratch;
  const std::size_t need = (slots + nvars + 1) * B + kRowAlign<T>;
  if (scratch.size() < need) scratch.resize(need);
  T* base = scratch.data();
  while (reinterpret_cast<std::uintptr_t>(base) % 64 != 0) ++base;
  T* const padded = base + slots * B;

  std::vector<T*> src(plan.num_sources(), nullptr);
  for (std::size_t s = 0; s < slots; ++s) src[plan.const_base + s] = base + s * B;
  for (std::size_t c = 0; c < plan.constants.size(); ++c)
    std::fill_n(src[plan.const_base + c], B, plan.constants[c]);

  for (std::size_t row = begin; row < end; row += B) {
    const std::size_t n = std::min(B, end - row);
    std::size_t count = B;
    if (n == B) {
      // Kernels only write to slots and the output, never to variable sources.
      for (std::uint32_t v : plan.used_vars) src[v] = const_cast<T*>(columns[v] + row);
      src[plan.out_index] = out + row;
    } else {
      count = (n + kRowAlign<T> - 1) / kRowAlign<T> * kRowAlign<T>;
      for (std::size_t j = 0; j < nvars; ++j) {
        const std::uint32_t v = plan.used_vars[j];
        src[v] = padded + j * B;
        std::memcpy(src[v], columns[v] + row, n * sizeof(T));
        std::fill(src[v] + n, src[v] + count, T(0));
      }
      src[plan.out_index] = padded + nvars * B;
    }
    for (const Instr& ins : plan.code) kernels(ins, src.data(), count);
    if (n != B) std::memcpy(out + row, src[plan.out_index], n * sizeof(T));
  }
}

}  // namespace shaderfit::eval_detail
