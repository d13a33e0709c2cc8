#include "search/enumeration/enum_kernels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "shaderfit/core/random.hpp"

namespace shaderfit::search_detail {
namespace {

constexpr std::size_t kRows = 64;

std::vector<float> random_column(Rng& rng, double lo, double hi) {
  std::vector<float> v(kRows);
  for (float& x : v) x = static_cast<float>(uniform(rng, lo, hi));
  return v;
}

TEST(EnumKernels, ArithmeticIsExactFloat) {
  Rng rng(1);
  const auto a = random_column(rng, -2, 2), b = random_column(rng, 0.5, 3);
  std::vector<float> out(kRows);
  compute_column(EKind::AddSub, Op::Const, 0, a.data(), b.data(), false, true, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i) EXPECT_EQ(out[i], a[i] - b[i]);
  compute_column(EKind::Mul, Op::Const, 0, a.data(), b.data(), false, false, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i) EXPECT_EQ(out[i], a[i] * b[i]);
  compute_column(EKind::Div, Op::Const, 0, a.data(), b.data(), false, false, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i) EXPECT_EQ(out[i], a[i] / b[i]);
  compute_column(EKind::IPow, Op::Const, 5, a.data(), nullptr, false, false, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i) EXPECT_EQ(out[i], apply_ipow(a[i], 5));
  compute_column(EKind::Min, Op::Const, 0, a.data(), b.data(), false, true, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i) EXPECT_EQ(out[i], std::fmin(a[i], -b[i]));
  compute_column(EKind::CopySign, Op::Const, 0, a.data(), b.data(), false, true, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i)
    EXPECT_EQ(out[i], apply_binary(Op::CopySign, a[i], -b[i]));
  compute_column(EKind::Unary, Op::Sign, 0, a.data(), nullptr, true, false, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i) EXPECT_EQ(out[i], apply_unary(Op::Sign, -a[i]));
  // The library functions are the scalar ones in float, lane by lane.
  compute_column(EKind::Atan2, Op::Const, 0, a.data(), b.data(), false, true, out.data(), kRows);
  for (std::size_t i = 0; i < kRows; ++i) EXPECT_EQ(out[i], apply_binary(Op::Atan2, a[i], -b[i]));
  for (Op op : {Op::Asin, Op::Acos, Op::Atan, Op::Tanh, Op::Erf}) {
    compute_column(EKind::Unary, op, 0, a.data(), nullptr, true, false, out.data(), kRows);
    for (std::size_t i = 0; i < kRows; ++i) {
      const float want = apply_unary(op, -a[i]);
      EXPECT_TRUE(out[i] == want || (std::isnan(out[i]) && std::isnan(want)))
          << op_info(op).name << "(" << -a[i] << ")";
    }
  }
}

TEST(EnumKernels, TranscendentalsAreCloseToLibm) {
  Rng rng(2);
  const auto pos = random_column(rng, 1e-3, 50), any = random_column(rng, -20, 20);
  std::vector<float> out(kRows);
  auto check = [&](Op op, const std::vector<float>& in, bool neg) {
    compute_column(EKind::Unary, op, 0, in.data(), nullptr, neg, false, out.data(), kRows);
    for (std::size_t i = 0; i < kRows; ++i) {
      const double want = apply_unary(op, static_cast<double>(neg ? -in[i] : in[i]));
      EXPECT_NEAR(out[i], want, 2e-6 * std::abs(want) + 1e-7)
          << op_info(op).name << "(" << in[i] << ")";
    }
  };
  check(Op::Sqrt, pos, false);
  check(Op::Rsqrt, pos, false);
  check(Op::Log2, pos, false);
  check(Op::Log, pos, false);
  check(Op::Exp2, any, false);
  check(Op::Exp, any, true);
  check(Op::Saturate, any, false);
  check(Op::Abs, any, true);
  // Outside the domain: NaN, as the scalar functions.
  compute_column(EKind::Unary, Op::Sqrt, 0, pos.data(), nullptr, true, false, out.data(), kRows);
  EXPECT_TRUE(std::isnan(out[0]));
}

TEST(EnumKernels, KeysIgnoreSignAndFloatNoise) {
  Rng rng(3);
  auto a = random_column(rng, 0.1, 2);
  std::vector<float> neg(kRows), noisy(kRows);
  for (std::size_t i = 0; i < kRows; ++i) {
    neg[i] = -a[i];
    noisy[i] = std::nextafter(a[i], 10.0f);
  }
  ColumnStats ka, kn, kz;
  column_key(a.data(), kRows, &ka);
  column_key(neg.data(), kRows, &kn);
  column_key(noisy.data(), kRows, &kz);
  EXPECT_EQ(ka.hash, kn.hash);
  EXPECT_NE(ka.canonical_neg, kn.canonical_neg);
  EXPECT_TRUE(columns_equivalent(a.data(), neg.data(), true, ka.scale, kRows));
  EXPECT_TRUE(columns_equivalent(a.data(), noisy.data(), false, ka.scale, kRows));
  std::vector<float> other = a;
  other[kRows - 1] *= 1.01f;
  EXPECT_FALSE(columns_equivalent(a.data(), other.data(), false, ka.scale, kRows));
  other = a;
  other[5] = std::nanf("");
  EXPECT_FALSE(columns_equivalent(a.data(), other.data(), false, ka.scale, kRows));
  EXPECT_FALSE(columns_equivalent(other.data(), other.data(), false, ka.scale, kRows));
}

// Columns that agree on their first rows and differ further down (min(x, 2) of inputs mostly
// above 2) have different keys: a probe compares a candidate with the columns of its key only.
TEST(EnumKernels, KeysTellColumnsApartOnEveryRow) {
  static_assert(kRows > 16);
  std::vector<float> a(kRows, 2.0f);
  std::set<std::uint64_t> keys;
  for (std::size_t i = 16; i < kRows; ++i) {
    std::vector<float> b = a;
    b[i] = 1.5f;
    ColumnStats k;
    column_key(b.data(), kRows, &k);
    EXPECT_TRUE(keys.insert(k.hash).second) << i;
  }
  // The same values in other rows are another column.
  std::vector<float> b = a, c = a;
  b[20] = 1.5f;
  c[36] = 1.5f;
  ColumnStats kb, kc;
  column_key(b.data(), kRows, &kb);
  column_key(c.data(), kRows, &kc);
  EXPECT_NE(kb.hash, kc.hash);
  // A column and its negation have one key, also where they differ from zero late.
  std::vector<float> late(kRows, 0.0f), late_neg(kRows, 0.0f);
  late[5] = 3.0f;
  late[50] = -1.0f;
  for (std::size_t i = 0; i < kRows; ++i) late_neg[i] = -late[i];
  column_key(late.data(), kRows, &kb);
  column_key(late_neg.data(), kRows, &kc);
  EXPECT_EQ(kb.hash, kc.hash);
  EXPECT_FALSE(kb.canonical_neg);
  EXPECT_TRUE(kc.canonical_neg);
}

TEST(EnumKernels, LossOfBothSignsAndValidity) {
  Rng rng(4);
  const auto x = random_column(rng, -1, 1), y = random_column(rng, -1, 1);
  std::vector<float> w(kRows, 1.0f / kRows), ly(kRows, 0.0f);
  double wyy = 0, lp = 0, ln = 0;
  for (std::size_t i = 0; i < kRows; ++i) {
    wyy += w[i] * y[i] * y[i];
    lp += w[i] * (x[i] - y[i]) * (x[i] - y[i]);
    ln += w[i] * (x[i] + y[i]) * (x[i] + y[i]);
  }
  const ScreenTarget t{y.data(), w.data(), ly.data(), wyy, Loss::Mse, kRows};
  const ColumnStats s = analyze_column(x.data(), t);
  EXPECT_TRUE(s.valid);
  EXPECT_NEAR(s.loss_pos, lp, 1e-5);
  EXPECT_NEAR(s.loss_neg, ln, 1e-5);
  std::vector<float> constant(kRows, 0.25f), inf = x;
  inf[3] = INFINITY;
  EXPECT_FALSE(analyze_column(constant.data(), t).valid);
  EXPECT_FALSE(analyze_column(inf.data(), t).valid);
}

TEST(EnumKernels, FusedSumsInClosedFormMatchTheirColumns) {
  Rng rng(5);
  const auto m = random_column(rng, -1, 1), v = random_column(rng, 0, 1),
             y = random_column(rng, -1, 2);
  std::vector<float> w(kRows, 1.0f / kRows), ly(kRows, 0.0f);
  double wyy = 0;
  for (std::size_t i = 0; i < kRows; ++i) wyy += w[i] * y[i] * y[i];
  const ScreenTarget t{y.data(), w.data(), ly.data(), wyy, Loss::Mse, kRows};
  FusedScreen fs;
  fs.y = y.data();
  fs.w = w.data();
  fs.n = kRows;
  const std::vector<float> lit(kRows, 0.5f);
  for (const float* c : {v.data(), lit.data()}) {
    fs.leaf_columns.push_back(c == lit.data() ? nullptr : c);
    fs.leaf_values.push_back(c == lit.data() ? 0.5f : 0.0f);
    double kp = 0, km = 0;
    for (std::size_t i = 0; i < kRows; ++i) {
      kp += w[i] * (c[i] - y[i]) * (c[i] - y[i]);
      km += w[i] * (-c[i] - y[i]) * (-c[i] - y[i]);
    }
    fs.k_plus.push_back(kp);
    fs.k_minus.push_back(km);
  }
  const FusedBest best = screen_fused(m.data(), fs);
  // The same minimum by computing all eight sums.
  float want = 1e30f;
  std::vector<float> col(kRows);
  for (const float* c : {v.data(), lit.data()}) {
    for (bool nb : {false, true}) {
      compute_column(EKind::FusedAdd, Op::Const, 0, m.data(), c, false, nb, col.data(), kRows);
      const ColumnStats s = analyze_column(col.data(), t);
      want = std::min({want, s.loss_pos, s.loss_neg});
    }
  }
  EXPECT_NEAR(best.loss, want, 1e-5);
  ASSERT_GE(best.leaf, 0);
}

}  // namespace
}  // namespace shaderfit::search_detail
