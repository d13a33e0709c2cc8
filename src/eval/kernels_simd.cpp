// The SIMD backend: per-op kernels over a batch, compiled once per CPU target with Highway and
// chosen at run time. All Highway code of the evaluator is in this file; foreach_target.h
// re-includes it once per target.
//
// Values match expr/op.hpp: arithmetic ops use the same IEEE operations in the same order (fma
// is a rounded product, then a rounded sum, as apply_fma); min/max follow fmin/fmax, including
// glibc's choice of the second operand for min(+0, -0); sign, copysign and select are exact
// (masks and sign bits); transcendental ops use Highway's
// polynomials with masks that restore the scalar special values; erf is std::erf row by row.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "eval/interpreter.hpp"

// Targets: SSE4, AVX2, AVX3 (AVX-512) and the portable EMU128 fallback. SSSE3 and AVX3_DL add
// compile time for little gain.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "eval/kernels_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// Must come after foreach_target.h.
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace shaderfit::eval_detail::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// |x| up to which Highway's Sin/Cos are used (their documented valid range); other lanes,
// infinities and NaN included, go through std::sin / std::cos.
constexpr double kSinCosLimit = 39000.0;

// 2^n for integral n with n + bias in [1, 2 bias]. n + (2^mantissa + bias) is exact and holds
// n + bias in its low bits; shifting them into the exponent field gives 2^n. (A float-to-int
// conversion would do too, but for doubles it is emulated on AVX2 and slow.)
template <class D, class V>
HWY_INLINE V Pow2Int(D d, V n) {
  using T = hn::TFromD<D>;
  constexpr int kMantissa = std::numeric_limits<T>::digits - 1;
  constexpr T kMagic =
      T(hwy::MakeUnsigned<T>(1) << kMantissa) + T(std::numeric_limits<T>::max_exponent - 1);
  const hn::RebindToUnsigned<D> du;
  return hn::BitCast(d, hn::ShiftLeft<kMantissa>(hn::BitCast(du, hn::Add(n, hn::Set(d, kMagic)))));
}

// p 2^n for integral |n| <= 2000 (double) or 200 (float): two exact power-of-two scalings, so
// 2^n never overflows the exponent field and a subnormal result is rounded once.
template <class D, class V>
HWY_INLINE V ScaleByPow2(D d, V p, V n) {
  using T = hn::TFromD<D>;
  const V n1 = hn::Floor(hn::Mul(n, hn::Set(d, T(0.5))));
  return hn::Mul(hn::Mul(p, Pow2Int(d, n1)), Pow2Int(d, hn::Sub(n, n1)));
}

// e^r for |r| <= ln(2)/2 (a little more is fine): the polynomial inside Highway's Exp.
template <class D, class V>
HWY_INLINE V ExpReduced(D d, V r) {
  using T = hn::TFromD<D>;
  hn::impl::ExpImpl<T> impl;
  return hn::Add(impl.ExpPoly(d, r), hn::Set(d, T(1)));
}

// exp2 (Highway 1.0 has none): 2^x = 2^n e^(f ln 2) with n = round(x), |f| <= 1/2 exact.
// Exp(x ln 2) instead would lose |x ln 2| ulp to the rounding of x ln 2.
template <class D, class V>
HWY_INLINE V Exp2V(D d, V x) {
  using T = hn::TFromD<D>;
  const T limit = sizeof(T) == 4 ? T(200) : T(2000);  // past this 2^x is 0 or inf anyway
  const V xc = hn::Min(hn::Max(x, hn::Set(d, -limit)), hn::Set(d, limit));
  const V n = hn::Round(xc);
  const V f = hn::Sub(xc, n);
  const V p = ExpReduced(d, hn::Mul(f, hn::Set(d, T(0.693147180559945309417232121458))));
  return hn::IfThenElse(hn::IsNaN(x), x, ScaleByPow2(d, p, n));
}

