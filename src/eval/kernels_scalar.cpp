// The scalar backend: one plain loop per op over a batch, calling the reference functions of
// expr/op.hpp. Compiled for the baseline target; the compiler may vectorize the arithmetic
// loops with the baseline's SIMD (SSE2 on x86-64), but not the libm calls.
#include <array>
#include <utility>

#include "eval/interpreter.hpp"

namespace shaderfit::eval_detail {

namespace {

template <typename T, Op kOp>
void op_loop(const Instr& ins, T* const* src, std::size_t count) {
  T* o = src[ins.out];
  const T* a = src[ins.arg[0]];
  if constexpr (arity(kOp) == 3) {
    const T* b = src[ins.arg[1]];
    const T* c = src[ins.arg[2]];
    for (std::size_t i = 0; i < count; ++i) o[i] = apply_ternary(kOp, a[i], b[i], c[i]);
  } else if constexpr (is_leaf(kOp) || kOp == Op::Count_) {
    // Plans never contain leaves; nothing to do.
  } else if constexpr (arity(kOp) == 1) {
    for (std::size_t i = 0; i < count; ++i) o[i] = unary_value<kOp>(a[i], ins.k);
  } else {
    const T* b = src[ins.arg[1]];
    for (std::size_t i = 0; i < count; ++i) o[i] = apply_binary(kOp, a[i], b[i]);
  }
}

template <typename T>
using OpLoop = void (*)(const Instr&, T* const*, std::size_t);

template <typename T, std::size_t... I>
constexpr std::array<OpLoop<T>, sizeof...(I)> make_loops(std::index_sequence<I...>) {
  return {&op_loop<T, static_cast<Op>(I)>...};
}

template <typename T>
struct ScalarKernels {
  static constexpr auto kLoops = make_loops<T>(std::make_index_sequence<kOpCount>());
  void operator()(const Instr& ins, T* const* src, std::size_t count) const {
    kLoops[static_cast<std::size_t>(ins.op)](ins, src, count);
  }
};

template <typename T>
void scalar_task(const Plan<T>& plan, const T* const* columns, T* out, std::size_t begin,
                 std::size_t end) {
  run_task(plan, columns, out, begin, end, ScalarKernels<T>{});
}

}  // namespace

// Defined in kernels_simd.cpp.
TaskFn<float> simd_task_f32();
TaskFn<double> simd_task_f64();

TaskFn<float> task_function_f32(Backend backend) {
  return backend == Backend::Scalar ? &scalar_task<float> : simd_task_f32();
}

TaskFn<double> task_function_f64(Backend backend) {
  return backend == Backend::Scalar ? &scalar_task<double> : simd_task_f64();
}

}  // namespace shaderfit::eval_detail
