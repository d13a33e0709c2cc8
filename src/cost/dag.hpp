// Internal: an expression lowered to a DAG in which equal subexpressions are one node.
//
// The cost model and code generation both start here, so that what is counted is what is
// printed. Lowering (docs/cost-model.md, "Lowering"):
//  - hash-consing: a node is looked up by its structure (op, operands with their signs, constant
//    bits) before it is created, so equal subtrees become one node; + * min max sort operands;
//  - negation is a flag on the reference (DagRef::neg), never a node: `a - b` is Add(a, -b);
//    Add keeps its first operand positive, Mul, Rcp, Sin, Asin, Atan, Tanh, Erf and Atan2's
//    first operand are positive (the sign moves to the result), Cos and Abs drop an operand's
//    sign;
//  - subtrees of literal constants are folded in float32, as a compiler folds float literals;
//    x*1 and x*-1 lose the constant, and x + -0 is x (exact identities only);
//  - every operator becomes the nodes of the instruction set: a / b = a * rcp(b); x^k is the
//    squaring chain of apply_ipow; fma(a, b, c) = a*b + c; pow(a, b) = exp2(b * log2(a));
//    log(x) = log2(x) * ln2 (the Mul carries `log_scale`, so code prints it as log(x)); exp stays
//    one node (a scale and an exp2 on GPUs, which never fuse with anything else); sign,
//    copysign and select stay one node each (sign(-x) = -sign(x), copysign drops its first
//    operand's sign and moves its second's out, select(a, -b, -c) = -select(a, b, c)).
// Nodes are in topological order: a node's operands have smaller ids.
//
// Lowered for half (`half` = true; the half code of codegen and the `sass-half2` target), the DAG
// keeps every rounding that eval/evaluate_in.hpp's half evaluation makes, so that the printed half
// code rounds where evaluate_half does: constants are binary16 values and fold as evaluate_half
// computes them (each result rounded to binary16); a / b is one Div node (one rounding), 1 / x an
// Rcp, and a / K a product only where 1/K is an exact power of two; fma(a, b, c) is one Fma node
// (a * b + c stays a product and a sum); log(x) is one Log node; 1 / sqrt(x) stays a division of
// the square root. The other rewrites above are exact in any precision and stay.
//
// Lowered for fast math (`fast_math` = true; the RDNA targets, whose compiler, LLVM under
// -cl-fast-relaxed-math, assumes no NaN, infinity or signed zero and rewrites the algebra), the DAG
// also makes these folds: x - x = 0, x * 0 = 0, x + 0 = x, x * (1 / x) = 1 (so x / x),
// 1 / (1 / x) = x, 1 / rsqrt(x) = sqrt(x), log2(exp2(x)) = x and log(exp(x)) = x. (LLVM also makes exp2(log2(x)) = x; the
// DAG does not, as it differs for x < 0 and a search would take pow(x, 1) for x.) Code
// generation never lowers so: it prints the formula's own arithmetic.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit::cost_detail {

struct DagRef {
  int id = -1;
  bool neg = false;

  friend bool operator==(const DagRef&, const DagRef&) = default;
};

// op is one of: Const, Var, Param (leaves); Add, Mul, Min, Max, CopySign, Atan2 (binary); Rcp,
// Sqrt, Rsqrt, Exp2, Log2, Exp, Sin, Cos, Abs, Saturate, Sign, Asin, Acos, Atan, Tanh, Erf
// (unary); Select (ternary, operand c); in a half DAG also Div (binary: a / b, both operands
// positive, the sign on the reference), Log (unary) and Fma (ternary: a * b + c, a and b
// positive).
struct DagNode {
  Op op = Op::Const;
  DagRef a, b, c;
  float value = 0.0f;      // Const: the magnitude (>= 0 or NaN; a binary16 value in a half DAG)
  // Const: the magnitude as the expression states it (a fold's: `value`). Literals that round
  // alike are told apart by it, and it decides the folds that remove work (x * 1, x + 0,
  // min(K1, max(K2, x))): a formula scored in float64 must not cost as if its constants were
  // equal where only their float32 roundings are.
  double exact = 0.0;
  int index = 0;           // Var, Param: index into the expression's tables
  bool log_scale = false;  // Mul: this is log2(x) * ln2, i.e. log(x)
};

struct Dag {
  std::vector<DagNode> nodes;
  std::vector<DagRef> roots;  // the values computed: one, or several sharing their nodes
  std::vector<int> uses;      // per node: references from live nodes, +1 per root
  std::vector<std::string> variables, parameters;
  bool half = false;       // lowered for binary16 arithmetic (see above)
  bool fast_math = false;  // lowered with fast math's folds (see above)

  [[nodiscard]] const DagNode& node(int id) const { return nodes[static_cast<std::size_t>(id)]; }
  [[nodiscard]] bool is_const(int id) const { return node(id).op == Op::Const; }
  [[nodiscard]] bool live(int id) const { return uses[static_cast<std::size_t>(id)] > 0; }
};

// Throws shaderfit::Error for an empty or malformed expression. `half`: lowered for binary16
// arithmetic (see above).
Dag lower_expression(const Expression& e, bool half = false, bool fast_math = false);
// Several values lowered into one DAG, equal subexpressions shared across them (one root each,
// in order); all over the first expression's variable and parameter tables.
Dag lower_expressions(std::span<const Expression> values, bool half = false, bool fast_math = false);

// Infix text of a DAG value for listings: names from the expression, at most `max_chars`
// characters (longer text is cut with "...").
std::string dag_infix(const Dag& dag, DagRef r, std::size_t max_chars = 48);

inline constexpr float kLn2 = 0.693147182f;     // float32 ln(2), as __logf scales log2
inline constexpr float kLog2E = 1.44269502f;    // float32 log2(e), as __expf scales its argument
inline constexpr float kInv2Pi = 0.159154937f;  // float32 1/(2 pi), the SASS sin/cos pre-scale

}  // namespace shaderfit::cost_detail
