// SASS selection for half: what ptxas makes of codegen's __half2 function (nvcc --use_fast_math
// -arch=sm_90), counted per __half2 call, i.e. for two values. Rules, each checked against
// cuobjdump output (docs/precision.md, "Half cost"):
//  - + - * fma min max are one packed instruction each: HADD2, HMUL2, HFMA2, HMNMX2 (immediates
//    free); the generated code writes __hadd2_rn / __hmul2_rn, which ptxas never contracts, so a
//    product and a sum stay two instructions unless the formula has an fma;
//  - min(min(a, b), c) (or max of max), the inner one read only there, is one three-operand
//    VHMNMX;
//  - saturate is __hadd2_sat(x, 0): HADD2.SAT;
//  - a negation or |x| read by those, by another negation or |x|, or by a function's conversion to
//    float, is an operand modifier: free; any other is HADD2 d, -x, -RZ (or |x|);
//  - the functions have no packed half instruction on sm_90: each converts both halves of its
//    operand to float (HADD2.F32 twice, once per distinct operand and modifier however many
//    functions read it), runs the float instruction on each (MUFU.RCP, MUFU.RSQ, MUFU.SQRT,
//    MUFU.EX2, MUFU.LG2, the last shared by log2 and log of one operand; sin and cos: FMUL.RZ,
//    once per distinct argument, and MUFU.SIN/COS, the __sinf of the helper) and packs the two
//    results back into half (F2FP.F16.F32.PACK_AB), with the fix-ups cuda_fp16.h adds for correct
//    rounding (exp2: one FFMA per half; log2, exp, log: HSET2 compares and HFMA2 on the packed
//    values);
//  - a / b (__h2div) converts both operands (not a literal), takes MUFU.RCP of each half of b (once
//    per divisor, shared with 1 / b, none for a literal) and then, per half, a product, a
//    rounding, a test and a correction path: 16 instructions (and a PRMT that packs the halves:
//    data movement, not counted, as the moves of constants are not).
// The sequences after the conversions are in cost/op_instructions.hpp (the functions) and below
// (a / b, 1 / b), as measured.
#include <fmt/format.h>

#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "cost/float_text.hpp"
#include "cost/op_instructions.hpp"
#include "cost/select.hpp"
#include "cost/step_text.hpp"
#include "shaderfit/core/error.hpp"

namespace shaderfit::cost_detail {

namespace {

// A value as the packed SASS reads it: a register with modifiers, or an immediate pair.
struct Val {
  int reg = -1;
  bool neg = false, abs = false;
  bool imm = false;
  float value = 0.0f;
  int lane = -1;  // a conversion's operand: .H0_H0 (0) or .H1_H1 (1)
};

// The measured instructions of a / b and 1 / b (__h2div, h2rcp) after their operands'
// conversions to float and the MUFU.RCP of b; the functions' lists (after the conversion, and
// after the FMUL.RZ of sin and cos or the MUFU.LG2 of log2 and log) are their rows'
// OpInstructions::half2.
constexpr std::string_view kReciprocal = "F2FP.F16.F32.PACK_AB";
constexpr std::string_view kQuotient =
    "FMUL.FTZ FMUL.FTZ F2FP.F16.F32.PACK_AB F2FP.F16.F32.PACK_AB HSETP2.GEU.AND HSETP2.GT.AND "
    "PLOP3.LUT HSETP2.GEU.AND HSETP2.GT.AND PLOP3.LUT FFMA.FTZ FFMA.FTZ FFMA.FTZ FFMA.FTZ "
    "F2FP.F16.F32.PACK_AB F2FP.F16.F32.PACK_AB";

InstructionUnit unit_of(std::string_view mnemonic) {
  if (mnemonic.rfind("MUFU", 0) == 0) return InstructionUnit::Mufu;
  if (mnemonic.rfind("HSET", 0) == 0 || mnemonic.find("HMNMX") != std::string_view::npos ||
      mnemonic.rfind("FSE", 0) == 0 || mnemonic.rfind("LOP3", 0) == 0 ||
      mnemonic.rfind("PLOP3", 0) == 0 || mnemonic.rfind("ISETP", 0) == 0 ||
      mnemonic.rfind("HSETP", 0) == 0)
    return InstructionUnit::MinMax;
  return InstructionUnit::Fp32;
}

class Half2Selector {
 public:
  Half2Selector(const Dag& dag, const Program& p, bool text) : dag_(dag), p_(p), text_(text) {
    const std::size_t n = p.steps.size();
    consumers_.assign(n, {});
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < p.steps[i].arity; ++k)
        if (p.steps[i].args[k].kind == Operand::Kind::Step)
          consumers_[static_cast<std::size_t>(p.steps[i].args[k].index)].push_back(
              static_cast<int>(i));
    next_reg_ = static_cast<int>(dag.variables.size() + dag.parameters.size());
    vals_.assign(n, {});
    // min(min(a, b), c): the inner one, read only by the outer, becomes part of a VHMNMX (one
    // inner per outer; an inner that took one of its own has three operands already).
    absorbed_.assign(n, false);
    std::vector<bool> merged(n, false);
    for (std::size_t i = 0; i < n; ++i) {
      const Step& st = p.steps[i];
      if (st.op != Op::Min && st.op != Op::Max) continue;
      for (int k = 0; k < 2 && !merged[i]; ++k) {
        const Operand& o = st.args[k];
        if (o.kind != Operand::Kind::Step) continue;
        const auto j = static_cast<std::size_t>(o.index);
        if (p.steps[j].op != st.op || merged[j] || p.steps[j].uses != 1 ||
            consumers_[j].size() != 1 || is_result(o.index))
          continue;
        absorbed_[j] = merged[i] = true;
      }
    }
  }

