// The GPU enumeration step's shared code against the CPU enumerator's kernels
// (enum_kernels.cpp, beside this test): the same columns, keys and screen losses, bit for bit, so
// that a GPU enumeration would deduplicate exactly as the CPU one.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "gpu/screen.hpp"
#include "gpu/screen_column.hpp"
#include "search/enumeration/enum_kernels.hpp"
#include "shaderfit/core/random.hpp"

namespace shaderfit::gpu_detail {
namespace {

using search_detail::EKind;

// The twin's constants are the enumerator's (gpu/ cannot include search/).
static_assert(kScreenKeyHeadRows == search_detail::kKeyHeadRows &&
              kScreenKeyHeadBits == search_detail::kKeyHeadBits &&
              kScreenKeyTailBits == search_detail::kKeyTailBits &&
              kScreenKeyRotation == search_detail::kKeyRotation);
static_assert(kMaxRelativeError == search_detail::kMaxRelativeError);

bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) ||
         (std::isnan(a) && std::isnan(b));
}

EKind ekind(ColumnOp op) {
  switch (op) {
    case ColumnOp::Unary: return EKind::Unary;
    case ColumnOp::IPow: return EKind::IPow;
    case ColumnOp::AddSub: return EKind::AddSub;
    case ColumnOp::Mul: return EKind::Mul;
    case ColumnOp::Div: return EKind::Div;
    case ColumnOp::Min: return EKind::Min;
    case ColumnOp::Max: return EKind::Max;
    case ColumnOp::Pow: return EKind::Pow;
    case ColumnOp::CopySign: return EKind::CopySign;
  }
  return EKind::AddSub;
}

// A column of n values of one of several shapes, with the special values the key and the loss
// treat specially: zeros and sub-noise values among the hashed rows, negative leads, constants,
// NaN and infinity.
std::vector<float> random_column(Rng& rng, std::size_t n) {
  std::vector<float> v(n);
  const int shape = static_cast<int>(uniform_index(rng, 7));
  const double lo = shape == 1 ? 0.01 : -2.0, hi = shape == 2 ? -0.01 : 3.0;
  for (float& x : v) x = static_cast<float>(uniform(rng, lo, hi));
  if (shape == 3)
    for (std::size_t i = 0; i < 5; ++i)
      v[uniform_index(rng, 16)] = bernoulli(rng, 0.5) ? 0.0f : 1e-9f;
  if (shape == 4) std::fill(v.begin(), v.end(), 0.75f);
  if (shape == 5)
    v[uniform_index(rng, n)] = bernoulli(rng, 0.5) ? std::numeric_limits<float>::quiet_NaN()
                                                   : std::numeric_limits<float>::infinity();
  if (shape == 6)
    for (float& x : v) x *= 1e20f;
  return v;
}

struct Target {
  std::vector<float> y, w, log2_y;
  search_detail::ScreenTarget cpu;
  ScreenTargetView gpu;
  Target(Rng& rng, std::size_t n, Loss loss) : y(n), w(n), log2_y(n) {
    double wyy = 0;
    for (std::size_t i = 0; i < n; ++i) {
      y[i] = static_cast<float>(uniform(rng, 0.05, 1.5));
      w[i] = loss == Loss::MaxAbs ? (bernoulli(rng, 0.9) ? 1.0f : 0.0f)
                                  : static_cast<float>(uniform(rng, 0.1, 2.0) / n);
      log2_y[i] = std::log2(y[i]);
      wyy += static_cast<double>(w[i]) * y[i] * y[i];
    }
    cpu = {y.data(), w.data(), log2_y.data(), wyy, loss, n};
    gpu.y = y.data();
    gpu.w = w.data();
    gpu.log2_y = log2_y.data();
    gpu.wyy = wyy;
    gpu.loss = loss;
    gpu.n = n;
  }
};

void expect_same(const search_detail::ColumnStats& want, const ScreenResult& got,
                 const std::string& what) {
  EXPECT_EQ(got.hash, want.hash) << what;
  EXPECT_EQ(got.canonical_neg, want.canonical_neg) << what;
  EXPECT_TRUE(same_bits(got.scale, want.scale))
      << what << ": " << got.scale << " vs " << want.scale;
  EXPECT_EQ(got.valid, want.valid) << what;
  EXPECT_TRUE(same_bits(got.loss_pos, want.loss_pos))
      << what << ": " << got.loss_pos << " vs " << want.loss_pos;
  EXPECT_TRUE(same_bits(got.loss_neg, want.loss_neg))
      << what << ": " << got.loss_neg << " vs " << want.loss_neg;
}

