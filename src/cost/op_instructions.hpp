// Internal: the cost record, a row per operator whose instructions are a fixed list: on every
// target the hardware's functions (sqrt, rsqrt, exp2, log2, sin, cos; the packed half forms of
// exp and log) and the library functions (asinf, acosf, atanf, atan2f, tanhf, erff in CUDA); on
// PTX and SPIR-V the arithmetic (+ - * fma neg abs min max). The selectors emit a row's list and
// read its properties; what depends on the formula around an operator (a negation folded, a
// scale merged, a reciprocal or a saturate absorbed) stays in their rules. op_instructions_test
// checks that every row is complete.
//
// The library functions' lists are measured with nvcc 13.0 --use_fast_math -arch=sm_90 (the
// `sass` and `ptx` targets' compiler), one kernel per function reading its arguments from memory
// (docs/cost-model.md, "Library functions"), counted as src/codegen/toolchain_test_support.hpp
// counts: the arithmetic instructions of PTX and SASS, in the order the compiler emitted them.
// atan2f divides with div.rn, whose SASS has an out-of-line slow path (27 instructions, run only
// for quotients beyond float's normal range) that is not counted; tanhf is MUFU.TANH under
// --use_fast_math. The generic target counts one OpExtInst for each (GLSL.std.450 Asin, Acos,
// Atan, Atan2, Tanh), and for erf the instructions of the helper that code generation writes
// (GLSL, HLSL and Metal have no erf; cost/erf_helper.hpp), as glslang emits them.
// The RDNA targets count the VALU instructions of ROCm's OCML functions (__ocml_asin_f32 ...),
// measured with clang 15 -O3 -cl-fast-relaxed-math for gfx1030 and gfx1100 (the same for both,
// a VOPD pair of gfx1100 counted as its two operations) against Debian's rocm-device-libs
// 5.2.3 (ocml.bc with the unsafe-math, finite-only and DAZ options on), in the same kernels.
#pragma once

#include <string_view>
#include <vector>

#include "cost/erf_helper.hpp"
#include "cost/step_program.hpp"
#include "shaderfit/cost/instruction_model.hpp"

namespace shaderfit::cost_detail {

// One operator's row. Lists are mnemonics, space-separated; the first instruction reads the
// operands, each next one the value before it, the last gives the result.
struct OpInstructions {
  std::string_view cuda;   // a library function's CUDA name ("asinf"); empty for the hardware's
  std::string_view sass;   // SASS
  std::string_view ptx;    // PTX
  std::string_view spirv;  // SPIR-V of the GLSL and HLSL code
  std::string_view ocml;   // the OCML function a library function's RDNA count is measured on
  std::string_view rdna;   // RDNA VALU
  // The helper that GLSL, HLSL and Metal code calls, which code generation writes (erf);
  // empty where those languages have the function.
  std::string_view helper = {};
  // ptxas gives a negated product read only by this call as the product and its negation
  // (FADD), where other readers take FMUL -a, b.
  bool negates_product = false;
  // The packed half form (sass-half2): the instructions after the operand's conversion to float,
  // as measured (docs/precision.md, "Half cost"), and the __half2 function codegen calls (its
  // spelling: codegen::call reads it here).
  std::string_view half2 = {};
  std::string_view half2_call = {};
  // An instruction that the half forms of one operand share, emitted for each half once per
  // distinct operand: sin's and cos's FMUL.RZ, log2's and log's MUFU.LG2.
  std::string_view half2_shared = {};
  // The instruction takes its argument in turns (SASS, RDNA): scaled by 1/(2 pi) first, once
  // per distinct argument (sin, cos).
  bool turns = false;
  // 1 / f(x) is f(-x) (exp2, exp): SASS and RDNA negate the argument of an f read only by a
  // reciprocal instead of computing the reciprocal.
  bool exponential = false;
  // Its SASS instruction (FADD, FMUL, FFMA, FMNMX, and their packed half forms) reads -x and |x|
  // operands for free.
  bool sass_modifiers = false;

