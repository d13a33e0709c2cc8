// Forward-mode differentiation of an expression with respect to its parameters.
//
// A postfix interpreter over blocks of rows: every stack entry holds a block of values and, for
// the parameters it depends on (a bit mask), a block of partial derivatives per parameter. The
// operator is dispatched once per node and block, never per row; inputs are read in place.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/fit/fit.hpp"

// Compiled for AVX2 and the baseline ISA, picked at load time (the row loops vectorise); the
// helpers are always inlined so that each clone compiles them for its own ISA.
#define SF_JACOBIAN_KERNEL __attribute__((target_clones("avx2", "default")))
#define SF_ALWAYS_INLINE inline __attribute__((always_inline))

namespace shaderfit {

namespace {

constexpr std::size_t kBlock = 64;

struct Entry {
  const double* v;     // kBlock values: an input column, or `own`
  double* own;         // this slot's value buffer
  double* d;           // partials: kBlock per parameter, valid where `mask` has the bit
  std::uint64_t mask;  // parameters with a (possibly) nonzero partial
};

// dy/dx of a unary op at x, given y = op(x) (the ops without a loop of their own below).
SF_ALWAYS_INLINE double unary_derivative(Op op, double x, double y) {
  constexpr double kLn2 = 0.6931471805599453;
  switch (op) {
    case Op::Rsqrt: return -0.5 * y / x;
    case Op::Rcp: return -y * y;
    case Op::Exp2: return kLn2 * y;
    case Op::Log2: return 1.0 / (kLn2 * x);
    case Op::Exp: return y;
    case Op::Log: return 1.0 / x;
    case Op::Abs: return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
    case Op::Saturate: return x > 0 && x < 1 ? 1.0 : 0.0;
    case Op::Sin: return std::cos(x);
    case Op::Cos: return -std::sin(x);
    default: return 0.0;
  }
}

// out = x^k over a block, by the squaring chain of apply_ipow (the same operations in the same
// order, so the same bits), with the chain's loop outside the row loop.
SF_ALWAYS_INLINE void ipow_block(const double* x, int k, double* out, std::size_t n) {
  const bool inverse = k < 0;
  unsigned e = static_cast<unsigned>(inverse ? -k : k);
  double base[kBlock];
  std::copy(x, x + n, base);
  bool first = true;
  while (e != 0) {
    if (e & 1u) {
      if (first)
        std::copy(base, base + n, out);
      else
        for (std::size_t i = 0; i < n; ++i) out[i] *= base[i];
      first = false;
    }
    e >>= 1u;
    if (e != 0)
      for (std::size_t i = 0; i < n; ++i) base[i] *= base[i];
  }
  if (first) std::fill(out, out + n, 1.0);
  if (inverse)
    for (std::size_t i = 0; i < n; ++i) out[i] = 1.0 / out[i];
}

template <typename F>
SF_ALWAYS_INLINE void for_each_bit(std::uint64_t mask, F f) {
  while (mask != 0) {
    const int j = __builtin_ctzll(mask);
    f(static_cast<std::size_t>(j));
    mask &= mask - 1;
  }
}

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
  if (np > 64) throw Error("evaluate_with_jacobian: at most 64 parameters");
  if (values.size() < rows || jacobian.size() < rows * np)
    throw Error("evaluate_with_jacobian: output too small");
  const std::size_t depth = e.nodes.size();
  thread_local std::vector<double> storage;
  storage.resize(depth * (1 + np) * kBlock);
  std::vector<Entry> stack;
  stack.reserve(depth);

