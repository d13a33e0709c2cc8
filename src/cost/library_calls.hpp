// Internal: the operators that are library functions on GPUs (asinf, acosf, atanf, atan2f, tanhf,
// erff in CUDA), with the instructions nvcc emits for each, as measured.
//
// Measured with nvcc 13.0 --use_fast_math -arch=sm_90 (the `sass` and `ptx` targets' compiler),
// one kernel per function reading its arguments from memory (docs/cost-model.md, "Library
// functions"), counted as src/codegen/toolchain_test_support.hpp counts: the arithmetic
// instructions of PTX and SASS, in the order the compiler emitted them. atan2f divides with
// div.rn, whose SASS has an out-of-line slow path (27 instructions, run only for quotients
// beyond float's normal range) that is not counted; tanhf is MUFU.TANH under --use_fast_math.
// The generic target counts one OpExtInst for each (GLSL.std.450 Asin, Acos, Atan, Atan2,
// Tanh), and for erf the instructions of the helper that code generation writes (GLSL, HLSL
// and Metal have no erf; cost/erf_helper.hpp), as glslang emits them.
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

struct LibraryCall {
  std::string_view cuda;   // the CUDA function: "asinf"
  std::string_view sass;   // SASS mnemonics, space-separated
  std::string_view ptx;    // PTX mnemonics, space-separated
  std::string_view spirv;  // SPIR-V instructions of the GLSL and HLSL code
  std::string_view ocml;   // the OCML function the RDNA count is measured on: "__ocml_asin_f32"
  std::string_view rdna;   // its RDNA VALU mnemonics, space-separated
  // The helper that GLSL, HLSL and Metal code calls, which code generation writes (erf);
  // empty where those languages have the function.
  std::string_view helper = {};
  // ptxas gives a negated product read only by this call as the product and its negation
  // (FADD), where other readers take FMUL -a, b.
  bool negates_product = false;
};

// The call a program step makes, or nullptr for a step that is no library call.
inline const LibraryCall* library_call(Op op) {
  static constexpr LibraryCall kAsin = {
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
  static constexpr LibraryCall kAcos = {
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
  static constexpr LibraryCall kAtan = {
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
      "v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_mul_f32 v_fmac_f32 v_sub_f32 v_cndmask_b32 "
      "v_bfi_b32"};
  static constexpr LibraryCall kAtan2 = {
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
  static constexpr LibraryCall kTanh = {"tanhf", "MUFU.TANH", "tanh.approx.f32", "OpExtInst Tanh",
      "__ocml_tanh_f32",
      "v_and_b32 v_cmp_le_f32 v_mul_f32 v_exp_f32 v_add_f32 v_rcp_f32 v_fma_f32 v_mul_f32 "
      "v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_fmaak_f32 v_mul_f32 v_fmac_f32 v_bfi_b32"};
  static constexpr LibraryCall kErf = {
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
    case Op::Asin: return &kAsin;
    case Op::Acos: return &kAcos;
    case Op::Atan: return &kAtan;
    case Op::Atan2: return &kAtan2;
    case Op::Tanh: return &kTanh;
    case Op::Erf: return &kErf;
    default: return nullptr;
  }
}

// The helper GLSL, HLSL and Metal code calls for `op`, or empty (LibraryCall::helper).
inline std::string_view helper_of(Op op) {
  const LibraryCall* c = library_call(op);
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
// additions, multiplications, negation and abs the FP32 pipe; compares, selects, copysign, LOP3, FCHK and min/max the
// MinMax class.
inline InstructionUnit mnemonic_unit(std::string_view m) {
  const auto starts = [&](std::string_view k) { return m.substr(0, k.size()) == k; };
  for (std::string_view k : {"FADD", "FMUL", "FFMA", "add.", "sub.", "mul.", "fma.", "neg.", "abs.",
                             "OpFAdd", "OpFSub", "OpFMul", "OpFNegate", "OpExtInst FAbs", "v_add_f",
                             "v_sub_f", "v_mul_f", "v_fma"})
    if (starts(k)) return InstructionUnit::Fp32;
  for (std::string_view k : {"OpExtInst FMin", "OpExtInst FMax"})
    if (starts(k)) return InstructionUnit::MinMax;
  for (std::string_view k :
       {"MUFU", "rcp.", "rsqrt.", "sqrt.", "ex2.", "lg2.", "tanh.", "div.", "OpExtInst", "v_rcp_",
        "v_rsq_", "v_sqrt_", "v_exp_", "v_log_", "v_sin_", "v_cos_"})
    if (starts(k)) return InstructionUnit::Mufu;
  return InstructionUnit::MinMax;
}

}  // namespace shaderfit::cost_detail
