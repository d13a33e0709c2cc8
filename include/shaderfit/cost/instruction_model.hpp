// The instruction-cost model: what a formula compiles to on a GPU, counted and listed.
//
//   Expression e = parse_formula("r0 + (1 - r0) * (1 - cos_theta)^5");
//   instruction_count(e, InstructionTarget::Sass) == 6;   // Schlick's listing
//   InstructionCost c = instruction_cost(e, InstructionTarget::Sass);
//   std::cout << format_listing(c);   // FADD.FTZ R2, -R1, 1 ; 1 - cos_theta ...
//
// The expression is lowered to a DAG with equal subexpressions computed once, then to the
// straight-line program that code generation prints (so what is counted is what is compiled),
// then counted for a target (docs/cost-model.md has every rule and its check against nvcc and
// glslang):
//  - Sass: NVIDIA SASS under nvcc --use_fast_math (sm_90, FTZ): FADD/FMUL/FFMA/FMNMX with free
//    negation and |x| operand modifiers and free immediates; a*b + c is one FFMA; x^k by squaring
//    with shared intermediates; MUFU.EX2/LG2/RSQ/RCP/SQRT/SIN/COS; sin and cos add one FMUL.RZ
//    per distinct argument; exp = FMUL + MUFU.EX2, log = MUFU.LG2 + FMUL; a / b = MUFU.RCP + FMUL.
//  - Ptx: the PTX that nvcc emits for the generated CUDA (the same program, with explicit neg.f32
//    and abs.f32, sin/cos one instruction each).
//  - Generic: one operation per operator of the generated GLSL/HLSL, with no fusion (a*b + c is
//    two, a / b one, -x one): what glslang emits as SPIR-V arithmetic instructions.
//  - SassHalf2: the SASS of the generated CUDA __half2 function (codegen's half form, NAME_x2),
//    which computes two values at once: the count is per __half2 call, half of it per value.
//    HADD2/HMUL2/HFMA2/HMNMX2 one each; exp2, log2, sqrt, ... convert both halves to float, run
//    two MUFU ops and pack the results back (docs/precision.md, "Half cost").
//  - Rdna2, Rdna3: AMD RDNA 2 (gfx1030: PlayStation 5, Xbox Series, Steam Deck) and RDNA 3
//    (gfx1100) VALU instructions as LLVM's AMDGPU back end selects them under fast math (the
//    program of sass, fused): v_fma_f32 for a*b + c; -x and |x| free source modifiers on every
//    float instruction; saturate the clamp bit of the instruction before it; min(max(x, K0), K1)
//    one v_med3_f32; v_rcp/v_rsq/v_sqrt/v_exp/v_log/v_sin/v_cos_f32 at quarter rate; exp, log,
//    sin and cos a scale and the instruction, the scale merged into a product with a literal;
//    select v_cmp + v_cndmask_b32; copysign v_bfi_b32. The two count the same (RDNA 3's dual
//    issue of two operations as one VOPD instruction is not modelled).
// Inputs, parameters and literal constants cost nothing; parameters count as run-time inputs.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

enum class InstructionTarget : std::uint8_t { Sass, Ptx, Generic, SassHalf2, Rdna2, Rdna3 };

// Every target, in the order tables list them.
inline constexpr InstructionTarget kInstructionTargets[] = {
    InstructionTarget::Sass,      InstructionTarget::Ptx,   InstructionTarget::Generic,
    InstructionTarget::SassHalf2, InstructionTarget::Rdna2, InstructionTarget::Rdna3};

// The hardware unit an instruction issues to; it sets the instruction's throughput weight.
enum class InstructionUnit : std::uint8_t {
  Fp32,    // FADD, FMUL, FFMA (and their PTX / SPIR-V counterparts); HADD2, HMUL2, HFMA2, F2FP;
           // RDNA v_add/v_sub/v_mul/v_fma_f32
  MinMax,  // FMNMX, and the compares, selects and bit operations of select, sign and copysign;
           // HMNMX2, VHMNMX, HSET2, HSETP2, PLOP3; RDNA v_min/v_max/v_med3_f32, v_cmp,
           // v_cndmask, v_bfi, v_and, v_xor
  Mufu,    // the multi-function unit: rcp, rsqrt, sqrt, exp2, log2, sin, cos (on RDNA the
           // quarter-rate transcendental instructions v_rcp ... v_cos_f32)
};

struct ListingLine {
  std::string instruction;  // "FADD.FTZ R2, -R1, 1", "v_sub_f32 v2, 1, v1"
  std::string comment;      // "1 - cos_theta": the value it computes
  InstructionUnit unit = InstructionUnit::Fp32;
};

struct InstructionCost {
  InstructionTarget target = InstructionTarget::Sass;
  int instructions = 0;  // arithmetic instructions (moves of constants are not counted)
  int fp32 = 0, minmax = 0, mufu = 0;  // instructions per unit
  // Throughput-weighted cost in FP32-instruction issue slots: the sum of throughput_weight over
  // the instructions, so an FFMA weighs 1 and a MUFU op 8 on sm_90.
  double weighted = 0.0;
  std::vector<ListingLine> listing;  // in evaluation order
};

// The count and the listing. Throws shaderfit::Error for an empty or malformed expression.
InstructionCost instruction_cost(const Expression& e, InstructionTarget target);

// The count alone (no listing); what the search's cost objective uses.
int instruction_count(const Expression& e, InstructionTarget target);

// One line per instruction: "FADD.FTZ R2, -R1, 1 ; 1 - cos_theta", columns aligned.
std::string format_listing(const InstructionCost& cost);

// Issue slots one instruction of the unit occupies, relative to an FP32 FMA (table and sources
// in src/cost/instruction_model.cpp).
double throughput_weight(InstructionTarget target, InstructionUnit unit);

// "sass" / "ptx" / "generic" / "sass-half2" / "rdna2" / "rdna3"; nullopt for any other name.
std::optional<InstructionTarget> instruction_target_from_name(std::string_view name);
// The same, or shaderfit::Error at `where` that lists the known names.
InstructionTarget parse_instruction_target(std::string_view name, const SourceLocation& where);
std::string_view instruction_target_name(InstructionTarget target);
std::string_view instruction_unit_name(InstructionUnit unit);

}  // namespace shaderfit