// exp: e^x = 2^n e^r with n = round(x / ln 2) and r = x - n ln 2 in two parts (Cody and Waite;
// the first part has few enough bits that n times it is exact), the same split as Highway's
// Exp, with the wider exponent range of ScaleByPow2 and NaN passed through.
template <class D, class V>
HWY_INLINE V ExpV(D d, V x) {
  using T = hn::TFromD<D>;
  const bool f32 = sizeof(T) == 4;
  const T limit = f32 ? T(138) : T(1386);  // ln 2 * (200 or 2000)
  const T ln2_hi = f32 ? T(0.693145751953125) : T(0.6931471805596629565116018);
  const T ln2_lo = f32 ? T(1.428606765330187045e-6) : T(0.28235290563031577122588448175e-12);
  const V xc = hn::Min(hn::Max(x, hn::Set(d, -limit)), hn::Set(d, limit));
  const V n = hn::Round(hn::Mul(xc, hn::Set(d, T(1.44269504088896340735992468))));
  const V r = hn::NegMulAdd(n, hn::Set(d, ln2_lo), hn::NegMulAdd(n, hn::Set(d, ln2_hi), xc));
  return hn::IfThenElse(hn::IsNaN(x), x, ScaleByPow2(d, ExpReduced(d, r), n));
}

// Special values of log and log2: log(±0) = -inf, log(x < 0) = NaN, log(inf) = inf, NaN -> NaN.
template <class D, class V>
HWY_INLINE V FixLog(D d, V x, V r) {
  using T = hn::TFromD<D>;
  const V inf = hn::Set(d, std::numeric_limits<T>::infinity());
  r = hn::IfThenElse(hn::Eq(x, hn::Zero(d)), hn::Neg(inf), r);
  r = hn::IfThenElse(hn::Eq(x, inf), inf, r);
  r = hn::IfThenElse(hn::Lt(x, hn::Zero(d)), hn::Set(d, std::numeric_limits<T>::quiet_NaN()), r);
  return hn::IfThenElse(hn::IsNaN(x), x, r);
}

template <class D, class V>
HWY_INLINE V LogV(D d, V x) {
  return FixLog(d, x, hn::Log(d, x));
}

// log2 = e + log(m) / ln 2 with x = m 2^e and m in [sqrt(1/2), sqrt(2)): exact for powers of
// two, and the error of log(m) stays small next to e. (Highway's Log2 is Log(x) * log2(e).)
// e and m come from the bits with unsigned shifts only, which AVX2 has for 64-bit lanes;
// log(m) is the polynomial inside Highway's Log.
template <class D, class V>
HWY_INLINE V Log2V(D d, V x) {
  using T = hn::TFromD<D>;
  using TU = hwy::MakeUnsigned<T>;
  constexpr int kMantissa = std::numeric_limits<T>::digits - 1;
  constexpr TU kBias = std::numeric_limits<T>::max_exponent - 1;
  constexpr TU kSqrtHalfBits = sizeof(T) == 4 ? TU(0x3F3504F3) : TU(0x3FE6A09E667F3BCDULL);
  constexpr T kTwoMantissa = T(TU(1) << kMantissa);
  const hn::RebindToUnsigned<D> du;
  // Subnormals are scaled into the normal range first.
  const auto tiny = hn::Lt(x, hn::Set(d, std::numeric_limits<T>::min()));
  const T scale = T(4) / std::numeric_limits<T>::epsilon();  // 2^25 or 2^54
  const V xs = hn::IfThenElse(tiny, hn::Mul(x, hn::Set(d, scale)), x);
  // t's exponent field is e + bias, its mantissa field m's bits minus those of sqrt(1/2).
  const auto t = hn::Add(hn::Sub(hn::BitCast(du, xs), hn::Set(du, kSqrtHalfBits)),
                         hn::Set(du, kBias << kMantissa));
  const auto mantissa_mask = hn::Set(du, (TU(1) << kMantissa) - 1);
  const V m = hn::BitCast(d, hn::Add(hn::And(t, mantissa_mask), hn::Set(du, kSqrtHalfBits)));
  // e as T without a conversion: 2^mantissa + (e + bias) has e + bias in its low bits.
  const auto biased_e =
      hn::Or(hn::ShiftRight<kMantissa>(t), hn::BitCast(du, hn::Set(d, kTwoMantissa)));
  const V e_adjust = hn::IfThenElseZero(tiny, hn::Set(d, T(kMantissa + 2)));
  const V e =
      hn::Sub(hn::BitCast(d, biased_e), hn::Add(hn::Set(d, kTwoMantissa + T(kBias)), e_adjust));
  // log(m) as Highway's Log computes it once its range reduction is done (exponent 0).
  hn::impl::LogImpl<T> impl;
  const V one = hn::Set(d, T(1));
  const V m1 = hn::Sub(m, one);
  const V z = hn::Div(m1, hn::Add(m, one));
  const V log_m = hn::NegMulAdd(z, hn::Sub(m1, impl.LogPoly(d, z)), m1);
  const V r = hn::Add(e, hn::Mul(log_m, hn::Set(d, T(1.44269504088896340735992468))));
  return FixLog(d, x, r);
}

