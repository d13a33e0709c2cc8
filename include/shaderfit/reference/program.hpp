// A reference function as a user writes it (a formula in the reference language, or a shader
// function; reference/language.hpp compiles both), held as a straight-line program: every
// instruction writes its own register from earlier ones, branches become selects, and named
// outputs read registers. It is evaluated in double here, and for any number type through
// reference/program_evaluate.hpp (Taylor jets for exact derivatives, intervals for certified
// bounds).
//
//   Program p = compile_reference({.formula = "acos(x)", .variables = {"x"}});
//   double y = p.evaluate(std::vector<double>{0.5});          // its last output: acos(0.5)
//   std::vector<double> all(p.outputs.size());
//   p.evaluate_all(std::vector<double>{0.5}, all);             // every output, in order
//
// The reference language's functions beyond the operators (cbrt, tan, floor, hypot, ...) exist
// only here: the operators a search may use (expr/op.hpp) are not changed by them.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace shaderfit::reference {

enum class ProgramOp : std::uint8_t {
  // Leaves.
  Const,  // Instruction::value
  Input,  // Instruction::index: the input, in Program::inputs order
  // Arithmetic.
  Add,
  Sub,
  Mul,
  Div,
  Neg,
  IPow,  // integer power a^k, k = Instruction::index (signed, any int), by repeated squaring
  // Comparisons and logic: 1 when true, 0 when false (NaN operands compare false).
  Less,
  LessEqual,
  Greater,
  GreaterEqual,
  Equal,
  NotEqual,
  And,     // both operands != 0
  Or,      // either operand != 0
  Not,     // the operand == 0
  Select,  // (c, a, b): a where c != 0, else b; only the chosen operand matters
  // The rest of C's math library, in double, with C's meaning (std::cbrt, ...).
  Sign,  // 1, -1, or the operand itself for +-0 and NaN (as GLSL's sign)
  Cbrt,
  Expm1,
  Log10,
  Log1p,
  Tan,
  Sinh,
  Cosh,
  Asinh,
  Acosh,
  Atanh,
  Erfc,
  Floor,
  Ceil,
  Trunc,
  Round,  // half away from zero, as std::round
  Pow,    // std::pow(a, b)
  Hypot,
  Fmod,
  Min,  // std::fmin
  Max,  // std::fmax
  // An operator of the approximations (expr/op.hpp), Instruction::index its Op: the functions
  // whose meaning in double is C's (sqrt, exp, acos, erf, atan2, copysign, ...), computed
  // as the operator's record defines them.
  Operator,
  // A built-in reference (reference/builtin.hpp): Instruction::index is its BuiltinId, the
  // operands its arguments in call order.
  Builtin,
  Count_
};

inline constexpr int kProgramOpCount = static_cast<int>(ProgramOp::Count_);
inline constexpr int kMaxProgramOperands = 4;

// The op's name as the reference language spells it ("+", "<=", "select"; "neg" and "ipow"
// for the unary minus and the integer power), and its number of operands (-1 for Operator and
// Builtin: given by the instruction).
std::string_view program_op_name(ProgramOp op);
int program_op_arity(ProgramOp op);

struct Instruction {
  ProgramOp op = ProgramOp::Const;
  std::uint8_t arity = 0;  // operands used in `operands`
  std::int32_t index = 0;  // Input: the input; IPow: the exponent; Operator: the Op; Builtin:
                           // the BuiltinId
  double value = 0;        // Const
  // Registers of the operands (each < this instruction's own register), first operand first.
  std::array<std::uint32_t, kMaxProgramOperands> operands{};
};

struct Program {
  std::vector<std::string> inputs;        // the variables, in argument order
  std::vector<Instruction> code;          // instruction i writes register i
  std::vector<std::string> output_names;  // one per output
  std::vector<std::uint32_t> outputs;     // the register each output reads
  std::string description;                // for people: the formula, or "FILE: FUNCTION"

  // The last output at one point (inputs.size() values): the reference, in the programs
  // compile_reference makes (their outputs are the variables, the definitions, then the
  // reference). Inputs of the wrong count throw Error.
  [[nodiscard]] double evaluate(std::span<const double> inputs) const;
  // Every output at one point, in order, into `out` (outputs.size() values; else Error).
  void evaluate_all(std::span<const double> inputs, std::span<double> out) const;
  // Every output at every row: columns[i] is input i, one value per row (all of one length, else
  // Error; a program without inputs has one row); returns one column per output.
  [[nodiscard]] std::vector<std::vector<double>> evaluate_columns(
      std::span<const std::span<const double>> columns) const;

  // The output with this name, or -1.
  [[nodiscard]] int find_output(std::string_view name) const;
  // The input with this name, or -1.
  [[nodiscard]] int find_input(std::string_view name) const;
};

}  // namespace shaderfit::reference
