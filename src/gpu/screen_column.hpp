// Internal: the enumeration's column step for the GPU -- one operator over operand columns gives
// a candidate's screen column, its dedup key and its screen loss -- as scalar SF_CPU_GPU code
// that gives the same bits as the CPU enumerator's kernels (the search's enum_kernels.cpp:
// compute_column, column_key, column_loss), so that a GPU enumeration deduplicates exactly as
// the CPU one. sin and cos are the exception: they call the platform's sinf/cosf (CUDA's are
// within 2 ulp of the CPU's).
//
// Bit-equality follows from mirroring the CPU kernels' arithmetic step by step: they work on
// eight-float vectors, so their reductions have eight lanes, lane l taking rows l, l + 8, ...;
// here ScreenLane l does the same, and the folds over the eight lanes run in lane order. On the
// GPU, eight threads take one candidate (thread l = lane l); in the tests, a loop over l.
// With no contraction on either side (-ffp-contract=off, nvcc --fmad=false), the float
// operations are the same IEEE operations.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include "eval/screen_math.hpp"
#include "gpu/device_program.hpp"
#include "shaderfit/eval/loss.hpp"

namespace shaderfit::gpu_detail {

inline constexpr int kScreenLanes = 8;      // the CPU kernels' vector width
// The key's head rows and the mantissa bits it keeps of them and of the rows after them, and
// its rotation from one pair of 8-row blocks to the next (search_detail::kKeyHeadRows, ...).
inline constexpr int kScreenKeyHeadRows = 2 * kScreenLanes;
inline constexpr int kScreenKeyHeadBits = 10;
inline constexpr int kScreenKeyTailBits = 6;
inline constexpr int kScreenKeyRotation = 5;
// The rel loss's cap on a row's relative error (search_detail::kMaxRelativeError).
inline constexpr float kMaxRelativeError = 1e15f;

// What a candidate computes from operand columns a and b (the enumerator's EKind without the
// leaves; a fused sum is computed as AddSub).
enum class ColumnOp : std::uint8_t { Unary, IPow, AddSub, Mul, Div, Min, Max, Pow, CopySign };

struct ColumnCandidate {
  std::uint32_t a = 0, b = 0;  // operand columns (indices into the column store)
  ColumnOp kind = ColumnOp::AddSub;
  Op unary = Op::Neg;      // the operator of Unary
  std::int8_t k = 2;       // the exponent of IPow
  std::uint8_t flags = 0;  // kNegA | kNegB
  static constexpr std::uint8_t kNegA = 1, kNegB = 2;
};

struct ScreenResult {
  std::uint64_t hash = 0;
  float scale = 0;
  float loss_pos = 0, loss_neg = 0;
  bool canonical_neg = false;
  bool valid = false;
};

namespace screen_detail {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

SF_CPU_GPU inline float nan_value() { return bits_float(0x7fc00000u); }
SF_CPU_GPU inline float abs_bits(float x) { return bits_float(float_bits(x) & 0x7fffffffu); }

}  // namespace screen_detail

// One lane of the CPU kernels' screening-precision functions (eval/screen_math.hpp).
using eval_detail::screen_exp2;
using eval_detail::screen_log2;
using eval_detail::screen_sqrt;
using eval_detail::screen_unary;

// One row of the candidate column from its operands' values on that row.
SF_CPU_GPU inline float screen_row(const ColumnCandidate& c, float a, float b) {
  const float sa = (c.flags & ColumnCandidate::kNegA) != 0 ? -1.0f : 1.0f;
  const float sb = (c.flags & ColumnCandidate::kNegB) != 0 ? -1.0f : 1.0f;
  switch (c.kind) {
    case ColumnOp::Unary: return screen_unary(c.unary, a * sa);
    case ColumnOp::IPow: return apply_ipow(a, int{c.k});
    case ColumnOp::AddSub: return a + sb * b;
    case ColumnOp::Mul: return a * b;
    case ColumnOp::Div: return a / b;
    case ColumnOp::Min: {
      const float y = sb * b;
      return y < a ? y : a;
    }
    case ColumnOp::Max: {
      const float y = sb * b;
      return y > a ? y : a;
    }
    case ColumnOp::Pow: return screen_exp2(sb * b * screen_log2(a));
    case ColumnOp::CopySign:
      return bits_float((float_bits(a) & 0x7fffffffu) | (float_bits(sb * b) & 0x80000000u));
  }
  return screen_detail::nan_value();
}

// The dedup key of a column of n rows (the CPU's column_key): lane l's sums take rows l, l + 8,
// ... in pairs of 8-row blocks, folded over the lanes in order.
SF_CPU_GPU inline void screen_key(const float* v, std::size_t n, ScreenResult* out) {
  using screen_detail::abs_bits;
  float maxabs = 0;
  for (int l = 0; l < kScreenLanes; ++l) {
    const float a0 = abs_bits(v[l]), a1 = abs_bits(v[l + kScreenLanes]);
    const float am = a0 > a1 ? a0 : a1;
    maxabs = am > maxabs ? am : maxabs;
  }
  const float tiny = 1e-6f * maxabs;
  bool neg = false;
  for (int i = 0; i < kScreenKeyHeadRows; ++i) {
    if (abs_bits(v[i]) > tiny) {
      neg = v[i] < 0;
      break;
    }
  }
  const float sign = neg ? -1.0f : 1.0f;
  constexpr std::uint32_t m0[kScreenLanes] = {0x9e3779b1u, 0x85ebca77u, 0xc2b2ae3du, 0x27d4eb2fu,
                                              0x165667b1u, 0xd3a2646cu, 0xfd7046c5u, 0xb55a4f09u};
  constexpr std::uint32_t m1[kScreenLanes] = {0x7feb352du, 0x846ca68bu, 0x68e31da4u, 0xb5297a4du,
                                              0x1b56c4e9u, 0x2c1b3c6du, 0x297a2d39u, 0x0bf58476u};
  constexpr std::uint32_t m2[kScreenLanes] = {0x94d049bbu, 0x133111ebu, 0xbf58476du, 0x1ce4e5b9u,
                                              0x2545f491u, 0x4f6cdd1du, 0xff51afd7u, 0xed558ccdu};
  constexpr std::uint32_t m3[kScreenLanes] = {0xc4ceb9feu, 0x1a85ec53u, 0x62a9d9edu, 0x799f3cd3u,
                                              0x8bc2e4f1u, 0xa24baed4u, 0x963fdb2bu, 0x5bd1e995u};
  // Row i's value rounded to `bits` mantissa bits.
  const auto rounded = [&](std::size_t i, int bits) -> std::uint32_t {
    if (i >= n) return 0;  // an odd n / 8 pairs the last block with zeros
    const float c = abs_bits(v[i]) > tiny ? v[i] * sign : 0.0f;
    const int drop = 23 - bits;
    return (float_bits(c) + (1u << (drop - 1))) >> drop;
  };
  // Multiply-sum hashes (mod 2^32): two over the first 16 rows, the first summed on over each
  // further pair of 8-row blocks, rotated at each.
  std::uint32_t s1 = 0, s2 = 0;
  for (int l = 0; l < kScreenLanes; ++l) {
    const std::size_t r = static_cast<std::size_t>(l);
    std::uint32_t q0 = rounded(r, kScreenKeyHeadBits);
    std::uint32_t q1 = rounded(r + kScreenLanes, kScreenKeyHeadBits);
    std::uint32_t h1 = q0 * (m0[l] | 1u) + q1 * (m1[l] | 1u);
    s2 += (q0 ^ (q0 >> 11)) * (m2[l] | 1u) + (q1 ^ (q1 >> 11)) * (m3[l] | 1u);
    for (std::size_t i = r + kScreenKeyHeadRows; i < n; i += 2 * kScreenLanes) {
      q0 = rounded(i, kScreenKeyTailBits);
      q1 = rounded(i + kScreenLanes, kScreenKeyTailBits);
      h1 = ((h1 << kScreenKeyRotation) | (h1 >> (32 - kScreenKeyRotation))) +
           q0 * (m0[l] | 1u) + q1 * (m1[l] | 1u);
    }
    s1 += h1;
  }
  std::uint64_t h = (std::uint64_t{s1} << 32) | s2;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  out->hash = h;
  out->canonical_neg = neg;
  out->scale = maxabs;
}

// The screen target (search_detail::ScreenTarget's arrays, n rows, a multiple of 8).
struct ScreenTargetView {
  const float* y = nullptr;
  const float* w = nullptr;
  const float* log2_y = nullptr;  // needed for the log loss only
  double wyy = 0;
  Loss loss = Loss::Mse;
  std::size_t n = 0;
};

// One lane's accumulators of column_loss: rows lane, lane + 8, ... in order.
struct ScreenLane {
  float vmin = screen_detail::kInf, vmax = -screen_detail::kInf;
  float a = 0, b = 0;  // mse, rmse: sum w x^2, sum w x y; otherwise the +- losses
  float nan = 0;

