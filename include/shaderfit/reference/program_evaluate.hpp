// A reference program (reference/program.hpp) evaluated for any number type T: double, Taylor
// jets (exact derivatives of every order, expr/jet.hpp), or intervals (certified bounds,
// verify/). T needs the arithmetic operators, construction from double, and the elementary
// functions found by argument-dependent lookup or in std (sqrt, acos, erf, atan2, ...).
//
// What depends on truth (comparisons, logic, select), the built-in references and the operators
// of expr/op.hpp go through ProgramLogic<T>. Its default suits types whose comparisons return
// bool (double, float, jets by their value); a type whose comparisons may be undecided (an interval
// straddling the other operand) specialises it: compare gives a T within [0, 1] that says "maybe",
// and select then joins both operands.
//
//   std::vector<Jet> regs;
//   evaluate_program<Jet>(program, inputs, regs);   // regs[program.outputs[0]] is the result
//
// Kept apart from program.hpp so that only the few sources that instantiate it for a new type
// compile the template.
#pragma once

#include <cmath>
#include <span>
#include <vector>

#include "shaderfit/expr/op.hpp"
#include "shaderfit/reference/builtin_evaluate.hpp"
#include "shaderfit/reference/program.hpp"

namespace shaderfit::reference {

template <typename T>
struct ProgramLogic {
  static T truth(bool b) { return T(b ? 1.0 : 0.0); }
  static bool is_true(const T& c) { return c < T(0) || c > T(0); }
  static T compare(ProgramOp op, const T& a, const T& b) {
    switch (op) {
      case ProgramOp::Less: return truth(a < b);
      case ProgramOp::LessEqual: return truth(a <= b);
      case ProgramOp::Greater: return truth(a > b);
      case ProgramOp::GreaterEqual: return truth(a >= b);
      case ProgramOp::Equal: return truth(a <= b && a >= b);
      default: return truth(a < b || a > b);  // NotEqual
    }
  }
  // And, Or on two operands; Not on `a` alone.
  static T logic(ProgramOp op, const T& a, const T& b) {
    switch (op) {
      case ProgramOp::And: return truth(is_true(a) && is_true(b));
      case ProgramOp::Or: return truth(is_true(a) || is_true(b));
      default: return truth(!is_true(a));  // Not
    }
  }
  static T select(const T& c, const T& a, const T& b) { return is_true(c) ? a : b; }
  // 1, -1, or a itself for +-0 and NaN (a * 0 keeps the zero's sign, and has no derivative).
  static T sign(const T& a) { return a > T(0.0) ? T(1.0) : (a < T(0.0) ? T(-1.0) : a * T(0.0)); }
  static T builtin(BuiltinId id, std::span<const T> args) { return evaluate_builtin<T>(id, args); }
  // An operator of expr/op.hpp on its operands (b unused by unary ones).
  static T apply(Op op, const T& a, const T& b) {
    return arity(op) == 1 ? apply_unary(op, a) : apply_binary(op, a, b);
  }
};

// Runs the program on `inputs` (program.inputs.size() values); registers[r] holds register r
// afterwards (resized to program.code.size()), and registers[program.outputs[k]] output k.
template <typename T>
void evaluate_program(const Program& program, std::span<const T> inputs,
                      std::vector<T>& registers) {
  using std::cbrt, std::expm1, std::log10, std::log1p, std::tan, std::sinh, std::cosh, std::asinh,
      std::acosh, std::atanh, std::erfc, std::floor, std::ceil, std::trunc, std::round, std::pow,
      std::hypot, std::fmod, std::fmin, std::fmax;
  using L = ProgramLogic<T>;
  registers.resize(program.code.size(), T(0.0));
  for (std::size_t i = 0; i < program.code.size(); ++i) {
    const Instruction& in = program.code[i];
    const T& a = registers[in.operands[0]];
    const T& b = registers[in.operands[1]];
    T r(0.0);
    switch (in.op) {
      case ProgramOp::Const: r = T(in.value); break;
      case ProgramOp::Input: r = inputs[static_cast<std::size_t>(in.index)]; break;
      case ProgramOp::Add: r = a + b; break;
      case ProgramOp::Sub: r = a - b; break;
      case ProgramOp::Mul: r = a * b; break;
      case ProgramOp::Div: r = a / b; break;
      case ProgramOp::Neg: r = -a; break;
      case ProgramOp::IPow: r = apply_ipow(a, in.index, T(1.0)); break;
      case ProgramOp::Less:
      case ProgramOp::LessEqual:
      case ProgramOp::Greater:
      case ProgramOp::GreaterEqual:
      case ProgramOp::Equal:
      case ProgramOp::NotEqual: r = L::compare(in.op, a, b); break;
      case ProgramOp::And:
      case ProgramOp::Or:
      case ProgramOp::Not: r = L::logic(in.op, a, b); break;
      case ProgramOp::Select: r = L::select(a, b, registers[in.operands[2]]); break;
      case ProgramOp::Sign: r = L::sign(a); break;
      case ProgramOp::Cbrt: r = cbrt(a); break;
      case ProgramOp::Expm1: r = expm1(a); break;
      case ProgramOp::Log10: r = log10(a); break;
      case ProgramOp::Log1p: r = log1p(a); break;
      case ProgramOp::Tan: r = tan(a); break;
      case ProgramOp::Sinh: r = sinh(a); break;
      case ProgramOp::Cosh: r = cosh(a); break;
      case ProgramOp::Asinh: r = asinh(a); break;
      case ProgramOp::Acosh: r = acosh(a); break;
      case ProgramOp::Atanh: r = atanh(a); break;
      case ProgramOp::Erfc: r = erfc(a); break;
      case ProgramOp::Floor: r = floor(a); break;
      case ProgramOp::Ceil: r = ceil(a); break;
      case ProgramOp::Trunc: r = trunc(a); break;
      case ProgramOp::Round: r = round(a); break;
      case ProgramOp::Pow: r = pow(a, b); break;
      case ProgramOp::Hypot: r = hypot(a, b); break;
      case ProgramOp::Fmod: r = fmod(a, b); break;
      case ProgramOp::Min: r = fmin(a, b); break;
      case ProgramOp::Max: r = fmax(a, b); break;
      case ProgramOp::Operator: r = L::apply(static_cast<Op>(in.index), a, b); break;
      case ProgramOp::Builtin: {
        T args[kMaxProgramOperands] = {T(0.0), T(0.0), T(0.0), T(0.0)};
        // Bounded by the array too, which the compiler cannot know of `arity`.
        const int n = in.arity < kMaxProgramOperands ? in.arity : kMaxProgramOperands;
        for (int k = 0; k < n; ++k) args[k] = registers[in.operands[k]];
        r = L::builtin(static_cast<BuiltinId>(in.index),
                       std::span<const T>(args, static_cast<std::size_t>(n)));
        break;
      }
      case ProgramOp::Count_: break;
    }
    registers[i] = r;
  }
}

}  // namespace shaderfit::reference
