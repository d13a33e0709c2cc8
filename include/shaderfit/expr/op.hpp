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

// The operators, one row each, in enum order (exact JSON stores operators by number: operators
// added later go last). Columns: the enumerator; the name in formulas ("sqrt") or the infix
// symbol ("+"); arity; commutative; infix (printed between its operands); library (computed by
// a library approximation, libm's, Highway's or CUDA's, rather than exactly rounded
// arithmetic); ulps (the bound on the vector forms' error against the scalar one,
// docs/evaluation.md; 0: the same bits); parity (a unary operator's symmetry: Odd, f(-a) =
// -f(a), or Even, f(-a) = f(a); ipow's depends on k); search (the operator's place in the list of
// those the search may use, as its messages list them; 0: not searchable); the LaTeX form, a
// pattern in which $0, $1, $2 stand for the operands as they are, $f0, $f1 for an operand as a
// factor (parenthesised below a product), $b0 for one as the base of a power (parenthesised
// unless an atom) and $k for Node::index; empty for the leaves and + and -, which
// expr/print.cpp writes itself (numbers, names, signs folded into sums).
//
// The meaning of each operator (value, derivative) is the apply_* and *_derivative functions
// below; a row's comment says what the name alone does not.
#define SHADERFIT_OPERATORS(X)                                                                    \
  /* Leaves: a literal constant (Node::value), a free parameter and an input variable */          \
  /* (Node::index into Expression::parameters and ::variables). */                                \
  X(Const, "const", 0, false, false, false, 0, None, 0, "")                                       \
  X(Param, "param", 0, false, false, false, 0, None, 0, "")                                       \
  X(Var, "var", 0, false, false, false, 0, None, 0, "")                                           \
  /* Binary. */                                                                                   \
  X(Add, "+", 2, true, true, false, 0, None, 1, "")                                               \
  X(Sub, "-", 2, false, true, false, 0, None, 2, "")                                              \
  X(Mul, "*", 2, true, true, false, 0, None, 3, "$f0 \\cdot $f1")                                 \
  X(Div, "/", 2, false, true, false, 0, None, 4, "\\frac{$0}{$1}")                                \
  X(Min, "min", 2, true, false, false, 0, None, 17, "\\min\\left($0, $1\\right)")                 \
  X(Max, "max", 2, true, false, false, 0, None, 18, "\\max\\left($0, $1\\right)")                 \
  /* pow(a, b) for real b, defined as exp2(b * log2(a)): NaN for a < 0, as on GPUs */             \
  X(Pow, "pow", 2, false, false, true, 4, None, 19, "$b0^{$1}")                                   \
  /* Unary. */                                                                                    \
  X(Neg, "neg", 1, false, false, false, 0, Odd, 0, "-$f0")                                        \
  /* integer power x^k, k = Node::index in [-16, -1] or [2, 16] */                                \
  X(IPow, "ipow", 1, false, false, false, 0, None, 5, "$b0^{$k}")                                 \
  X(Sqrt, "sqrt", 1, false, false, false, 0, None, 6, "\\sqrt{$0}")                               \
  X(Rsqrt, "rsqrt", 1, false, false, false, 0, None, 7, "\\frac{1}{\\sqrt{$0}}")                  \
  X(Rcp, "rcp", 1, false, false, false, 0, Odd, 8, "\\frac{1}{$0}")                               \
  X(Exp2, "exp2", 1, false, false, true, 2, None, 9, "2^{$0}")                                    \
  X(Log2, "log2", 1, false, false, true, 3, None, 10, "\\log_2\\left($0\\right)")                 \
  X(Exp, "exp", 1, false, false, true, 2, None, 11, "e^{$0}")                                     \
  X(Log, "log", 1, false, false, true, 3, None, 12, "\\ln\\left($0\\right)")                      \
  X(Abs, "abs", 1, false, false, false, 0, Even, 13, "\\left|$0\\right|")                         \
  /* clamp to [0, 1] */                                                                           \
  X(Saturate, "saturate", 1, false, false, false, 0, None, 14,                                    \
    "\\operatorname{saturate}\\left($0\\right)")                                                  \
  X(Sin, "sin", 1, false, false, true, 3, Odd, 15, "\\sin\\left($0\\right)")                      \
  X(Cos, "cos", 1, false, false, true, 3, Even, 16, "\\cos\\left($0\\right)")                     \
  /* Ternary: fma(a, b, c) = a * b + c. */                                                        \
  X(Fma, "fma", 3, false, false, false, 0, None, 0, "$f0 \\cdot $f1 + $2")                        \
  /* Operators added later. Unary: 1 for a > 0, -1 for a < 0, a itself for +-0 and NaN. */        \
  X(Sign, "sign", 1, false, false, false, 0, Odd, 20, "\\operatorname{sign}\\left($0\\right)")    \
  /* binary: |a| with the sign bit of b, as C's copysign: copysign(2, -0.0) = -2. For a NaN b */  \
  /* the sign is that NaN's sign bit, which backends set differently (x86 makes negative NaNs, */ \
  /* CUDA positive ones): the search rejects formulas with a NaN there (not finite). */           \
  X(CopySign, "copysign", 2, false, false, false, 0, None, 21,                                    \
    "\\operatorname{copysign}\\left($0, $1\\right)")                                              \
  /* ternary: select(a, b, c) = a >= 0 ? b : c; -0.0 takes b, NaN takes c */                      \
  X(Select, "select", 3, false, false, false, 0, None, 22,                                        \
    "\\begin{cases}$1 & $0 \\geq 0 \\\\ $2 & \\text{otherwise}\\end{cases}")                      \
  /* As C's libm; unary but atan2 (NaN outside the domain: asin and acos of |a| > 1). */          \
  X(Asin, "asin", 1, false, false, true, 3, Odd, 23, "\\arcsin\\left($0\\right)")                 \
  X(Acos, "acos", 1, false, false, true, 3, None, 24, "\\arccos\\left($0\\right)")                \
  X(Atan, "atan", 1, false, false, true, 3, Odd, 25, "\\arctan\\left($0\\right)")                 \
  /* binary: atan2(a, b) as C's atan2(y = a, x = b), in [-pi, pi] */                              \
  X(Atan2, "atan2", 2, false, false, true, 3, None, 26,                                           \
    "\\operatorname{atan2}\\left($0, $1\\right)")                                                 \
  X(Tanh, "tanh", 1, false, false, true, 4, Odd, 27, "\\tanh\\left($0\\right)")                   \
  X(Erf, "erf", 1, false, false, true, 0, Odd, 28, "\\operatorname{erf}\\left($0\\right)")

