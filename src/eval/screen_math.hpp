// Internal: the search's screening-precision sqrt, exp2 and log2 (relative error below 1e-6,
// branch-free so that they vectorise; NaN outside the domain, as the scalar functions) and the
// screen's value of a unary operator, written once for a lane type V: float, one value (the GPU
// screen, src/gpu/screen_column.hpp), or the CPU enumerator's eight-float vectors
// (src/search/enumeration/enum_kernels.cpp). The same IEEE operations in the same order give
// both the same bits, value for value (with no contraction on either side).
//
// L, the lanes' operations: I (the integer lanes), bits(V) -> I and from_bits(I) -> V (the
// same bits), pick(mask, a, b), to_int(V) (toward zero; INT32_MIN for NaN, as cvttps2dq),
// to_float(I), one_where(mask) -> I (1 where true, else 0), shl23(I), splat(float) -> V, and
// apply(op, V): the operator's own form (expr/op.hpp) for those without a screening form here.
#pragma once

#include <cstdint>
#include <cstring>

#include "shaderfit/expr/op.hpp"

namespace shaderfit::eval_detail {

template <typename V>
struct ScreenLanes;

// One float.
template <>
struct ScreenLanes<float> {
  using I = std::int32_t;
  SF_OP_INLINE static I bits(float x) {
    std::uint32_t u;
    std::memcpy(&u, &x, sizeof u);
    return static_cast<I>(u);
  }
  SF_OP_INLINE static float from_bits(I i) {
    const auto u = static_cast<std::uint32_t>(i);
    float x;
    std::memcpy(&x, &u, sizeof x);
    return x;
  }
  SF_OP_INLINE static float pick(bool m, float a, float b) { return m ? a : b; }
  SF_OP_INLINE static I to_int(float x) {
    return x == x && x > -2147483648.0f && x < 2147483648.0f ? static_cast<I>(x)
                                                             : static_cast<I>(0x80000000u);
  }
  SF_OP_INLINE static float to_float(I i) { return static_cast<float>(i); }
  SF_OP_INLINE static I one_where(bool m) { return m ? 1 : 0; }
  SF_OP_INLINE static I shl23(I i) { return static_cast<I>(static_cast<std::uint32_t>(i) << 23); }
  SF_OP_INLINE static float splat(float x) { return x; }
  SF_OP_INLINE static float apply(Op op, float a) { return apply_unary(op, a); }
};

inline constexpr float kScreenInf = __builtin_huge_valf();

// The quiet NaN of every backend (0x7fc00000) in each lane.
template <typename V, typename L = ScreenLanes<V>>
SF_OP_INLINE V screen_nan() {
  return L::from_bits(L::bits(L::splat(0.0f)) + 0x7fc00000);
}

// Bit-level initial guess, then three Newton steps on y^2 = x.
template <typename V, typename L = ScreenLanes<V>>
SF_OP_INLINE V screen_sqrt(V x) {
  const typename L::I i = L::bits(x);
  V y = L::from_bits((i >> 1) + 0x1fbd1df5);
  const V half = L::splat(0.5f);
  y = half * (y + x / y);
  y = half * (y + x / y);
  y = half * (y + x / y);
  y = L::pick(x == 0.0f, L::splat(0.0f), y);
  y = L::pick(x == kScreenInf, L::splat(kScreenInf), y);
  return L::pick(x >= 0.0f, y, screen_nan<V, L>());
}

// 2^n p(f) with n = round(x) and p a degree-8 Taylor polynomial of e^(f ln 2), f in [-0.5, 0.5].
template <typename V, typename L = ScreenLanes<V>>
SF_OP_INLINE V screen_exp2(V x) {
  using I = typename L::I;
  const V xc = L::pick(x > 128.0f, L::splat(128.0f), L::pick(x < -126.0f, L::splat(-126.0f), x));
  const V r = xc + 0.5f;
  I n = L::to_int(r);
  n -= L::one_where(L::to_float(n) > r);  // floor
  const V f = xc - L::to_float(n);        // in [-0.5, 0.5]
  const V t = f * 0.69314718f;
  V p = L::splat(1.0f / 5040);
  p = p * t + 1.0f / 720;
  p = p * t + 1.0f / 120;
  p = p * t + 1.0f / 24;
  p = p * t + 1.0f / 6;
  p = p * t + 0.5f;
  p = p * t + 1.0f;
  p = p * t + 1.0f;
  const auto big = n > 127;
  const V scale = L::from_bits(L::shl23((n - L::one_where(big)) + 127));
  V y = p * scale * L::pick(big, L::splat(2.0f), L::splat(1.0f));
  y = L::pick(x > 128.0f, L::splat(kScreenInf), y);
  y = L::pick(x < -126.0f, L::splat(0.0f), y);
  return L::pick(x == x, y, screen_nan<V, L>());
}

// The exponent, plus 2 atanh(t) / ln 2 with t = (m - 1) / (m + 1) for the mantissa m in
// [sqrt(2) / 2, sqrt(2)).
template <typename V, typename L = ScreenLanes<V>>
SF_OP_INLINE V screen_log2(V x) {
  using I = typename L::I;
  const I bits = L::bits(x);
  I e = ((bits >> 23) & 0xff) - 127;
  V m = L::from_bits((bits & 0x007fffff) | 0x3f800000);  // [1, 2)
  const auto high = m > 1.41421356f;
  m = L::pick(high, m * 0.5f, m);
  e += L::one_where(high);
  const V t = (m - 1.0f) / (m + 1.0f);
  const V t2 = t * t;
  V p = L::splat(1.0f / 9);
  p = p * t2 + 1.0f / 7;
  p = p * t2 + 1.0f / 5;
  p = p * t2 + 1.0f / 3;
  p = p * t2 + 1.0f;
  V y = L::to_float(e) + (2.0f * 1.44269504f) * t * p;
  y = L::pick(x == kScreenInf, L::splat(kScreenInf), y);
  y = L::pick(x == 0.0f, L::splat(-kScreenInf), y);
  return L::pick(x > 0.0f, y, L::pick(x == 0.0f, y, screen_nan<V, L>()));
}

// The screen's value of unary operator `op` at a: the screening forms above for the functions
// they compute, exact arithmetic for the others, and the operator's own form (L::apply) for sin,
// cos, asin ... erf, which are rare.
template <typename V, typename L = ScreenLanes<V>>
SF_OP_INLINE V screen_unary(Op op, V a) {
  switch (op) {
    case Op::Sqrt: return screen_sqrt<V, L>(a);
    case Op::Rsqrt: return 1.0f / screen_sqrt<V, L>(a);
    case Op::Rcp: return 1.0f / a;
    case Op::Exp2: return screen_exp2<V, L>(a);
    case Op::Log2: return screen_log2<V, L>(a);
    case Op::Exp: return screen_exp2<V, L>(a * 1.44269504f);
    case Op::Log: return screen_log2<V, L>(a) * 0.69314718f;
    case Op::Abs: return L::from_bits(L::bits(a) & 0x7fffffff);
    case Op::Saturate:
      return L::pick(a < 0.0f, L::splat(0.0f), L::pick(a > 1.0f, L::splat(1.0f), a));
    case Op::Sign:  // as apply_unary: +-1, and a * 0 for zeros and NaN
      return L::pick(a > 0.0f, L::splat(1.0f), L::pick(a < 0.0f, L::splat(-1.0f), a * 0.0f));
    default: return L::apply(op, a);
  }
}

}  // namespace shaderfit::eval_detail
