// Device selection (runs everywhere) and the GPU backend against its CPU emulation and the CPU
// path (GpuDevice.*: skipped with "skipped: no CUDA device" where there is none).
#include "shaderfit/gpu/device.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gpu/pack.hpp"
#include "gpu/population_test_util.hpp"
#include "gpu/screen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/gpu/evaluator.hpp"

namespace shaderfit {
namespace {

using gpu_detail::emulate_population;
using gpu_detail::to_score;
using gpu_test::HostPopulation;
using gpu_test::OpSet;
using gpu_test::RandomColumns;

#define SF_REQUIRE_GPU() \
  if (!cuda_available()) GTEST_SKIP() << "skipped: " << cuda_unavailable_reason()

bool near(double got, double want, double rel) {
  if (std::isnan(want)) return std::isnan(got);
  if (std::isinf(want)) return got == want;
  return std::abs(got - want) <= rel * std::abs(want) + 1e-300;
}

// ---------------------------------------------------------------------------------------------
// Selection: the same answers with and without a GPU.

TEST(GpuSelection, DeviceNames) {
  for (ComputeDevice d : {ComputeDevice::Auto, ComputeDevice::Cpu, ComputeDevice::Cuda})
    EXPECT_EQ(device_from_name(device_name(d)), d);
  EXPECT_EQ(device_from_name("gpu"), ComputeDevice::Cuda);
  EXPECT_FALSE(device_from_name("tpu").has_value());
}

TEST(GpuSelection, ResolveFollowsAvailability) {
#ifdef SHADERFIT_HAVE_CUDA
  EXPECT_TRUE(cuda_built());
#else
  EXPECT_FALSE(cuda_built());
  EXPECT_FALSE(cuda_available());
  EXPECT_NE(cuda_unavailable_reason().find("no CUDA support"), std::string::npos);
#endif
  EXPECT_EQ(resolve_device(ComputeDevice::Cpu), ComputeDevice::Cpu);
  EXPECT_EQ(resolve_device(ComputeDevice::Auto),
            cuda_available() ? ComputeDevice::Cuda : ComputeDevice::Cpu);
  if (cuda_available()) {
    EXPECT_EQ(resolve_device(ComputeDevice::Cuda), ComputeDevice::Cuda);
    EXPECT_FALSE(cuda_device_name().empty());
    EXPECT_TRUE(cuda_unavailable_reason().empty());
    return;
  }
  EXPECT_TRUE(cuda_device_name().empty());
  try {
    resolve_device(ComputeDevice::Cuda);
    ADD_FAILURE() << "no error without a GPU";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "ComputeDevice");
    EXPECT_NE(e.message().find("cannot use the GPU: "), std::string::npos) << e.what();
    EXPECT_EQ(e.message().find('\n'), std::string::npos);
  }
}

TEST(GpuSelection, WithoutAGpuTheGpuApiThrows) {
  if (cuda_available()) GTEST_SKIP() << "a CUDA device is present";
  const std::vector<double> x = {1, 2, 3}, y = {1, 2, 3};
  const std::vector<const double*> cols = {x.data()};
  EXPECT_THROW(GpuEvaluator(cols, y), Error);
  const std::vector<float> t(16, 1.0f);
  EXPECT_THROW(gpu_detail::GpuScreen(t, t, {}, 16.0, Loss::Mse), Error);
}

// ---------------------------------------------------------------------------------------------
// The GPU against the CPU.

TEST(GpuDevice, PopulationMatchesTheEmulationAndTheCpuPath) {
  SF_REQUIRE_GPU();
  Rng rng(101);
  const std::vector<std::string> vars = {"u", "v", "w"};
  for (std::size_t rows : {std::size_t{256}, std::size_t{4096}, 3 * gpu_detail::kChunkRows + 5}) {
    const RandomColumns in(rng, 3, rows, 0.1, 2.0);
    std::vector<double> y(rows), w(rows);
    for (std::size_t r = 0; r < rows; ++r) {
      y[r] = uniform(rng, 0.2, 3.0);
      w[r] = bernoulli(rng, 0.1) ? 0.0 : uniform(rng, 0.5, 2.0);
    }
    const double syy = 0;  // only the losses and f's moments are compared
    const GpuEvaluator gpu(in.pointers, y, w);
    for (OpSet set : {OpSet::Exact, OpSet::All}) {
      const std::vector<Expression> pop =
          gpu_test::random_population(rng, 200, vars, 10, 30, set, true);
      const std::vector<const Expression*> ptrs = gpu_test::pointers_to(pop);
      HostPopulation host(ptrs, in.pointers, y, w);
      for (Loss loss : {Loss::Mse, Loss::MaxAbs, Loss::Relative, Loss::Log}) {
        const std::vector<PopulationScore> got = gpu.evaluate_population(ptrs, loss);
        const std::vector<gpu_detail::RowSums> emu =
            emulate_population(host.view(loss), pop.size());
        int far = 0;
        for (std::size_t i = 0; i < pop.size(); ++i) {
          const PopulationScore want = to_score(emu[i], loss, syy);
          // Exact operators: the same float32 values and the same order of float64 sums; only
          // the log loss's float64 log may differ by an ulp. Others: CUDA's exp2, sin, ... are
          // within 2 ulp of the CPU's, which a formula may magnify.
          const bool ok = set == OpSet::Exact
                              ? near(got[i].loss, want.loss, loss == Loss::Log ? 1e-12 : 0.0) &&
                                    got[i].sfy == want.sfy
                              : near(got[i].loss, want.loss, 1e-4);
          if (set == OpSet::Exact) {
            EXPECT_TRUE(ok) << "rows " << rows << " formula " << i << ": " << got[i].loss << " vs "
                            << want.loss;
          }
          far += ok ? 0 : 1;
        }
        EXPECT_LE(far, 4) << "rows " << rows << " loss " << loss_name(loss);
      }
    }
  }
}

TEST(GpuDevice, LibraryFunctionsMatchTheEmulation) {
  // asin ... erf on the GPU (CUDA's asinf ... erff, full precision) against the CPU emulation of
  // the kernels (the C library's, in float32): both within a few ulp of the true values.
  SF_REQUIRE_GPU();
  Rng rng(105);
  const std::size_t rows = 4096;
  const RandomColumns in(rng, 2, rows, -1.0, 1.0);
  std::vector<double> y(rows), w(rows, 1.0);
  for (double& t : y) t = uniform(rng, -1.0, 1.0);
  ParseOptions po;
  po.variables = {"x", "y"};
  std::vector<Expression> pop;
  for (const char* f : {"asin(x * 0.99)", "acos(y)", "atan(4 * x) * y", "atan2(y, x)",
                        "atan2(x - y, -0.5)", "tanh(3 * x + y)", "erf(2 * y) - x"})
    pop.push_back(parse_formula(f, po));
  const std::vector<const Expression*> ptrs = gpu_test::pointers_to(pop);
  const GpuEvaluator gpu(in.pointers, y, w);
  HostPopulation host(ptrs, in.pointers, y, w);
  for (Loss loss : {Loss::Mse, Loss::MaxAbs}) {
    const std::vector<PopulationScore> got = gpu.evaluate_population(ptrs, loss);
    const std::vector<gpu_detail::RowSums> emu = emulate_population(host.view(loss), pop.size());
    for (std::size_t i = 0; i < pop.size(); ++i) {
      const PopulationScore want = to_score(emu[i], loss, 0.0);
      EXPECT_TRUE(near(got[i].loss, want.loss, 1e-5)) << to_infix(pop[i]) << " " << loss_name(loss)
                                                      << ": " << got[i].loss << " vs " << want.loss;
      EXPECT_NEAR(got[i].mean_f, want.mean_f, 1e-6) << to_infix(pop[i]);
    }
  }
}

TEST(GpuDevice, ResultsDoNotDependOnTheBatch) {
  SF_REQUIRE_GPU();
  Rng rng(102);
  const std::vector<std::string> vars = {"x", "y"};
  const std::size_t rows = 20000;
  const RandomColumns in(rng, 2, rows, 0.1, 1.0);
  std::vector<double> y(rows);
  for (double& t : y) t = uniform(rng, 0.1, 1.0);
  const GpuEvaluator gpu(in.pointers, y);
  const std::vector<Expression> pop =
      gpu_test::random_population(rng, 64, vars, 10, 30, OpSet::All);
  const std::vector<const Expression*> all = gpu_test::pointers_to(pop);
  const auto together = gpu.evaluate_population(all, Loss::Mse);
  for (std::size_t i = 0; i < pop.size(); i += 7) {
    const auto alone = gpu.evaluate_population(std::span(all).subspan(i, 1), Loss::Mse);
    EXPECT_TRUE(alone[0].loss == together[i].loss ||
                (std::isnan(alone[0].loss) && std::isnan(together[i].loss)));
    EXPECT_EQ(alone[0].mean_f, together[i].mean_f);
  }
}

TEST(GpuDevice, LinearScalingSecondPass) {
  SF_REQUIRE_GPU();
  Rng rng(103);
  const std::size_t rows = 5000;
  const RandomColumns in(rng, 1, rows, 0.0, 1.0);
  std::vector<double> y(rows);
  for (std::size_t r = 0; r < rows; ++r) y[r] = 3.0 * in.values[0][r] * in.values[0][r] - 0.5;
  ParseOptions po;
  po.variables = {"x"};
  const Expression e = parse_formula("x^2", po);
  const std::vector<const Expression*> pop = {&e};
  const GpuEvaluator gpu(in.pointers, y);
  const PopulationScore s = gpu.evaluate_population(pop, Loss::Mse)[0];
  const LinearScaling ls = s.linear_scaling();
  EXPECT_NEAR(ls.a, 3.0, 1e-5);
  EXPECT_NEAR(ls.b, -0.5, 1e-5);
  const PopulationScore scaled = gpu.evaluate_population(pop, Loss::Mse, {&ls, 1})[0];
  EXPECT_LT(scaled.loss, 1e-10);
}

TEST(GpuDevice, AMillionRows) {
  SF_REQUIRE_GPU();
  Rng rng(104);
  const std::size_t rows = 1'000'000;
  const RandomColumns in(rng, 2, rows, 0.1, 1.0);
  std::vector<double> y(rows);
  for (double& t : y) t = uniform(rng, 0.0, 1.0);
  const std::vector<Expression> pop =
      gpu_test::random_population(rng, 6, {"x", "y"}, 10, 30, OpSet::Exact);
  const std::vector<const Expression*> ptrs = gpu_test::pointers_to(pop);
  const GpuEvaluator gpu(in.pointers, y);
  const auto got = gpu.evaluate_population(ptrs, Loss::Mse);
  for (std::size_t i = 0; i < pop.size(); ++i) {
    std::vector<std::vector<float>> cols;
    std::vector<const float*> cp;
    for (const auto& c : in.values) cols.emplace_back(c.begin(), c.end());
    for (const auto& c : cols) cp.push_back(c.data());
    std::vector<float> f(rows);
    evaluate(pop[i], cp, f);
    const std::vector<double> fd(f.begin(), f.end());
    EXPECT_TRUE(near(got[i].loss, loss_of(Loss::Mse, fd, y), 1e-9)) << i;
  }
}

TEST(GpuDevice, NormalEquationsMatchTheEmulation) {
  SF_REQUIRE_GPU();
  ParseOptions po;
  po.variables = {"x", "y"};
  const Expression g1 = parse_formula("x", po), g2 = parse_formula("x * y", po),
                   g0 = parse_formula("y^2", po);
  Rng rng(105);
  const std::size_t rows = 3 * gpu_detail::kChunkRows + 11;
  const RandomColumns in(rng, 2, rows, -1.0, 1.0);
  std::vector<double> y(rows);
  for (double& t : y) t = uniform(rng, -1.0, 1.0);
  const GpuEvaluator gpu(in.pointers, y);
  const std::vector<const Expression*> basis = {&g1, &g2};
  const NormalEquations got = gpu.normal_equations(basis, &g0);
  const std::vector<const Expression*> all = {&g1, &g2, &g0};
  HostPopulation host(all, in.pointers, y);
  const gpu_detail::NormalSums want =
      gpu_detail::emulate_normal_sums(host.view(Loss::Mse), 2, true);
  EXPECT_TRUE(got.finite);
  EXPECT_DOUBLE_EQ(got.rr, want.rr);
  EXPECT_DOUBLE_EQ(got.jtj[0], want.jtj[0]);
  EXPECT_DOUBLE_EQ(got.jtj[1], want.jtj[1]);
  EXPECT_DOUBLE_EQ(got.jtj[2], want.jtj[1]);
  EXPECT_DOUBLE_EQ(got.jtj[3], want.jtj[2]);
  EXPECT_DOUBLE_EQ(got.jtr[0], want.jtr[0]);
  EXPECT_DOUBLE_EQ(got.jtr[1], want.jtr[1]);
}

TEST(GpuDevice, EnumerationStepMatchesTheCpuBitForBit) {
  SF_REQUIRE_GPU();
  Rng rng(106);
  const std::size_t n = 64;
  std::vector<float> y(n), w(n), log2_y(n);
  double wyy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    y[i] = static_cast<float>(uniform(rng, 0.05, 1.0));
    w[i] = 1.0f / n;
    log2_y[i] = std::log2(y[i]);
    wyy += static_cast<double>(w[i]) * y[i] * y[i];
  }
  std::vector<float> store;
  const std::size_t columns = 50;
  for (std::size_t c = 0; c < columns * n; ++c)
    store.push_back(static_cast<float>(uniform(rng, -1.5, 2.0)));
  const gpu_detail::ColumnOp kinds[] = {
      gpu_detail::ColumnOp::AddSub, gpu_detail::ColumnOp::Mul,   gpu_detail::ColumnOp::Div,
      gpu_detail::ColumnOp::IPow,   gpu_detail::ColumnOp::Unary, gpu_detail::ColumnOp::Min,
      gpu_detail::ColumnOp::Max,    gpu_detail::ColumnOp::Pow,   gpu_detail::ColumnOp::CopySign};
  const Op unary[] = {Op::Sqrt, Op::Rcp, Op::Exp2,     Op::Log2, Op::Exp,
                      Op::Log,  Op::Abs, Op::Saturate, Op::Sign};
  for (Loss loss : {Loss::Mse, Loss::MaxAbs, Loss::Log}) {
    gpu_detail::GpuScreen gpu(y, w, log2_y, wyy, loss);
    gpu.add_columns(std::span(store).first(10 * n));  // in two appends, as an enumerator would
    gpu.add_columns(std::span(store).subspan(10 * n));
    ASSERT_EQ(gpu.stored(), columns);
    std::vector<gpu_detail::ColumnCandidate> cands;
    for (int i = 0; i < 5000; ++i) {
      gpu_detail::ColumnCandidate c;
      c.a = static_cast<std::uint32_t>(uniform_index(rng, columns));
      c.b = static_cast<std::uint32_t>(uniform_index(rng, columns));
      c.kind = kinds[uniform_index(rng, std::size(kinds))];
      c.unary = unary[uniform_index(rng, std::size(unary))];
      c.k = static_cast<std::int8_t>(2 + uniform_index(rng, 4));
      c.flags = static_cast<std::uint8_t>(uniform_index(rng, 4));
      cands.push_back(c);
    }
    std::vector<float> got_cols, want_cols;
    const auto got = gpu.screen(cands, &got_cols);
    gpu_detail::ScreenTargetView t;
    t.y = y.data();
    t.w = w.data();
    t.log2_y = log2_y.data();
    t.wyy = wyy;
    t.loss = loss;
    t.n = n;
    const auto want = gpu_detail::screen_on_cpu(cands, store, t, &want_cols);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      ASSERT_EQ(got[i].hash, want[i].hash) << i;
      ASSERT_EQ(got[i].valid, want[i].valid) << i;
      ASSERT_EQ(got[i].canonical_neg, want[i].canonical_neg) << i;
      ASSERT_TRUE(got[i].loss_pos == want[i].loss_pos ||
                  (std::isnan(got[i].loss_pos) && std::isnan(want[i].loss_pos)))
          << i;
    }
    for (std::size_t i = 0; i < got_cols.size(); ++i)
      ASSERT_TRUE(got_cols[i] == want_cols[i] ||
                  (std::isnan(got_cols[i]) && std::isnan(want_cols[i])))
          << i;
  }
}

}  // namespace
}  // namespace shaderfit
