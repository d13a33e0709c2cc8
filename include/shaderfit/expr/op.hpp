// The operators of shaderfit expressions, their arity and names, their meaning and their first
// derivatives: the one statement of what each operator computes.
//
// Every backend (CPU evaluator, search, GPU, code generation) computes what `apply_unary`,
// `apply_binary`, `apply_ipow`, `apply_fma` and `apply_select` below define; the SIMD and GPU paths
// are tested against them. They are templates on the number type: the scalar evaluator instantiates
// them on float and double, the search's vector kernels on vectors, and forward-mode
// differentiation on Taylor jets (expr/jet.hpp, through expr/forward.hpp), whose arithmetic and
// elementary functions are found by argument-dependent lookup. The Jacobian evaluator pairs each
// value with the first derivatives defined beside it (`unary_derivative`, `binary_partials`,
// `ipow_derivative`, `ternary_partials`).
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

#include "shaderfit/core.hpp"

// The definitions below are always inlined: callers compiled for a wider ISA (the Jacobian's and
// the search's target clones) then compute them with their own vector instructions.
#if defined(__CUDACC__)
#define SF_OP_INLINE SF_CPU_GPU __forceinline__
#else
#define SF_OP_INLINE SF_CPU_GPU inline __attribute__((always_inline))
#endif

