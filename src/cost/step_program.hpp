// Internal: the straight-line program that code generation prints and the cost model counts.
//
// A program is built from the DAG for one of two policies:
//  - fused (CUDA, C++, Metal; the `sass` and `ptx` targets): every add with a product operand
//    becomes one Fma (the product with the fewest uses, when both are products); a product all of
//    whose uses were fused is not computed on its own;
//  - unfused (GLSL, HLSL; the `generic` target): a*b + c stays a multiply and an add, and
//    a * rcp(b) with a single-use reciprocal is one division.
// A half DAG (dag.hpp) is always built unfused, and a * rcp(b) stays a product: its Div, Rcp,
// Fma and Log nodes are one step each and nothing else merges, so that each step rounds where
// evaluate_half (eval/evaluate_in.hpp) rounds.
// Signs are resolved so that negations cost as little as the languages allow: a - b and b - a
// are both one subtraction, a negative literal is free, -(a * K) is a * -K; what remains is an
// explicit Neg step, one per value (docs/cost-model.md, "Negation").
#pragma once

#include <cstdint>
#include <vector>

#include "cost/dag.hpp"

namespace shaderfit::cost_detail {

struct Operand {
  enum class Kind : std::uint8_t { None, Step, Var, Param, Const };
  Kind kind = Kind::None;
  int index = 0;       // Step: step index; Var, Param: table index
  float value = 0.0f;  // Const: the signed literal
};

struct Step {
  // An operator of expr/op.hpp, as the languages compute it: never a leaf, IPow, Pow or Rcp
  // (powers are products, a reciprocal is a Div of a literal 1).
  Op op = Op::Add;
  Operand args[3];
  int arity = 0;
  int dag_id = -1;       // the DAG node whose value (or negation) this step computes
  bool negated = false;  // the step computes minus that node's value
  int uses = 0;          // operand references from later steps, +1 if it is the result
  // Exp only, fused programs: the operand is read negated, exp(-x). nvcc folds that negation
  // into the log2(e) scale, so it is no instruction of its own.
  // Select: the condition is read negated, -a >= 0, which every language writes a <= 0 (the same
  // for every a, zeros and NaN included): one comparison either way.
  bool neg_arg = false;
  // Sub (a - b), or Add of a literal (a + K), read only as the condition of selects: not
  // computed; each select compares its operands instead (a - b >= 0 is a >= b, the same for
  // finite a and b), as people write x > 0.5 ? ... (select_comparison).
  bool compared = false;
};

struct Program {
  std::vector<Step> steps;
  std::vector<Operand> results;  // one per DAG root, in order
  bool fused = true;
};

Program build_program(const Dag& dag, bool fused);

// What a Select step compares: lhs >= rhs, or lhs <= rhs when the step's neg_arg is set. The
// operands of its condition when that step is `compared`, else the condition and a literal 0.
struct Comparison {
  Operand lhs, rhs;
};
Comparison select_comparison(const Program& p, const Step& select);

// Who reads each step of a program: the selectors' view of uses.
class StepReaders {
 public:
  explicit StepReaders(const Program& p);
  // The steps that read step s, in program order (a step reading s twice is listed twice).
  [[nodiscard]] const std::vector<int>& of(int s) const { return readers_[static_cast<std::size_t>(s)]; }
  // Step s is one of the program's results.
  [[nodiscard]] bool is_result(int s) const;
  // The one step that reads step s (s used once, not a result), or -1.
  [[nodiscard]] int only_reader(int s) const;

 private:
  const Program& p_;
  std::vector<std::vector<int>> readers_;
};

// Whether the step is a reciprocal: a division of the literal 1 or -1 (1 / x, -1 / x).
inline bool is_reciprocal(const Step& st) {
  return st.op == Op::Div && st.args[0].kind == Operand::Kind::Const &&
         (st.args[0].value == 1.0f || st.args[0].value == -1.0f);
}

}  // namespace shaderfit::cost_detail