  std::vector<TargetInstruction> run() {
    for (std::size_t i = 0; i < p_.steps.size(); ++i) select(static_cast<int>(i));
    return std::move(out_);
  }

 private:
  [[nodiscard]] bool is_result(int s) const {
    for (const Operand& r : p_.results)
      if (r.kind == Operand::Kind::Step && r.index == s) return true;
    return false;
  }
  // The instructions of a function's __half2 call after the conversions, or empty for a step
  // that is no function.
  [[nodiscard]] static std::string_view function_of(const Step& st) {
    if (st.op == Op::Div) return is_reciprocal(st) ? kReciprocal : kQuotient;
    const OpInstructions* f = op_instructions(st.op);
    return f != nullptr ? f->half2 : std::string_view{};
  }
  // True when every reader of step s takes a negated or absolute operand for free: the packed
  // arithmetic, and the conversions to float that the functions start with.
  [[nodiscard]] bool modifiers_free(int s) const {
    if (is_result(s)) return false;
    for (int c : consumers_[static_cast<std::size_t>(s)]) {
      const Step& rd = p_.steps[static_cast<std::size_t>(c)];
      if (takes_operand_modifiers(rd.op) || rd.op == Op::Saturate) continue;
      // A negation or |x| that is an instruction of its own takes the other one with it.
      if (rd.op == Op::Neg || rd.op == Op::Abs) continue;
      if (!function_of(rd).empty()) continue;  // the conversions to float take both
      return false;
    }
    return true;
  }

  [[nodiscard]] Val val(const Operand& o) const {
    switch (o.kind) {
      case Operand::Kind::Const: return Val{-1, false, false, true, o.value};
      case Operand::Kind::Var: return Val{o.index};
      case Operand::Kind::Param: return Val{static_cast<int>(dag_.variables.size()) + o.index};
      default: return vals_[static_cast<std::size_t>(o.index)];
    }
  }
  static std::string text(const Val& v) {
    if (v.imm) {
      const std::string t = float_text(v.value);
      return t + ", " + t;  // both halves
    }
    std::string r = v.reg < 0 ? std::string("RZ") : "R" + std::to_string(v.reg);
    if (v.abs) r = "|" + r + "|";
    if (v.lane >= 0) r += v.lane == 0 ? ".H0_H0" : ".H1_H1";
    return v.neg ? "-" + r : r;
  }
  static Val negated(Val v) {
    if (v.imm)
      v.value = -v.value;
    else
      v.neg = !v.neg;
    return v;
  }

  Val emit(std::string_view op, std::initializer_list<Val> args, const std::string& comment) {
    const Val d{next_reg_++};
    TargetInstruction ins;
    ins.unit = unit_of(op);
    if (text_) {
      ins.text = std::string(op) + " " + text(d);
      for (const Val& a : args) ins.text += ", " + text(a);
      ins.comment = comment;
    }
    out_.push_back(std::move(ins));
    return d;
  }

  // Both halves of `a` in float: HADD2.F32 twice, once per distinct value and modifier.
  void convert(const Val& a, const Operand& o) {
    if (a.imm || !converted_.insert({a.reg, a.neg, a.abs}).second) return;
    for (int lane : {0, 1}) {
      Val h = a;
      h.lane = lane;
      emit("HADD2.F32", {Val{-1, true}, h},
           text_ ? fmt::format("half {} of {} to float", lane, operand_text(o)) : "");
    }
  }

  // Once per distinct operand and modifier: the two MUFU.RCP of a divisor's halves, or the
  // shared instruction of the functions of one operand (OpInstructions::half2_shared).
  void once_per_operand(std::string_view op, const Val& a, const Operand& o) {
    if (a.imm || !once_.insert({op, a.reg, a.neg, a.abs}).second) return;
    for (int lane : {0, 1})
      emit(op, {a}, text_ ? fmt::format("{} of half {} of {}", op, lane, operand_text(o)) : "");
  }

  // A measured sequence, listed without operands (each half has its own registers); the last
  // instruction gives the value.
  Val sequence(std::string_view mnemonics, const std::string& what, std::string_view name) {
    const std::vector<std::string_view> ops = cost_detail::mnemonics(mnemonics);
    Val v;
    for (std::size_t k = 0; k < ops.size(); ++k) {
      const std::string c =
          !text_ || k + 1 == ops.size() ? what : fmt::format("{} {}/{}", name, k + 1, ops.size());
      v = emit(ops[k], {}, c);
    }
    return v;
  }

