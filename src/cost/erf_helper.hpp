// Internal: erf for the languages that have none (GLSL, HLSL, Metal): the helper function that
// code generation writes into a source once when a formula uses erf, its coefficients, its
// instructions (the `generic` cost of erf, hence here beside the cost model), and the same
// function in C++ float arithmetic, which the tests measure.
//
//   erf(x) = a + a R(a^2)     for a = |x| < 1,
//            1 - 2^Q(min(a, 4))  otherwise,        with the sign of x,
// R a polynomial of degree 6 in a^2 fitted to erf(a)/a - 1 on [0, 1] (relative error 1.2e-9),
// Q of degree 6 in a fitted to log2(erfc(a)) on [1, 4], weighted so that the error it makes in
// erf is relative (1.1e-9); both fits are our own (Lawson's iteratively reweighted least squares
// on 3000 Chebyshev points, erf from mpmath), with the coefficients rounded to float32. Beyond
// a = 4 erf rounds to 1 in float32, which 1 - 2^Q(4) gives. Max error over every float32 x, in
// float32 arithmetic without contraction and with glibc's exp2f (within 0.51 ulp): 1.32 ulp (at
// x = 0.9968; 1.31 ulp at 1.006 on the other branch). A GPU's exp2 adds its own error, scaled
// by erfc(a) <= 0.16. NaN gives 1 or NaN, as the language's min treats it; -0 gives +0.
#pragma once

#include <cmath>
#include <string_view>

namespace shaderfit::cost_detail {

inline constexpr std::string_view kErfHelperName = "sf_erf";
// R's and Q's coefficients, lowest degree first.
inline constexpr float kErfSmall[7] = {0.12837917f,  -0.37612626f,    0.112835854f, -0.026853813f,
                                       0.005188329f, -0.00080102036f, 7.853892e-05f};
inline constexpr float kErfLarge[7] = {-0.0004927133f, -1.626046f,    -0.9206484f,   -0.1487516f,
                                       0.031505667f,   -0.004252572f, 0.00026888837f};
inline constexpr float kErfSplit = 1.0f;  // the first branch below it
inline constexpr float kErfClamp = 4.0f;  // Q's argument at most this

// The helper's SPIR-V arithmetic as glslang emits it from the GLSL and the HLSL (the `generic`
// cost of erf): |x|, a^2, R by Horner, min, Q by Horner, a + a R, exp2, 1 - 2^Q, the branch's
// compare and select, the sign's negation, compare and select.
inline constexpr std::string_view kErfHelperSpirv =
    "OpExtInst FAbs OpFMul "
    "OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd "
    "OpExtInst FMin "
    "OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd OpFMul OpFAdd "
    "OpFMul OpFAdd OpExtInst Exp2 OpFSub OpFOrdLessThan OpSelect OpFNegate OpFOrdLessThan "
    "OpSelect";

// The helper in float, operation for operation as the generated code writes it.
inline float erf_helper(float x) {
  const float a = std::fabs(x);
  const float s = a * a;
  float r = kErfSmall[6];
  for (int k = 5; k >= 0; --k) r = r * s + kErfSmall[k];
  const float t = std::fmin(a, kErfClamp);
  float q = kErfLarge[6];
  for (int k = 5; k >= 0; --k) q = q * t + kErfLarge[k];
  const float lo = a + a * r;
  const float hi = 1.0f - std::exp2(q);
  const float e = a < kErfSplit ? lo : hi;
  const float n = -e;
  return x < 0.0f ? n : e;
}

}  // namespace shaderfit::cost_detail