TEST(GpuKernelLogic, ColumnKeyTwinMatchesTheEnumerator) {
  Rng rng(71);
  // Row counts of one, an odd and an even number of pairs of 8-row blocks.
  const std::size_t rows[] = {16, 24, 64, 136};
  for (int trial = 0; trial < 5000; ++trial) {
    const std::size_t n = rows[trial % 4];
    const std::vector<float> v = random_column(rng, n);
    search_detail::ColumnStats want;
    search_detail::column_key(v.data(), n, &want);
    ScreenResult got;
    screen_key(v.data(), n, &got);
    ASSERT_EQ(got.hash, want.hash) << trial;
    ASSERT_EQ(got.canonical_neg, want.canonical_neg) << trial;
    ASSERT_TRUE(same_bits(got.scale, want.scale)) << trial;
  }
  // Negation and float noise below the key's rounding give the same key.
  std::vector<float> a = random_column(rng, 16), b = a;
  for (float& x : b) x = -x;
  ScreenResult ka, kb;
  screen_key(a.data(), 16, &ka);
  screen_key(b.data(), 16, &kb);
  EXPECT_EQ(ka.hash, kb.hash);
}

TEST(GpuKernelLogic, ColumnStepMatchesTheEnumeratorBitForBit) {
  Rng rng(72);
  const Op unary[] = {Op::Neg, Op::Sqrt, Op::Rsqrt,    Op::Rcp, Op::Exp2, Op::Log2, Op::Exp,
                      Op::Log, Op::Abs,  Op::Saturate, Op::Sin, Op::Cos,  Op::Sign};
  const ColumnOp kinds[] = {ColumnOp::Unary, ColumnOp::IPow, ColumnOp::AddSub,
                            ColumnOp::Mul,   ColumnOp::Div,  ColumnOp::Min,
                            ColumnOp::Max,   ColumnOp::Pow,  ColumnOp::CopySign};
  const Loss losses[] = {Loss::Mse, Loss::Relative, Loss::MaxAbs, Loss::Log};
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = 16 * (1 + uniform_index(rng, 8));
    const Target target(rng, n, losses[trial % 4]);
    std::vector<float> store = random_column(rng, n);
    const std::vector<float> b = random_column(rng, n);
    store.insert(store.end(), b.begin(), b.end());
    std::vector<ColumnCandidate> candidates;
    for (ColumnOp kind : kinds) {
      for (int variant = 0; variant < 4; ++variant) {
        ColumnCandidate c;
        c.a = 0;
        c.b = 1;
        c.kind = kind;
        c.unary = unary[uniform_index(rng, std::size(unary))];
        c.k = static_cast<std::int8_t>(2 + uniform_index(rng, 5));
        if (bernoulli(rng, 0.3)) c.k = static_cast<std::int8_t>(-c.k);
        c.flags = static_cast<std::uint8_t>(variant);
        candidates.push_back(c);
      }
    }
    std::vector<float> columns;
    const std::vector<ScreenResult> got = screen_on_cpu(candidates, store, target.gpu, &columns);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const ColumnCandidate& c = candidates[i];
      std::vector<float> want(n);
      search_detail::compute_column(ekind(c.kind), c.unary, c.k, store.data(), store.data() + n,
                                    (c.flags & ColumnCandidate::kNegA) != 0,
                                    (c.flags & ColumnCandidate::kNegB) != 0, want.data(), n);
      const std::string what =
          "trial " + std::to_string(trial) + " kind " + std::to_string(static_cast<int>(c.kind)) +
          " op " + std::string(op_info(c.unary).name) + " flags " + std::to_string(c.flags);
      for (std::size_t r = 0; r < n; ++r)
        ASSERT_TRUE(same_bits(columns[i * n + r], want[r]))
            << what << " row " << r << ": " << columns[i * n + r] << " vs " << want[r];
      expect_same(search_detail::analyze_column(want.data(), target.cpu), got[i], what);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 400 * 4 * static_cast<int>(std::size(kinds)));
}

TEST(GpuKernelLogic, FusedSumIsComputedAsAddSub) {
  Rng rng(73);
  const std::size_t n = 64;
  std::vector<float> store = random_column(rng, n);
  const std::vector<float> b = random_column(rng, n);
  store.insert(store.end(), b.begin(), b.end());
  for (std::uint8_t flags : {0, 2}) {
    std::vector<float> want(n);
    search_detail::compute_column(EKind::FusedAdd, Op::Neg, 2, store.data(), store.data() + n,
                                  false, flags != 0, want.data(), n);
    ColumnCandidate c;
    c.b = 1;
    c.kind = ColumnOp::AddSub;
    c.flags = flags;
    for (std::size_t r = 0; r < n; ++r)
      EXPECT_TRUE(same_bits(screen_row(c, store[r], store[n + r]), want[r])) << r;
  }
}

}  // namespace
}  // namespace shaderfit::gpu_detail
