// A reference program (reference/program.hpp) written as a formula of the search's operators
// (expr/op.hpp), where it can be: the shader function or formula as its author wrote it, with
// helpers inlined, constants folded, min and max, a clamp to [0, 1] as saturate, mix and lerp,
// the C functions the operators share (exp, log, acos, erf, ...) as those operators, those
// they write exactly in real arithmetic (tan as sin / cos, cbrt, log10, log1p, expm1, sinh, cosh,
// asinh, acosh, atanh, erfc, hypot) in them, and a branch on a comparison (if/else, ?:, an early
// return; == and != as -|x - y| >= 0) as a select (NaN operands of the comparison aside). Its cost is then the cost model's (cost/cost_model.hpp), which counts a
// subexpression the program computes once (a register read twice) once.
//
//   ProgramFormula f = program_formula(compile_reference(text), {"NoV", "NoL", "LoH", "r"});
//   if (f.formula) expression_cost(*f.formula, CostTarget::Instructions);  // cost/cost_model.hpp
//   else std::cout << f.why;   // "it calls floor, which the search's operators cannot write"
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/reference/program.hpp"

namespace shaderfit::reference {

struct ProgramFormula {
  std::optional<Expression> formula;  // over `variables`, in their order
  std::string why;                    // when there is none: what the operators cannot write
};

// The program's last output (the reference) as a formula over `variables` (names of the
// program's inputs, in any order; an input not among them is a why). An integer power beyond
// +-16 is written with pow; a comparison read as a number, a logical operator, a built-in
// reference (fresnel_exact, ...) and the functions the operators cannot write (floor, ceil,
// trunc, round, fmod) have no formula. A formula of more than `max_nodes` nodes (a program that
// reads its registers many times over: an unrolled Newton iteration grows the tree about
// threefold a step, where the program and its cost grow by a few instructions) is not written
// either. The search works on formulas of kMaxProgramFormulaNodes at most; the cost model, which
// counts a value computed once once, takes kMaxCostedFormulaNodes.
inline constexpr std::size_t kMaxProgramFormulaNodes = 4096;
inline constexpr std::size_t kMaxCostedFormulaNodes = std::size_t{1} << 20;
ProgramFormula program_formula(const Program& program, std::span<const std::string> variables,
                               std::size_t max_nodes = kMaxProgramFormulaNodes);

}  // namespace shaderfit::reference
