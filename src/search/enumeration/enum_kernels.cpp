// v8f helpers (and op.hpp's apply_ipow on v8f) are always inlined: no v8f crosses a call.
#pragma GCC diagnostic ignored "-Wpsabi"

#include "search/enumeration/enum_kernels.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "eval/screen_math.hpp"

// Eight-lane GCC vector types: the compiler emits AVX for the avx2 clone and SSE pairs for the
// baseline one. Reductions are written lane-wise, so no -ffast-math is needed to vectorise them.
#define SF_KERNEL __attribute__((target_clones("avx2", "default")))
// Helpers are always inlined, so each clone compiles them for its own ISA.
#define SF_INLINE inline __attribute__((always_inline))

namespace shaderfit::search_detail {

namespace {

using v8f = float __attribute__((vector_size(32)));
using v8i = std::int32_t __attribute__((vector_size(32)));

SF_INLINE v8f load(const float* p) {
  v8f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
SF_INLINE void store(float* p, v8f v) { std::memcpy(p, &v, sizeof v); }
SF_INLINE v8f splat(float x) { return v8f{} + x; }
SF_INLINE v8f select(v8i mask, v8f a, v8f b) {
  return std::bit_cast<v8f>((mask & std::bit_cast<v8i>(a)) | (~mask & std::bit_cast<v8i>(b)));
}

constexpr float kInf = std::numeric_limits<float>::infinity();

// The lanes' operations of eval/screen_math.hpp for eight-float vectors.
struct V8Lanes {
  using I = v8i;
  SF_INLINE static v8i bits(v8f x) { return std::bit_cast<v8i>(x); }
  SF_INLINE static v8f from_bits(v8i i) { return std::bit_cast<v8f>(i); }
  SF_INLINE static v8f pick(v8i m, v8f a, v8f b) { return select(m, a, b); }
  SF_INLINE static v8i to_int(v8f x) { return __builtin_convertvector(x, v8i); }
  SF_INLINE static v8f to_float(v8i i) { return __builtin_convertvector(i, v8f); }
  SF_INLINE static v8i one_where(v8i m) { return m & 1; }
  SF_INLINE static v8i shl23(v8i i) { return i << 23; }
  SF_INLINE static v8f splat(float x) { return shaderfit::search_detail::splat(x); }
  // sin, cos, asin ... erf: rare, scalar.
  SF_INLINE static v8f apply(Op op, v8f a) {
    v8f r = {};
    for (int l = 0; l < 8; ++l) r[l] = apply_unary(op, a[l]);
    return r;
  }
};

SF_INLINE v8f vexp2(v8f x) { return eval_detail::screen_exp2<v8f, V8Lanes>(x); }
SF_INLINE v8f vlog2(v8f x) { return eval_detail::screen_log2<v8f, V8Lanes>(x); }
SF_INLINE v8f vunary(Op op, v8f a) { return eval_detail::screen_unary<v8f, V8Lanes>(op, a); }

}  // namespace

SF_KERNEL void compute_column(EKind kind, Op unary, int k, const float* a, const float* b,
                              bool neg_a, bool neg_b, float* out, std::size_t n) {
  const float sa = neg_a ? -1.0f : 1.0f;
  const float sb = neg_b ? -1.0f : 1.0f;
  switch (kind) {
    case EKind::Unary:
      for (std::size_t i = 0; i < n; i += 8) store(out + i, vunary(unary, load(a + i) * sa));
      return;
    case EKind::IPow:
      for (std::size_t i = 0; i < n; i += 8)
        store(out + i, apply_ipow(load(a + i), k, splat(1.0f)));
      return;
    case EKind::AddSub:
    case EKind::FusedAdd:
      for (std::size_t i = 0; i < n; i += 8) store(out + i, load(a + i) + sb * load(b + i));
      return;
    case EKind::Mul:
      for (std::size_t i = 0; i < n; i += 8) store(out + i, load(a + i) * load(b + i));
      return;
    case EKind::Div:
      for (std::size_t i = 0; i < n; i += 8) store(out + i, load(a + i) / load(b + i));
      return;
    case EKind::Min:
      for (std::size_t i = 0; i < n; i += 8) {
        const v8f x = load(a + i), y = sb * load(b + i);
        store(out + i, select(y < x, y, x));
      }
      return;
    case EKind::Max:
      for (std::size_t i = 0; i < n; i += 8) {
        const v8f x = load(a + i), y = sb * load(b + i);
        store(out + i, select(y > x, y, x));
      }
      return;
    case EKind::Pow:
      for (std::size_t i = 0; i < n; i += 8)
        store(out + i, vexp2(sb * load(b + i) * vlog2(load(a + i))));
      return;
    case EKind::CopySign:
      for (std::size_t i = 0; i < n; i += 8) {
        const v8i x = std::bit_cast<v8i>(load(a + i)), y = std::bit_cast<v8i>(sb * load(b + i));
        store(out + i, std::bit_cast<v8f>((x & 0x7fffffff) |
                                          (y & std::numeric_limits<std::int32_t>::min())));
      }
      return;
    case EKind::Atan2:  // rare, scalar
      for (std::size_t i = 0; i < n; ++i) out[i] = apply_binary(Op::Atan2, a[i], sb * b[i]);
      return;
    case EKind::Var:
    case EKind::Literal: return;  // leaves are filled by the caller
  }
}

SF_KERNEL void column_key(const float* v, std::size_t n, ColumnStats* s) {
  const v8f x0 = load(v), x1 = load(v + 8);
  const v8f a0 = std::bit_cast<v8f>(std::bit_cast<v8i>(x0) & 0x7fffffff);
  const v8f a1 = std::bit_cast<v8f>(std::bit_cast<v8i>(x1) & 0x7fffffff);
  const v8f am = select(a0 > a1, a0, a1);
  float maxabs = 0;
  for (int l = 0; l < 8; ++l) maxabs = am[l] > maxabs ? am[l] : maxabs;
  // Values below the noise floor of the first 16 rows count as zero; the first of those rows
  // above it is made positive.
  const float tiny = 1e-6f * maxabs;
  bool neg = false;
  for (std::size_t i = 0; i < kKeyHeadRows; ++i) {
    if (std::abs(v[i]) > tiny) {
      neg = v[i] < 0;
      break;
    }
  }
  const float sign = neg ? -1.0f : 1.0f;
  const v8f zero = {};
  // The first 16 values rounded to 10 mantissa bits (relative 1e-3), so float noise rarely
  // changes them, and two independent multiply-sum hashes over them; the further rows rounded
  // to kKeyTailBits (coarser: there a rounding boundary would more often split two equivalent
  // columns) and summed on into the first hash, rotated at each pair of 8-row blocks so that
  // the same values in other rows hash differently.
  using v8u = std::uint32_t __attribute__((vector_size(32)));
  const v8u m0 = {0x9e3779b1u, 0x85ebca77u, 0xc2b2ae3du, 0x27d4eb2fu,
                  0x165667b1u, 0xd3a2646cu, 0xfd7046c5u, 0xb55a4f09u};
  const v8u m1 = {0x7feb352du, 0x846ca68bu, 0x68e31da4u, 0xb5297a4du,
                  0x1b56c4e9u, 0x2c1b3c6du, 0x297a2d39u, 0x0bf58476u};
  const v8u m2 = {0x94d049bbu, 0x133111ebu, 0xbf58476du, 0x1ce4e5b9u,
                  0x2545f491u, 0x4f6cdd1du, 0xff51afd7u, 0xed558ccdu};
  const v8u m3 = {0xc4ceb9feu, 0x1a85ec53u, 0x62a9d9edu, 0x799f3cd3u,
                  0x8bc2e4f1u, 0xa24baed4u, 0x963fdb2bu, 0x5bd1e995u};
  const auto rounded = [&](v8f x, v8f a, int bits) {
    const int drop = 23 - bits;
    const v8u c = std::bit_cast<v8u>(select(a > tiny, x * sign, zero));
    return (c + (1u << (drop - 1))) >> drop;
  };
  const auto tail = [&](const float* p) {
    const v8f x = load(p);
    return rounded(x, std::bit_cast<v8f>(std::bit_cast<v8i>(x) & 0x7fffffff), kKeyTailBits);
  };
  static_assert(kKeyHeadRows == 16);  // x0 and x1
  v8u q0 = rounded(x0, a0, kKeyHeadBits), q1 = rounded(x1, a1, kKeyHeadBits);
  v8u h1 = q0 * (m0 | 1u) + q1 * (m1 | 1u);
  const v8u h2 = (q0 ^ (q0 >> 11)) * (m2 | 1u) + (q1 ^ (q1 >> 11)) * (m3 | 1u);
  for (std::size_t i = kKeyHeadRows; i < n; i += 16) {
    // An odd n / 8 leaves a last block alone: it pairs with zeros.
    q0 = tail(v + i);
    q1 = i + 8 < n ? tail(v + i + 8) : v8u{};
    h1 = ((h1 << kKeyRotation) | (h1 >> (32 - kKeyRotation))) + q0 * (m0 | 1u) + q1 * (m1 | 1u);
  }
  std::uint32_t s1 = 0, s2 = 0;
  for (int l = 0; l < 8; ++l) {
    s1 += h1[l];
    s2 += h2[l];
  }
  std::uint64_t h = (std::uint64_t{s1} << 32) | s2;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  s->hash = h;
  s->canonical_neg = neg;
  s->scale = maxabs;
}

SF_KERNEL void column_loss(const float* v, const ScreenTarget& target, ColumnStats* s) {
  const std::size_t n = target.n;
  v8f vmin = splat(kInf), vmax = splat(-kInf), lp = {}, ln = {}, nan = {};
  const Loss loss = target.loss;
  if (loss == Loss::Mse || loss == Loss::Rmse) {
    // sum w (x -+ y)^2 = sum w x^2 -+ 2 sum w x y + sum w y^2: two accumulators serve both signs.
    v8f sxx = {}, sxy = {};
    for (std::size_t i = 0; i < n; i += 8) {
      const v8f x = load(v + i), wx = load(target.w + i) * x;
      vmin = select(x < vmin, x, vmin);
      vmax = select(x > vmax, x, vmax);
      sxx += wx * x;
      sxy += wx * load(target.y + i);
    }
    lp = sxx - 2.0f * sxy;
    ln = sxx + 2.0f * sxy;
  } else if (loss == Loss::MaxAbs) {
    for (std::size_t i = 0; i < n; i += 8) {
      const v8f x = load(v + i), y = load(target.y + i), w = load(target.w + i);
      nan += x * 0.0f;  // NaN if any value is NaN or infinite
      vmin = select(x < vmin, x, vmin);
      vmax = select(x > vmax, x, vmax);
      const v8f ap = w * std::bit_cast<v8f>(std::bit_cast<v8i>(x - y) & 0x7fffffff);
      const v8f an = w * std::bit_cast<v8f>(std::bit_cast<v8i>(x + y) & 0x7fffffff);
      lp = select(ap > lp, ap, lp);
      ln = select(an > ln, an, ln);
    }
  } else if (loss == Loss::Relative) {
    // sum w (x / y -+ 1)^2, divided row by row: weights w / y^2 would overflow float32 on a
    // target spanning many orders of magnitude. A row's relative error counts at most
    // kMaxRelativeError, so that rows where every candidate is astronomically off (a lobe's
    // tail) do not overflow the sums and drop every candidate.
    const v8f cap = splat(kMaxRelativeError);
    for (std::size_t i = 0; i < n; i += 8) {
      const v8f x = load(v + i), w = load(target.w + i), r = x / load(target.y + i);
      nan += x * 0.0f;
      vmin = select(x < vmin, x, vmin);
      vmax = select(x > vmax, x, vmax);
      v8f fp = std::bit_cast<v8f>(std::bit_cast<v8i>(r - 1.0f) & 0x7fffffff);
      v8f fn = std::bit_cast<v8f>(std::bit_cast<v8i>(r + 1.0f) & 0x7fffffff);
      fp = select(fp > cap, cap, fp);
      fn = select(fn > cap, cap, fn);
      lp += w * fp * fp;
      ln += w * fn * fn;
    }
  } else {  // log: ln p - ln y with p floored at 1e-30, as the full metric
    for (std::size_t i = 0; i < n; i += 8) {
      const v8f x = load(v + i), w = load(target.w + i), ly = load(target.log2_y + i);
      nan += x * 0.0f;
      vmin = select(x < vmin, x, vmin);
      vmax = select(x > vmax, x, vmax);
      const v8f fp = vlog2(select(x > 1e-30f, x, splat(1e-30f))) - ly;
      const v8f fn = vlog2(select(-x > 1e-30f, -x, splat(1e-30f))) - ly;
      lp += w * fp * fp;
      ln += w * fn * fn;
    }
  }
  float mn = kInf, mx = -kInf, nans = 0;
  double p = 0, m = 0;
  for (int l = 0; l < 8; ++l) {
    nans += nan[l];
    mn = vmin[l] < mn ? vmin[l] : mn;
    mx = vmax[l] > mx ? vmax[l] : mx;
    if (loss == Loss::MaxAbs) {
      p = lp[l] > p ? lp[l] : p;
      m = ln[l] > m ? ln[l] : m;
    } else {
      p += lp[l];
      m += ln[l];
    }
  }
  if (loss == Loss::Log) {
    constexpr double kLn2Sq = 0.4804530139182014;  // (ln 2)^2: log2 differences to natural log
    p *= kLn2Sq;
    m *= kLn2Sq;
  } else if (loss == Loss::Mse || loss == Loss::Rmse) {
    p = std::max(p + target.wyy, 0.0);
    m = std::max(m + target.wyy, 0.0);
  }
  const float spread = std::max(std::abs(mn), std::abs(mx));
  // Invalid: a NaN or infinity (the min/max lose NaNs, the sums keep them), or a constant.
  s->valid = nans == 0 && std::isfinite(p) && std::isfinite(m) && std::isfinite(mn) &&
             std::isfinite(mx) && mx - mn > 1e-5f * spread;
  s->loss_pos = static_cast<float>(p);
  s->loss_neg = static_cast<float>(m);
}

SF_KERNEL bool columns_equivalent(const float* a, const float* b, bool negate_b, float scale,
                                  std::size_t n) {
  const float sb = negate_b ? -1.0f : 1.0f;
  const float abs_tol = 1e-6f * scale;
  v8i bad = {};
  for (std::size_t i = 0; i < n; i += 8) {
    const v8f x = load(a + i), y = sb * load(b + i);
    const v8f d = x - y;
    const v8f ad = std::bit_cast<v8f>(std::bit_cast<v8i>(d) & 0x7fffffff);
    const v8f mag = std::bit_cast<v8f>(std::bit_cast<v8i>(x) & 0x7fffffff) +
                    std::bit_cast<v8f>(std::bit_cast<v8i>(y) & 0x7fffffff);
    bad |= ~(ad <= 2e-5f * mag + abs_tol);  // NaN compares false: never equivalent
  }
  int any = 0;
  for (int l = 0; l < 8; ++l) any |= bad[l];
  return any == 0;
}

SF_KERNEL static void fused_dots(const float* m, const float* y, const float* w, std::size_t n,
                                 float* smm, float* smy, float* sm) {
  v8f a = {}, b = {}, c = {};
  for (std::size_t i = 0; i < n; i += 8) {
    const v8f x = load(m + i), wx = load(w + i) * x;
    a += wx * x;
    b += wx * load(y + i);
    c += wx;
  }
  *smm = *smy = *sm = 0;
  for (int l = 0; l < 8; ++l) {
    *smm += a[l];
    *smy += b[l];
    *sm += c[l];
  }
}

SF_KERNEL static float weighted_dot(const float* m, const float* v, const float* w, std::size_t n) {
  v8f a = {};
  for (std::size_t i = 0; i < n; i += 8) a += load(w + i) * load(m + i) * load(v + i);
  float s = 0;
  for (int l = 0; l < 8; ++l) s += a[l];
  return s;
}

FusedBest screen_fused(const float* m, const FusedScreen& fs) {
  float smm, smy, sm;
  fused_dots(m, fs.y, fs.w, fs.n, &smm, &smy, &sm);
  FusedBest best;
  double best_loss = best.loss;
  for (std::size_t j = 0; j < fs.leaf_values.size(); ++j) {
    const double smc = fs.leaf_columns[j] != nullptr
                           ? weighted_dot(m, fs.leaf_columns[j], fs.w, fs.n)
                           : static_cast<double>(fs.leaf_values[j]) * sm;
    for (int b = 0; b < 2; ++b) {
      const double k = b == 0 ? fs.k_plus[j] : fs.k_minus[j];
      const double sb = b == 0 ? 1.0 : -1.0;
      for (int a = 0; a < 2; ++a) {
        const double sa = a == 0 ? 1.0 : -1.0;
        const double loss = smm + 2 * sa * sb * smc - 2 * sa * smy + k;
        if (loss < best_loss) {
          best_loss = loss;
          best.leaf = static_cast<std::int16_t>(j);
          best.neg_leaf = sa * sb < 0;  // a m + b c = a (m + (a b) c)
          best.negate = a == 1;
        }
      }
    }
  }
  best.loss = static_cast<float>(std::max(best_loss, 0.0));
  return best;
}

}  // namespace shaderfit::search_detail