  [[nodiscard]] bool library() const { return !cuda.empty(); }
};

// The row of `op`, or nullptr for an operator whose instructions each selector writes.
inline const OpInstructions* op_instructions(Op op) {
  // The arithmetic: one instruction on PTX and SPIR-V; the register-level targets' rules fold
  // negations, |x| and saturation into them and write their own, reading sass_modifiers.
  static constexpr OpInstructions kAdd = {
      .ptx = "add.ftz.f32", .spirv = "OpFAdd", .sass_modifiers = true};
  static constexpr OpInstructions kSub = {
      .ptx = "sub.ftz.f32", .spirv = "OpFSub", .sass_modifiers = true};
  static constexpr OpInstructions kMul = {
      .ptx = "mul.ftz.f32", .spirv = "OpFMul", .sass_modifiers = true};
  static constexpr OpInstructions kFma = {
      .ptx = "fma.rn.ftz.f32", .spirv = "OpExtInst Fma", .sass_modifiers = true};
  static constexpr OpInstructions kNeg = {.ptx = "neg.ftz.f32", .spirv = "OpFNegate"};
  static constexpr OpInstructions kAbs = {.ptx = "abs.ftz.f32", .spirv = "OpExtInst FAbs"};
  static constexpr OpInstructions kMin = {
      .ptx = "min.ftz.f32", .spirv = "OpExtInst FMin", .sass_modifiers = true};
  static constexpr OpInstructions kMax = {
      .ptx = "max.ftz.f32", .spirv = "OpExtInst FMax", .sass_modifiers = true};
  static constexpr OpInstructions kSqrt = {.sass = "MUFU.SQRT",
                                           .ptx = "sqrt.approx.ftz.f32",
                                           .spirv = "OpExtInst Sqrt",
                                           .rdna = "v_sqrt_f32",
                                           .half2 = "MUFU.SQRT MUFU.SQRT F2FP.F16.F32.PACK_AB",
                                           .half2_call = "h2sqrt"};
  static constexpr OpInstructions kRsqrt = {.sass = "MUFU.RSQ",
                                            .ptx = "rsqrt.approx.ftz.f32",
                                            .spirv = "OpExtInst InverseSqrt",
                                            .rdna = "v_rsq_f32",
                                            .half2 = "MUFU.RSQ MUFU.RSQ F2FP.F16.F32.PACK_AB",
                                            .half2_call = "h2rsqrt"};
  static constexpr OpInstructions kExp2 = {
      .sass = "MUFU.EX2",
      .ptx = "ex2.approx.ftz.f32",
      .spirv = "OpExtInst Exp2",
      .rdna = "v_exp_f32",
      .half2 = "MUFU.EX2 MUFU.EX2 FFMA FFMA F2FP.F16.F32.PACK_AB",
      .half2_call = "h2exp2",
      .exponential = true};
  static constexpr OpInstructions kLog2 = {
      .sass = "MUFU.LG2",
      .ptx = "lg2.approx.ftz.f32",
      .spirv = "OpExtInst Log2",
      .rdna = "v_log_f32",
      .half2 = "F2FP.F16.F32.PACK_AB HSET2.BF.EQ.AND HFMA2 HSET2.BF.EQ.AND HFMA2",
      .half2_call = "h2log2",
      .half2_shared = "MUFU.LG2"};
  static constexpr OpInstructions kSin = {.sass = "MUFU.SIN",
                                          .ptx = "sin.approx.ftz.f32",
                                          .spirv = "OpExtInst Sin",
                                          .rdna = "v_sin_f32",
                                          .half2 = "MUFU.SIN MUFU.SIN F2FP.F16.F32.PACK_AB",
                                          .half2_call = "sf_h2sin",
                                          .half2_shared = "FMUL.RZ",
                                          .turns = true};
  static constexpr OpInstructions kCos = {.sass = "MUFU.COS",
                                          .ptx = "cos.approx.ftz.f32",
                                          .spirv = "OpExtInst Cos",
                                          .rdna = "v_cos_f32",
                                          .half2 = "MUFU.COS MUFU.COS F2FP.F16.F32.PACK_AB",
                                          .half2_call = "sf_h2cos",
                                          .half2_shared = "FMUL.RZ",
                                          .turns = true};
  // exp and log: a scale by log2(e) before MUFU.EX2 (ln(2) after MUFU.LG2), which each selector
  // writes as its rules merge it; here their half forms.
  static constexpr OpInstructions kExp = {
      .half2 =
          "HSET2.BF.EQ.AND HSET2.BF.EQ.AND FFMA FFMA MUFU.EX2 MUFU.EX2 F2FP.F16.F32.PACK_AB "
          "HSET2.BF.EQ.AND HSET2.BF.EQ.AND HFMA2 HFMA2 HFMA2 HFMA2",
      .half2_call = "h2exp",
      .exponential = true};
  static constexpr OpInstructions kLog = {
      .half2 =
          "HSET2.BF.EQ.AND HSET2.BF.EQ.AND FMUL FMUL F2FP.F16.F32.PACK_AB HSET2.BF.EQ.AND "
          "HSET2.BF.EQ.AND HFMA2 HFMA2 HFMA2 HFMA2",
      .half2_call = "h2log",
      .half2_shared = "MUFU.LG2"};
  static constexpr OpInstructions kAsin = {
      "asinf",
      "FADD.FTZ FSETP.GT.FTZ.AND FSETP.NEU.FTZ.AND FFMA.FTZ MUFU.RSQ FMUL.FTZ FMUL.FTZ FFMA.FTZ "
      "FFMA.FTZ FSEL FMUL.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FMUL.FTZ FFMA.FTZ FMUL.FTZ "
      "FFMA.FTZ FSETP.GTU.FTZ.AND LOP3.LUT FSEL",
      "abs.ftz.f32 neg.ftz.f32 fma.rn.ftz.f32 rsqrt.approx.ftz.f32 mul.ftz.f32 mul.ftz.f32 "
      "neg.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 setp.eq.ftz.f32 selp.f32 setp.gt.ftz.f32 selp.f32 "
      "mul.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 mul.ftz.f32 "
      "fma.rn.ftz.f32 mul.ftz.f32 fma.rn.ftz.f32 selp.f32 setp.le.ftz.f32 copysign.f32 selp.f32",
      "OpExtInst Asin",
      "__ocml_asin_f32",
      "v_fma_f32 v_mul_f32 v_cmp_ge_f32 v_cndmask_b32 v_cmp_lt_f32 v_fmaak_f32 v_sqrt_f32 "
      "v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_mul_f32 v_fmac_f32 v_fma_f32 v_fmaak_f32 "
      "v_cndmask_b32 v_bfi_b32"};
  static constexpr OpInstructions kAcos = {
      "acosf",
      "FADD.FTZ FSETP.GT.FTZ.AND FSETP.NEU.FTZ.AND FFMA.FTZ MUFU.RSQ FMUL.FTZ FMUL.FTZ FFMA.FTZ "
      "FFMA.FTZ FSEL FSETP.GT.FTZ.AND LOP3.LUT FMUL.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ "
      "FFMA.FTZ FMUL.FTZ FFMA.FTZ FADD.FTZ FSEL FFMA.FTZ FADD.FTZ",
      "abs.ftz.f32 neg.ftz.f32 fma.rn.ftz.f32 rsqrt.approx.ftz.f32 mul.ftz.f32 mul.ftz.f32 "
      "neg.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 setp.eq.ftz.f32 selp.f32 setp.gt.ftz.f32 selp.f32 "
      "copysign.f32 mul.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 "
      "fma.rn.ftz.f32 mul.ftz.f32 fma.rn.ftz.f32 neg.ftz.f32 selp.f32 fma.rn.ftz.f32 "
      "setp.gt.ftz.f32 selp.f32 add.ftz.f32 selp.f32",
      "OpExtInst Acos",
      "__ocml_acos_f32",
      "v_fma_f32 v_mul_f32 v_cmp_gt_f32 v_cndmask_b32 v_fmaak_f32 v_sqrt_f32 v_cmp_gt_f32 "
      "v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_mul_f32 v_fmac_f32 v_fmac_f32 v_add_f32 "
      "v_fmaak_f32 v_sub_f32 v_cndmask_b32 v_cndmask_b32",
      {},
      true};
  static constexpr OpInstructions kAtan = {
      "atanf",
      "FSETP.GT.FTZ.AND FADD.FTZ MUFU.RCP FMUL.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ "
      "FFMA.FTZ FFMA.FTZ FMUL.FTZ FFMA.FTZ FFMA.FTZ FSETP.GTU.FTZ.AND LOP3.LUT FSEL",
      "abs.ftz.f32 setp.leu.ftz.f32 setp.gt.ftz.f32 rcp.approx.ftz.f32 selp.f32 mul.ftz.f32 "
      "fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 "
      "fma.rn.ftz.f32 mul.ftz.f32 fma.rn.ftz.f32 neg.ftz.f32 fma.rn.ftz.f32 copysign.f32 "
      "setp.le.ftz.f32 selp.f32",
      "OpExtInst Atan",
      "__ocml_atan_f32",
      "v_rcp_f32 v_cmp_gt_f32 v_cndmask_b32 v_mul_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 "
      "v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_mul_f32 v_fmac_f32 v_sub_f32 "
      "v_cndmask_b32 v_bfi_b32"};
  static constexpr OpInstructions kAtan2 = {
      "atan2f",
      "FADD.FTZ FADD.FTZ FSETP.GT.FTZ.AND FSEL FSEL MUFU.RCP FCHK FFMA FFMA FFMA FFMA FFMA "
      "FMUL.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ FMUL.FTZ FFMA.FTZ "
      "FFMA.FTZ FFMA.FTZ FFMA.FTZ FSETP.NEU.FTZ.AND FSETP.NEU.FTZ.AND FSEL FADD.FTZ FSEL "
      "FSETP.GTU.FTZ.AND LOP3.LUT FSEL",
      "abs.ftz.f32 abs.ftz.f32 setp.gt.ftz.f32 selp.f32 selp.f32 div.rn.ftz.f32 mul.ftz.f32 "
      "fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 fma.rn.ftz.f32 "
      "fma.rn.ftz.f32 mul.ftz.f32 fma.rn.ftz.f32 neg.ftz.f32 fma.rn.ftz.f32 neg.ftz.f32 "
      "fma.rn.ftz.f32 fma.rn.ftz.f32 selp.f32 selp.f32 setp.eq.ftz.f32 selp.f32 setp.eq.ftz.f32 "
      "selp.f32 add.ftz.f32 abs.ftz.f32 setp.gtu.ftz.f32 copysign.f32 selp.f32",
      "OpExtInst Atan2",
      "__ocml_atan2_f32",
      "v_max_f32 v_min_f32 v_cmp_lt_f32 v_cndmask_b32 v_cmp_gt_f32 v_mul_f32 v_rcp_f32 "
      "v_mul_f32 v_mul_f32 v_mul_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 "
      "v_fmaak_f32 v_fmaak_f32 v_mul_f32 v_fmac_f32 v_sub_f32 v_cndmask_b32 v_cmp_gt_f32 v_sub_f32 "
      "v_cndmask_b32 v_cmp_gt_i32 v_cndmask_b32 v_cmp_eq_f32 v_cndmask_b32 v_bfi_b32"};
  static constexpr OpInstructions kTanh = {
      "tanhf",
      "MUFU.TANH",
      "tanh.approx.f32",
      "OpExtInst Tanh",
      "__ocml_tanh_f32",
      "v_and_b32 v_cmp_le_f32 v_mul_f32 v_exp_f32 v_add_f32 v_rcp_f32 v_fma_f32 v_mul_f32 "
      "v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_mul_f32 v_fmac_f32 v_bfi_b32"};
  static constexpr OpInstructions kErf = {
      "erff",
      "FADD.FTZ FMUL.FTZ FSETP.GE.FTZ.AND FSEL FSEL FSEL FSEL FSEL FFMA.FTZ FFMA.FTZ FSEL "
      "FFMA.FTZ FSEL FFMA.FTZ FADD.FTZ FSEL FFMA.FTZ FSEL FFMA.FTZ FFMA.FTZ MUFU.EX2 FADD.FTZ "
      "LOP3.LUT",
      "abs.ftz.f32 setp.ltu.ftz.f32 setp.ge.ftz.f32 mul.ftz.f32 selp.f32 selp.f32 selp.f32 "
      "fma.rn.ftz.f32 selp.f32 fma.rn.ftz.f32 selp.f32 fma.rn.ftz.f32 selp.f32 fma.rn.ftz.f32 "
      "selp.f32 fma.rn.ftz.f32 selp.f32 fma.rn.ftz.f32 neg.ftz.f32 selp.f32 fma.rn.ftz.f32 "
      "ex2.approx.ftz.f32 sub.ftz.f32 copysign.f32",
      kErfHelperSpirv,
      "__ocml_erf_f32",
      "v_and_b32 v_cmp_ge_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 "
      "v_fmaak_f32 v_fmac_f32 v_mul_f32 v_exp_f32 v_sub_f32 v_mul_f32 v_fmaak_f32 v_fmaak_f32 "
      "v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmac_f32 v_bfi_b32",
      kErfHelperName};
  switch (op) {
    case Op::Add: return &kAdd;
    case Op::Sub: return &kSub;
    case Op::Mul: return &kMul;
    case Op::Fma: return &kFma;
    case Op::Neg: return &kNeg;
    case Op::Abs: return &kAbs;
    case Op::Min: return &kMin;
    case Op::Max: return &kMax;
    case Op::Sqrt: return &kSqrt;
    case Op::Rsqrt: return &kRsqrt;
    case Op::Exp2: return &kExp2;
    case Op::Log2: return &kLog2;
    case Op::Sin: return &kSin;
    case Op::Cos: return &kCos;
    case Op::Exp: return &kExp;
    case Op::Log: return &kLog;
    case Op::Asin: return &kAsin;
    case Op::Acos: return &kAcos;
    case Op::Atan: return &kAtan;
    case Op::Atan2: return &kAtan2;
    case Op::Tanh: return &kTanh;
    case Op::Erf: return &kErf;
    default: return nullptr;
  }
}

// The row of a library function, or nullptr for the other operators.
inline const OpInstructions* library_call(Op op) {
  const OpInstructions* f = op_instructions(op);
  return f != nullptr && f->library() ? f : nullptr;
}

// Whether `op`'s instruction takes its argument in turns (OpInstructions::turns).
inline bool in_turns(Op op) {
  const OpInstructions* f = op_instructions(op);
  return f != nullptr && f->turns;
}

// Whether 1 / op(x) is op(-x) (OpInstructions::exponential).
inline bool exponential(Op op) {
  const OpInstructions* f = op_instructions(op);
  return f != nullptr && f->exponential;
}

// Whether `op`'s SASS instruction reads -x and |x| for free (OpInstructions::sass_modifiers).
inline bool takes_operand_modifiers(Op op) {
  const OpInstructions* f = op_instructions(op);
  return f != nullptr && f->sass_modifiers;
}

// The helper GLSL, HLSL and Metal code calls for `op`, or empty (OpInstructions::helper).
inline std::string_view helper_of(Op op) {
  const OpInstructions* c = library_call(op);
  return c != nullptr ? c->helper : std::string_view{};
}

// The instructions of a list: its words, "OpExtInst" taken with the word after it.
inline std::vector<std::string_view> mnemonics(std::string_view list) {
  std::vector<std::string_view> out;
  while (!list.empty()) {
    std::size_t end = list.find(' ');
    if (list.substr(0, end) == "OpExtInst") end = list.find(' ', end + 1);
    out.push_back(list.substr(0, end));
    if (end == std::string_view::npos) break;
    list.remove_prefix(end + 1);
  }
  return out;
}

// The unit an instruction issues to: MUFU, PTX's approximate functions and div, SPIR-V's
// extended functions but abs and min/max, and RDNA's transcendentals the multi-function unit;
// additions, multiplications, negation and abs the FP32 pipe; compares, selects, copysign, LOP3,
// FCHK and min/max the MinMax class.
inline InstructionUnit mnemonic_unit(std::string_view m) {
  const auto starts = [&](std::string_view k) { return m.substr(0, k.size()) == k; };
  for (std::string_view k : {"FADD", "FMUL", "FFMA", "add.", "sub.", "mul.", "fma.", "neg.", "abs.",
                             "OpFAdd", "OpFSub", "OpFMul", "OpFNegate", "OpExtInst FAbs",
                             "OpExtInst Fma", "v_add_f", "v_sub_f", "v_mul_f", "v_fma"})
    if (starts(k)) return InstructionUnit::Fp32;
  for (std::string_view k : {"OpExtInst FMin", "OpExtInst FMax"})
    if (starts(k)) return InstructionUnit::MinMax;
  for (std::string_view k :
       {"MUFU", "rcp.", "rsqrt.", "sqrt.", "ex2.", "lg2.", "sin.", "cos.", "tanh.", "div.",
        "OpExtInst", "v_rcp_", "v_rsq_", "v_sqrt_", "v_exp_", "v_log_", "v_sin_", "v_cos_"})
    if (starts(k)) return InstructionUnit::Mufu;
  return InstructionUnit::MinMax;
}

}  // namespace shaderfit::cost_detail
