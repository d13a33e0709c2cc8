#include "shaderfit/cost/instruction_model.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "cost/dag.hpp"
#include "cost/step_program.hpp"
#include "cost/select.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit {

namespace cost_detail {

std::vector<TargetInstruction> select_for(const Dag& dag, InstructionTarget target,
                                          bool with_text) {
  if (dag.half != lowers_half(target) || dag.fast_math != lowers_fast_math(target))
    throw Error("internal: a DAG lowered for the wrong arithmetic for its target");
  const Program program = build_program(dag, target != InstructionTarget::Generic);
  switch (target) {
    case InstructionTarget::Sass: return select_sass(dag, program, with_text);
    case InstructionTarget::Ptx: return select_ptx(dag, program, with_text);
    case InstructionTarget::Generic: return select_generic(dag, program, with_text);
    case InstructionTarget::SassHalf2: return select_sass_half2(dag, program, with_text);
    case InstructionTarget::Rdna2: return select_rdna(dag, program, with_text, false);
    case InstructionTarget::Rdna3: return select_rdna(dag, program, with_text, true);
  }
  return {};
}

Dag lower_for(std::span<const Expression> values, InstructionTarget target) {
  return lower_expressions(values, lowers_half(target), lowers_fast_math(target));
}

InstructionCost tally(std::vector<TargetInstruction> instructions, InstructionTarget target) {
  InstructionCost cost;
  cost.target = target;
  for (TargetInstruction& ins : instructions) {
    ++cost.instructions;
    cost.fp32 += ins.unit == InstructionUnit::Fp32;
    cost.minmax += ins.unit == InstructionUnit::MinMax;
    cost.mufu += ins.unit == InstructionUnit::Mufu;
    cost.weighted += throughput_weight(target, ins.unit);
    cost.listing.push_back({std::move(ins.text), std::move(ins.comment), ins.unit});
  }
  return cost;
}

}  // namespace cost_detail

// Throughput weights: issue slots per instruction relative to an FP32 FMA, i.e. (FP32 FMA results
// per clock) / (the unit's results per clock).
// NVIDIA (sass, ptx, sass-half2; generic too, taking sm_90 as the reference GPU,
// docs/cost-model.md): CUDA C++ Programming Guide, section "Arithmetic Instructions", table
// "Throughput of Native Arithmetic Instructions (operations per clock cycle per multiprocessor)",
// column compute capability 9.0:
//   32-bit floating-point add, multiply, multiply-add ............................ 128
//   32-bit floating-point reciprocal, reciprocal square root, base-2 logarithm
//   (__log2f), base-2 exponential (exp2f), sine (__sinf), cosine (__cosf) ......... 16
//   compare, minimum, maximum ...................................................... 64
//   (the MinMax unit; FSETP, FSEL and LOP3 are counted there too: 32-bit compare and
//   bitwise AND/OR/XOR are 64 per clock in the same table)
// AMD RDNA 2 and 3: AMD's RDNA 2 and RDNA 3 ISA reference guides: a SIMD32 issues one 32-lane
// VALU instruction per clock, compares, selects and bit operations included; the transcendental
// instructions (v_rcp, v_rsq, v_sqrt, v_exp, v_log, v_sin, v_cos) run at quarter rate.
double throughput_weight(InstructionTarget target, InstructionUnit unit) {
  const bool rdna = target == InstructionTarget::Rdna2 || target == InstructionTarget::Rdna3;
  constexpr double kFp32PerClock = 128.0, kMinMaxPerClock = 64.0, kMufuPerClock = 16.0;
  constexpr double kRdnaTranscendentalRate = 0.25;
  switch (unit) {
    case InstructionUnit::Fp32: return 1.0;
    case InstructionUnit::MinMax: return rdna ? 1.0 : kFp32PerClock / kMinMaxPerClock;
    case InstructionUnit::Mufu: return rdna ? 1.0 / kRdnaTranscendentalRate : kFp32PerClock / kMufuPerClock;
  }
  return 1.0;
}

InstructionCost instruction_cost(const Expression& e, InstructionTarget target) {
  const cost_detail::Dag dag = cost_detail::lower_for({&e, 1}, target);
  return cost_detail::tally(cost_detail::select_for(dag, target, true), target);
}

int instruction_count(const Expression& e, InstructionTarget target) {
  const cost_detail::Dag dag = cost_detail::lower_for({&e, 1}, target);
  return static_cast<int>(cost_detail::select_for(dag, target, false).size());
}

std::string format_listing(const InstructionCost& cost) {
  std::size_t width = 0;
  for (const ListingLine& l : cost.listing) width = std::max(width, l.instruction.size());
  std::string out;
  for (const ListingLine& l : cost.listing)
    out += fmt::format("{:<{}} ; {}\n", l.instruction, width, l.comment);
  return out;
}

std::optional<InstructionTarget> instruction_target_from_name(std::string_view name) {
  for (InstructionTarget t : kInstructionTargets)
    if (name == instruction_target_name(t)) return t;
  return std::nullopt;
}

InstructionTarget parse_instruction_target(std::string_view name, const SourceLocation& where) {
  if (const auto t = instruction_target_from_name(name)) return *t;
  std::string known;
  for (InstructionTarget t : kInstructionTargets)
    known += (known.empty() ? "" : ", ") + std::string(instruction_target_name(t));
  throw Error("unknown target '" + std::string(name) + "' (known: " + known + ")", where);
}

std::string_view instruction_target_name(InstructionTarget target) {
  switch (target) {
    case InstructionTarget::Sass: return "sass";
    case InstructionTarget::Ptx: return "ptx";
    case InstructionTarget::Generic: return "generic";
    case InstructionTarget::SassHalf2: return "sass-half2";
    case InstructionTarget::Rdna2: return "rdna2";
    case InstructionTarget::Rdna3: return "rdna3";
  }
  return "sass";
}

std::string_view instruction_unit_name(InstructionUnit unit) {
  switch (unit) {
    case InstructionUnit::Fp32: return "fp32";
    case InstructionUnit::MinMax: return "minmax";
    case InstructionUnit::Mufu: return "mufu";
  }
  return "fp32";
}

}  // namespace shaderfit
