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
  using program_detail::binary_rows;
  using program_detail::unary_rows;
  float st[kMaxStack][R];
  int sp = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const GpuNode n = code[i];
    switch (n.op) {
      case Op::Const:
      case Op::Param:
        for (int j = 0; j < R; ++j) st[sp][j] = n.value;
        ++sp;
        break;
      case Op::Var: {
        const float* c = columns + static_cast<std::size_t>(n.index) * column_stride;
        for (int j = 0; j < R; ++j) st[sp][j] = c[row[j]];
        ++sp;
        break;
      }
      case Op::Add:
        --sp;
        binary_rows<Op::Add>(st[sp - 1], st[sp]);
        break;
      case Op::Sub:
        --sp;
        binary_rows<Op::Sub>(st[sp - 1], st[sp]);
        break;
      case Op::Mul:
        --sp;
        binary_rows<Op::Mul>(st[sp - 1], st[sp]);
        break;
      case Op::Div:
        --sp;
        binary_rows<Op::Div>(st[sp - 1], st[sp]);
        break;
      case Op::Min:
        --sp;
        binary_rows<Op::Min>(st[sp - 1], st[sp]);
        break;
      case Op::Max:
        --sp;
        binary_rows<Op::Max>(st[sp - 1], st[sp]);
        break;
      case Op::Pow:
        --sp;
        binary_rows<Op::Pow>(st[sp - 1], st[sp]);
        break;
      case Op::CopySign:
        --sp;
        binary_rows<Op::CopySign>(st[sp - 1], st[sp]);
        break;
      case Op::Atan2:
        --sp;
        binary_rows<Op::Atan2>(st[sp - 1], st[sp]);
        break;
      case Op::Neg: unary_rows<Op::Neg>(st[sp - 1]); break;
      case Op::IPow:
        for (int j = 0; j < R; ++j) st[sp - 1][j] = apply_ipow(st[sp - 1][j], int{n.index});
        break;
      case Op::Sqrt: unary_rows<Op::Sqrt>(st[sp - 1]); break;
      case Op::Rsqrt: unary_rows<Op::Rsqrt>(st[sp - 1]); break;
      case Op::Rcp: unary_rows<Op::Rcp>(st[sp - 1]); break;
      case Op::Exp2: unary_rows<Op::Exp2>(st[sp - 1]); break;
      case Op::Log2: unary_rows<Op::Log2>(st[sp - 1]); break;
      case Op::Exp: unary_rows<Op::Exp>(st[sp - 1]); break;
      case Op::Log: unary_rows<Op::Log>(st[sp - 1]); break;
      case Op::Abs: unary_rows<Op::Abs>(st[sp - 1]); break;
      case Op::Saturate: unary_rows<Op::Saturate>(st[sp - 1]); break;
      case Op::Sin: unary_rows<Op::Sin>(st[sp - 1]); break;
      case Op::Cos: unary_rows<Op::Cos>(st[sp - 1]); break;
      case Op::Sign: unary_rows<Op::Sign>(st[sp - 1]); break;
      case Op::Asin: unary_rows<Op::Asin>(st[sp - 1]); break;
      case Op::Acos: unary_rows<Op::Acos>(st[sp - 1]); break;
      case Op::Atan: unary_rows<Op::Atan>(st[sp - 1]); break;
      case Op::Tanh: unary_rows<Op::Tanh>(st[sp - 1]); break;
      case Op::Erf: unary_rows<Op::Erf>(st[sp - 1]); break;
      case Op::Fma:
        sp -= 2;
        for (int j = 0; j < R; ++j)
          st[sp - 1][j] = apply_fma(st[sp - 1][j], st[sp][j], st[sp + 1][j]);
        break;
      case Op::Select:
        sp -= 2;
        for (int j = 0; j < R; ++j)
          st[sp - 1][j] = apply_select(st[sp - 1][j], st[sp][j], st[sp + 1][j]);
        break;
      default: break;  // packing admits no other opcode
    }
  }
  for (int j = 0; j < R; ++j) out[j] = st[0][j];
}

}  // namespace shaderfit::gpu_detail
