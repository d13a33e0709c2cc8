// Internal: instruction selection of a program for one target, with or without listing text.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "cost/dag.hpp"
#include "cost/step_program.hpp"
#include "shaderfit/cost/instruction_model.hpp"

namespace shaderfit::cost_detail {

struct TargetInstruction {
  InstructionUnit unit = InstructionUnit::Fp32;
  std::string text;     // empty unless asked for
  std::string comment;  // empty unless asked for
};

// The target's instructions for `program` (built fused for Sass, Ptx and RDNA, unfused for
// Generic).
std::vector<TargetInstruction> select_sass(const Dag& dag, const Program& program, bool with_text);
std::vector<TargetInstruction> select_ptx(const Dag& dag, const Program& program, bool with_text);
std::vector<TargetInstruction> select_generic(const Dag& dag, const Program& program,
                                              bool with_text);
// SassHalf2: the program of a half DAG (dag.hpp), as nvcc compiles codegen's __half2 form.
std::vector<TargetInstruction> select_sass_half2(const Dag& dag, const Program& program,
                                                 bool with_text);

// Rdna2 and Rdna3 (`rdna3`): the fused program as LLVM's AMDGPU back end selects it
// (select_rdna.cpp).
std::vector<TargetInstruction> select_rdna(const Dag& dag, const Program& program, bool with_text,
                                           bool rdna3);

// True for the targets that count half code: their DAG is lowered with half = true.
constexpr bool lowers_half(InstructionTarget target) {
  return target == InstructionTarget::SassHalf2;
}

// True for the targets whose compiler rewrites the algebra under fast math: their DAG is lowered
// with fast_math = true (dag.hpp).
constexpr bool lowers_fast_math(InstructionTarget target) {
  return target == InstructionTarget::Rdna2 || target == InstructionTarget::Rdna3;
}

// `values` lowered as the target's compiler sees them (lowers_half, lowers_fast_math).
Dag lower_for(std::span<const Expression> values, InstructionTarget target);

// The program of `dag` for the target (fused for all but Generic), selected. The DAG must be lowered
// for the target's arithmetic (lowers_half).
std::vector<TargetInstruction> select_for(const Dag& dag, InstructionTarget target, bool with_text);
// The instructions counted per unit, weighted and listed.
InstructionCost tally(std::vector<TargetInstruction> instructions, InstructionTarget target);

}  // namespace shaderfit::cost_detail
