// Internal: helpers for the evaluator's tests (values, references, tolerances, random trees).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

#include "eval/interpreter.hpp"
#include "eval/sample_formulas_test_util.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit::eval_test {

template <typename T>
using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;

template <typename T>
bool same_bits(T a, T b) {
  return std::bit_cast<Bits<T>>(a) == std::bit_cast<Bits<T>>(b);
}

// Units in the last place between a and b, +0 and -0 counting as one value; 0 when both are
// NaN, the maximum when only one is.
template <typename T>
std::uint64_t ulp_distance(T a, T b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b) ? 0 : UINT64_MAX;
  const Bits<T> sign = Bits<T>(1) << (sizeof(T) * 8 - 1);
  const Bits<T> ba = std::bit_cast<Bits<T>>(a), bb = std::bit_cast<Bits<T>>(b);
  const std::uint64_t ma = ba & ~sign, mb = bb & ~sign;  // magnitudes, ordered like the values
  if ((ba & sign) != (bb & sign)) return ma + mb;        // across zero
  return ma > mb ? ma - mb : mb - ma;
}

// Values where implementations tend to differ: zeros, ±1, subnormals, the extremes, infinities,
// NaN, and the edges of the exp, exp2 and sin/cos ranges.
template <typename T>
std::vector<T> edge_values() {
  using L = std::numeric_limits<T>;
  std::vector<T> v = {T(0),
                      T(-0.0),
                      T(1),
                      T(-1),
                      T(0.5),
                      T(-0.5),
                      T(2),
                      T(-3),
                      T(0.1),
                      L::min(),
                      -L::min(),
                      L::denorm_min(),
                      -L::denorm_min(),
                      L::min() / T(8),
                      L::max(),
                      -L::max(),
                      L::infinity(),
                      -L::infinity(),
                      L::quiet_NaN(),
                      T(1e-20),
                      T(1e20),
                      T(88.7),
                      T(89),
                      T(-104),
                      T(127.9),
                      T(128),
                      T(-149.5),
                      T(-150),
                      T(200),
                      T(709.7),
                      T(1023.9),
                      T(1024),
                      T(-1074),
                      T(-1080),
                      T(3.14159265358979),
                      T(-6.28318530717959),
                      T(38999),
                      T(39001),
                      T(1e6)};
  return v;
}

// Edge values, then random ones: moderate, wide, near the sin/cos limit, and log-uniform
// magnitudes over the whole range (subnormals included), both signs.
template <typename T>
std::vector<T> test_values(Rng& rng, std::size_t n) {
  std::vector<T> v = edge_values<T>();
  const double max_exp10 = sizeof(T) == 4 ? 38.0 : 307.0;
  const double min_exp10 = sizeof(T) == 4 ? -45.0 : -323.0;
  while (v.size() < n) {
    const double sign = bernoulli(rng, 0.5) ? 1.0 : -1.0;
    double x = 0;
    switch (uniform_index(rng, 5)) {
      case 0: x = uniform(rng, -4.0, 4.0); break;
      case 1: x = uniform(rng, -200.0, 200.0); break;
      case 2: x = sign * uniform(rng, 30000.0, 45000.0); break;
      case 3: x = sign * std::pow(10.0, uniform(rng, min_exp10, max_exp10)); break;
      default: x = uniform(rng, 0.0, 2.0); break;
    }
    v.push_back(static_cast<T>(x));
  }
  return v;
}

// Makes the Simd backend use one target while in scope.
struct ForceTarget {
  explicit ForceTarget(std::int64_t target) { eval_detail::force_simd_target(target); }
  ~ForceTarget() { eval_detail::force_simd_target(0); }
  ForceTarget(const ForceTarget&) = delete;
  ForceTarget& operator=(const ForceTarget&) = delete;
};

// x0 op x1 (and x2): one node applied to as many variables as it takes.
inline Expression single_op(Op op, int k) {
  Expression e;
  e.variables = {"x0", "x1", "x2"};
  e.variables.resize(static_cast<std::size_t>(std::max(1, arity(op))));
  for (int i = 0; i < arity(op); ++i) e.nodes.push_back(Node::variable(i));
  e.nodes.push_back(op == Op::IPow ? Node::ipow(k) : Node::op_node(op));
  return e;
}

// The scalar meaning of one op in T: the op.hpp functions in float, evaluate_scalar in double.
template <typename T>
T reference(const Expression& e, Op op, int k, T x, T y, T z) {
  if constexpr (sizeof(T) == 8) {
    const double row[] = {x, y, z};
    return evaluate_scalar(e, std::span<const double>(row, e.variables.size()));
  } else {
    switch (arity(op)) {
      case 1: return op == Op::IPow ? apply_ipow(x, k) : apply_unary(op, x);
      case 2: return apply_binary(op, x, y);
      default: return apply_ternary(op, x, y, z);
    }
  }
}

// The documented bounds (docs/evaluation.md), a little above the largest errors measured on
// SSE4, AVX2, AVX-512 and EMU128 (exp2, exp, log, acos: 1 ulp; log2, sin, cos, asin, atan,
// atan2: 2 ulp; tanh: 3 ulp); 0 means the same bits.
inline std::uint64_t ulp_tolerance(Op op) {
  return static_cast<std::uint64_t>(op_info(op).ulps);  // erf: std::erf itself
}

