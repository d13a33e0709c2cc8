// Internal: the packed form of expressions that the GPU kernels read, and the per-row postfix
// interpreter they run. Shared by the CUDA kernels (src/gpu/*.cu) and the CPU, where the tests
// check it against evaluate() and evaluate_scalar().
//
// A packed population is one flat GpuNode array; program e is nodes[offsets[e], offsets[e + 1]).
// Parameters are resolved to their values at packing time, so a program is self-contained.
// Everything here is SF_CPU_GPU: no allocation, no exceptions, no virtual calls; dispatch is a
// switch on the opcode, with the per-row work of each case a loop over R rows with a
// compile-time operator, so the opcode is decoded once per R rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "shaderfit/core.hpp"
#include "shaderfit/expr/op.hpp"

namespace shaderfit::gpu_detail {

// The deepest postfix stack a packed program may use (packing rejects deeper ones). A formula of
// n nodes needs at most (n + 1) / 2 slots, so this covers every formula of up to 63 nodes.
inline constexpr int kMaxStack = 32;

struct GpuNode {
  Op op = Op::Const;
  std::uint8_t arity = 0;
  std::int16_t index = 0;  // variable (Var) or exponent (IPow)
  float value = 0;         // Const, and Param resolved to its value, in float32
};
static_assert(sizeof(GpuNode) == 8, "GpuNode is read by every GPU lane: keep it 8 bytes");

// Float <-> bits without std::bit_cast (not usable in device code without relaxed constexpr).
SF_CPU_GPU inline std::uint32_t float_bits(float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
SF_CPU_GPU inline float bits_float(std::uint32_t u) {
  float x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

namespace program_detail {

template <Op O, int R>
SF_CPU_GPU inline void unary_rows(float (&x)[R]) {
  for (int j = 0; j < R; ++j) x[j] = apply_unary(O, x[j]);
}

template <Op O, int R>
SF_CPU_GPU inline void binary_rows(float (&x)[R], const float (&y)[R]) {
  for (int j = 0; j < R; ++j) x[j] = apply_binary(O, x[j], y[j]);
}

// One instruction of operator O on R rows: pushes a leaf, or replaces the top operands by the
// result. Always inlined into the switch of run_program, one case per operator.
template <Op O, int R>
SF_OP_INLINE void step(const GpuNode& n, float (&st)[kMaxStack][R], int& sp, const float* columns,
                       std::size_t column_stride, const std::size_t (&row)[R]) {
  if constexpr (O == Op::Var) {
    const float* c = columns + static_cast<std::size_t>(n.index) * column_stride;
    for (int j = 0; j < R; ++j) st[sp][j] = c[row[j]];
    ++sp;
  } else if constexpr (is_leaf(O)) {  // Const, and Param resolved to its value
    for (int j = 0; j < R; ++j) st[sp][j] = n.value;
    ++sp;
  } else if constexpr (O == Op::IPow) {
    for (int j = 0; j < R; ++j) st[sp - 1][j] = apply_ipow(st[sp - 1][j], int{n.index});
  } else if constexpr (arity(O) == 1) {
    unary_rows<O>(st[sp - 1]);
  } else if constexpr (arity(O) == 2) {
    --sp;
    binary_rows<O>(st[sp - 1], st[sp]);
  } else {
    sp -= 2;
    for (int j = 0; j < R; ++j)
      st[sp - 1][j] = apply_ternary(O, st[sp - 1][j], st[sp][j], st[sp + 1][j]);
  }
}

}  // namespace program_detail

// Evaluates one packed program on R rows at once: columns holds the variables one after the
// other (variable v of row r at columns[v * column_stride + r]); row[j] names the j-th row.
// The program must be well formed with a stack depth <= kMaxStack (pack_population checks it).
// Values are those of apply_unary / apply_binary / apply_ipow / apply_fma / apply_select in
// float32.
template <int R>
SF_CPU_GPU inline void run_program(const GpuNode* code, std::uint32_t count, const float* columns,
                                   std::size_t column_stride, const std::size_t (&row)[R],
                                   float (&out)[R]) {
  float st[kMaxStack][R];
  int sp = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const GpuNode n = code[i];
    switch (n.op) {
#define SHADERFIT_GPU_STEP(name, ...) \
  case Op::name: program_detail::step<Op::name>(n, st, sp, columns, column_stride, row); break;
      SHADERFIT_OPERATORS(SHADERFIT_GPU_STEP)
#undef SHADERFIT_GPU_STEP
      default: break;  // packing admits no other opcode
    }
  }
  for (int j = 0; j < R; ++j) out[j] = st[0][j];
}

}  // namespace shaderfit::gpu_detail