  [[nodiscard]] std::string operand_text(const Operand& o) const {
    switch (o.kind) {
      case Operand::Kind::Const: return float_text(o.value);
      case Operand::Kind::Var: return dag_.variables[static_cast<std::size_t>(o.index)];
      case Operand::Kind::Param: return dag_.parameters[static_cast<std::size_t>(o.index)];
      default: return names_text_.of(o.index, 32);
    }
  }

  void select(int s) {
    const Step& st = p_.steps[static_cast<std::size_t>(s)];
    const std::string c = text_ ? names_text_.of(s) : std::string();
    const Val a = st.arity > 0 ? val(st.args[0]) : Val{};
    const Val b = st.arity > 1 ? val(st.args[1]) : Val{};
    const Val rz{-1, true, false, false, 0.0f};
    Val& out = vals_[static_cast<std::size_t>(s)];
    // Immediates go last, as ptxas writes them.
    const auto ordered = [](Val x, Val y) {
      return x.imm && !y.imm ? std::make_pair(y, x) : std::make_pair(x, y);
    };
    switch (st.op) {
      case Op::Add:
      case Op::Sub: {
        const auto [x, y] = ordered(a, st.op == Op::Sub ? negated(b) : b);
        out = emit("HADD2", {x, y}, c);
        return;
      }
      case Op::Mul: {
        const auto [x, y] = ordered(a, b);
        out = emit("HMUL2", {x, y}, c);
        return;
      }
      case Op::Fma: {
        const auto [x, y] = ordered(a, b);
        out = emit("HFMA2", {x, y, val(st.args[2])}, c);
        return;
      }
      case Op::Min:
      case Op::Max: {
        if (absorbed_[static_cast<std::size_t>(s)]) {  // computed by its reader's VHMNMX
          out = a;
          return;
        }
        for (int k : {0, 1}) {
          const Operand& o = st.args[k];
          if (o.kind != Operand::Kind::Step || !absorbed_[static_cast<std::size_t>(o.index)])
            continue;
          const Step& inner = p_.steps[static_cast<std::size_t>(o.index)];
          out = emit("VHMNMX", {val(inner.args[0]), val(inner.args[1]), k == 0 ? b : a}, c);
          return;
        }
        const auto [x, y] = ordered(a, b);
        out = emit("HMNMX2", {x, y}, c);
        return;
      }
      case Op::Saturate: out = emit("HADD2.SAT", {a, rz}, c); return;
      case Op::Neg:
        out = modifiers_free(s) ? negated(a) : emit("HADD2", {negated(a), rz}, c);
        return;
      case Op::Abs: {
        Val m = a;
        m.abs = true;
        m.neg = false;
        out = modifiers_free(s) ? m : emit("HADD2", {m, rz}, c);
        return;
      }
      default: break;
    }
    if (const std::string_view f = function_of(st); !f.empty()) {
      if (st.op != Op::Div) {
        convert(a, st.args[0]);
        const std::string_view shared = op_instructions(st.op)->half2_shared;
        if (!shared.empty()) once_per_operand(shared, a, st.args[0]);
        out = sequence(f, c, step_name(st));
        return;
      }
      // 1 / x reads x (-1 / x is 1 / -x, the sign free in the conversion); a / b reads both.
      const bool rcp = is_reciprocal(st);
      const Val x = rcp && st.args[0].value < 0 ? negated(b) : b;
      if (!rcp) convert(a, st.args[0]);
      convert(x, st.args[1]);
      once_per_operand("MUFU.RCP", x, st.args[1]);
      out = sequence(f, c, step_name(st));
      return;
    }
    throw Error(fmt::format("{} has no half form (docs/precision.md)", step_name(st)),
                SourceLocation{"formula"});
  }

  static std::string step_name(const Step& st) {
    if (st.op == Op::Div) return is_reciprocal(st) ? "h2rcp" : "__h2div";
    if (st.op == Op::Select) return "select";
    const OpInstructions* f = op_instructions(st.op);
    return std::string(f != nullptr && !f->half2_call.empty() ? f->half2_call
                                                              : step_call_name(st.op));
  }

  const Dag& dag_;
  const Program& p_;
  StepText names_text_{dag_, p_};
  bool text_;
  std::vector<std::vector<int>> consumers_;
  std::vector<Val> vals_;
  std::vector<bool> absorbed_;  // a min or max that is part of its reader's VHMNMX
  // By register and modifiers: the values converted to float; by instruction too, those with
  // their MUFU.RCP or their shared instruction (FMUL.RZ, MUFU.LG2) done.
  std::set<std::tuple<int, bool, bool>> converted_;
  std::set<std::tuple<std::string_view, int, bool, bool>> once_;
  std::vector<TargetInstruction> out_;
  int next_reg_ = 0;
};

}  // namespace

std::vector<TargetInstruction> select_sass_half2(const Dag& dag, const Program& program,
                                                 bool with_text) {
  return Half2Selector(dag, program, with_text).run();
}

}  // namespace shaderfit::cost_detail
