// Forward-mode differentiation of an expression with respect to its parameters: the postfix walk
// of expr/forward.hpp over dual numbers in a batch-of-rows layout.
//
// A number is a block of kBlock rows: their values and, for the parameters it depends on (a bit
// mask), a block of partial derivatives per parameter. Each operator's value and local partials
// are expr/op.hpp's definitions, applied row by row with the operator fixed at compile time (one
// loop per operator, dispatched once per node and block, never per row); the chain rule then
// touches only the parameters in the mask. Inputs are read in place.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/forward.hpp"
#include "shaderfit/fit/fit.hpp"

// Compiled for AVX2 and the baseline ISA, picked at load time (the row loops vectorise); the
// helpers are always inlined so that each clone compiles them for its own ISA.
#define SF_JACOBIAN_KERNEL __attribute__((target_clones("avx2", "default")))
#define SF_ALWAYS_INLINE inline __attribute__((always_inline))
#define SF_LAMBDA_INLINE __attribute__((always_inline))

namespace shaderfit {

namespace {

constexpr std::size_t kBlock = 64;

struct Dual {
  const double* v;     // kBlock values: an input column, or `own`
  double* own;         // this slot's value buffer
  double* d;           // partials: kBlock per parameter, valid where `mask` has the bit
  std::uint64_t mask;  // parameters with a (possibly) nonzero partial
};

template <typename F>
SF_ALWAYS_INLINE void for_each_bit(std::uint64_t mask, F f) {
  while (mask != 0) {
    const int j = __builtin_ctzll(mask);
    f(static_cast<std::size_t>(j));
    mask &= mask - 1;
  }
}

// Calls f(std::integral_constant<Op, op>) for the runtime `op`.
template <typename F, std::size_t... I>
SF_ALWAYS_INLINE void with_op(Op op, F&& f, std::index_sequence<I...> /*ops*/) {
  (void)((op == static_cast<Op>(I) &&
          (f(std::integral_constant<Op, static_cast<Op>(I)>{}), true)) ||
         ...);
}
template <typename F>
SF_ALWAYS_INLINE void with_op(Op op, F&& f) {
  with_op(op, std::forward<F>(f), std::make_index_sequence<kOpCount>());
}

// Calls f(std::integral_constant<int, k>) for the runtime IPow exponent k.
template <typename F, int... K>
SF_ALWAYS_INLINE void with_exponent(int k, F&& f, std::integer_sequence<int, K...> /*ks*/) {
  (void)((k == K + kMinIntegerPower &&
          (f(std::integral_constant<int, K + kMinIntegerPower>{}), true)) ||
         ...);
}
template <typename F>
SF_ALWAYS_INLINE void with_exponent(int k, F&& f) {
  with_exponent(k, std::forward<F>(f),
                std::make_integer_sequence<int, kMaxIntegerPower - kMinIntegerPower + 1>());
}

// The Numbers policy (expr/forward.hpp) of one block: rows [r0, r0 + nb).
struct DualBlocks {
  using value_type = Dual;
  const Expression& e;
  std::span<const double* const> columns;
  double* storage;  // (1 + parameters) * kBlock doubles per stack depth
  std::size_t np = 0, r0 = 0, nb = 0;

  SF_ALWAYS_INLINE Dual leaf(const Node& n, std::size_t depth) const {
    double* base = storage + depth * (1 + np) * kBlock;
    Dual t{base, base, base + kBlock, 0};
    if (n.op == Op::Var) {
      t.v = columns[static_cast<std::size_t>(n.index)] + r0;
    } else if (n.op == Op::Param) {
      const auto j = static_cast<std::size_t>(n.index);
      std::fill(t.own, t.own + nb, e.parameter_values[j]);
      std::fill(t.d + j * kBlock, t.d + j * kBlock + nb, 1.0);
      t.mask = std::uint64_t{1} << j;
    } else {
      std::fill(t.own, t.own + nb, n.value);
    }
    return t;
  }

  SF_ALWAYS_INLINE void unary(const Node& n, Dual& a) const {
    with_op(n.op, [&](auto kop) SF_LAMBDA_INLINE {
      constexpr Op op = decltype(kop)::value;
      if constexpr (arity(op) == 1) {
        const double* x = a.v;
        double* r = a.own;
        double g[kBlock];
        if constexpr (op == Op::IPow) {
          // The exponent fixed at compile time: the squaring chain unrolls, the rows vectorise.
          with_exponent(n.index, [&](auto kc) SF_LAMBDA_INLINE {
            constexpr int k = decltype(kc)::value;
            if (a.mask != 0)
              for (std::size_t i = 0; i < nb; ++i) g[i] = ipow_derivative(x[i], k);
            for (std::size_t i = 0; i < nb; ++i) r[i] = apply_ipow(x[i], k);
          });
        } else {
          for (std::size_t i = 0; i < nb; ++i) {
            const double xi = x[i];
            r[i] = apply_unary(op, xi);
            g[i] = unary_derivative(op, xi, r[i]);
          }
        }
        for_each_bit(a.mask, [&](std::size_t j) {
          double* da = a.d + j * kBlock;
          for (std::size_t i = 0; i < nb; ++i) da[i] *= g[i];
        });
        a.v = a.own;
      }
    });
  }

