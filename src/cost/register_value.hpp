// Internal: what the register-level selectors (select_sass.cpp, select_rdna.cpp) share: a value
// as a machine instruction reads it (a register with the negation and |x| modifiers, an
// immediate, or a named token), their state while they walk a program, and the emission of a
// library function's measured instructions.
#pragma once

#include <fmt/format.h>

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "cost/dag.hpp"
#include "cost/float_text.hpp"
#include "cost/op_instructions.hpp"
#include "cost/select.hpp"
#include "cost/step_program.hpp"
#include "cost/step_text.hpp"

namespace shaderfit::cost_detail {

struct RegisterValue {
  int reg = -1;
  bool neg = false, abs = false;
  bool imm = false;
  float value = 0.0f;
  const char* token = nullptr;  // printed as is: RZ, PT, vcc_lo, 0x80000000
};

// "R3" / "v3" (by `prefix`), with "-" and "|...|" as modified; an immediate as float_text.
inline std::string register_value_text(const RegisterValue& v, const char* prefix) {
  if (v.token) return v.neg ? std::string("-") + v.token : std::string(v.token);
  if (v.imm) return float_text(v.value);
  std::string r = prefix + std::to_string(v.reg);
  if (v.abs) r = "|" + r + "|";
  return v.neg ? "-" + r : r;
}

// -v: an immediate's value flips, anything else takes the negation modifier.
inline RegisterValue negated(RegisterValue v) {
  if (v.imm && !v.token)
    v.value = -v.value;
  else
    v.neg = !v.neg;
  return v;
}

// An operand of a program step: a literal, an input's register (variables, then parameters,
// numbered from 0), or the value a step left in `steps`.
inline RegisterValue operand_value(const Operand& o, const Dag& dag,
                                   const std::vector<RegisterValue>& steps) {
  switch (o.kind) {
    case Operand::Kind::Const: return RegisterValue{-1, false, false, true, o.value};
    case Operand::Kind::Var: return RegisterValue{o.index};
    case Operand::Kind::Param:
      return RegisterValue{static_cast<int>(dag.variables.size()) + o.index};
    default: return steps[static_cast<std::size_t>(o.index)];
  }
}

// What a register-level selector (SASS, RDNA) keeps while it walks a program: the program, who
// reads each step, the steps' listing text, the value each step left, the instructions so far and
// the next free register (the inputs hold the first ones).
struct SelectorState {
  SelectorState(const Dag& dag, const Program& p, bool text)
      : dag_(dag),
        p_(p),
        readers_(p),
        text_(text),
        vals_(p.steps.size()),
        next_reg_(static_cast<int>(dag.variables.size() + dag.parameters.size())) {}

  [[nodiscard]] RegisterValue val(const Operand& o) const { return operand_value(o, dag_, vals_); }

  const Dag& dag_;
  const Program& p_;
  StepReaders readers_;
  StepText names_text_{dag_, p_};
  bool text_;
  std::vector<RegisterValue> vals_;
  std::vector<TargetInstruction> out_;
  int next_reg_;
};

// The measured instructions `list` of a library function (cost/op_instructions.hpp) called `name`,
// through `emit(unit, mnemonic, operands, comment)`: the first reads the call's operands (a, and
// b for arity 2), each next one the value before it; the last carries `comment`, the others
// "name k/n" (when `text`). Returns the last one's value.
template <class Emit>
RegisterValue emit_library_call(std::string_view list, std::string_view name, RegisterValue a,
                                RegisterValue b, int arity, const std::string& comment, bool text,
                                Emit&& emit) {
  const std::vector<std::string_view> ops = mnemonics(list);
  RegisterValue v;
  for (std::size_t k = 0; k < ops.size(); ++k) {
    const std::string what =
        text ? (k + 1 == ops.size() ? comment : fmt::format("{} {}/{}", name, k + 1, ops.size()))
             : std::string();
    if (k == 0 && arity == 2)
      v = emit(mnemonic_unit(ops[k]), std::string(ops[k]), {a, b}, what);
    else
      v = emit(mnemonic_unit(ops[k]), std::string(ops[k]), {k == 0 ? a : v}, what);
  }
  return v;
}

}  // namespace shaderfit::cost_detail