// tanh: Highway's, except that |x| below 2^-12 (float) or 2^-27 (double), where tanh(x) rounds
// to x, is x itself (Highway's expm1 loses subnormals), and NaN is passed through (Highway's
// expm1 converts its argument to an integer, which a NaN must not reach).
template <class D, class V>
HWY_INLINE V TanhV(D d, V x) {
  using T = hn::TFromD<D>;
  const T tiny = sizeof(T) == 4 ? T(0x1p-12) : T(0x1p-27);
  const auto nan = hn::IsNaN(x);
  const V r = hn::Tanh(d, hn::IfThenZeroElse(nan, x));
  return hn::IfThenElse(hn::Or(nan, hn::Lt(hn::Abs(x), hn::Set(d, tiny))), x, r);
}

// atan2(y, x) from a = atan(t), t the smaller magnitude over the larger (in [0, 1], so the
// quotient neither overflows nor loses more than its rounding), placed in the quadrant:
// base +- a with base 0, pi/2 (|y| > |x|) or pi (x has its sign bit set, x = -0 included; pi/2
// when both hold), a subtracted when exactly one holds; y's sign last. The bases are split in
// two parts, so that the sum rounds as one. t = 1 takes pi/4 exactly; both zero (t = 0) and both
// infinite (t = 1) give C's values; NaN stays NaN.
template <class D, class V>
HWY_INLINE V Atan2V(D d, V y, V x) {
  using T = hn::TFromD<D>;
  const bool f32 = sizeof(T) == 4;
  const V zero = hn::Zero(d), one = hn::Set(d, T(1));
  const V ay = hn::Abs(y), ax = hn::Abs(x);
  const V lo = hn::Min(ay, ax), hi = hn::Max(ay, ax);
  V t = hn::Div(lo, hi);
  t = hn::IfThenElse(hn::Eq(hi, zero), zero, t);
  t = hn::IfThenElse(hn::Eq(lo, hn::Set(d, std::numeric_limits<T>::infinity())), one, t);
  // Min and Max may drop a NaN operand: bring it back.
  t = hn::IfThenElse(hn::Or(hn::IsNaN(y), hn::IsNaN(x)), hn::Add(y, x), t);
  const V a = hn::IfThenElse(hn::Eq(t, one), hn::Set(d, T(0.785398163397448309615660845820)),
                             hn::Atan(d, t));
  const auto swap = hn::Gt(ay, ax);
  const auto x_negative = hn::Lt(hn::CopySign(one, x), zero);
  const V half_pi_hi = hn::Set(d, T(1.57079632679489661923));
  const V half_pi_lo = hn::Set(d, f32 ? T(-4.37113883e-8) : T(6.123233995736766e-17));
  const V pi_hi = hn::Set(d, T(3.14159265358979323846));
  const V pi_lo = hn::Set(d, f32 ? T(-8.74227766e-8) : T(1.2246467991473532e-16));
  const V base_hi = hn::IfThenElse(swap, half_pi_hi, hn::IfThenElseZero(x_negative, pi_hi));
  const V base_lo = hn::IfThenElse(swap, half_pi_lo, hn::IfThenElseZero(x_negative, pi_lo));
  const auto minus = hn::Xor(swap, x_negative);
  const V r = hn::Add(hn::Add(base_hi, hn::IfThenElse(minus, hn::Neg(a), a)), base_lo);
  return hn::CopySign(r, y);
}