  SF_ALWAYS_INLINE void binary(Op o, Dual& a, const Dual& b) const {
    with_op(o, [&](auto kop) SF_LAMBDA_INLINE {
      constexpr Op op = decltype(kop)::value;
      if constexpr (arity(op) == 2) {
        double ga[kBlock], gb[kBlock];
        const double* x = a.v;
        const double* y = b.v;
        double* r = a.own;
        for (std::size_t i = 0; i < nb; ++i) {
          const double ri = apply_binary(op, x[i], y[i]);
          const BinaryPartials<double> p = binary_partials(op, x[i], y[i], ri);
          ga[i] = p.da;
          gb[i] = p.db;
          r[i] = ri;
        }
        for_each_bit(a.mask | b.mask, [&](std::size_t j) {
          double* da = a.d + j * kBlock;
          const double* db = b.d + j * kBlock;
          const bool in_a = (a.mask >> j) & 1u, in_b = (b.mask >> j) & 1u;
          if (in_a && in_b) {
            for (std::size_t i = 0; i < nb; ++i) da[i] = da[i] * ga[i] + db[i] * gb[i];
          } else if (in_a) {
            for (std::size_t i = 0; i < nb; ++i) da[i] *= ga[i];
          } else {
            for (std::size_t i = 0; i < nb; ++i) da[i] = db[i] * gb[i];
          }
        });
        a.mask |= b.mask;
        a.v = a.own;
      }
    });
  }

  // fma(a, b, c): partials b, a and 1; select(a, b, c): 0, cond and 1 - cond (op.hpp).
  SF_ALWAYS_INLINE void ternary(Op o, Dual& a, const Dual& b, const Dual& c) const {
    if (o == Op::Select) {
      select(a, b, c);
      return;
    }
    for_each_bit(a.mask | b.mask | c.mask, [&](std::size_t j) {
      double* da = a.d + j * kBlock;
      const bool in_a = (a.mask >> j) & 1u, in_b = (b.mask >> j) & 1u, in_c = (c.mask >> j) & 1u;
      for (std::size_t i = 0; i < nb; ++i) {
        const double pa = in_a ? da[i] * b.v[i] : 0.0;
        const double pb = in_b ? b.d[j * kBlock + i] * a.v[i] : 0.0;
        const double pc = in_c ? c.d[j * kBlock + i] : 0.0;
        da[i] = pa + pb + pc;
      }
    });
    for (std::size_t i = 0; i < nb; ++i) a.own[i] = apply_fma(a.v[i], b.v[i], c.v[i]);
    a.mask |= b.mask | c.mask;
    a.v = a.own;
  }

  SF_ALWAYS_INLINE void select(Dual& a, const Dual& b, const Dual& c) const {
    for_each_bit(b.mask | c.mask, [&](std::size_t j) {
      double* da = a.d + j * kBlock;
      const bool in_b = (b.mask >> j) & 1u, in_c = (c.mask >> j) & 1u;
      for (std::size_t i = 0; i < nb; ++i) {
        const TernaryPartials<double> p = ternary_partials(Op::Select, a.v[i], b.v[i], c.v[i]);
        const double pb = in_b ? b.d[j * kBlock + i] * p.db : 0.0;
        const double pc = in_c ? c.d[j * kBlock + i] * p.dc : 0.0;
        da[i] = pb + pc;
      }
    });
    for (std::size_t i = 0; i < nb; ++i) a.own[i] = apply_select(a.v[i], b.v[i], c.v[i]);
    a.mask = b.mask | c.mask;
    a.v = a.own;
  }
};

}  // namespace

SF_JACOBIAN_KERNEL void evaluate_with_jacobian(const Expression& e,
                                               std::span<const double* const> columns,
                                               std::size_t rows, std::span<double> values,
                                               std::span<double> jacobian) {
  const std::size_t np = e.parameters.size();
  if (columns.size() != e.variables.size())
    throw Error("evaluate_with_jacobian: one column per variable expected");
  if (e.parameter_values.size() != np)
    throw Error("evaluate_with_jacobian: one value per parameter expected");
  if (np > kMaxFitParameters)
    throw Error("evaluate_with_jacobian: at most " + std::to_string(kMaxFitParameters) +
                " parameters");
  if (values.size() < rows || jacobian.size() < rows * np)
    throw Error("evaluate_with_jacobian: output too small");
  thread_local std::vector<double> storage;
  thread_local std::vector<Dual> stack;
  storage.resize(e.nodes.size() * (1 + np) * kBlock);
  stack.reserve(e.nodes.size());
  DualBlocks blocks{e, columns, storage.data(), np};

  for (std::size_t r0 = 0; r0 < rows; r0 += kBlock) {
    blocks.r0 = r0;
    blocks.nb = std::min(kBlock, rows - r0);
    const std::size_t nb = blocks.nb;
    const Dual top = evaluate_forward(e, blocks, stack);
    std::copy(top.v, top.v + nb, values.data() + r0);
    for (std::size_t j = 0; j < np; ++j) {
      double* out = jacobian.data() + j * rows + r0;
      if ((top.mask >> j) & 1u)
        std::copy(top.d + j * kBlock, top.d + j * kBlock + nb, out);
      else
        std::fill(out, out + nb, 0.0);
    }
  }
}

}  // namespace shaderfit
