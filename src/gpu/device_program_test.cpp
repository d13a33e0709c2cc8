// The GPU kernels' per-row interpreter and the packing, run on the CPU (no GPU needed): the
// shared SF_CPU_GPU code against the scalar semantics and the CPU evaluator.
#include "gpu/device_program.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "expr/random_expression_test_util.hpp"
#include "gpu/pack.hpp"
#include "gpu/population_test_util.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit::gpu_detail {
namespace {

// Same bits, NaN matching NaN and +0 matching -0 (the sign of min(+0, -0) is left open).
bool same_value(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) ||
         (std::isnan(a) && std::isnan(b)) || (a == 0 && b == 0);
}

struct Rows {
  std::vector<float> columns;  // variable v of row r at v * rows + r
  std::size_t rows = 0, vars = 0;
  Rows(Rng& rng, std::size_t v, std::size_t n, double lo, double hi) : rows(n), vars(v) {
    for (std::size_t i = 0; i < v * n; ++i)
      columns.push_back(static_cast<float>(uniform(rng, lo, hi)));
  }
  [[nodiscard]] std::vector<float> row(std::size_t r) const {
    std::vector<float> x;
    for (std::size_t v = 0; v < vars; ++v) x.push_back(columns[v * rows + r]);
    return x;
  }
  [[nodiscard]] std::vector<const float*> pointers() const {
    std::vector<const float*> p;
    for (std::size_t v = 0; v < vars; ++v) p.push_back(columns.data() + v * rows);
    return p;
  }
};

// run_program for every row, four rows at a time when `four`.
std::vector<float> run_all(const PackedPrograms& p, std::size_t program, const Rows& in,
                           bool four) {
  const GpuNode* code = p.nodes.data() + p.offsets[program];
  const std::uint32_t count = p.offsets[program + 1] - p.offsets[program];
  std::vector<float> out(in.rows);
  for (std::size_t r = 0; r < in.rows; r += four ? 4 : 1) {
    if (four && r + 4 <= in.rows) {
      const std::size_t rows[4] = {r + 2, r, r + 3, r + 1};  // any order of rows
      float v[4];
      run_program<4>(code, count, in.columns.data(), in.rows, rows, v);
      for (int j = 0; j < 4; ++j) out[rows[j]] = v[j];
    } else {
      for (std::size_t s = r; s < std::min(in.rows, r + (four ? 4 : 1)); ++s) {
        const std::size_t row[1] = {s};
        float v[1];
        run_program<1>(code, count, in.columns.data(), in.rows, row, v);
        out[s] = v[0];
      }
    }
  }
  return out;
}

TEST(GpuKernelLogic, InterpreterGivesTheScalarSemanticsBitForBit) {
  // Every operator, with parameters: the interpreter computes apply_* in float32, as the
  // float reference does, so every row has the same bits.
  Rng rng(81);
  const std::vector<std::string> vars = {"a", "b", "c"};
  for (int trial = 0; trial < 300; ++trial) {
    const Expression e = testing::random_expression(rng, vars, 5, /*with_param=*/true);
    const Rows in(rng, 3, 37, -3.0, 3.0);
    PackedPrograms p;
    append_program(p, e, 3);
    for (bool four : {false, true}) {
      const std::vector<float> got = run_all(p, 0, in, four);
      for (std::size_t r = 0; r < in.rows; ++r) {
        const float want = testing::eval_reference<float>(e, in.row(r));
        ASSERT_TRUE(same_value(got[r], want))
            << "trial " << trial << " row " << r << ": " << got[r] << " vs " << want;
      }
    }
  }
}