enum class Op : std::uint8_t {
#define SHADERFIT_OP_ENUMERATOR(name, ...) name,
  SHADERFIT_OPERATORS(SHADERFIT_OP_ENUMERATOR)
#undef SHADERFIT_OP_ENUMERATOR
      Count_
};

inline constexpr int kOpCount = static_cast<int>(Op::Count_);
inline constexpr int kMinIntegerPower = -16;
inline constexpr int kMaxIntegerPower = 16;

// How a unary operator's value at -a relates to its value at a.
enum class OpParity : std::uint8_t {
  None,
  Odd,   // f(-a) = -f(a)
  Even,  // f(-a) = f(a)
};

// One operator's row of SHADERFIT_OPERATORS.
struct OpInfo {
  std::string_view name;  // function name in formulas ("sqrt"), or the operator symbol ("+")
  int arity;
  bool commutative;
  bool infix;    // printed between its operands (+ - * /), not as a call
  bool library;  // computed by a library approximation (libm, Highway, CUDA), not exactly rounded
  int ulps;      // the vector forms' error bound against the scalar one; 0: the same bits
  OpParity parity;         // a unary operator's symmetry in its operand; None for the others
  int search;              // 1-based place among the searchable operators; 0: not searchable
  std::string_view latex;  // LaTeX pattern ($0, $f0, $b0, $k); empty where print.cpp writes it
};

