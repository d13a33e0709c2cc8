#include "shaderfit/eval/evaluate.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <string_view>
#include <vector>

#include "eval/eval_test_support.hpp"
#include "eval/interpreter.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit {
namespace {

using namespace eval_test;

// ---------------------------------------------------------------------------------------------
// Every op against the scalar reference, for every SIMD target this CPU runs.

// The largest error seen per op over all targets, printed at the end of the test.
template <typename T>
std::map<std::string_view, std::uint64_t>& worst_ulp() {
  static std::map<std::string_view, std::uint64_t> m;
  return m;
}
// The largest (pow error - 4 ulp) / |b log2 a|.
template <typename T>
double& pow_excess() {
  static double v = 0;
  return v;
}

template <typename T>
void check_op(Op op, int k, Rng& rng) {
  const int n_args = arity(op);
  const std::vector<T> pool = test_values<T>(rng, 20000);
  // Unary: every pool value. Binary and fma: every pair of edge values, then random pairs.
  std::vector<std::vector<T>> args(static_cast<std::size_t>(n_args));
  if (n_args == 1) {
    args[0] = pool;
  } else {
    const std::vector<T> edges = edge_values<T>();
    for (T x : edges)
      for (T y : edges) {
        args[0].push_back(x);
        args[1].push_back(y);
      }
    if (n_args == 3)  // the third operand: random pool values
      for (std::size_t i = 0; i < args[0].size(); ++i)
        args[2].push_back(pool[uniform_index(rng, pool.size())]);
    while (args[0].size() < 6000)
      for (auto& column : args) column.push_back(pool[uniform_index(rng, pool.size())]);
  }
  const Expression e = single_op(op, k);
  const std::size_t rows = args[0].size();
  std::vector<const T*> columns(args.size());
  for (std::size_t j = 0; j < args.size(); ++j) columns[j] = args[j].data();
  std::vector<T> out(rows);
  evaluate(e, std::span<const T* const>(columns), std::span<T>(out), {.threads = 1});

  std::uint64_t worst = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    const T x = args[0][i];
    const T y = n_args > 1 ? args[1][i] : T(0);
    const T z = n_args > 2 ? args[2][i] : T(0);
    const T ref = reference<T>(e, op, k, x, y, z);
    const std::uint64_t allowed = op == Op::Pow ? pow_tolerance(x, y) : ulp_tolerance(op);
    const std::uint64_t d = ulp_distance(out[i], ref);
    // C leaves the sign of min(+0, -0) and max(+0, -0) open (glibc and musl differ).
    const bool zero_tie = (op == Op::Min || op == Op::Max) && out[i] == 0 && ref == 0;
    const bool exact =
        same_bits(out[i], ref) || zero_tie || (std::isnan(ref) && std::isnan(out[i]));
    // Infinities and NaN must come out exactly; finite values within the bound.
    const bool special = std::isnan(ref) || std::isinf(ref);
    if ((allowed == 0 || special) ? !exact : d > allowed) {
      ADD_FAILURE() << op_info(op).name << (op == Op::IPow ? std::to_string(k) : "") << "(" << x
                    << ", " << y << ", " << z << "): got " << out[i] << ", want " << ref << " ("
                    << d << " ulp, allowed " << allowed << ")";
      return;
    }
    if (op != Op::Pow) {
      worst = std::max(worst, d);
    } else if (d > 4 && allowed > 0) {
      const double amplification = std::abs(double(y) * std::log2(double(x)));
      pow_excess<T>() = std::max(pow_excess<T>(), double(d - 4) / amplification);
    }
  }
  std::uint64_t& w = worst_ulp<T>()[op_info(op).name];
  w = std::max(w, worst);
}

template <typename T>
void check_all_ops() {
  for (std::int64_t target : eval_detail::simd_targets()) {
    SCOPED_TRACE(eval_detail::simd_target_name(target));
    const ForceTarget force(target);
    Rng rng(7);
    for (int i = 0; i < kOpCount; ++i) {
      const Op op = static_cast<Op>(i);
      if (is_leaf(op)) continue;
      if (op == Op::IPow) {
        for (int k = kMinIntegerPower; k <= kMaxIntegerPower; ++k) check_op<T>(op, k, rng);
      } else {
        check_op<T>(op, 0, rng);
      }
    }
  }
  std::string report;
  for (const auto& [name, ulp] : worst_ulp<T>())
    if (ulp > 0) report += std::string(name) + " " + std::to_string(ulp) + " ulp, ";
  std::printf("largest errors: %s pow excess %g\n", report.c_str(), pow_excess<T>());
}

TEST(EvalOps, EveryOpMatchesScalarFloat) { check_all_ops<float>(); }
TEST(EvalOps, EveryOpMatchesScalarDouble) { check_all_ops<double>(); }