TEST(GpuKernelLogic, InterpreterMatchesTheCpuEvaluator) {
  // With the operators the CPU evaluator computes exactly, the same bits; with all of them
  // (its exp2, log2, sin, ... are SIMD approximations), within float32 tolerance.
  Rng rng(82);
  const std::vector<std::string> vars = {"x", "y"};
  std::size_t rows_total = 0, far = 0;
  for (gpu_test::OpSet set : {gpu_test::OpSet::Exact, gpu_test::OpSet::All}) {
    for (int trial = 0; trial < 200; ++trial) {
      const Expression e = gpu_test::random_formula_of_size(rng, vars, 10, 30, set, true);
      const Rows in(rng, 2, 300, 0.05, 2.0);
      PackedPrograms p;
      append_program(p, e, 2);
      const std::vector<float> got = run_all(p, 0, in, true);
      std::vector<float> want(in.rows);
      evaluate(e, in.pointers(), want, {.threads = 1});
      for (std::size_t r = 0; r < in.rows; ++r) {
        if (set == gpu_test::OpSet::Exact) {
          ASSERT_TRUE(same_value(got[r], want[r]))
              << "trial " << trial << " row " << r << ": " << got[r] << " vs " << want[r];
          continue;
        }
        ++rows_total;
        const bool close = same_value(got[r], want[r]) ||
                           std::abs(got[r] - want[r]) <= 1e-4f * std::abs(want[r]) + 1e-6f;
        far += close ? 0 : 1;
      }
    }
  }
  // An expression can magnify an ulp without bound (a difference that crosses zero before a
  // log); nearly every row must agree.
  EXPECT_LE(far, rows_total / 200) << far << " of " << rows_total << " rows differ";
}

TEST(GpuKernelLogic, PackingResolvesParametersAndOffsets) {
  ParseOptions po;
  po.variables = {"x"};
  po.parameters = {"a"};
  po.parameter_values = {0.25};
  const Expression e1 = parse_formula("a * x + 1", po);
  const Expression e2 = parse_formula("x^3", po);
  const std::vector<const Expression*> all = {&e1, &e2};
  const PackedPrograms p = pack_programs(all, 1);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.offsets, (std::vector<std::uint32_t>{0, 5, 7}));
  EXPECT_EQ(p.nodes[0].op, Op::Param);
  EXPECT_EQ(p.nodes[0].value, 0.25f);
  EXPECT_EQ(p.nodes[6].op, Op::IPow);
  EXPECT_EQ(p.nodes[6].index, 3);
  EXPECT_EQ(p.max_stack, 2);
}

TEST(GpuKernelLogic, PackingRejectsWhatTheKernelsCannotRun) {
  ParseOptions po;
  po.variables = {"x", "y"};
  const Expression ok = parse_formula("x + y", po);
  PackedPrograms p;
  EXPECT_THROW(append_program(p, ok, 3), Error);  // variable count
  Expression bad = ok;
  bad.nodes.pop_back();  // two trees
  EXPECT_THROW(append_program(p, bad, 2), Error);
  Expression missing = ok;
  missing.nodes[0] = Node::parameter(0);  // no parameter value
  EXPECT_THROW(append_program(p, missing, 2), Error);
  Expression power = parse_formula("x^2", po);
  power.nodes.back().index = 17;
  EXPECT_THROW(append_program(p, power, 2), Error);
  // x + (x + (x + ...)): a stack one deeper per level.
  Expression deep;
  deep.variables = {"x", "y"};
  for (int i = 0; i < kMaxStack + 1; ++i) deep.nodes.push_back(Node::variable(0));
  for (int i = 0; i < kMaxStack; ++i) deep.nodes.push_back(Node::op_node(Op::Add));
  deep.update_lengths();
  EXPECT_THROW(append_program(p, deep, 2), Error);
  EXPECT_EQ(p.size(), 0u);  // nothing half-appended
  EXPECT_TRUE(p.nodes.empty());
  deep.nodes.erase(deep.nodes.begin());
  deep.nodes.pop_back();
  deep.update_lengths();
  EXPECT_NO_THROW(append_program(p, deep, 2));  // exactly kMaxStack deep
}

}  // namespace
}  // namespace shaderfit::gpu_detail
