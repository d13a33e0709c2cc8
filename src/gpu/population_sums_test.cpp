// The batched population evaluation and the normal-equation sums, as the GPU kernels compute
// them (same lanes, chunks and fold order), run on the CPU through the shared code and compared
// with the CPU path: evaluate() + loss_of / fit_linear_scaling, and plain loops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "gpu/pack.hpp"
#include "gpu/population_test_util.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/linear.hpp"

namespace shaderfit::gpu_detail {
namespace {

using gpu_test::HostPopulation;
using gpu_test::OpSet;
using gpu_test::RandomColumns;

bool near(double got, double want, double rel) {
  if (std::isnan(want)) return std::isnan(got);
  if (std::isinf(want)) return got == want;
  return std::abs(got - want) <= rel * std::abs(want) + 1e-300;
}

// The CPU path's prediction of e (float32 evaluation, as the GPU), widened to double.
std::vector<double> cpu_prediction(const Expression& e, const RandomColumns& in, std::size_t rows) {
  std::vector<std::vector<float>> cols;
  std::vector<const float*> ptrs;
  for (const auto& c : in.values) cols.emplace_back(c.begin(), c.end());
  for (const auto& c : cols) ptrs.push_back(c.data());
  std::vector<float> f(rows);
  evaluate(e, ptrs, f, {.threads = 1});
  return {f.begin(), f.end()};
}

constexpr Loss kLosses[] = {Loss::Mse, Loss::Rmse, Loss::MaxAbs, Loss::Relative, Loss::Log};

TEST(GpuKernelLogic, PopulationLossesMatchTheCpuPath) {
  // Three chunk counts (one partial chunk, one exact chunk plus a tail, several), weights with
  // zeros, every loss; formulas whose float32 values the CPU evaluator gives exactly, so only
  // the order of the float64 sums differs.
  Rng rng(91);
  const std::vector<std::string> vars = {"u", "v", "w"};
  for (std::size_t rows : {std::size_t{1000}, kChunkRows + 77, 3 * kChunkRows + 5}) {
    const RandomColumns in(rng, 3, rows, 0.1, 2.0);
    std::vector<double> y(rows), w(rows);
    for (std::size_t r = 0; r < rows; ++r) {
      y[r] = uniform(rng, 0.2, 3.0);
      w[r] = bernoulli(rng, 0.1) ? 0.0 : uniform(rng, 0.5, 2.0);
    }
    const std::vector<Expression> pop =
        gpu_test::random_population(rng, 40, vars, 10, 30, OpSet::Exact, true);
    const std::vector<const Expression*> ptrs = gpu_test::pointers_to(pop);
    HostPopulation host(ptrs, in.pointers, y, w);
    for (Loss loss : kLosses) {
      const std::vector<RowSums> sums = emulate_population(host.view(loss), pop.size());
      for (std::size_t i = 0; i < pop.size(); ++i) {
        const std::vector<double> f = cpu_prediction(pop[i], in, rows);
        const double want = loss_of(loss, f, y, w);
        const double got = loss_from_sums(loss, sums[i]);
        ASSERT_TRUE(near(got, want, 1e-10)) << "rows " << rows << " loss " << loss_name(loss)
                                            << " formula " << i << ": " << got << " vs " << want;
      }
    }
  }
}

TEST(GpuKernelLogic, LinearScalingFromTheSums) {
  // The scaling from the returned sums is fit_linear_scaling's; the loss of the scaled formula
  // (the second launch) is loss_of of a * f + b.
  Rng rng(92);
  const std::vector<std::string> vars = {"x", "y"};
  const std::size_t rows = 2500;
  const RandomColumns in(rng, 2, rows, 0.1, 1.0);
  std::vector<double> target(rows), weights(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    target[r] = 0.3 + in.values[0][r] * in.values[1][r];
    weights[r] = uniform(rng, 0.0, 2.0);
  }
  const std::vector<Expression> pop =
      gpu_test::random_population(rng, 30, vars, 10, 20, OpSet::Exact);
  const std::vector<const Expression*> ptrs = gpu_test::pointers_to(pop);
  HostPopulation host(ptrs, in.pointers, target, weights);
  double sw = 0, swy = 0, syy = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    sw += weights[r];
    swy += weights[r] * target[r];
  }
  for (std::size_t r = 0; r < rows; ++r)
    syy += weights[r] * (target[r] - swy / sw) * (target[r] - swy / sw);
  const std::vector<RowSums> raw = emulate_population(host.view(Loss::Mse), pop.size());
  for (std::size_t i = 0; i < pop.size(); ++i) {
    std::vector<double> f = cpu_prediction(pop[i], in, rows);
    const PopulationScore score = to_score(raw[i], Loss::Mse, syy);
    const LinearScaling want = fit_linear_scaling(f, target, weights);
    const LinearScaling got = score.linear_scaling();
    if (!std::isfinite(want.mse)) {
      EXPECT_FALSE(score.finite);
      continue;
    }
    if (std::all_of(f.begin(), f.end(), [&](double v) { return v == f[0]; })) {
      // A constant: a = 0 from the moments; the CPU's two-pass sums leave round-off in f - mean.
      EXPECT_EQ(got.a, 0.0) << i;
      continue;
    }
    EXPECT_TRUE(near(got.a, want.a, 1e-7)) << i << ": " << got.a << " vs " << want.a;
    EXPECT_TRUE(near(got.b, want.b, 1e-7) || std::abs(got.b - want.b) < 1e-9) << i;
    EXPECT_TRUE(near(got.mse, want.mse, 1e-4) || std::abs(got.mse - want.mse) < 1e-12) << i;
    host.affine.assign(pop.size(), Affine{});
    host.affine[i] = {got.a, got.b};
    for (Loss loss : {Loss::Mse, Loss::MaxAbs}) {
      const RowSums scaled = emulate_population(host.view(loss), pop.size())[i];
      std::vector<double> p = f;
      for (double& v : p) v = got.a * v + got.b;
      EXPECT_TRUE(near(loss_from_sums(loss, scaled), loss_of(loss, p, target, weights), 1e-9))
          << i << " " << loss_name(loss);
    }
  }
}

TEST(GpuKernelLogic, NonFiniteAndUnsuitableTargets) {
  ParseOptions po;
  po.variables = {"x"};
  const Expression blow = parse_formula("1 / (x - x)", po);
  const Expression fine = parse_formula("x * 2", po);
  const std::vector<const Expression*> pop = {&blow, &fine};
  const std::vector<double> x = {0.5, 1.0, 1.5, 2.0};
  const std::vector<const double*> cols = {x.data()};
  const std::vector<double> y = {1.0, 0.0, 3.0, 4.0};  // a zero: no relative or log loss
  HostPopulation host(pop, cols, y);
  for (Loss loss : kLosses) {
    const std::vector<RowSums> s = emulate_population(host.view(loss), 2);
    std::vector<double> p = {1.0, 2.0, 3.0, 4.0};
    EXPECT_EQ(loss_from_sums(loss, s[0]), std::numeric_limits<double>::infinity());
    EXPECT_TRUE(near(loss_from_sums(loss, s[1]), loss_of(loss, p, y), 1e-12)) << loss_name(loss);
    EXPECT_FALSE(to_score(s[0], loss, 0).finite);
  }
}

TEST(GpuKernelLogic, AllOperatorsWithinFloat32Tolerance) {
  // The CPU evaluator's exp2, log2, sin, ... are SIMD approximations and the GPU's are CUDA's:
  // both within a few ulp of libm, so losses agree to float32 tolerance (a formula that
  // magnifies an ulp without bound may not; nearly all must). Formulas with copysign are left
  // out: with a NaN second operand it copies that NaN's sign bit, which x86 and CUDA set
  // differently (op.hpp); InterpreterGivesTheScalarSemanticsBitForBit covers it on the CPU.
  Rng rng(93);
  const std::vector<std::string> vars = {"x", "y"};
  const std::size_t rows = 4096;
  const RandomColumns in(rng, 2, rows, 0.05, 2.0);
  std::vector<double> y(rows);
  for (double& t : y) t = uniform(rng, 0.1, 1.0);
  std::vector<Expression> pop = gpu_test::random_population(rng, 300, vars, 10, 30, OpSet::All);
  std::erase_if(pop, [](const Expression& e) {
    return std::any_of(e.nodes.begin(), e.nodes.end(),
                       [](const Node& n) { return n.op == Op::CopySign; });
  });
  const std::vector<const Expression*> ptrs = gpu_test::pointers_to(pop);
  HostPopulation host(ptrs, in.pointers, y);
  const std::vector<RowSums> sums = emulate_population(host.view(Loss::Mse), pop.size());
  int far = 0, finite = 0;
  for (std::size_t i = 0; i < pop.size(); ++i) {
    const double want = loss_of(Loss::Mse, cpu_prediction(pop[i], in, rows), y);
    const double got = loss_from_sums(Loss::Mse, sums[i]);
    finite += std::isfinite(want) ? 1 : 0;
    far += near(got, want, 1e-4) ? 0 : 1;
  }
  EXPECT_GT(finite, 30);
  EXPECT_LE(far, static_cast<int>(pop.size() / 50))
      << far << " of " << pop.size() << " formulas differ";
}

TEST(GpuKernelLogic, NormalEquationSumsMatchPlainLoops) {
  ParseOptions po;
  po.variables = {"x", "y"};
  const Expression g1 = parse_formula("x", po), g2 = parse_formula("x^2", po),
                   g3 = parse_formula("x * y - 1", po), g0 = parse_formula("y / 2", po);
  const std::vector<const Expression*> basis = {&g1, &g2, &g3};
  Rng rng(94);
  for (std::size_t rows : {std::size_t{100}, 2 * kChunkRows + 3}) {
    const RandomColumns in(rng, 2, rows, -1.0, 1.0);
    std::vector<double> y(rows), w(rows);
    for (std::size_t r = 0; r < rows; ++r) {
      y[r] = uniform(rng, -1.0, 1.0);
      w[r] = bernoulli(rng, 0.2) ? 0.0 : 1.5;
    }
    std::vector<const Expression*> all = basis;
    all.push_back(&g0);
    HostPopulation host(all, in.pointers, y, w);
    for (bool offset : {false, true}) {
      const NormalSums got = emulate_normal_sums(host.view(Loss::Mse), 3, offset);
      std::vector<std::vector<double>> g;
      for (const Expression* e : all) g.push_back(cpu_prediction(*e, in, rows));
      double jtj[3][3] = {}, jtr[3] = {}, rr = 0;
      for (std::size_t r = 0; r < rows; ++r) {
        if (!(w[r] > 0)) continue;
        const double res = y[r] - (offset ? g[3][r] : 0.0);
        rr += w[r] * res * res;
        for (int i = 0; i < 3; ++i) {
          jtr[i] += w[r] * g[static_cast<std::size_t>(i)][r] * res;
          for (int j = 0; j < 3; ++j)
            jtj[i][j] +=
                w[r] * g[static_cast<std::size_t>(i)][r] * g[static_cast<std::size_t>(j)][r];
        }
      }
      EXPECT_EQ(got.bad, 0u);
      EXPECT_TRUE(near(got.rr, rr, 1e-10));
      for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(near(got.jtr[i], jtr[i], 1e-9)) << i;
        for (int j = i; j < 3; ++j)
          EXPECT_TRUE(near(got.jtj[packed_index(i, j, 3)], jtj[i][j], 1e-10)) << i << j;
      }
    }
  }
}

}  // namespace
}  // namespace shaderfit::gpu_detail