  SF_CPU_GPU void add(float x, std::size_t i, const ScreenTargetView& t) {
    vmin = x < vmin ? x : vmin;
    vmax = x > vmax ? x : vmax;
    const float w = t.w[i];
    switch (t.loss) {
      case Loss::MaxAbs: {
        nan += x * 0.0f;
        const float y = t.y[i];
        const float ap = w * screen_detail::abs_bits(x - y);
        const float an = w * screen_detail::abs_bits(x + y);
        a = ap > a ? ap : a;
        b = an > b ? an : b;
        break;
      }
      case Loss::Relative: {  // |x / y -+ 1| capped at kMaxRelativeError, as the CPU's
        nan += x * 0.0f;
        const float r = x / t.y[i];
        float fp = screen_detail::abs_bits(r - 1.0f), fn = screen_detail::abs_bits(r + 1.0f);
        fp = fp > kMaxRelativeError ? kMaxRelativeError : fp;
        fn = fn > kMaxRelativeError ? kMaxRelativeError : fn;
        a += w * fp * fp;
        b += w * fn * fn;
        break;
      }
      case Loss::Log: {
        nan += x * 0.0f;
        const float ly = t.log2_y[i];
        const float fp = screen_log2(x > 1e-30f ? x : 1e-30f) - ly;
        const float fn = screen_log2(-x > 1e-30f ? -x : 1e-30f) - ly;
        a += w * fp * fp;
        b += w * fn * fn;
        break;
      }
      default: {
        const float wx = w * x;
        a += wx * x;
        b += wx * t.y[i];
        break;
      }
    }
  }
};

// The loss part of column_loss from the eight lanes, folded in lane order.
SF_CPU_GPU inline void screen_loss_fold(const ScreenLane (&lanes)[kScreenLanes],
                                        const ScreenTargetView& t, ScreenResult* out) {
  const Loss loss = t.loss;
  const bool squared = loss == Loss::Mse || loss == Loss::Rmse;  // expanded around wyy
  float mn = screen_detail::kInf, mx = -screen_detail::kInf, nans = 0;
  double p = 0, m = 0;
  for (int l = 0; l < kScreenLanes; ++l) {
    const ScreenLane& s = lanes[l];
    const float lp = squared ? s.a - 2.0f * s.b : s.a;
    const float ln = squared ? s.a + 2.0f * s.b : s.b;
    nans += s.nan;
    mn = s.vmin < mn ? s.vmin : mn;
    mx = s.vmax > mx ? s.vmax : mx;
    if (loss == Loss::MaxAbs) {
      p = lp > p ? lp : p;
      m = ln > m ? ln : m;
    } else {
      p += lp;
      m += ln;
    }
  }
  if (loss == Loss::Log) {
    constexpr double kLn2Sq = 0.4804530139182014;
    p *= kLn2Sq;
    m *= kLn2Sq;
  } else if (squared) {
    p = p + t.wyy < 0.0 ? 0.0 : p + t.wyy;  // std::max(p + wyy, 0.0), NaN kept
    m = m + t.wyy < 0.0 ? 0.0 : m + t.wyy;
  }
  const float amn = screen_detail::abs_bits(mn), amx = screen_detail::abs_bits(mx);
  const float spread = amn < amx ? amx : amn;
  const auto finite = [](double x) { return x - x == 0.0; };
  out->valid =
      nans == 0 && finite(p) && finite(m) && finite(mn) && finite(mx) && mx - mn > 1e-5f * spread;
  out->loss_pos = static_cast<float>(p);
  out->loss_neg = static_cast<float>(m);
}

// The whole step for one candidate, lane by lane as on the GPU: writes the column to out[0, n)
// and returns its key and loss. `store` holds the operand columns, n floats each.
SF_CPU_GPU inline ScreenResult screen_candidate(const ColumnCandidate& c, const float* store,
                                                const ScreenTargetView& t, float* out) {
  const float* a = store + static_cast<std::size_t>(c.a) * t.n;
  const float* b = store + static_cast<std::size_t>(c.b) * t.n;
  ScreenLane lanes[kScreenLanes];
  for (int l = 0; l < kScreenLanes; ++l) {
    for (std::size_t i = static_cast<std::size_t>(l); i < t.n; i += kScreenLanes) {
      out[i] = screen_row(c, a[i], b[i]);
      lanes[l].add(out[i], i, t);
    }
  }
  ScreenResult r;
  screen_key(out, t.n, &r);
  screen_loss_fold(lanes, t, &r);
  return r;
}

}  // namespace shaderfit::gpu_detail