namespace shaderfit {

enum class Op : std::uint8_t {
  // Leaves.
  Const,  // literal constant (Node::value)
  Param,  // named free parameter (Node::index into Expression::parameters)
  Var,    // named input variable (Node::index into Expression::variables)
  // Binary.
  Add,
  Sub,
  Mul,
  Div,
  Min,
  Max,
  Pow,  // pow(a, b) for real b, defined as exp2(b * log2(a)): NaN for a < 0, as on GPUs
  // Unary.
  Neg,
  IPow,  // integer power x^k, k = Node::index in [-16, -1] or [2, 16]
  Sqrt,
  Rsqrt,
  Rcp,
  Exp2,
  Log2,
  Exp,
  Log,
  Abs,
  Saturate,  // clamp to [0, 1]
  Sin,
  Cos,
  // Ternary.
  Fma,  // fma(a, b, c) = a * b + c
  // Operators added later go last: exact JSON stores operators by number.
  Sign,  // unary: 1 for a > 0, -1 for a < 0, a itself for +-0 and NaN
  // binary: |a| with the sign bit of b, as C's copysign: copysign(2, -0.0) = -2. For a NaN b the
  // sign is that NaN's sign bit, which backends set differently (x86 makes negative NaNs, CUDA
  // positive ones): the search rejects formulas with a NaN there (not finite everywhere).
  CopySign,
  Select,  // ternary: select(a, b, c) = a >= 0 ? b : c; -0.0 takes b, NaN takes c
  // As C's libm; unary but atan2 (NaN outside the domain: asin and acos of |a| > 1).
  Asin,
  Acos,
  Atan,
  Atan2,  // binary: atan2(a, b) as C's atan2(y = a, x = b), in [-pi, pi]
  Tanh,
  Erf,
  Count_
};

inline constexpr int kOpCount = static_cast<int>(Op::Count_);
inline constexpr int kMinIntegerPower = -16;
inline constexpr int kMaxIntegerPower = 16;

struct OpInfo {
  std::string_view name;  // function name in formulas ("sqrt"), or the operator symbol ("+")
  int arity;
  bool commutative;
  bool infix;  // printed between its operands (+ - * /), not as a call
};

inline constexpr OpInfo kOpInfo[kOpCount] = {
    {"const", 0, false, false}, {"param", 0, false, false},    {"var", 0, false, false},
    {"+", 2, true, true},       {"-", 2, false, true},         {"*", 2, true, true},
    {"/", 2, false, true},      {"min", 2, true, false},       {"max", 2, true, false},
    {"pow", 2, false, false},   {"neg", 1, false, false},      {"ipow", 1, false, false},
    {"sqrt", 1, false, false},  {"rsqrt", 1, false, false},    {"rcp", 1, false, false},
    {"exp2", 1, false, false},  {"log2", 1, false, false},     {"exp", 1, false, false},
    {"log", 1, false, false},   {"abs", 1, false, false},      {"saturate", 1, false, false},
    {"sin", 1, false, false},   {"cos", 1, false, false},      {"fma", 3, false, false},
    {"sign", 1, false, false},  {"copysign", 2, false, false}, {"select", 3, false, false},
    {"asin", 1, false, false},  {"acos", 1, false, false},     {"atan", 1, false, false},
    {"atan2", 2, false, false}, {"tanh", 1, false, false},     {"erf", 1, false, false},
};

constexpr const OpInfo& op_info(Op op) { return kOpInfo[static_cast<int>(op)]; }
constexpr int arity(Op op) { return op_info(op).arity; }
constexpr bool is_leaf(Op op) { return arity(op) == 0; }

// The operator whose formula name (or symbol) is `name`; Op::Count_ when there is none.
// Accepts the names of functions with arguments (sqrt, pow, fma, ...) and the infix symbols.
Op op_from_name(std::string_view name);

// x^k by repeated squaring, as the generated shader code computes it; k < 0 gives 1 / x^-k. The
// approximations' k is in [-16, 16]; a reference program's any int (reference/program.hpp).
// `one` is T's 1 (given explicitly by number types without a conversion from int: vectors).
template <typename T>
SF_OP_INLINE T apply_ipow(T x, int k, T one = T(1)) {
  const bool inverse = k < 0;
  // 0u - k is |k| for every int, the most negative one included.
  unsigned n = inverse ? 0u - static_cast<unsigned>(k) : static_cast<unsigned>(k);
  T result = one;
  T base = x;
  bool first = true;
  while (n != 0) {
    if (n & 1u) {
      result = first ? base : result * base;
      first = false;
    }
    n >>= 1u;
    if (n != 0) base = base * base;
  }
  return inverse ? one / result : result;
}

template <typename T>
SF_OP_INLINE T apply_unary(Op op, T a) {
  using std::abs, std::acos, std::asin, std::atan, std::cos, std::erf, std::exp, std::exp2,
      std::log, std::log2, std::sin, std::sqrt, std::tanh;
  switch (op) {
    case Op::Neg: return -a;
    case Op::Sqrt: return sqrt(a);
    case Op::Rsqrt: return T(1) / sqrt(a);
    case Op::Rcp: return T(1) / a;
    case Op::Exp2: return exp2(a);
    case Op::Log2: return log2(a);
    case Op::Exp: return exp(a);
    case Op::Log: return log(a);
    case Op::Abs: return abs(a);
    case Op::Saturate: return a < T(0) ? T(0) : (a > T(1) ? T(1) : a);
    case Op::Sin: return sin(a);
    case Op::Cos: return cos(a);
    // a * 0 keeps the zero's sign and a NaN, and has no derivative part (Taylor jets).
    case Op::Sign: return a > T(0) ? T(1) : (a < T(0) ? T(-1) : a * T(0));
    case Op::Asin: return asin(a);
    case Op::Acos: return acos(a);
    case Op::Atan: return atan(a);
    case Op::Tanh: return tanh(a);
    case Op::Erf: return erf(a);
    default: return a / T(0) * T(0);  // NaN: not a unary operator
  }
}

template <typename T>
SF_OP_INLINE T apply_binary(Op op, T a, T b) {
  using std::atan2, std::copysign, std::exp2, std::fmax, std::fmin, std::log2;
  switch (op) {
    case Op::Add: return a + b;
    case Op::Sub: return a - b;
    case Op::Mul: return a * b;
    case Op::Div: return a / b;
    case Op::Min: return fmin(a, b);
    case Op::Max: return fmax(a, b);
    case Op::Pow: return exp2(b * log2(a));
    case Op::CopySign: return copysign(a, b);
    case Op::Atan2: return atan2(a, b);
    default: return a / T(0) * T(0);
  }
}

template <typename T>
SF_OP_INLINE T apply_fma(T a, T b, T c) {
  return a * b + c;
}

// select(a, b, c) = a >= 0 ? b : c: -0.0 takes b, NaN takes c. `zero` is T's 0 (given
// explicitly by number types without a conversion from int: vectors, whose comparison gives a
// lane mask that `?:` applies lane by lane).
template <typename T>
SF_OP_INLINE T apply_select(T a, T b, T c, T zero = T(0)) {
  return a >= zero ? b : c;
}

// The ternary operators by name: Fma or Select.
template <typename T>
SF_OP_INLINE T apply_ternary(Op op, T a, T b, T c) {
  return op == Op::Select ? apply_select(a, b, c) : apply_fma(a, b, c);
}

// d apply_unary(op, a) / da, given y = apply_unary(op, a). Kinks (abs at 0, saturate at 0 and 1)
// take the derivative 0.
template <typename T>
SF_OP_INLINE T unary_derivative(Op op, T a, T y) {
  using std::cos, std::exp, std::sin, std::sqrt;
  constexpr double kLn2 = 0.6931471805599453;
  constexpr double kTwoOverSqrtPi = 1.1283791670955126;
  switch (op) {
    case Op::Neg: return T(-1);
    case Op::Sqrt: return T(0.5) / y;
    case Op::Rsqrt: return T(-0.5) * y / a;
    case Op::Rcp: return -y * y;
    case Op::Exp2: return T(kLn2) * y;
    case Op::Log2: return T(1) / (T(kLn2) * a);
    case Op::Exp: return y;
    case Op::Log: return T(1) / a;
    case Op::Abs: return a > T(0) ? T(1) : (a < T(0) ? T(-1) : T(0));
    case Op::Saturate: return a > T(0) && a < T(1) ? T(1) : T(0);
    case Op::Sin: return cos(a);
    case Op::Cos: return -sin(a);
    case Op::Sign: return T(0);
    case Op::Asin: return T(1) / sqrt(T(1) - a * a);  // NaN outside [-1, 1], inf at +-1
    case Op::Acos: return T(-1) / sqrt(T(1) - a * a);
    case Op::Atan: return T(1) / (T(1) + a * a);
    case Op::Tanh: return T(1) - y * y;
    case Op::Erf: return T(kTwoOverSqrtPi) * exp(-(a * a));
    default: return a / T(0) * T(0);  // NaN: not a unary operator (IPow: ipow_derivative)
  }
}

// d apply_ipow(a, k) / da = k a^(k-1), the power by the same squaring chain.
template <typename T>
SF_OP_INLINE T ipow_derivative(T a, int k, T one = T(1)) {
  return apply_ipow(a, k - 1, one) * T(k);
}

// The partial derivatives of apply_binary(op, a, b) in a and in b, given y = apply_binary(op,
// a, b). min and max take a's branch on a tie.
template <typename T>
struct BinaryPartials {
  T da, db;
};

template <typename T>
SF_OP_INLINE BinaryPartials<T> binary_partials(Op op, T a, T b, T y) {
  using std::copysign, std::log;
  switch (op) {
    case Op::Add: return {T(1), T(1)};
    case Op::Sub: return {T(1), T(-1)};
    case Op::Mul: return {b, a};
    case Op::Div: return {T(1) / b, -y / b};
    case Op::Min: {
      const T in_a = a <= b ? T(1) : T(0);
      return {in_a, T(1) - in_a};
    }
    case Op::Max: {
      const T in_a = a >= b ? T(1) : T(0);
      return {in_a, T(1) - in_a};
    }
    case Op::Pow: return {b * y / a, y * log(a)};
    // d/da = sign(a) * (sign of b) (0 at a = +-0); b only contributes its sign bit: d/db = 0.
    case Op::CopySign: return {apply_unary(Op::Sign, a) * copysign(T(1), b), T(0)};
    // atan2(a, b) is atan(a / b) up to a constant: d/da = b / r2, d/db = -a / r2, r2 = a^2 + b^2.
    case Op::Atan2: {
      const T r2 = a * a + b * b;
      return {b / r2, -a / r2};
    }
    default: return {a / T(0) * T(0), a / T(0) * T(0)};  // NaN: not a binary operator
  }
}

// The partials of a ternary operator in a, b and c: fma's are b, a and 1; select's are 0, the
// condition (1 where a >= 0, else 0) and its complement (the condition is flat almost everywhere).
template <typename T>
struct TernaryPartials {
  T da, db, dc;
};

template <typename T>
SF_OP_INLINE TernaryPartials<T> ternary_partials(Op op, T a, T b, T /*c*/) {
  if (op == Op::Select) {
    const T in_b = apply_select(a, T(1), T(0));
    return {T(0), in_b, T(1) - in_b};
  }
  return {b, a, T(1)};
}

}  // namespace shaderfit