TEST(EvalOps, SpecialValues) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  constexpr float kPi = 3.14159265358979f, kHalfPi = 1.57079632679490f,
                  kQuarterPi = 0.785398163397448f;
  struct Case {
    Op op;
    float x, y, want;
  };
  const Case cases[] = {
      {Op::Log2, 0.0f, 0, -inf},
      {Op::Log2, -0.0f, 0, -inf},
      {Op::Log2, inf, 0, inf},
      {Op::Log, 0.0f, 0, -inf},
      {Op::Exp2, 200.0f, 0, inf},
      {Op::Exp2, -inf, 0, 0.0f},
      {Op::Exp2, 128.0f, 0, inf},
      {Op::Exp2, -200.0f, 0, 0.0f},
      {Op::Exp, 1000.0f, 0, inf},
      {Op::Exp, -inf, 0, 0.0f},
      {Op::Exp, inf, 0, inf},
      {Op::Rcp, 0.0f, 0, inf},
      {Op::Rcp, -0.0f, 0, -inf},
      {Op::Rsqrt, 0.0f, 0, inf},
      {Op::Exp2, 3.0f, 0, 8.0f},
      {Op::Log2, 8.0f, 0, 3.0f},
      {Op::Log2, 0x1p-149f, 0, -149.0f},
      {Op::Pow, 0.0f, 2.0f, 0.0f},
      {Op::Pow, 2.0f, 3.0f, 8.0f},
      {Op::Min, NAN, 1.0f, 1.0f},
      {Op::Max, 1.0f, NAN, 1.0f},
      {Op::Saturate, -inf, 0, 0.0f},
      {Op::Cos, 0.0f, 0, 1.0f},
      {Op::Sign, -0.0f, 0, -0.0f},
      {Op::Sign, 0.0f, 0, 0.0f},
      {Op::Sign, -inf, 0, -1.0f},
      {Op::Sign, 1e-45f, 0, 1.0f},
      {Op::CopySign, 2.0f, -0.0f, -2.0f},
      {Op::CopySign, -inf, 0.0f, inf},
      {Op::CopySign, -3.0f, NAN, 3.0f},  // the NaN's sign bit is clear
      {Op::Select, -0.0f, 5.0f, 5.0f},   // select(x, y, 0): -0 >= 0 takes y
      {Op::Select, -1e-45f, 5.0f, 0.0f},
      {Op::Select, NAN, 5.0f, 0.0f},  // NaN takes the third operand
      {Op::Select, inf, 5.0f, 5.0f},
      {Op::Asin, -0.0f, 0, -0.0f},
      {Op::Asin, 1.0f, 0, kHalfPi},
      {Op::Acos, 1.0f, 0, 0.0f},
      {Op::Acos, -1.0f, 0, kPi},
      {Op::Atan, -inf, 0, -kHalfPi},
      {Op::Atan, -0.0f, 0, -0.0f},
      {Op::Tanh, inf, 0, 1.0f},
      {Op::Tanh, -0.0f, 0, -0.0f},
      {Op::Tanh, 1e-30f, 0, 1e-30f},
      {Op::Tanh, -1e-40f, 0, -1e-40f},  // subnormal
      {Op::Erf, -inf, 0, -1.0f},
      {Op::Erf, -0.0f, 0, -0.0f},
      {Op::Atan2, 0.0f, -0.0f, kPi},  // both zero: the signs decide
      {Op::Atan2, -0.0f, -1.0f, -kPi},
      {Op::Atan2, -0.0f, 0.0f, -0.0f},
      {Op::Atan2, inf, inf, kQuarterPi},
      {Op::Atan2, -inf, -inf, -3 * kQuarterPi},
      {Op::Atan2, 1.0f, -inf, kPi},
      {Op::Atan2, inf, -0.0f, kHalfPi},
      {Op::Atan2, 1e-30f, 1e30f, 0.0f},
  };
  const Op nan_ops[] = {Op::Log2, Op::Log,  Op::Sqrt, Op::Saturate, Op::Sin,  Op::Cos, Op::Exp2,
                        Op::Sign, Op::Asin, Op::Acos, Op::Atan,     Op::Tanh, Op::Erf, Op::Acos};
  const float nan_args[] = {-1.0f, -1.0f, -1.0f, NAN, inf, -inf, NAN,
                            NAN,   1.5f,  -inf,  NAN, NAN, NAN,  -1.0001f};
  for (std::int64_t target : eval_detail::simd_targets()) {
    SCOPED_TRACE(eval_detail::simd_target_name(target));
    const ForceTarget force(target);
    for (const Case& c : cases) {
      const float got = eval1(single_op(c.op, 0), c.x, c.y);
      EXPECT_TRUE(same_bits(got, c.want)) << op_info(c.op).name << "(" << c.x << ", " << c.y
                                          << ") = " << got << ", want " << c.want;
    }
    for (std::size_t i = 0; i < std::size(nan_ops); ++i)
      EXPECT_TRUE(std::isnan(eval1(single_op(nan_ops[i], 0), nan_args[i], 0.0f)))
          << op_info(nan_ops[i]).name << "(" << nan_args[i] << ")";
    EXPECT_TRUE(std::isnan(eval1(single_op(Op::Pow, 0), -2.0f, 2.0f)));  // a < 0
    EXPECT_TRUE(std::isnan(eval1(single_op(Op::Pow, 0), 0.0f, 0.0f)));   // 0 * log2(0)
    EXPECT_TRUE(std::isnan(eval1(single_op(Op::Atan2, 0), NAN, 1.0f)));
    EXPECT_TRUE(std::isnan(eval1(single_op(Op::Atan2, 0), inf, NAN)));
  }
}

}  // namespace
}  // namespace shaderfit