inline constexpr OpInfo kOpInfo[kOpCount] = {
#define SHADERFIT_OP_INFO(enumerator, name, arity, commutative, infix, library, ulps, parity, \
                          search, latex)                                                      \
  {name, arity, commutative, infix, library, ulps, OpParity::parity, search, latex},
    SHADERFIT_OPERATORS(SHADERFIT_OP_INFO)
#undef SHADERFIT_OP_INFO
};

// SF_CPU_GPU for the `if constexpr` tests of device code (program.hpp, apply_unary); at run time
// only host code reads the table.
SF_CPU_GPU constexpr const OpInfo& op_info(Op op) { return kOpInfo[static_cast<int>(op)]; }
SF_CPU_GPU constexpr int arity(Op op) { return op_info(op).arity; }
SF_CPU_GPU constexpr bool is_leaf(Op op) { return arity(op) == 0; }

// How tightly the operator binds where it is written as an operator (formulas, generated code,
// listings): 1 the sums (+ -), 2 the products (* /), 3 negation, 4 the rest (calls and leaves).
// The infix operators are left associative: their right operand is written one level higher.
SF_CPU_GPU constexpr int precedence(Op op) {
  switch (op) {
    case Op::Add:
    case Op::Sub: return 1;
    case Op::Mul:
    case Op::Div: return 2;
    case Op::Neg: return 3;
    default: return 4;
  }
}

// f.template operator()<O>() for the operator O that `op` names (O = Op::Count_ for a value outside
// the table): code that treats operators differently dispatches through this, one instantiation
// per operator, instead of a switch of its own that names them.
template <typename F>
constexpr decltype(auto) visit_op(Op op, F&& f) {
  switch (op) {
#define SHADERFIT_OP_VISIT_CASE(name, ...) \
  case Op::name: return f.template operator()<Op::name>();
    SHADERFIT_OPERATORS(SHADERFIT_OP_VISIT_CASE)
#undef SHADERFIT_OP_VISIT_CASE
    default: return f.template operator()<Op::Count_>();
  }
}

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

// The value of unary operator O (not ipow: apply_ipow) at a. Each operator's form is
// instantiated alone, so a number type needs only what the operators it is used with need
// (intervals: verify/interval.hpp, which gives saturate and sign forms of its own).
template <Op O, typename T>
SF_OP_INLINE T unary_value(T a) {
  using std::abs, std::acos, std::asin, std::atan, std::cos, std::erf, std::exp, std::exp2,
      std::log, std::log2, std::sin, std::sqrt, std::tanh;
  if constexpr (O == Op::Neg)
    return -a;
  else if constexpr (O == Op::Sqrt)
    return sqrt(a);
  else if constexpr (O == Op::Rsqrt)
    return T(1) / sqrt(a);
  else if constexpr (O == Op::Rcp)
    return T(1) / a;
  else if constexpr (O == Op::Exp2)
    return exp2(a);
  else if constexpr (O == Op::Log2)
    return log2(a);
  else if constexpr (O == Op::Exp)
    return exp(a);
  else if constexpr (O == Op::Log)
    return log(a);
  else if constexpr (O == Op::Abs)
    return abs(a);
  else if constexpr (O == Op::Saturate)
    return a < T(0) ? T(0) : (a > T(1) ? T(1) : a);
  else if constexpr (O == Op::Sin)
    return sin(a);
  else if constexpr (O == Op::Cos)
    return cos(a);
  // a * 0 keeps the zero's sign and a NaN, and has no derivative part (Taylor jets).
  else if constexpr (O == Op::Sign)
    return a > T(0) ? T(1) : (a < T(0) ? T(-1) : a * T(0));
  else if constexpr (O == Op::Asin)
    return asin(a);
  else if constexpr (O == Op::Acos)
    return acos(a);
  else if constexpr (O == Op::Atan)
    return atan(a);
  else if constexpr (O == Op::Tanh)
    return tanh(a);
  else if constexpr (O == Op::Erf)
    return erf(a);
  else
    return a / T(0) * T(0);  // NaN: not a unary operator
}