// Elementwise ops as small function objects, so each kernel loop is specialized for one op.
// `one` is 1 in the lane type.
#define SF_UNARY(Name, expr)                                       \
  struct Name {                                                    \
    template <class D, class V>                                    \
    HWY_INLINE V operator()(D d, V a) const {                      \
      [[maybe_unused]] const V one = hn::Set(d, hn::TFromD<D>(1)); \
      return expr;                                                 \
    }                                                              \
  };
#define SF_BINARY(Name, expr)                      \
  struct Name {                                    \
    template <class D, class V>                    \
    HWY_INLINE V operator()(D d, V a, V b) const { \
      (void)d;                                     \
      return expr;                                 \
    }                                              \
  };
SF_UNARY(NegOp, hn::Neg(a))
SF_UNARY(AbsOp, hn::Abs(a))
SF_UNARY(SqrtOp, hn::Sqrt(a))
SF_UNARY(RsqrtOp, hn::Div(one, hn::Sqrt(a)))
SF_UNARY(RcpOp, hn::Div(one, a))
SF_UNARY(Exp2Op, Exp2V(d, a))
SF_UNARY(ExpOp, ExpV(d, a))
SF_UNARY(Log2Op, Log2V(d, a))
SF_UNARY(LogOp, LogV(d, a))
SF_UNARY(SaturateOp, hn::IfThenElse(hn::Lt(a, hn::Zero(d)), hn::Zero(d),
                                    hn::IfThenElse(hn::Gt(a, one), one, a)))
// sign: a * 0 keeps a zero's sign and a NaN, as apply_unary.
SF_UNARY(SignOp, hn::IfThenElse(hn::Gt(a, hn::Zero(d)), one,
                                hn::IfThenElse(hn::Lt(a, hn::Zero(d)), hn::Neg(one),
                                               hn::Mul(a, hn::Zero(d)))))
SF_BINARY(AddOp, hn::Add(a, b))
SF_BINARY(SubOp, hn::Sub(a, b))
SF_BINARY(MulOp, hn::Mul(a, b))
SF_BINARY(DivOp, hn::Div(a, b))
// fmin/fmax: a NaN operand yields the other one; for min(+0, -0) C leaves the sign open, and
// this takes the second operand, as glibc's fmin/fmax (minsd/maxsd) do.
SF_BINARY(MinOp, hn::IfThenElse(hn::Or(hn::Lt(a, b), hn::IsNaN(b)), a, b))
SF_BINARY(MaxOp, hn::IfThenElse(hn::Or(hn::Gt(a, b), hn::IsNaN(b)), a, b))
SF_BINARY(PowOp, Exp2V(d, hn::Mul(b, Log2V(d, a))))
SF_BINARY(CopySignOp, hn::CopySign(a, b))
// asin, acos, atan: Highway's; |x| > 1, infinities and NaN come out NaN (asin, acos) and
// +-pi/2, NaN (atan) as in libm.
SF_UNARY(AsinOp, hn::Asin(d, a))
SF_UNARY(AcosOp, hn::Acos(d, a))
SF_UNARY(AtanOp, hn::Atan(d, a))
SF_UNARY(TanhOp, TanhV(d, a))
SF_BINARY(Atan2Op, Atan2V(d, a, b))
#undef SF_UNARY
#undef SF_BINARY

