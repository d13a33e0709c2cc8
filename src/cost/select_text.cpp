// PTX and generic (SPIR-V-like) selection: one instruction per program step (the arithmetic and
// the hardware's functions: their rows in cost/op_instructions.hpp), except that PTX
// spells exp as mul + ex2 and log as lg2 + mul, as __expf and __logf do under --use_fast_math,
// and the steps of sign, copysign and select, as the generated code writes them:
//  - select(a, b, c), `a >= 0 ? b : c`: a comparison and a select; nvcc compares each distinct
//    condition once (PTX), glslang every time (SPIR-V);
//  - copysign: PTX copysign.f32; GLSL/HLSL (no copysign) the bits, a & 0x7fffffff | b &
//    0x80000000, two ANDs and an OR (one AND folds when a is a literal);
//  - sign(x): PTX (|x| > 0 ? copysignf(1, x) : x) abs, setp, copysign, selp; GLSL/HLSL
//    (x > 0 ? 1 : (x < 0 ? -1 : x)) two comparisons and two selects;
//  - sqrt, rsqrt, exp2, log2, sin, cos: one instruction each; asin, acos, atan, atan2, tanh,
//    erf: PTX the instructions of CUDA's asinf ... erff as measured, SPIR-V one OpExtInst, erf
//    the instructions of the helper function GLSL and HLSL call (cost/erf_helper.hpp); both from
//    cost/op_instructions.hpp.
#include <fmt/format.h>

#include <bit>
#include <cstdio>
#include <map>

#include "cost/erf_helper.hpp"
#include "cost/float_text.hpp"
#include "cost/op_instructions.hpp"
#include "cost/select.hpp"
#include "cost/step_text.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit::cost_detail {

namespace {

std::string ptx_const(float v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0f%08X", std::bit_cast<std::uint32_t>(v));
  return buf;
}

class TextSelector {
 public:
  TextSelector(const Dag& dag, const Program& p, bool text, bool ptx) : dag_(dag), p_(p), text_(text), ptx_(ptx) {
    names_.resize(p.steps.size());
  }

  std::vector<TargetInstruction> run() {
    for (std::size_t i = 0; i < p_.steps.size(); ++i) select(static_cast<int>(i));
    return std::move(out_);
  }

 private:
  std::string name(const Operand& o) const {
    switch (o.kind) {
      case Operand::Kind::Const: return ptx_ ? ptx_const(o.value) : float_text(o.value);
      case Operand::Kind::Var:
        return ptx_ ? "%f" + std::to_string(o.index + 1) : "%" + dag_.variables[static_cast<std::size_t>(o.index)];
      case Operand::Kind::Param: {
        const std::size_t i = dag_.variables.size() + static_cast<std::size_t>(o.index);
        return ptx_ ? "%f" + std::to_string(i + 1) : "%" + dag_.parameters[static_cast<std::size_t>(o.index)];
      }
      default: return names_[static_cast<std::size_t>(o.index)];
    }
  }

  std::string emit(InstructionUnit unit, const std::string& op, std::initializer_list<std::string> args,
                   const std::string& comment) {
    const std::string d = ptx_ ? "%f" + std::to_string(dag_.variables.size() + dag_.parameters.size() + ++count_)
                               : "%" + std::to_string(++count_);
    TargetInstruction ins;
    ins.unit = unit;
    if (text_) {
      ins.text = ptx_ ? op + " " + d : d + " = " + op;
      bool first = !ptx_;
      for (const std::string& a : args) {
        ins.text += (first ? " " : ", ") + a;
        first = false;
      }
      ins.comment = comment;
    }
    out_.push_back(std::move(ins));
    return d;
  }