  for (std::size_t r0 = 0; r0 < rows; r0 += kBlock) {
    const std::size_t nb = std::min(kBlock, rows - r0);
    stack.clear();
    auto push = [&]() -> Entry& {
      double* base = storage.data() + stack.size() * (1 + np) * kBlock;
      stack.push_back({base, base, base + kBlock, 0});
      return stack.back();
    };
    for (const Node& n : e.nodes) {
      switch (n.op) {
        case Op::Const: {
          Entry& t = push();
          std::fill(t.own, t.own + nb, n.value);
          break;
        }
        case Op::Var: {
          Entry& t = push();
          t.v = columns[static_cast<std::size_t>(n.index)] + r0;
          break;
        }
        case Op::Param: {
          Entry& t = push();
          const auto j = static_cast<std::size_t>(n.index);
          std::fill(t.own, t.own + nb, e.parameter_values[j]);
          std::fill(t.d + j * kBlock, t.d + j * kBlock + nb, 1.0);
          t.mask = std::uint64_t{1} << j;
          break;
        }
        case Op::Add:
        case Op::Sub:
        case Op::Mul:
        case Op::Div:
        case Op::Min:
        case Op::Max:
        case Op::Pow: {
          const Entry b = stack.back();
          stack.pop_back();
          Entry& a = stack.back();
          // r = a op b into a's own buffer, with ga = dr/da and gb = dr/db; one loop per op.
          double ga[kBlock], gb[kBlock];
          const double* x = a.v;
          const double* y = b.v;
          double* r = a.own;
          switch (n.op) {
            case Op::Add:
              for (std::size_t i = 0; i < nb; ++i) {
                r[i] = x[i] + y[i];
                ga[i] = 1;
                gb[i] = 1;
              }
              break;
            case Op::Sub:
              for (std::size_t i = 0; i < nb; ++i) {
                r[i] = x[i] - y[i];
                ga[i] = 1;
                gb[i] = -1;
              }
              break;
            case Op::Mul:
              for (std::size_t i = 0; i < nb; ++i) {
                ga[i] = y[i];
                gb[i] = x[i];
                r[i] = x[i] * y[i];
              }
              break;
            case Op::Div:
              for (std::size_t i = 0; i < nb; ++i) {
                const double q = x[i] / y[i];
                ga[i] = 1 / y[i];
                gb[i] = -q / y[i];
                r[i] = q;
              }
              break;
            case Op::Min:
              for (std::size_t i = 0; i < nb; ++i) {
                ga[i] = x[i] <= y[i] ? 1 : 0;
                gb[i] = 1 - ga[i];
                r[i] = std::fmin(x[i], y[i]);
              }
              break;
            case Op::Max:
              for (std::size_t i = 0; i < nb; ++i) {
                ga[i] = x[i] >= y[i] ? 1 : 0;
                gb[i] = 1 - ga[i];
                r[i] = std::fmax(x[i], y[i]);
              }
              break;
            default:  // pow = exp2(y log2 x)
              for (std::size_t i = 0; i < nb; ++i) {
                const double p = apply_binary(Op::Pow, x[i], y[i]);
                ga[i] = y[i] * p / x[i];
                gb[i] = p * std::log(x[i]);
                r[i] = p;
              }
              break;
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
          break;
        }
        case Op::Fma: {
          const Entry c = stack.back();
          stack.pop_back();
          const Entry b = stack.back();
          stack.pop_back();
          Entry& a = stack.back();
          for_each_bit(a.mask | b.mask | c.mask, [&](std::size_t j) {
            double* da = a.d + j * kBlock;
            const bool in_a = (a.mask >> j) & 1u, in_b = (b.mask >> j) & 1u,
                       in_c = (c.mask >> j) & 1u;
            for (std::size_t i = 0; i < nb; ++i) {
              const double pa = in_a ? da[i] * b.v[i] : 0.0;
              const double pb = in_b ? b.d[j * kBlock + i] * a.v[i] : 0.0;
              const double pc = in_c ? c.d[j * kBlock + i] : 0.0;
              da[i] = pa + pb + pc;
            }
          });
          for (std::size_t i = 0; i < nb; ++i) a.own[i] = a.v[i] * b.v[i] + c.v[i];
          a.mask |= b.mask | c.mask;
          a.v = a.own;
          break;
        }
        default: {  // unary: values into the own buffer, then dr/da per row; one loop per op
          Entry& a = stack.back();
          const int k = n.index;
          const double* x = a.v;
          double* r = a.own;
          double g[kBlock];
          switch (n.op) {
            case Op::Neg:
              for (std::size_t i = 0; i < nb; ++i) {
                r[i] = -x[i];
                g[i] = -1;
              }
              break;
            case Op::IPow:
              if (a.mask != 0) {
                ipow_block(x, k - 1, g, nb);  // x^(k-1), then scaled by k below
                for (std::size_t i = 0; i < nb; ++i) g[i] *= k;
              }
              ipow_block(x, k, r, nb);
              break;
            case Op::Sqrt:
              for (std::size_t i = 0; i < nb; ++i) {
                r[i] = std::sqrt(x[i]);
                g[i] = 0.5 / r[i];
              }
              break;
            default:
              for (std::size_t i = 0; i < nb; ++i) {
                const double xi = x[i];
                r[i] = apply_unary(n.op, xi);
                g[i] = unary_derivative(n.op, xi, r[i]);
              }
              break;
          }
          for_each_bit(a.mask, [&](std::size_t j) {
            double* da = a.d + j * kBlock;
            for (std::size_t i = 0; i < nb; ++i) da[i] *= g[i];
          });
          a.v = a.own;
          break;
        }
      }
    }
    const Entry& top = stack.back();
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