template <class D, class T, class F>
HWY_INLINE void Map1(D d, const T* a, T* o, size_t count, F f) {
  const size_t N = hn::Lanes(d);
  for (size_t i = 0; i < count; i += N) hn::StoreU(f(d, hn::LoadU(d, a + i)), d, o + i);
}

template <class D, class T, class F>
HWY_INLINE void Map2(D d, const T* a, const T* b, T* o, size_t count, F f) {
  const size_t N = hn::Lanes(d);
  for (size_t i = 0; i < count; i += N)
    hn::StoreU(f(d, hn::LoadU(d, a + i), hn::LoadU(d, b + i)), d, o + i);
}

// select(a, b, c) = a >= 0 ? b : c; NaN compares false and takes c.
template <class D, class T>
HWY_INLINE void Select(D d, const T* a, const T* b, const T* c, T* o, size_t count) {
  const size_t N = hn::Lanes(d);
  for (size_t i = 0; i < count; i += N) {
    const auto cond = hn::Ge(hn::LoadU(d, a + i), hn::Zero(d));
    hn::StoreU(hn::IfThenElse(cond, hn::LoadU(d, b + i), hn::LoadU(d, c + i)), d, o + i);
  }
}

// x^k by the same sequence of multiplications as apply_ipow.
template <class D, class T>
HWY_INLINE void IPow(D d, const T* a, T* o, size_t count, int k) {
  const size_t N = hn::Lanes(d);
  const unsigned n0 = static_cast<unsigned>(k < 0 ? -k : k);
  for (size_t i = 0; i < count; i += N) {
    auto base = hn::LoadU(d, a + i);
    auto result = hn::Set(d, T(1));
    bool first = true;
    for (unsigned n = n0; n != 0;) {
      if (n & 1u) {
        result = first ? base : hn::Mul(result, base);
        first = false;
      }
      n >>= 1u;
      if (n != 0) base = hn::Mul(base, base);
    }
    if (k < 0) result = hn::Div(hn::Set(d, T(1)), result);
    hn::StoreU(result, d, o + i);
  }
}

template <bool kSin, class D, class V>
HWY_INLINE V SinOrCos(D d, V x) {
  if constexpr (kSin) {
    return hn::Sin(d, x);
  } else {
    return hn::Cos(d, x);
  }
}

// sin or cos; lanes outside Highway's valid range are redone with the scalar function.
template <bool kSin, class D, class T>
HWY_INLINE void SinCos(D d, const T* a, T* o, size_t count) {
  const size_t N = hn::Lanes(d);
  const auto limit = hn::Set(d, T(kSinCosLimit));
  for (size_t i = 0; i < count; i += N) {
    const auto x = hn::LoadU(d, a + i);
    const auto in_range = hn::Le(hn::Abs(x), limit);  // false for NaN
    // Lanes out of range go to Highway as 0 (and are redone below): Highway's scalar target
    // converts its argument to int, which is undefined behaviour for NaN.
    const auto r = SinOrCos<kSin>(d, hn::IfThenElseZero(in_range, x));
    if (HWY_LIKELY(hn::AllTrue(d, in_range))) {
      hn::StoreU(r, d, o + i);
      continue;
    }
    T xs[kRowAlign<T>];  // a may be o: keep the inputs
    hn::StoreU(x, d, xs);
    hn::StoreU(r, d, o + i);
    for (size_t j = 0; j < N; ++j)
      if (!(std::abs(xs[j]) <= T(kSinCosLimit)))
        o[i + j] = kSin ? std::sin(xs[j]) : std::cos(xs[j]);
  }
}

// erf: std::erf row by row (Highway has no erf; the search rarely uses it).
template <class T>
HWY_INLINE void ErfRows(const T* a, T* o, size_t count) {
  for (size_t i = 0; i < count; ++i) o[i] = std::erf(a[i]);
}