  void select(int s) {
    const Step& st = p_.steps[static_cast<std::size_t>(s)];
    if (st.compared) return;  // its selects compare its operands
    const std::string c = text_ ? names_text_.of(s) : std::string();
    const std::string a = st.arity > 0 ? name(st.args[0]) : std::string();
    const std::string b = st.arity > 1 ? name(st.args[1]) : std::string();
    std::string& out = names_[static_cast<std::size_t>(s)];
    using U = InstructionUnit;
    auto simple = [&](U unit, const char* ptx_op, const char* spirv_op, std::initializer_list<std::string> args) {
      out = emit(unit, ptx_ ? ptx_op : spirv_op, args, c);
    };
    switch (st.op) {
      case Op::Div:
        if (ptx_ && is_reciprocal(st) && st.args[0].value > 0)
          simple(U::Mufu, "rcp.approx.ftz.f32", "", {b});
        else
          simple(U::Mufu, "div.approx.ftz.f32", "OpFDiv", {a, b});
        break;
      case Op::Saturate: simple(U::Fp32, "cvt.ftz.sat.f32.f32", "OpExtInst FClamp", ptx_ ? std::initializer_list<std::string>{a} : std::initializer_list<std::string>{a, "0", "1"}); break;
      case Op::Exp:
        if (ptx_) {
          const std::string t = emit(U::Fp32, "mul.ftz.f32", {a, ptx_const(kLog2E)}, "log2(e) * ...");
          out = emit(U::Mufu, "ex2.approx.ftz.f32", {t}, c);
        } else {
          simple(U::Mufu, "", "OpExtInst Exp", {a});
        }
        break;
      case Op::Sign:
        if (ptx_) {
          const std::string t = emit(U::Fp32, "abs.ftz.f32", {a}, "magnitude for " + c);
          const std::string p =
              emit(U::MinMax, "setp.gt.ftz.f32", {t, ptx_const(0.0f)}, "test of " + c);
          const std::string one =
              emit(U::MinMax, "copysign.f32", {a, ptx_const(1.0f)}, "copysign(1, ...)");
          out = emit(U::MinMax, "selp.f32", {one, a, p}, c);
        } else {
          const std::string gt = emit(U::MinMax, "OpFOrdGreaterThan", {a, "0"}, "test of " + c);
          const std::string lt = emit(U::MinMax, "OpFOrdLessThan", {a, "0"}, "test of " + c);
          const std::string in = emit(U::MinMax, "OpSelect", {lt, "-1", a}, "");
          out = emit(U::MinMax, "OpSelect", {gt, "1", in}, c);
        }
        break;
      case Op::CopySign:
        if (ptx_) {
          simple(U::MinMax, "copysign.f32", "", {b, a});
        } else {
          const std::string m = st.args[0].kind == Operand::Kind::Const
                                    ? a
                                    : emit(U::MinMax, "OpBitwiseAnd", {a, "0x7fffffff"}, "|...|");
          const std::string sb = emit(U::MinMax, "OpBitwiseAnd", {b, "0x80000000"}, "sign bit");
          out = emit(U::MinMax, "OpBitwiseOr", {m, sb}, c);
        }
        break;
      case Op::Select: {
        std::string p;
        const auto key = std::make_pair(a, st.neg_arg);
        if (ptx_ && conditions_.count(key)) {
          p = conditions_.at(key);
        } else {
          const char* op = ptx_ ? (st.neg_arg ? "setp.le.ftz.f32" : "setp.ge.ftz.f32")
                                : (st.neg_arg ? "OpFOrdLessThanEqual" : "OpFOrdGreaterThanEqual");
          const Comparison cmp = select_comparison(p_, st);
          p = emit(U::MinMax, op, {name(cmp.lhs), name(cmp.rhs)}, "condition of " + c);
          conditions_[key] = p;
        }
        simple(U::MinMax, "selp.f32", "OpSelect",
               ptx_ ? std::initializer_list<std::string>{b, name(st.args[2]), p}
                    : std::initializer_list<std::string>{p, b, name(st.args[2])});
        break;
      }
      case Op::Log:
        if (ptx_) {
          const std::string t = emit(U::Mufu, "lg2.approx.ftz.f32", {a}, "log2 of ...");
          out = emit(U::Fp32, "mul.ftz.f32", {t, ptx_const(kLn2)}, c);
        } else {
          simple(U::Mufu, "", "OpExtInst Log", {a});
        }
        break;
      default: {
        const OpInstructions* f = op_instructions(st.op);
        if (f == nullptr || (ptx_ ? f->ptx : f->spirv).empty())
          throw Error("internal: no text form for '" + std::string(op_info(st.op).name) + "'");
        const std::vector<std::string_view> ops = mnemonics(ptx_ ? f->ptx : f->spirv);
        const std::string_view call = ptx_ ? f->cuda : f->helper;  // a library function's
        for (std::size_t k = 0; k < ops.size(); ++k) {
          const std::string what =
              !text_ || k + 1 == ops.size() ? c : fmt::format("{} {}/{}", call, k + 1, ops.size());
          const U unit = mnemonic_unit(ops[k]);
          if (k == 0 && st.arity == 3)
            out = emit(unit, std::string(ops[k]), {a, b, name(st.args[2])}, what);
          else if (k == 0 && st.arity == 2)
            out = emit(unit, std::string(ops[k]), {a, b}, what);
          else
            out = emit(unit, std::string(ops[k]), {k == 0 ? a : std::string(out)}, what);
        }
        break;
      }
    }
  }

  const Dag& dag_;
  const Program& p_;
  StepText names_text_{dag_, p_};
  bool text_, ptx_;
  std::vector<std::string> names_;
  std::map<std::pair<std::string, bool>, std::string> conditions_;  // PTX: setp per condition
  std::vector<TargetInstruction> out_;
  std::size_t count_ = 0;
};

}  // namespace

std::vector<TargetInstruction> select_ptx(const Dag& dag, const Program& program, bool with_text) {
  return TextSelector(dag, program, with_text, true).run();
}

std::vector<TargetInstruction> select_generic(const Dag& dag, const Program& program, bool with_text) {
  return TextSelector(dag, program, with_text, false).run();
}

}  // namespace shaderfit::cost_detail