// pow = exp2(b log2 a) magnifies an error in log2 a by |b log2 a| ln 2 in the result, in the
// scalar reference as in the SIMD code: allowed 4 + 4 |b log2 a| ulp (measured: 4 + 1.6 |.|).
template <typename T>
std::uint64_t pow_tolerance(T a, T b) {
  const double y = std::abs(static_cast<double>(b) * std::log2(static_cast<double>(a)));
  if (!(y < 1e6)) return 0;  // the result is 0, inf or NaN: must be exact
  return 4 + static_cast<std::uint64_t>(4.0 * y);
}

// Both NaN, equal, or within `rel` of each other relative to the larger magnitude, or to
// `floor` when both are smaller than that (cancellation in a sum loses relative accuracy).
inline bool close(double a, double b, double rel, double floor = 0.0) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (a == b) return true;
  return std::abs(a - b) <= rel * std::max({std::abs(a), std::abs(b), floor});
}

// Column-major inputs with uniform values in [lo, hi).
template <typename T>
struct Inputs {
  std::vector<std::vector<T>> columns;
  std::size_t rows = 0;

  Inputs(Rng& rng, std::size_t num_vars, std::size_t n, double lo, double hi) : rows(n) {
    columns.resize(num_vars);
    for (auto& c : columns)
      for (std::size_t i = 0; i < n; ++i) c.push_back(static_cast<T>(uniform(rng, lo, hi)));
  }
  template <typename U>
  explicit Inputs(const Inputs<U>& other) : rows(other.rows) {
    for (const auto& c : other.columns) columns.emplace_back(c.begin(), c.end());
  }
  [[nodiscard]] std::vector<double> row(std::size_t i) const {
    std::vector<double> r;
    for (const auto& c : columns) r.push_back(static_cast<double>(c[i]));
    return r;
  }
};

template <typename T>
std::vector<T> run(const Expression& e, const Inputs<T>& in, const EvalOptions& options = {},
                   eval_detail::Backend backend = eval_detail::Backend::Simd) {
  std::vector<const T*> pointers;
  for (const auto& c : in.columns) pointers.push_back(c.data());
  std::vector<T> out(in.rows);
  eval_detail::evaluate_with_backend(e, std::span<const T* const>(pointers), std::span<T>(out),
                                     options, backend);
  return out;
}

// One row through the batched float path.
inline float eval1(const Expression& e, float x, float y) {
  const float values[] = {x, y, 0.0f};
  const float* columns[] = {&values[0], &values[1], &values[2]};
  float out = 0;
  evaluate(e, std::span<const float* const>(columns, e.variables.size()),
           std::span<float>(&out, 1));
  return out;
}

// A random tree over variables x0..x{num_vars-1}, constants and one parameter, at most depth 4.
inline void grow(Rng& rng, int depth, int num_vars, bool arithmetic_only, std::vector<Node>& out) {
  // The operators in enum order, the arithmetic ones first and CopySign last of them: it is left
  // out with the library ones (op.hpp), whose NaNs carry a sign bit that differs between the
  // SIMD functions and libm, and copysign reads that bit.
  static constexpr auto kOps = [] {
    std::array<Op, kOpCount> ops{};
    std::size_t n = 0;
    for (bool library : {false, true})
      for (int i = 0; i < kOpCount; ++i) {
        const Op op = static_cast<Op>(i);
        if (!is_leaf(op) && op_info(op).library == library && op != Op::CopySign) ops[n++] = op;
        if (!library && i == kOpCount - 1) ops[n++] = Op::CopySign;
      }
    return ops;
  }();
  static constexpr std::size_t kArithmeticCount = [] {
    std::size_t n = 0;
    for (int i = 0; i < kOpCount; ++i)
      n += !is_leaf(static_cast<Op>(i)) && !op_info(static_cast<Op>(i)).library;
    return n;
  }();
  static constexpr std::span<const Op> kArithmetic(kOps.data(), kArithmeticCount);
  static constexpr std::span<const Op> kOther(kOps.data() + kArithmeticCount,
                                              kOpCount - 3 - kArithmeticCount);
  if (depth == 0 || bernoulli(rng, 0.25)) {
    const double r = uniform01(rng);
    if (r < 0.6)
      out.push_back(Node::variable(static_cast<int>(uniform_index(rng, num_vars))));
    else if (r < 0.9)
      out.push_back(Node::constant(uniform(rng, -2.0, 2.0)));
    else
      out.push_back(Node::parameter(0));
    return;
  }
  const std::size_t n_arith = std::size(kArithmetic) - (arithmetic_only ? 0 : 1);
  const std::size_t pick =
      uniform_index(rng, arithmetic_only ? n_arith : n_arith + std::size(kOther));
  const Op op = pick < n_arith ? kArithmetic[pick] : kOther[pick - n_arith];
  for (int i = 0; i < arity(op); ++i) grow(rng, depth - 1, num_vars, arithmetic_only, out);
  out.push_back(op == Op::IPow ? Node::ipow(static_cast<int>(uniform_index(rng, 10)) - 4)
                               : Node::op_node(op));
}

inline Expression random_expression(Rng& rng, int num_vars, bool arithmetic_only) {
  Expression e;
  for (int i = 0; i < num_vars; ++i) e.variables.push_back("x" + std::to_string(i));
  e.parameters = {"p"};
  e.parameter_values = {0.75};
  grow(rng, 4, num_vars, arithmetic_only, e.nodes);
  e.update_lengths();
  return e;
}

inline std::vector<Expression> formulas() {
  std::vector<Expression> out;
  for (auto& f : eval_detail::sample_formulas()) out.push_back(std::move(f.expression));
  return out;
}

}  // namespace shaderfit::eval_test