template <typename T>
struct SimdKernels {
  void operator()(const Instr& ins, T* const* src, size_t count) const {
    const hn::ScalableTag<T> d;
    T* o = src[ins.out];
    const T* a = src[ins.arg[0]];
    const T* b = src[ins.arg[1]];
    switch (ins.op) {
      case Op::Add: return Map2(d, a, b, o, count, AddOp());
      case Op::Sub: return Map2(d, a, b, o, count, SubOp());
      case Op::Mul: return Map2(d, a, b, o, count, MulOp());
      case Op::Div: return Map2(d, a, b, o, count, DivOp());
      case Op::Min: return Map2(d, a, b, o, count, MinOp());
      case Op::Max: return Map2(d, a, b, o, count, MaxOp());
      case Op::Pow: return Map2(d, a, b, o, count, PowOp());
      case Op::Neg: return Map1(d, a, o, count, NegOp());
      case Op::IPow: return IPow(d, a, o, count, ins.k);
      case Op::Sqrt: return Map1(d, a, o, count, SqrtOp());
      case Op::Rsqrt: return Map1(d, a, o, count, RsqrtOp());
      case Op::Rcp: return Map1(d, a, o, count, RcpOp());
      case Op::Exp2: return Map1(d, a, o, count, Exp2Op());
      case Op::Log2: return Map1(d, a, o, count, Log2Op());
      case Op::Exp: return Map1(d, a, o, count, ExpOp());
      case Op::Log: return Map1(d, a, o, count, LogOp());
      case Op::Abs: return Map1(d, a, o, count, AbsOp());
      case Op::Saturate: return Map1(d, a, o, count, SaturateOp());
      case Op::Sin: return SinCos<true>(d, a, o, count);
      case Op::Cos: return SinCos<false>(d, a, o, count);
      case Op::Sign: return Map1(d, a, o, count, SignOp());
      case Op::CopySign: return Map2(d, a, b, o, count, CopySignOp());
      case Op::Asin: return Map1(d, a, o, count, AsinOp());
      case Op::Acos: return Map1(d, a, o, count, AcosOp());
      case Op::Atan: return Map1(d, a, o, count, AtanOp());
      case Op::Atan2: return Map2(d, a, b, o, count, Atan2Op());
      case Op::Tanh: return Map1(d, a, o, count, TanhOp());
      case Op::Erf: return ErfRows(a, o, count);
      case Op::Select: return Select(d, a, b, static_cast<const T*>(src[ins.arg[2]]), o, count);
      case Op::Fma:
        // Two passes, so that no compiler can fuse the product into the sum. The third operand
        // is never in the output slot (it sits two places higher on the postfix stack).
        Map2(d, a, b, o, count, MulOp());
        return Map2(d, static_cast<const T*>(o), static_cast<const T*>(src[ins.arg[2]]), o, count,
                    AddOp());
      default: return;  // leaves never appear in a plan
    }
  }
};

void TaskF32(const Plan<float>& plan, const float* const* columns, float* out, size_t begin,
             size_t end) {
  run_task(plan, columns, out, begin, end, SimdKernels<float>());
}

void TaskF64(const Plan<double>& plan, const double* const* columns, double* out, size_t begin,
             size_t end) {
  run_task(plan, columns, out, begin, end, SimdKernels<double>());
}

}  // namespace shaderfit::eval_detail::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace shaderfit::eval_detail {

HWY_EXPORT(TaskF32);
HWY_EXPORT(TaskF64);

TaskFn<float> simd_task_f32() { return HWY_DYNAMIC_DISPATCH(TaskF32); }
TaskFn<double> simd_task_f64() { return HWY_DYNAMIC_DISPATCH(TaskF64); }

std::vector<std::int64_t> simd_targets() { return hwy::SupportedAndGeneratedTargets(); }

std::string simd_target_name(std::int64_t target) { return hwy::TargetName(target); }

void force_simd_target(std::int64_t target) {
  hwy::SetSupportedTargetsForTest(target);
  hwy::GetChosenTarget().Update(hwy::SupportedTargets());
}

}  // namespace shaderfit::eval_detail
#endif  // HWY_ONCE