// The value of unary operator O at a, ipow's exponent `index` (Node::index) included.
template <Op O, typename T>
SF_OP_INLINE T unary_value(T a, int index) {
  if constexpr (O == Op::IPow)
    return apply_ipow(a, index);
  else
    return unary_value<O>(a);
}

// The value of binary operator O at (a, b).
template <Op O, typename T>
SF_OP_INLINE T binary_value(T a, T b) {
  using std::atan2, std::copysign, std::exp2, std::fmax, std::fmin, std::log2;
  if constexpr (O == Op::Add)
    return a + b;
  else if constexpr (O == Op::Sub)
    return a - b;
  else if constexpr (O == Op::Mul)
    return a * b;
  else if constexpr (O == Op::Div)
    return a / b;
  else if constexpr (O == Op::Min)
    return fmin(a, b);
  else if constexpr (O == Op::Max)
    return fmax(a, b);
  else if constexpr (O == Op::Pow)
    return exp2(b * log2(a));
  else if constexpr (O == Op::CopySign)
    return copysign(a, b);
  else if constexpr (O == Op::Atan2)
    return atan2(a, b);
  else
    return a / T(0) * T(0);  // NaN: not a binary operator
}

// erf^-1(y) for y in (-1, 1), to double precision; +-inf at +-1, NaN outside.
double inverse_erf(double y);

// Where a library function can be undone on a target (the search's probe of library operators,
// search/starts/library_operators.cpp: is f^-1(target) simpler than the target?): the values it
// takes, and f^-1 there (op_inverse_value); atan2's angle is undone as atan's. `invertible` is
// false for the other operators.
struct OpInverse {
  bool invertible = false;
  double lo = 0, hi = 0;  // the range
  bool open = false;      // the range excludes its ends
};
inline OpInverse op_inverse(Op op) {
  constexpr double pi = 3.141592653589793;
  switch (op) {
    case Op::Asin: return {true, -pi / 2, pi / 2, false};
    case Op::Acos: return {true, 0, pi, false};
    case Op::Atan: return {true, -pi / 2, pi / 2, true};
    case Op::Atan2: return {true, -pi, pi, false};
    case Op::Tanh: return {true, -1, 1, true};
    case Op::Erf: return {true, -1, 1, true};
    default: return {};
  }
}
inline double op_inverse_value(Op op, double y) {
  switch (op) {
    case Op::Asin: return std::sin(y);
    case Op::Acos: return std::cos(y);
    case Op::Atan:
    case Op::Atan2: return std::tan(y);
    case Op::Tanh: return std::atanh(y);
    case Op::Erf: return inverse_erf(y);
    default: return y / 0.0 * 0.0;  // NaN
  }
}

// Whether the operator's value is >= 0 (or NaN) for every value of its operands, given which
// operands are: operand_nonnegative(k) for operand k (called only where the answer needs it).
// `index` is Node::index (ipow's exponent). The leaves are the caller's.
template <typename F>
constexpr bool value_nonnegative(Op op, int index, F&& operand_nonnegative) {
  switch (op) {
    case Op::Sqrt:
    case Op::Rsqrt:
    case Op::Exp2:
    case Op::Exp:
    case Op::Abs:
    case Op::Saturate: return true;
    case Op::IPow: return index % 2 == 0 || operand_nonnegative(0);
    case Op::Rcp:
    case Op::Pow: return operand_nonnegative(0);
    case Op::Add:
    case Op::Mul:
    case Op::Div:
    case Op::Min: return operand_nonnegative(0) && operand_nonnegative(1);
    case Op::Max: return operand_nonnegative(0) || operand_nonnegative(1);
    case Op::Select: return operand_nonnegative(1) && operand_nonnegative(2);
    default: return false;
  }
}

// Whether the operator is piecewise (min, max, abs, saturate, sign, copysign, select): two
// formulas with one can agree on many points and differ elsewhere, where formulas of the others
// (rational and analytic functions) that agree on a few dozen points are the same.
constexpr bool is_piecewise(Op op) {
  switch (op) {
    case Op::Min:
    case Op::Max:
    case Op::Abs:
    case Op::Saturate:
    case Op::Sign:
    case Op::CopySign:
    case Op::Select: return true;
    default: return false;
  }
}

// Whether the operator is periodic in its operand (sin, cos): the operator probe
// (search/starts/operator_probe.cpp) offers these together where an input looks like an angle.
constexpr bool is_periodic(Op op) { return op == Op::Sin || op == Op::Cos; }

// Whether the operator's value can be finite while an operand is not (x / inf = 0, rcp(inf) = 0,
// min(inf, x) = x, saturate(inf) = 1, exp2(-inf) = 0, x^-k = rcp(x^k), pow through exp2,
// sign(inf) = 1, copysign(x, inf) = |x|, select's branch not taken, atan(inf) = pi/2,
// tanh(inf) = erf(inf) = 1, atan2(x, inf) = 0): a NaN or an infinity can hide below it. Through
// every other operator it reaches the result. `index` is Node::index (ipow's exponent).
constexpr bool absorbs_non_finite(Op op, int index) {
  switch (op) {
    case Op::Div:
    case Op::Rcp:
    case Op::Rsqrt:
    case Op::Min:
    case Op::Max:
    case Op::Saturate:
    case Op::Exp2:
    case Op::Exp:
    case Op::Pow:
    case Op::Sign:
    case Op::CopySign:
    case Op::Select:
    case Op::Atan:
    case Op::Tanh:
    case Op::Erf:
    case Op::Atan2: return true;
    case Op::IPow: return index < 0;
    default: return false;
  }
}

// Two calls of f that one call does: f(a) outer f(b) = f(a inner b) in real arithmetic wherever
// the left side is finite (there a and b are in f's domain). The simplifier's merge_calls
// (expr/simplify.hpp); pow with one exponent is there too.
struct CallMerge {
  Op call;
  Op outer;
  Op inner;
};
inline constexpr CallMerge kCallMerges[] = {
    {Op::Rcp, Op::Mul, Op::Mul},  {Op::Sqrt, Op::Mul, Op::Mul}, {Op::Rsqrt, Op::Mul, Op::Mul},
    {Op::Exp2, Op::Mul, Op::Add}, {Op::Exp, Op::Mul, Op::Add},  {Op::Exp2, Op::Div, Op::Sub},
    {Op::Exp, Op::Div, Op::Sub},  {Op::Log2, Op::Add, Op::Mul}, {Op::Log, Op::Add, Op::Mul},
};

// The unary operators by name (a switch over the table, each case unary_value).
template <typename T>
SF_OP_INLINE T apply_unary(Op op, T a) {
  switch (op) {
#define SHADERFIT_OP_UNARY_CASE(name, ...)                      \
  case Op::name:                                                \
    if constexpr (arity(Op::name) == 1 && Op::name != Op::IPow) \
      return unary_value<Op::name>(a);                          \
    else                                                        \
      break;
    SHADERFIT_OPERATORS(SHADERFIT_OP_UNARY_CASE)
#undef SHADERFIT_OP_UNARY_CASE
    default: break;
  }
  return a / T(0) * T(0);  // NaN: not a unary operator
}

// The unary operators by name, ipow's exponent `index` (Node::index) included.
template <typename T>
SF_OP_INLINE T apply_unary(Op op, T a, int index) {
  return op == Op::IPow ? apply_ipow(a, index) : apply_unary(op, a);
}

// The binary operators by name.
template <typename T>
SF_OP_INLINE T apply_binary(Op op, T a, T b) {
  switch (op) {
#define SHADERFIT_OP_BINARY_CASE(name, ...) \
  case Op::name:                            \
    if constexpr (arity(Op::name) == 2)     \
      return binary_value<Op::name>(a, b);  \
    else                                    \
      break;
    SHADERFIT_OPERATORS(SHADERFIT_OP_BINARY_CASE)
#undef SHADERFIT_OP_BINARY_CASE
    default: break;
  }
  return a / T(0) * T(0);
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
